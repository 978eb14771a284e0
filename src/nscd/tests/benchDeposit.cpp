// SPDX-License-Identifier: GPL-3.0-or-later
// Dense deposit benchmark (not a test).
//   nscdBench substeps <out.json> [quick]   sub-steps of advance() (benchSubsteps.cpp)
//   nscdBench state <grainState.h5> <dt> <steps> <out.json> [tol [maxIt]]   the contact
//       solver methods on a state saved by a run (benchState.cpp)
//   nscdBench suite <out.json> [quick]   the tests/bench/nscdDeposit suite (see
//       runSuite below): settled polydisperse beds (d = 230 um, lambda = 1.2,
//       rho = 2500, dt = 1e-4 s, box), 70,000 discs at rest with mu = 0.4 and 0,
//       scaling 5,000 / 20,000 discs, settling from a loose lattice, 20,000
//       spheres; writes a JSON result file. "quick" = smaller sizes (smoke run).
// Legacy mode: N discs in a box, settled, then timed at rest.
// Usage: nscdBench [N=20000] [settleSteps=3000] [timedSteps=100] [dim=2] [layout=hex|rain]
// hex: 2D polydisperse discs (r in [0.95, 1] r0) on a hexagonal lattice of
//      spacing 2 r0 in a box (a dense packing from the start; it compacts a
//      little while settling); rain: loose jittered grid that falls.
// env: NSCD_TOL (tolerance), NSCD_SLOP (overlapSlop), NSCD_RELAX (relaxation),
//      NSCD_SYMMETRIC (symmetric sweeps), NSCD_SKIN (verletSkin), NSCD_POLY (hex radii in [1-poly, 1] r0,
//      default 0.05), NSCD_SETTLE_TOL (tolerance while settling), NSCD_SAVE / NSCD_LOAD (HDF5 state after settling / instead of it),
//      NSCD_DUMP (HDF5 state after the timed steps).
#include "nscd/System.H"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace nscd;

int runSuite(int argc, char** argv);
int runMethods(int argc, char** argv);
int runSubsteps(int argc, char** argv);
int runState(int argc, char** argv);
int runReorder(int argc, char** argv);
int runReorderCase(int argc, char** argv);
int legacyMain(int argc, char** argv);

int main(int argc, char** argv)
{
    if (argc > 1 && std::string(argv[1]) == "suite") return runSuite(argc, argv);
    if (argc > 1 && std::string(argv[1]) == "methods") return runMethods(argc, argv);
    if (argc > 1 && std::string(argv[1]) == "substeps") return runSubsteps(argc, argv);
    if (argc > 1 && std::string(argv[1]) == "state") return runState(argc, argv);
    if (argc > 1 && std::string(argv[1]) == "reorder") return runReorder(argc, argv);
    if (argc > 1 && std::string(argv[1]) == "reorder-case") return runReorderCase(argc, argv);
    return legacyMain(argc, argv);
}

