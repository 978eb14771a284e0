// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmark driver (src/nscd/README.md "Tolerance and bed depth"):
// a column of discs between frictionless side walls, poured from a loose
// lattice and stepped with nscd::System::advance, to measure the velocity
// noise the contact solver's stopping test leaves in a bed N layers deep.
// 1 mm discs (d in [0.9, 1] mm), rho 2500, mu 0.3, ten discs wide (10 mm),
// dt 5e-4 s, overlapSlop 1e-4. Every 10th step it prints: max grain speed
// [m/s], kinetic energy [J/m], centre-of-mass vertical velocity [m/s], the
// walls' vertical impulse over the step / (weight dt), contacts, sweeps,
// sub-steps, residual, max overlap. Built and run by tests/bench/nscdColumnDepth.
//
// usage: nscdColumnDepth GRAINS STEPS TOLERANCE MAX_ITERATIONS [METHOD]
//        env NSCD_BETA, NSCD_COMPLIANCE: Material::relativeCompliance,
//        compliance [m^2/N] (contact compliance; default 0, hard);
//        NSCD_RELAX: Settings::relaxation; NSCD_CONVERGENCE=rms and
//        NSCD_RMS_TOL: Settings::convergence, rmsTolerance
//        NSCD_NEWTON_TOL, NSCD_SIGMA, NSCD_LINEAR=cg|cholesky: the Newton
//        method's newtonTolerance, tangentialRegularisation, newtonLinearSolver
//        METHOD: the Settings::Method number (0 NLGS, 1 overRelaxedNLGS,
//        2 APGD, 3 NNCG, 4 Newton), default 0. Newton: "sweeps" are Newton
//        iterations; the last line adds the linear-solver (CG) iterations and
//        the most sweeps (iterations) of one step
#include "nscd/System.H"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>

using namespace nscd;

namespace
{
/// The solver settings of the command line (TOLERANCE MAX_ITERATIONS
/// [METHOD]) and of the environment (see the usage above).
void setSolver(System::Settings& S, int argc, char** argv)
{
    S.tolerance = std::atof(argv[3]);
    S.maxIterations = std::atoi(argv[4]);
    if (argc > 5) S.method = System::Settings::Method(std::atoi(argv[5]));
    // env NSCD_RELAX: Settings::relaxation (over-relaxation factor of the NLGS update)
    if (const char* e = std::getenv("NSCD_RELAX")) S.relaxation = std::atof(e);
    // env NSCD_CONVERGENCE=rms, NSCD_RMS_TOL: Settings::convergence, rmsTolerance
    if (const char* e = std::getenv("NSCD_CONVERGENCE"))
        S.convergence =
            std::string(e) == "rms" ? System::Settings::Convergence::RMS : System::Settings::Convergence::Max;
    if (const char* e = std::getenv("NSCD_RMS_TOL")) S.rmsTolerance = std::atof(e);
    // env NSCD_NEWTON_TOL, NSCD_SIGMA, NSCD_LINEAR=cg: Settings::newtonTolerance,
    // tangentialRegularisation, newtonLinearSolver (METHOD 4, Newton)
    if (const char* e = std::getenv("NSCD_NEWTON_TOL")) S.newtonTolerance = std::atof(e);
    if (const char* e = std::getenv("NSCD_SIGMA")) S.tangentialRegularisation = std::atof(e);
    if (const char* e = std::getenv("NSCD_LINEAR"))
        S.newtonLinearSolver = std::string(e) == "cg"
                                   ? System::Settings::NewtonLinearSolver::ConjugateGradient
                                   : System::Settings::NewtonLinearSolver::Cholesky;
}

/// One line of the column's state after step k (report r): max speed,
/// kinetic energy, centre-of-mass vertical velocity, the walls' vertical
/// impulse / (weight dt), contacts, sweeps, sub-steps, residual, max overlap.
void printColumn(const System& s, int k, const StepReport& r, double dt, double rho, double weight)
{
    double vmax = 0, ke = 0, p = 0, M = 0;
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        const double mi = rho * M_PI * s.radii()[i] * s.radii()[i], v = s.velocities()[i].norm();
        vmax = std::max(vmax, v);
        ke += 0.5 * mi * v * v;
        p += mi * s.velocities()[i].y();
        M += mi;
    }
    double lift = 0;
    for (const auto& c : s.contacts())
        if (c.j < 0) lift += c.impulse.y();
    std::printf("step %d t %.3f vmax %.2e KE %.3e vycm %.2e lift/W %.4f contacts %d sweeps %d sub %d "
                "res %.2e ov %.2e\n",
                k + 1, (k + 1) * dt, vmax, ke, p / M, lift / dt / weight, r.contacts, r.sweeps, r.substeps,
                r.residual, r.maxOverlap);
}
} // namespace

