// SPDX-License-Identifier: GPL-3.0-or-later
// nscdBench reorder: the cache effect of the grain order.
//
// Beds at rest of 1,000 / 10,000 / 70,000 / 200,000 discs (mirror tilings of
// one settled 500-disc block, as tests/bench/nscdDeposit, warm-started from
// the block's contact impulses) are stepped from the same state with the
// grains given to the System
//  - "tiled": in the order of the tiling (block by block, each block in its
//    lattice rows: already close to a spatial order);
//  - "rows": row-major across the whole width (height bands of one mean
//    diameter, then x: the fill order of an insertion lattice, as
//    grainDeposit's), neighbours above and below ~width/d indices away;
//  - "shuffled": in a random order (the worst case: a grain's neighbours are
//    anywhere in memory);
// each with reorderInterval 0 (kept) and 100 (Morton order, Reorder.cpp),
// the two stepped in turn from the same state (paired CPU ratio on/off).
// One core, thread CPU time per step (median over the timed steps), the
// detection and solve times of StepReport, sweeps and local solves; the
// time per contact update is the step's CPU time / (sweeps x contacts) and
// the solve's time per local solve.
//   nscdBench reorder <out.json> [quick]
#include "benchBeds.H"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <random>
#include <sstream>
#include <string>

using namespace nscd;
using namespace nscdBench;