int legacyMain(int argc, char** argv)
{
    const int N = argc > 1 ? std::atoi(argv[1]) : 20000;
    const int settle = argc > 2 ? std::atoi(argv[2]) : 3000;
    const int timed = argc > 3 ? std::atoi(argv[3]) : 100;
    const int dim = argc > 4 ? std::atoi(argv[4]) : 2;
    const std::string layout = argc > 5 ? argv[5] : "hex";
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    System s(dim);
    const int m = s.addMaterial({2500, 0.3});
    std::mt19937 gen(1);
    const double r0 = 1e-3;
    std::uniform_real_distribution<double> U(0.8 * r0, 1.2 * r0);
    const double h = (dim == 3 ? 3.2 : 2.6) * r0;
    std::uniform_real_distribution<double> J(0, 1);
    const int nz = dim == 3 ? 10 : 1;
    int nx = dim == 2 ? int(std::sqrt(N) * 1.0) : int(std::sqrt(N / nz));
    if (layout == "hex" && dim == 2)
    {
        // hexagonal lattice, rows alternately nx and nx - 1 discs
        nx = int(std::sqrt(N * 0.8));
        const double poly = std::getenv("NSCD_POLY") ? std::atof(std::getenv("NSCD_POLY")) : 0.05;
        std::uniform_real_distribution<double> R((1 - poly) * r0, r0);
        int k = 0;
        for (int b = 0; k < N; ++b)
            for (int a = 0; a < nx - (b % 2) && k < N; ++a, ++k)
                s.addGrain(Vec3(r0 * (2 * a + 1 + (b % 2)), r0 * (1 + b * std::sqrt(3.0)), 0), R(gen), m);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
        s.addPlane(Vec3(2 * r0 * nx, 0, 0), Vec3(-1, 0, 0));
    }
    else
    {
        const int ny = (N + nx * nz - 1) / (nx * nz);
        int k = 0;
        for (int b = 0; b < ny && k < N; ++b)
            for (int c = 0; c < nz && k < N; ++c)
                for (int a = 0; a < nx && k < N; ++a, ++k)
                    s.addGrain(Vec3((a + 0.5 + 0.2 * (J(gen) - 0.5)) * h, (b + 0.5) * h,
                                    dim == 3 ? (c + 0.5 + 0.2 * (J(gen) - 0.5)) * h : 0.0),
                               U(gen), m);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
        s.addPlane(Vec3(nx * h, 0, 0), Vec3(-1, 0, 0));
        if (dim == 3)
        {
            s.addPlane(Vec3(0, 0, 0), Vec3(0, 0, 1));
            s.addPlane(Vec3(0, 0, nz * h), Vec3(0, 0, -1));
        }
    }
    s.checkInitialOverlaps();
    s.setGravity(Vec3(0, -9.81, 0));
    s.settings().tolerance = std::getenv("NSCD_TOL") ? std::atof(std::getenv("NSCD_TOL")) : 1e-6;
    if (std::getenv("NSCD_SLOP")) s.settings().overlapSlop = std::atof(std::getenv("NSCD_SLOP"));
    if (std::getenv("NSCD_RELAX")) s.settings().relaxation = std::atof(std::getenv("NSCD_RELAX"));
    if (std::getenv("NSCD_SYMMETRIC")) s.settings().ordering = System::Settings::Ordering::Symmetric;
    if (std::getenv("NSCD_SKIN")) s.settings().verletSkin = std::atof(std::getenv("NSCD_SKIN"));
    const double dt = 1e-4;
    if (std::getenv("NSCD_LOAD"))
    {
        // reuse a settled state, keep the settings chosen above
        const System::Settings keep = s.settings();
        s = System::readHDF5(std::getenv("NSCD_LOAD"));
        s.settings() = keep;
    }
    // settling may use a looser tolerance (NSCD_SETTLE_TOL) to reach rest quickly
    const System::Settings measured = s.settings();
    if (std::getenv("NSCD_SETTLE_TOL")) s.settings().tolerance = std::atof(std::getenv("NSCD_SETTLE_TOL"));
    auto wall = []
    { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); };
    double t0 = wall();
    for (int i = 0; i < settle; ++i)
    {
        const StepReport r = s.step(dt);
        if (i % 100 == 0 || i == settle - 1)
        {
            double vm = 0;
            for (const auto& v : s.velocities()) vm = std::max(vm, v.norm());
            std::printf("settle %d contacts %d sweeps %d residual %.2e overlap/r %.2e detect %.3f solve %.3f "
                        "s vmax %.2e\n",
                        i, r.contacts, r.sweeps, r.residual, r.maxOverlap / r0, r.detectSeconds,
                        r.solveSeconds, vm);
        }
    }
    const double tSettle = wall() - t0;
    s.settings() = measured;
    if (std::getenv("NSCD_SAVE")) s.writeHDF5(std::getenv("NSCD_SAVE"));
    const std::vector<Vec3> x0 = s.positions();
    std::vector<double> times;
    double sweeps = 0, det = 0, sol = 0, ov = 0;
    int contacts = 0;
    for (int i = 0; i < timed; ++i)
    {
        const double a = wall();
        const StepReport r = s.step(dt);
        times.push_back(wall() - a);
        sweeps += r.sweeps;
        det += r.detectSeconds;
        sol += r.solveSeconds;
        ov = std::max(ov, r.maxOverlap);
        contacts = r.contacts;
    }
    if (const char* dump = std::getenv("NSCD_DUMP")) s.writeHDF5(dump); // final state (bit-identity checks)
    std::sort(times.begin(), times.end());
    double vmax = 0;
    for (const auto& v : s.velocities()) vmax = std::max(vmax, v.norm());
    double dmax = 0;
    for (std::size_t i = 0; i < s.size(); ++i) dmax = std::max(dmax, (s.positions()[i] - x0[i]).norm());
    std::printf("{\"grains\": %d, \"dim\": %d, \"contacts\": %d, \"settle_seconds\": %.3f, "
                "\"seconds_per_step_median\": %.5f, \"sweeps_per_step\": %.1f, \"detect_s\": %.5f, "
                "\"solve_s\": %.5f, \"max_overlap_over_r\": %.2e, \"vmax\": %.2e, "
                "\"max_displacement_over_r\": %.2e, \"tolerance\": %.1e, \"overlapSlop\": %.1e}\n",
                N, dim, contacts, tSettle, times[times.size() / 2], sweeps / timed, det / timed, sol / timed,
                ov / r0, vmax, dmax / r0, s.settings().tolerance, s.settings().overlapSlop);
    return 0;
}
