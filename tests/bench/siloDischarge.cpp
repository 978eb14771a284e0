// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmark driver (docs/validation/contactCompliance.md): a 2D silo
// discharging through an orifice of 8 d, the textbook dense granular flow.
// 2,000 glass discs of 2-2.4 mm (rho 2500, mu 0.5, walls the grains'
// friction) in a flat-bottomed silo 0.1 m wide, poured from a loose lattice
// onto a gate closing the orifice (0.6 s), then the gate drops away (2 m/s,
// frictionless) and the silo discharges for DISCHARGE_TIME s. Grains 5 cm below
// the floor are removed (nscd::System::removeGrains). Steps of 5e-4 s with
// System::advance(dt, 0.1) (grainFoam's maxDisplacementFraction), tolerance
// 1e-5 d_min, maxIterations 10,000 (the library's default cap).
// Prints, for the discharge: steps, steps at the cap, sweeps (median, mean,
// max per step), CPU seconds per step (thread CPU), grains out per time, and
// the discharge rate over its steady part (grains that left between 0.15 s
// and the end, per second). The observable that compliance and tolerance
// could move is that rate, compared between the runs; Beverloo's law in its
// 2D form, W = C phi rho sqrt(g) (D - k d)^(3/2) per unit depth (W. A.
// Beverloo, H. A. Leniger, J. van de Velde, Chem. Eng. Sci. 15, 260, 1961,
// for the form), is printed with C = 0.58, k = 1.5, phi = 0.82 as an order
// of magnitude only: C and k are fit constants of each material and silo.
// The solid (area) fraction over the same steady part, every 10 steps: in
// the box of 2 D x D above the orifice (D the orifice width; the flowing,
// sheared zone) and in a box of the column (x 0.01-0.09 m, y 0.02-0.05 m),
// from the discs whose centres lie in each box: the dilation a friction law
// or a compliance could cause.
//
// usage: siloDischarge DISCHARGE_TIME
// env NSCD_BETA (Material::relativeCompliance), NSCD_COMPLIANCE (compliance
//     [m^2/N]), NSCD_RELAX (Settings::relaxation), NSCD_TOL (tolerance),
//     NSCD_RMS (Settings::convergence rms with this rmsTolerance; unset: the
//     default max test), NSCD_FRICTION (Settings::frictionLaw: coulomb,
//     the default, or anitescu), NSCD_SILO_SEED (seed of the pour's diameters and
//     lattice jitter, default 7: another seed is another start of the same
//     silo), NSCD_SILO_STATE=<file.h5> (the settled silo: read if present,
//     else settled with the hard law and written there).
#include "nscd/System.H"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using namespace nscd;