namespace
{
struct Run
{
    std::string order;
    int interval = 0;
    int grains = 0, contacts = 0, steps = 0;
    double cpu = 0, detect = 0, solve = 0, sweeps = 0, localSolves = 0;
    double nsPerContactSweep = 0, nsPerLocalSolve = 0, nsDetectPerContact = 0;
};

/// The tiled bed with its contact impulses, grains permuted by perm
/// (perm[k] = tiled index of the k-th grain added).
System build(const Bed& bed, const std::vector<System::ContactView>& views, const std::vector<int>& perm)
{
    Bed b = bed;
    std::vector<int> inv(perm.size());
    for (std::size_t k = 0; k < perm.size(); ++k)
    {
        b.x[k] = bed.x[perm[k]];
        b.r[k] = bed.r[perm[k]];
        inv[perm[k]] = int(k);
    }
    System s = makeSystem(b, 0.4);
    std::vector<System::ContactView> v = views;
    for (auto& c : v)
    {
        c.i = inv[c.i];
        if (c.j >= 0) c.j = inv[c.j];
    }
    s.setContactImpulses(v, dt);
    return s;
}

/// The bed's grains in row-major order across the whole width: by height
/// band of one mean diameter, then by x (the fill order of a lattice, as
/// grainDeposit's insertion lattice, bottom first).
std::vector<int> rowOrder(const Bed& bed)
{
    std::vector<int> p(bed.x.size());
    std::iota(p.begin(), p.end(), 0);
    auto band = [&](int k) { return long(std::floor(bed.x[k].y() / dMean)); };
    std::sort(p.begin(), p.end(),
              [&](int a, int b)
              { return band(a) < band(b) || (band(a) == band(b) && bed.x[a].x() < bed.x[b].x()); });
    return p;
}

/// Time one step of s (thread CPU) into R's per-step lists.
struct Samples
{
    std::vector<double> cpu, det, sol, sw, ls, perCs, perLs, perDet;
    int contacts = 0;
};

double timeStep(System& s, Samples& S)
{
    const double c0 = cpu();
    const StepReport r = s.step(dt);
    const double c = cpu() - c0;
    S.cpu.push_back(c);
    S.det.push_back(r.detectSeconds);
    S.sol.push_back(r.solveSeconds);
    S.sw.push_back(r.sweeps);
    S.ls.push_back(double(r.localSolves));
    S.perCs.push_back(1e9 * c / std::max(1.0, double(r.sweeps) * r.contacts));
    S.perLs.push_back(1e9 * r.solveSeconds / std::max(1.0, double(r.localSolves)));
    S.perDet.push_back(1e9 * r.detectSeconds / std::max(1, r.contacts));
    S.contacts = r.contacts;
    return c;
}

Run summary(const Samples& S, const std::string& order, int interval, int grains)
{
    Run R;
    R.order = order;
    R.interval = interval;
    R.grains = grains;
    R.contacts = S.contacts;
    R.steps = int(S.cpu.size());
    R.cpu = median(S.cpu);
    R.detect = median(S.det);
    R.solve = median(S.sol);
    R.sweeps = median(S.sw);
    R.localSolves = median(S.ls);
    R.nsPerContactSweep = median(S.perCs);
    R.nsPerLocalSolve = median(S.perLs);
    R.nsDetectPerContact = median(S.perDet);
    std::fprintf(stderr,
                 "  %7d discs %-8s interval %3d: CPU %.4f s/step (detect %.4f, solve %.4f), %.0f sweeps, "
                 "%.1f ns/contact-sweep, %.1f ns/local solve\n",
                 R.grains, order.c_str(), interval, R.cpu, R.detect, R.solve, R.sweeps, R.nsPerContactSweep,
                 R.nsPerLocalSolve);
    return R;
}

/// Reordering off (interval 0) and on (interval) from the same state, the
/// two systems stepped in turn (off, on, off, on, ...) so that a drift of
/// the shared machine's speed hits both: per-pair CPU ratio on/off.
std::pair<Run, Run> pairedRuns(const Bed& bed, const std::vector<System::ContactView>& views,
                               const std::vector<int>& perm, const std::string& order, int interval,
                               int relax, int timed, double& ratio, double first[2])
{
    System off = build(bed, views, perm), on = build(bed, views, perm);
    for (System* s : {&off, &on}) s->settings().maxIterations = 1000; // production setting (nscd README)
    off.settings().reorderInterval = 0;
    on.settings().reorderInterval = interval;
    // the first step of "on" re-sorts the grains (then every interval steps)
    for (int k = 0; k < relax; ++k)
    {
        const double c0 = cpu();
        off.step(dt);
        const double c1 = cpu();
        on.step(dt);
        if (k == 0)
        {
            first[0] = c1 - c0;
            first[1] = cpu() - c1;
        }
    }
    Samples a, b;
    std::vector<double> ratios;
    for (int k = 0; k < timed; ++k)
    {
        const double ta = timeStep(off, a);
        const double tb = timeStep(on, b);
        ratios.push_back(tb / ta);
    }
    ratio = median(ratios);
    const int N = int(bed.x.size());
    std::pair<Run, Run> out{summary(a, order, 0, N), summary(b, order, interval, N)};
    std::fprintf(stderr, "  %7d discs %-8s CPU on/off %.3f (median of %d paired steps)\n", N, order.c_str(),
                 ratio, timed);
    return out;
}

std::string json(const Run& R)
{
    std::ostringstream o;
    o << "{\"grains\": " << R.grains << ", \"order\": \"" << R.order
      << "\", \"reorder_interval\": " << R.interval << ", \"contacts\": " << R.contacts
      << ", \"timed_steps\": " << R.steps << ", \"cpu_seconds_per_step_median\": " << R.cpu
      << ", \"detect_seconds_per_step_median\": " << R.detect
      << ", \"solve_seconds_per_step_median\": " << R.solve << ", \"sweeps_per_step_median\": " << R.sweeps
      << ", \"local_solves_per_step_median\": " << R.localSolves
      << ", \"cpu_ns_per_contact_sweep_median\": " << R.nsPerContactSweep
      << ", \"solve_ns_per_local_solve_median\": " << R.nsPerLocalSolve
      << ", \"detect_ns_per_contact_median\": " << R.nsDetectPerContact << "}";
    return o.str();
}

/// The settled block (mu 0.4); with NSCD_BLOCK=<file.h5> read from the
/// file if it exists, else settled and written there (for repeated runs).
System settledBlock(const Bed& b0, bool quick)
{
    const char* cache = std::getenv("NSCD_BLOCK");
    if (cache && std::ifstream(cache).good()) return System::readHDF5(cache);
    System blk = makeBlock(b0, 0.4);
    settle(blk, quick ? 300 : 3000, "block");
    if (cache) blk.writeHDF5(cache);
    return blk;
}
} // namespace