int main(int argc, char** argv)
{
    if (argc < 5)
    {
        std::fprintf(stderr, "usage: %s GRAINS STEPS TOLERANCE MAX_ITERATIONS [METHOD]\n", argv[0]);
        return 2;
    }
    const int nGrains = std::atoi(argv[1]);
    const int nSteps = std::atoi(argv[2]);
    const double d = 1e-3, w = 10e-3, H = 0.3, dt = 5e-4, rho = 2500;
    System s(2);
    // env NSCD_BETA / NSCD_COMPLIANCE: Material::relativeCompliance [-] /
    // compliance [m^2/N] (default 0: the hard law)
    Material mat{rho, 0.3};
    if (const char* e = std::getenv("NSCD_BETA")) mat.relativeCompliance = std::atof(e);
    if (const char* e = std::getenv("NSCD_COMPLIANCE")) mat.compliance = std::atof(e);
    // env NSCD_MU: the grains' (and the floor's) friction coefficient (default 0.3)
    if (const char* e = std::getenv("NSCD_MU")) mat.friction = std::atof(e);
    const int m = s.addMaterial(mat);
    setSolver(s.settings(), argc, argv);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    const double sp = 1.3 * d;
    for (int j = 0, n = 0; n < nGrains; ++j)
        for (int i = 0; i < int(w / sp) && n < nGrains; ++i, ++n)
        {
            const double dd = 0.9 * d + 0.1 * d * u(rng);
            s.addGrain(Vec3((i + 0.5) * sp + 0.1 * d * (2 * u(rng) - 1),
                            (j + 0.5) * sp + 0.1 * d * (2 * u(rng) - 1), 0),
                       dd / 2, m);
        }
    s.addSegment(Vec3(0, 0, 0), Vec3(w, 0, 0));
    s.setWallFriction(s.addSegment(Vec3(0, 0, 0), Vec3(0, H, 0)), 0.0);
    s.setWallFriction(s.addSegment(Vec3(w, 0, 0), Vec3(w, H, 0)), 0.0);
    s.setGravity(Vec3(0, -9.81, 0));
    double weight = 0;
    for (double r : s.radii()) weight += rho * M_PI * r * r * 9.81;
    long sweeps = 0, unconverged = 0, linear = 0;
    double solveSeconds = 0;
    // env NSCD_HISTORY_STEP=k: the residual history of step k (StepReport::
    // residualHistory: the Max residual per sweep; Newton: SAP's ratio per iteration)
    const int histStep = std::getenv("NSCD_HISTORY_STEP") ? std::atoi(std::getenv("NSCD_HISTORY_STEP")) : -1;
    // env NSCD_SWITCH_STEP=k, NSCD_SWITCH_METHOD=m: from step k on, Settings::Method m
    // (e.g. land with NLGS, then time the column at rest with each method);
    // the last line adds the sweeps, contact-solve seconds, most sweeps of a
    // step and CPU seconds of advance() from step k on
    const int switchStep = std::getenv("NSCD_SWITCH_STEP") ? std::atoi(std::getenv("NSCD_SWITCH_STEP")) : -1;
    long restSweeps = 0;
    double restSeconds = 0;
    int maxStepSweeps = 0, restMaxStepSweeps = 0; // the most sweeps (Newton: iterations) of one step
    // CPU seconds of this thread in advance() from the switch step on (the
    // solver's solveSeconds is wall-clock time, which a shared core inflates)
    double restCpu = 0;
    auto threadCpu = []
    {
        timespec t;
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
        return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
    };
    for (int k = 0; k < nSteps; ++k)
    {
        if (k == switchStep && std::getenv("NSCD_SWITCH_METHOD"))
            s.settings().method = System::Settings::Method(std::atoi(std::getenv("NSCD_SWITCH_METHOD")));
        s.settings().residualHistory = k + 1 == histStep;
        const double cpu0 = threadCpu();
        const StepReport r = s.advance(dt, 0.1);
        if (switchStep >= 0 && k >= switchStep) restCpu += threadCpu() - cpu0;
        if (k + 1 == histStep)
        {
            std::printf("history step %d:", k + 1);
            for (double h : r.residualHistory) std::printf(" %.3e", h);
            std::printf("\n");
        }
        sweeps += r.sweeps;
        maxStepSweeps = std::max(maxStepSweeps, r.sweeps);
        if (switchStep >= 0 && k >= switchStep)
        {
            restSweeps += r.sweeps;
            restSeconds += r.solveSeconds;
            restMaxStepSweeps = std::max(restMaxStepSweeps, r.sweeps);
        }
        linear += r.linearIterations;
        solveSeconds += r.solveSeconds;
        unconverged += r.converged ? 0 : 1;
        if (k % 10 != 9) continue;
        printColumn(s, k, r, dt, rho, weight);
    }
    std::printf(
        "total sweeps %ld steps %d unconverged %ld beta %g compliance %g method %d linear %ld solve_s %.3f "
        "after_switch_sweeps %ld after_switch_solve_s %.3f max_step_sweeps %d after_switch_max_step_sweeps "
        "%d after_switch_cpu_s %.3f\n",
        sweeps, nSteps, unconverged, mat.relativeCompliance, mat.compliance, int(s.settings().method), linear,
        solveSeconds, restSweeps, restSeconds, maxStepSweeps, restMaxStepSweeps, restCpu);
}