namespace
{
constexpr double width = 0.1, height = 0.5, dt = 5e-4, rho = 2500, mu = 0.5;
constexpr double dMean = 2.2e-3, orifice = 8 * dMean;
constexpr int nGrains = 2000;

double cpu()
{
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/// The silo with its grains poured and settled on the gate (wall 4).
System settledSilo(unsigned seed)
{
    System s(2);
    const int m = s.addMaterial({rho, mu});
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const double sp = 1.15 * 2.4e-3;
    const int perRow = int(width / sp);
    for (int n = 0; n < nGrains; ++n)
    {
        const int i = n % perRow, j = n / perRow;
        const double d = 2e-3 + 0.4e-3 * u(rng);
        s.addGrain(Vec3((i + 0.5) * sp + 0.05e-3 * (2 * u(rng) - 1), 0.004 + (j + 0.5) * sp, 0), d / 2, m);
    }
    const double a = 0.5 * (width - orifice), b = 0.5 * (width + orifice);
    s.addSegment(Vec3(0, 0, 0), Vec3(0, height, 0));
    s.addSegment(Vec3(width, 0, 0), Vec3(width, height, 0));
    s.addSegment(Vec3(0, 0, 0), Vec3(a, 0, 0));
    s.addSegment(Vec3(b, 0, 0), Vec3(width, 0, 0));
    s.addSegment(Vec3(a, 0, 0), Vec3(b, 0, 0)); // the gate
    s.setGravity(Vec3(0, -9.81, 0));
    s.settings().tolerance = 1e-5;
    for (int k = 0; k < int(0.6 / dt); ++k) s.advance(dt, 0.1);
    return s;
}
} // namespace

int main(int argc, char** argv)
{
    if (argc < 2)
    {
        std::fprintf(stderr, "usage: %s DISCHARGE_TIME\n", argv[0]);
        return 2;
    }
    const double tEnd = std::atof(argv[1]);
    const char* state = std::getenv("NSCD_SILO_STATE");
    const unsigned seed =
        std::getenv("NSCD_SILO_SEED") ? unsigned(std::atol(std::getenv("NSCD_SILO_SEED"))) : 7u;
    System s = [&]()
    {
        if (state && std::ifstream(state).good()) return System::readHDF5(state);
        System t = settledSilo(seed);
        if (state) t.writeHDF5(state);
        return t;
    }();
    Material mat = s.material(0);
    if (const char* e = std::getenv("NSCD_BETA")) mat.relativeCompliance = std::atof(e);
    if (const char* e = std::getenv("NSCD_COMPLIANCE")) mat.compliance = std::atof(e);
    s.setMaterial(0, mat);
    if (const char* e = std::getenv("NSCD_RELAX")) s.settings().relaxation = std::atof(e);
    s.settings().tolerance = std::getenv("NSCD_TOL") ? std::atof(std::getenv("NSCD_TOL")) : 1e-5;
    s.settings().maxIterations = 10000;
    const char* rmsTol = std::getenv("NSCD_RMS");
    if (rmsTol)
    {
        s.settings().convergence = System::Settings::Convergence::RMS;
        s.settings().rmsTolerance = std::atof(rmsTol);
    }
    const char* friction = std::getenv("NSCD_FRICTION");
    const bool anitescu = friction && std::string(friction) == "anitescu";
    if (friction && !anitescu && std::string(friction) != "coulomb")
    {
        std::fprintf(stderr, "siloDischarge: NSCD_FRICTION must be coulomb or anitescu, not %s\n", friction);
        std::exit(1);
    }
    if (anitescu) s.settings().frictionLaw = System::Settings::FrictionLaw::Anitescu;
    s.setWallFriction(4, 0.0);
    s.setWallVelocity(4, Vec3(0, -2, 0)); // the gate drops away
    std::vector<int> sweeps;
    std::vector<double> tOut; // time at which each grain left
    int capped = 0;
    double maxOverlap = 0;
    // solid fraction of the discs whose centres lie in [x0, x1] x [y0, y1]
    auto solidFraction = [&s](double x0, double x1, double y0, double y1)
    {
        double a = 0;
        for (std::size_t i = 0; i < s.size(); ++i)
        {
            const Vec3& x = s.positions()[i];
            if (x.x() >= x0 && x.x() <= x1 && x.y() >= y0 && x.y() <= y1)
                a += M_PI * s.radii()[i] * s.radii()[i];
        }
        return a / ((x1 - x0) * (y1 - y0));
    };
    double phiOrifice = 0, phiColumn = 0;
    int phiSamples = 0;
    const double c0 = cpu();
    const int steps = int(tEnd / dt + 0.5);
    for (int k = 0; k < steps; ++k)
    {
        const StepReport r = s.advance(dt, 0.1);
        sweeps.push_back(r.sweeps);
        capped += r.converged ? 0 : 1;
        maxOverlap = std::max(maxOverlap, r.maxOverlap);
        std::vector<std::size_t> gone;
        for (std::size_t i = 0; i < s.size(); ++i)
            if (s.positions()[i].y() < -0.05) gone.push_back(i);
        if (!gone.empty()) s.removeGrains(gone);
        for (std::size_t n = 0; n < gone.size(); ++n) tOut.push_back((k + 1) * dt);
        if ((k + 1) * dt > 0.15 && k % 10 == 0)
        {
            phiOrifice += solidFraction(0.5 * width - orifice, 0.5 * width + orifice, 0.0, orifice);
            phiColumn += solidFraction(0.01, 0.09, 0.02, 0.05);
            ++phiSamples;
        }
    }
    const double sec = cpu() - c0;
    std::vector<int> sorted = sweeps;
    std::sort(sorted.begin(), sorted.end());
    double mean = 0;
    for (int v : sweeps) mean += v;
    mean /= std::max<std::size_t>(1, sweeps.size());
    const double t0 = 0.15;
    const long steady = std::count_if(tOut.begin(), tOut.end(), [&](double t) { return t > t0; });
    const double rate = tEnd > t0 ? steady / (tEnd - t0) : 0.0; // grains/s
    const double mGrain = rho * M_PI * dMean * dMean / 4;       // mean disc mass per unit depth [kg/m]
    const double beverloo =
        0.58 * 0.82 * rho * std::sqrt(9.81) * std::pow(orifice - 1.5 * dMean, 1.5); // [kg/(m s)]
    std::printf(
        "{\"discharge_time\": %g, \"steps\": %d, \"steps_at_cap\": %d, \"sweeps_median\": %d, "
        "\"sweeps_mean\": %.1f, \"sweeps_max\": %d, \"cpu_seconds\": %.3f, \"cpu_seconds_per_step\": %.4f, "
        "\"grains_out\": %zu, \"discharge_rate_grains_per_s\": %.1f, \"discharge_rate_kg_per_m_s\": %.3f, "
        "\"beverloo_kg_per_m_s\": %.3f, \"max_overlap_over_d\": %.2e, \"relativeCompliance\": %g, "
        "\"compliance\": %g, \"relaxation\": %g, \"tolerance\": %g, \"convergence\": \"%s\", "
        "\"rms_tolerance\": %g, \"friction_law\": \"%s\", \"solid_fraction_orifice\": %.4f, "
        "\"solid_fraction_column\": %.4f, \"seed\": %u}\n",
        tEnd, steps, capped, sorted.empty() ? 0 : sorted[sorted.size() / 2], mean,
        sorted.empty() ? 0 : sorted.back(), sec, sec / std::max(1, steps), tOut.size(), rate, rate * mGrain,
        beverloo, maxOverlap / dMean, mat.relativeCompliance, mat.compliance, s.settings().relaxation,
        s.settings().tolerance, rmsTol ? "rms" : "max", rmsTol ? s.settings().rmsTolerance : 0.0,
        anitescu ? "anitescu" : "coulomb", phiOrifice / std::max(1, phiSamples),
        phiColumn / std::max(1, phiSamples), seed);
}