/// nscdBench reorder-case <tiles> <tiled|shuffled> <interval> <steps>: one
/// bed (tiles x 500 discs), 10 steps then <steps> steps; prints the CPU
/// seconds of the stepping (for timing whole processes in pairs), per step
/// (mean, median), sweeps, the steps in which the relax stage ran
/// (StepReport::relaxSolves), the max overlap and the max displacement over
/// the <steps> steps, the median detection time and the Verlet list builds.
/// Environment: NSCD_LOAD (start from this HDF5 state), NSCD_RELAX
/// (Settings::relaxation), NSCD_SKIN (Settings::verletSkin), NSCD_TOL
/// (Settings::tolerance), NSCD_SLOP (Settings::overlapSlop), NSCD_BETA
/// (Material::relativeCompliance of every material), NSCD_CONVERGENCE=rms
/// and NSCD_RMS_TOL (Settings::convergence, rmsTolerance), NSCD_DUMP
/// (write the final HDF5 state), NSCD_TRACE (a per-step trace), NSCD_DIM=3 (spheres: a block of 500 in
/// fcc layers of 8 x 8, tiles x NSCD_TILES_Z copies side by side).
int runReorderCase(int argc, char** argv)
{
    if (argc < 6)
    {
        std::fprintf(stderr, "usage: nscdBench reorder-case <tiles> <tiled|shuffled> <interval> <steps>\n");
        return 2;
    }
    const int nt = std::atoi(argv[2]), interval = std::atoi(argv[4]), steps = std::atoi(argv[5]);
    const std::string order = argv[3];
    if (order != "tiled" && order != "rows" && order != "shuffled")
    {
        std::fprintf(stderr, "nscdBench reorder-case: order must be tiled, rows or shuffled, got %s\n",
                     argv[3]);
        return 2;
    }
    const int dim = std::getenv("NSCD_DIM") ? std::atoi(std::getenv("NSCD_DIM")) : 2;
    const int nz = dim == 3 && std::getenv("NSCD_TILES_Z") ? std::atoi(std::getenv("NSCD_TILES_Z")) : 1;
    if ((dim != 2 && dim != 3) || nz < 1)
    {
        std::fprintf(stderr, "nscdBench reorder-case: NSCD_DIM must be 2 or 3 and NSCD_TILES_Z >= 1\n");
        return 2;
    }
    const Bed b0 = lattice(dim, 500, 8, 1);
    const System blk = settledBlock(b0, false);
    const Bed bed = tile(fromSystem(blk, b0), nt, nz);
    std::vector<int> perm(bed.x.size());
    std::iota(perm.begin(), perm.end(), 0);
    if (order == "shuffled") std::shuffle(perm.begin(), perm.end(), std::mt19937(42));
    if (order == "rows") perm = rowOrder(bed);
    System s = build(bed, tileContacts(blk, nt, nz), perm);
    s.settings().maxIterations = 1000;
    // NSCD_LOAD=<file.h5>: start from a saved state instead (e.g. a relaxed
    // bed written with NSCD_DUMP), its settings but the interval given
    if (const char* load = std::getenv("NSCD_LOAD")) s = System::readHDF5(load);
    s.settings().reorderInterval = interval;
    if (const char* om = std::getenv("NSCD_RELAX")) s.settings().relaxation = std::atof(om);
    if (const char* sk = std::getenv("NSCD_SKIN")) s.settings().verletSkin = std::atof(sk);
    if (const char* tol = std::getenv("NSCD_TOL")) s.settings().tolerance = std::atof(tol);
    if (const char* slop = std::getenv("NSCD_SLOP")) s.settings().overlapSlop = std::atof(slop);
    // NSCD_BETA: Material::relativeCompliance of every material (contact
    // compliance), NSCD_CONVERGENCE=rms with NSCD_RMS_TOL: the RMS stopping test
    if (const char* beta = std::getenv("NSCD_BETA"))
        for (int id = 0; id < s.nMaterials(); ++id)
        {
            Material mat = s.material(id);
            mat.relativeCompliance = std::atof(beta);
            s.setMaterial(id, mat);
        }
    if (const char* cv = std::getenv("NSCD_CONVERGENCE"))
        s.settings().convergence = std::string(cv) == "rms" ? System::Settings::Convergence::RMS
                                                            : System::Settings::Convergence::Max;
    if (const char* rt = std::getenv("NSCD_RMS_TOL")) s.settings().rmsTolerance = std::atof(rt);
    // NSCD_METHOD: Settings::Method number (4: Newton, with NSCD_NEWTON_TOL,
    // NSCD_SIGMA, NSCD_LINEAR=cg: newtonTolerance, tangentialRegularisation,
    // newtonLinearSolver); "sweeps" are then Newton iterations
    if (const char* me = std::getenv("NSCD_METHOD"))
        s.settings().method = System::Settings::Method(std::atoi(me));
    if (const char* nt = std::getenv("NSCD_NEWTON_TOL")) s.settings().newtonTolerance = std::atof(nt);
    if (const char* sg = std::getenv("NSCD_SIGMA")) s.settings().tangentialRegularisation = std::atof(sg);
    if (const char* ls = std::getenv("NSCD_LINEAR"))
        s.settings().newtonLinearSolver = std::string(ls) == "cg"
                                              ? System::Settings::NewtonLinearSolver::ConjugateGradient
                                              : System::Settings::NewtonLinearSolver::Cholesky;
    for (int k = 0; k < 10; ++k) s.step(dt);
    // per step: thread CPU time, sweeps, relax stage (StepReport::relaxSolves),
    // max overlap; over the timed steps: max displacement (all in r_min)
    const std::vector<Vec3> x0 = s.positions();
    std::vector<double> stepCpu, sweeps, detect;
    int relaxSteps = 0, builds = 0;
    long relaxSolves = 0;
    double overlap = 0;
    // NSCD_TRACE=<file>: one line a step (sweeps, relax-stage local solves,
    // contacts, largest overlap / r_min, kinetic energy of the grains [J/m]),
    // outside the per-step CPU times (the mean over the steps includes it)
    std::FILE* trace = std::getenv("NSCD_TRACE") ? std::fopen(std::getenv("NSCD_TRACE"), "w") : nullptr;
    if (trace)
        std::fprintf(trace, "# step sweeps relaxLocalSolves contacts maxOverlap/r_min kineticEnergy\n");
    const double c0 = cpu();
    for (int k = 0; k < steps; ++k)
    {
        const double a = cpu();
        const StepReport r = s.step(dt);
        stepCpu.push_back(cpu() - a);
        if (trace)
        {
            double e = 0;
            for (std::size_t i = 0; i < s.size(); ++i)
                e += 0.5 * s.mass(i) * s.velocities()[i].squaredNorm()
                     + 0.5 * s.inertia(i) * s.angularVelocities()[i].squaredNorm();
            std::fprintf(trace, "%d %d %ld %d %.4e %.6e\n", k, r.sweeps, r.relaxLocalSolves, r.contacts,
                         r.maxOverlap / (0.5 * dMin), e);
        }
        sweeps.push_back(r.sweeps);
        detect.push_back(r.detectSeconds);
        builds += r.verletBuilds;
        relaxSteps += r.relaxSolves;
        relaxSolves += r.relaxLocalSolves;
        overlap = std::max(overlap, r.maxOverlap);
    }
    const double total = cpu() - c0, rmin = 0.5 * dMin;
    if (trace) std::fclose(trace);
    double disp = 0;
    for (std::size_t i = 0; i < s.size(); ++i) disp = std::max(disp, (s.positions()[i] - x0[i]).norm());
    std::printf("%zu discs %s interval %d: %.4f CPU s/step (median %.4f), %.1f sweeps/step (median %.0f), "
                "relax stage "
                "in %d of %d steps (%.3f sweeps/step), max overlap %.3e r_min, max displacement %.3e r_min; "
                "detection %.4f s/step (median), verletSkin %g, %d list builds\n",
                s.size(), argv[3], interval, total / steps, median(stepCpu),
                std::accumulate(sweeps.begin(), sweeps.end(), 0.0) / steps, median(sweeps), relaxSteps, steps,
                double(relaxSolves) / steps / std::max<double>(1, double(s.nContacts())), overlap / rmin,
                disp / rmin, median(detect), s.settings().verletSkin, builds);
    // NSCD_DUMP=<file.h5>: the final state (positions, velocities, contact
    // impulses) for bit-identity checks of library changes (h5diff)
    if (const char* dump = std::getenv("NSCD_DUMP")) s.writeHDF5(dump);
    return 0;
}

