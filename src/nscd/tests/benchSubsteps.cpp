// SPDX-License-Identifier: GPL-3.0-or-later
// Sub-steps of System::advance on the nscdDeposit beds.
//   nscdBench substeps <out.json> [quick]
// Cases (d = 230 um beds of benchSuite.cpp, one core):
//  - block: the 500-disc block settling from its layered lattice, advanced
//    with advance(5e-4 s, 0.1) for 0.1 s (the dt of the droplet bench);
//  - deposit: the 70,000-disc tiled deposit at rest (warm-started from the
//    block's impulses) with one grain flying over it at 5 d per step of
//    1e-4 s, advance(1e-4 s, 0.1), 10 steps (after 100 relaxation steps);
//  - impact: the same grain shot down into the deposit at 20 d per step;
//  - the deposit alone over the same 10 steps (reference).
// Reports sub-steps, sweeps and CPU seconds per step (medians and totals).
#include "benchBeds.H"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace nscd;
using namespace nscdBench;

namespace
{
struct Run
{
    std::vector<double> cpu, substeps, sweeps, redetections;
    double maxOverlapOverR = 0;
    bool converged = true;
};

Run advanceSteps(System& s, double h, int steps, const char* tag)
{
    Run R;
    for (int k = 0; k < steps; ++k)
    {
        const double c0 = cpu();
        const StepReport r = s.advance(h, 0.1);
        R.cpu.push_back(cpu() - c0);
        R.substeps.push_back(r.substeps);
        R.sweeps.push_back(r.sweeps);
#ifndef NSCD_BENCH_BEFORE_REDETECTIONS
        R.redetections.push_back(r.redetections);
#else
        R.redetections.push_back(0);
#endif
        R.maxOverlapOverR = std::max(R.maxOverlapOverR, r.maxOverlap / (0.5 * dMin));
        R.converged = R.converged && r.converged;
        if (k % 20 == 0 || k == steps - 1)
            std::fprintf(stderr,
                         "  [%s] step %d substeps %d sweeps %d contacts %d redetections %g cpu %.3f s\n", tag,
                         k, r.substeps, r.sweeps, r.contacts, R.redetections.back(), R.cpu.back());
    }
    return R;
}

double sum(const std::vector<double>& v)
{
    double t = 0;
    for (double a : v) t += a;
    return t;
}

void write(std::FILE* f, const char* name, const Run& R, double h, bool last)
{
    std::fprintf(f,
                 "  \"%s\": {\"dt\": %g, \"steps\": %zu, \"substeps_per_step_median\": %g,"
                 " \"substeps_per_step_max\": %g, \"substeps_total\": %g, \"sweeps_per_step_median\": %g,"
                 " \"sweeps_total\": %g, \"redetections_total\": %g, \"cpu_seconds_per_step_median\": %g, "
                 "\"cpu_seconds_total\": %g,"
                 " \"max_overlap_over_rmin\": %g, \"converged_every_step\": %s}%s\n",
                 name, h, R.cpu.size(), median(R.substeps),
                 *std::max_element(R.substeps.begin(), R.substeps.end()), sum(R.substeps), median(R.sweeps),
                 sum(R.sweeps), sum(R.redetections), median(R.cpu), sum(R.cpu), R.maxOverlapOverR,
                 R.converged ? "true" : "false", last ? "" : ",");
}
} // namespace

int runSubsteps(int argc, char** argv)
{
    if (argc < 3)
    {
        std::fprintf(stderr, "usage: nscdBench substeps <out.json> [quick]\n");
        return 1;
    }
    const bool quick = argc > 3 && std::strcmp(argv[3], "quick") == 0;
    const int nBig = quick ? 14 : 140;

    // block settling from the lattice, large steps
    Bed b0 = lattice(2, 500, 8, 1);
    System blk = makeBlock(b0, 0.4);
    blk.settings().maxIterations = 1000;
    const double hBlock = 5e-4;
    const Run block = advanceSteps(blk, hBlock, quick ? 40 : 200, "block");

    // settle it at dt (as the suite) and tile it
    System rest = makeBlock(b0, 0.4);
    rest.settings().maxIterations = 1000;
    for (int k = 0; k < 3000 && (k < 50 || vmax(rest) > 0.1 * g * dt); ++k) rest.step(dt);
    const Bed tiled = tile(fromSystem(rest, b0), nBig, 1);
    double top = 0;
    for (std::size_t i = 0; i < tiled.x.size(); ++i) top = std::max(top, tiled.x[i].y() + tiled.r[i]);

    // the tiled deposit relaxed 100 steps (as the suite, shorter), kept as a state
    std::vector<Vec3> xs, vs, ws;
    std::vector<System::ContactView> cs;
    {
        System s = makeSystem(tiled, 0.4);
        s.setContactImpulses(tileContacts(rest, nBig, 1), dt);
        s.settings().maxIterations = 1000;
        for (int k = 0; k < 100; ++k) s.step(dt);
        xs = s.positions();
        vs = s.velocities();
        ws = s.angularVelocities();
        cs = s.contacts();
    }
    auto deposit = [&](const Vec3& x, const Vec3& v, bool fast = true)
    {
        System s = makeSystem(tiled, 0.4);
        // the fast grain first: the contact list refers to walls by index
        // after the grains (System::addGrain does not renumber it)
        const int f = fast ? s.addGrain(x, 0.5 * dMax, 0) : -1;
        std::copy(xs.begin(), xs.end(), s.positions().begin());
        std::copy(vs.begin(), vs.end(), s.velocities().begin());
        std::copy(ws.begin(), ws.end(), s.angularVelocities().begin());
        if (fast) s.velocities()[f] = v;
        s.setContactImpulses(cs, dt);
        s.settings().maxIterations = 1000;
        return s;
    };
    // reference: the deposit alone, same steps
    System alone = deposit(Vec3::Zero(), Vec3::Zero(), false);
    const Run aloneRun = advanceSteps(alone, dt, 10, "deposit alone");
    // a grain flying over the bed along x at 5 d per step
    System fly = deposit(Vec3(0.05 * tiled.W, top + 2 * dMax, 0), Vec3(5 * dMean / dt, 0, 0));
    const Run flyRun = advanceSteps(fly, dt, 10, "deposit+fly");
    // the same grain shot down into the bed at 20 d per step
    System hit = deposit(Vec3(0.5 * tiled.W, top + 30 * dMax, 0), Vec3(0, -20 * dMean / dt, 0));
    const Run hitRun = advanceSteps(hit, dt, 10, "deposit+impact");

    std::FILE* f = std::fopen(argv[2], "w");
    if (!f)
    {
        std::fprintf(stderr, "cannot write %s\n", argv[2]);
        return 1;
    }
    std::fprintf(f, "{\n  \"benchmark\": \"nscdSubsteps\",\n  \"grains_deposit\": %zu,\n",
                 tiled.x.size() + 1);
    std::fprintf(f, "  \"machine\": \"%s\",\n", machineNote().c_str());
    write(f, "block_settling_500", block, hBlock, false);
    write(f, "deposit_alone", aloneRun, dt, false);
    write(f, "deposit_fast_grain_flying_5d_per_step", flyRun, dt, false);
    write(f, "deposit_fast_grain_impact_20d_per_step", hitRun, dt, true);
    std::fprintf(f, "}\n");
    std::fclose(f);
    return 0;
}