int runReorder(int argc, char** argv)
{
    if (argc < 3)
    {
        std::fprintf(stderr, "usage: nscdBench reorder <out.json> [quick]\n");
        return 2;
    }
    const std::string out = argv[2];
    const bool quick = argc > 3 && std::string(argv[3]) == "quick";
    std::setvbuf(stderr, nullptr, _IOLBF, 0);
    const double t0 = now();
    // the nscdDeposit block: 500 discs, 8 columns, settled with mu = 0.4
    const int blockN = 500, ncol = 8;
    Bed b0 = lattice(2, blockN, ncol, 1);
    System blk = settledBlock(b0, quick);
    const Bed block = fromSystem(blk, b0);
    const std::vector<int> tiles = quick ? std::vector<int>{2, 20} : std::vector<int>{2, 20, 140, 400};
    const int relax = quick ? 3 : 10, timed = quick ? 5 : 20;
    std::vector<std::string> rows, ratios;
    for (int nt : tiles)
    {
        const Bed bed = tile(block, nt, 1);
        const auto views = tileContacts(blk, nt, 1);
        const int N = int(bed.x.size());
        std::vector<int> id(N), sh(N);
        std::iota(id.begin(), id.end(), 0);
        sh = id;
        std::shuffle(sh.begin(), sh.end(), std::mt19937(42));
        std::vector<int> byRows = rowOrder(bed);
        for (const auto& o :
             {std::make_pair(std::string("tiled"), &id), std::make_pair(std::string("rows"), &byRows),
              std::make_pair(std::string("shuffled"), &sh)})
        {
            double ratio = 1, first[2] = {0, 0};
            const auto p = pairedRuns(bed, views, *o.second, o.first, 100, relax, timed, ratio, first);
            std::ostringstream r;
            r << "{\"grains\": " << N << ", \"order\": \"" << o.first
              << "\", \"cpu_ratio_on_over_off_paired_median\": " << ratio
              << ", \"first_step_cpu_seconds_off\": " << first[0]
              << ", \"first_step_cpu_seconds_on\": " << first[1] << "}";
            rows.push_back(json(p.first));
            rows.push_back(json(p.second));
            ratios.push_back(r.str());
        }
    }
    std::ofstream f(out);
    f << "{\n  \"benchmark\": \"nscdReorder\",\n"
      << "  \"what\": \"cache effect of the grain order (issue 26 item 4): CPU time per step and per contact "
         "update "
         "of 2D beds at rest vs grain count, grains in the tiling order, row-major across the width or "
         "shuffled, internal Morton reordering "
         "off (reorderInterval 0) or on (100)\",\n"
      << "  \"setup\": \"mirror tilings of one settled " << blockN << "-disc block (" << ncol
      << " columns, nscdDeposit's "
         "construction: d 230 um mean, lambda 1.2, rho 2500, mu 0.4, dt 1e-4 s, tolerance 1e-6 d_min, at "
         "most 1000 "
         "sweeps/step), warm-started from the block's impulses; the same bed is given to the System in the "
         "tiling order "
         "(block by block, rows within a block), row-major across the whole width (height bands of one mean "
         "diameter, then x: "
         "an insertion lattice's fill order, as grainDeposit's) or in a random order (std::mt19937 seed 42); "
         "reordering off and on "
         "stepped in turn from the same state; "
      << relax << " steps, then " << timed
      << " timed steps (medians). Time per contact update = step CPU time / "
         "(sweeps x contacts); per local solve = solve time / local solves (queue handling included); "
         "detection "
         "per contact = detection time / contacts\",\n"
      << "  \"machine\": \"" << machineNote() << "\",\n"
      << "  \"wall_seconds_total\": " << now() - t0 << ",\n"
      << "  \"runs\": [\n";
    for (std::size_t k = 0; k < rows.size(); ++k)
        f << "    " << rows[k] << (k + 1 < rows.size() ? ",\n" : "\n");
    f << "  ],\n  \"paired\": [\n";
    for (std::size_t k = 0; k < ratios.size(); ++k)
        f << "    " << ratios[k] << (k + 1 < ratios.size() ? ",\n" : "\n");
    f << "  ],\n  \"paired_note\": \"off and on stepped in turn from the same state (off, on, off, on, ...): "
         "median over the timed steps of the per-pair CPU ratio on/off (< 1: reordering faster); "
         "first_step_*: CPU time of "
         "the first step, in which \\\"on\\\" re-sorts the grains (the cost of a reorder, paid every "
         "reorderInterval steps, "
         "with the cold first step of both)\"\n}\n";
    std::fprintf(stderr, "wrote %s (%.0f s)\n", out.c_str(), now() - t0);
    return 0;
}
