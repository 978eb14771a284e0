// SPDX-License-Identifier: GPL-3.0-or-later
// overlapMap benchmark: cost of one full grain -> cell map (candidate search,
// exact overlaps, solid fraction) on one core.
//   Case 1 (2D): 70,000 discs, d = 230 um, on a triangle mesh with edge h = 2d
//                (thesis section 3.3.1, granular Rayleigh-Taylor: 56 x 68 mm).
//   Case 2 (3D): 20,000 spheres on a hex mesh with h/d = 1, timed with the
//                closed form for box cells (default) and, for comparison, through
//                the general `overlap` library path (closedFormBoxes = false).
// Grains are placed on a jittered lattice (dense, non-overlapping) and get
// small random displacements between maps. Writes a JSON result file.
//
// Usage: overlapMapBench [output.json] [repetitions] [2d|3d]
// (the third argument runs one case only and writes no JSON)
#include "benchMachine.H"
#include "overlapMapping/overlapMapping.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace overlapMapping;
using Clock = std::chrono::steady_clock;

namespace
{

double seconds(Clock::time_point a, Clock::time_point b)
{
    return std::chrono::duration<double>(b - a).count();
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double peakRssMb()
{
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss / 1024.0; // Linux: kilobytes
}

std::string machineNote()
{
    std::ostringstream s;
    s << benchMachine::cpuModel() << ", 1 core (single-threaded), GCC " << __GNUC__ << "." << __GNUC_MINOR__
      << " -O3";
    return s.str();
}

struct Result
{
    double msMedian = 0, msMin = 0, msMax = 0;
    double msPcm = 0;
    double entriesPerGrain = 0, evalsPerGrain = 0;
    label grains = 0, cells = 0;
    double phiMax = 0;
};

Result run(const CellMesh& mesh, const std::vector<Vec3>& base, const std::vector<double>& rad, double jitter,
           int reps, unsigned seed, const MappingSettings& settings = {}, bool withPcm = true)
{
    Result res;
    res.grains = label(base.size());
    res.cells = mesh.nCells();
    OverlapMapper om(mesh, settings);
    std::vector<Vec3> x = base;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-jitter, jitter);
    const bool twoD = mesh.twoD();
    auto move = [&]()
    {
        for (size_t i = 0; i < x.size(); ++i)
        {
            x[i][0] = base[i][0] + U(rng);
            x[i][1] = base[i][1] + U(rng);
            if (!twoD) x[i][2] = base[i][2] + U(rng);
        }
    };
    om.map(x, rad); // warm-up: first location through the bins
    std::vector<double> t;
    for (int k = 0; k < reps; ++k)
    {
        move();
        const auto t0 = Clock::now();
        om.map(x, rad);
        const auto t1 = Clock::now();
        t.push_back(1e3 * seconds(t0, t1));
    }
    res.msMedian = median(t);
    res.msMin = *std::min_element(t.begin(), t.end());
    res.msMax = *std::max_element(t.begin(), t.end());
    res.entriesPerGrain = double(om.nEntries()) / x.size();
    res.evalsPerGrain = double(om.lastCellsEvaluated()) / x.size();
    for (double p : om.solidFraction()) res.phiMax = std::max(res.phiMax, p);
    if (!withPcm)
    {
        return res;
    }
    // PCM for comparison
    MappingSettings s;
    s.method = MappingMethod::ParticleCentroid;
    om.setSettings(s);
    om.map(x, rad);
    std::vector<double> tp;
    for (int k = 0; k < std::max(3, reps / 2); ++k)
    {
        move();
        const auto t0 = Clock::now();
        om.map(x, rad);
        tp.push_back(1e3 * seconds(t0, Clock::now()));
    }
    res.msPcm = median(tp);
    return res;
}

// ---- the two cases ------------------------------------------------------------

constexpr double kD = 230e-6;                             ///< grain diameter [m]
constexpr double kW = 56e-3, kH = 68e-3, kDepth = 2.3e-3; ///< 2D domain, thesis 3.3.1 [m]
constexpr int kGrains2D = 70000;                          ///< discs of case 1
constexpr int kGrains3D = 20000;                          ///< spheres of case 2

/// Cells of the 2D mesh along a side of length @p L (edge h = 2d).
int cells2D(double L)
{
    const double h = 2 * kD;
    return int(std::round(L / h));
}

/// A prepared mesh with its grains and the time its preparation took.
struct BenchCase
{
    CellMesh mesh;
    double meshSeconds;
    std::vector<Vec3> x;   ///< grain centres [m]
    std::vector<double> r; ///< grain radii [m]
};

/// Timings of case 2 with and without the closed form for box cells.
struct Result3D
{
    Result closedForm, general;
    label nBox = 0;
};

/// Case 1 set-up: triangle mesh (edge h = 2d) and a jittered triangular
/// lattice of discs, spacing 1.04 d, placed from the bottom.
BenchCase setup2D()
{
    const double d = kD, r = d / 2;
    const auto t0 = Clock::now();
    CellMesh mesh2(
        grid2DMesh(gradedSpacing(0, kW, cells2D(kW)), gradedSpacing(0, kH, cells2D(kH)), 0, kDepth, true));
    const double tMesh2 = seconds(t0, Clock::now());
    const double s = 1.04 * d, jit0 = 0.01 * d;
    std::vector<Vec3> x2;
    std::vector<double> r2;
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> U(-jit0, jit0);
    for (int j = 0; label(x2.size()) < kGrains2D; ++j)
    {
        const double y = r + 0.02 * d + j * s * std::sqrt(3.0) / 2;
        if (y > kH - r - 0.02 * d) break;
        for (int i = 0; label(x2.size()) < kGrains2D; ++i)
        {
            const double xx = r + 0.02 * d + i * s + (j % 2) * 0.5 * s;
            if (xx > kW - r - 0.02 * d) break;
            x2.emplace_back(xx + U(rng), y + U(rng), 0.5 * kDepth);
            r2.push_back(r);
        }
    }
    return BenchCase{std::move(mesh2), tMesh2, std::move(x2), std::move(r2)};
}

/// Case 1 run: time the 2D maps and print their line.
Result run2D(const BenchCase& c, int reps)
{
    const Result res2 = run(c.mesh, c.x, c.r, 0.005 * kD, reps, 1);
    std::printf("2D: %d discs, %d cells (mesh build %.2f s): map median %.2f ms "
                "(min %.2f, max %.2f), PCM %.2f ms, %.2f entries/grain, "
                "%.2f evaluations/grain, max phi %.4f\n",
                res2.grains, res2.cells, c.meshSeconds, res2.msMedian, res2.msMin, res2.msMax, res2.msPcm,
                res2.entriesPerGrain, res2.evalsPerGrain, res2.phiMax);
    return res2;
}

/// Case 2 set-up: hex mesh with h = d around a jittered simple cubic
/// lattice of spheres, spacing 1.05 d (28^3 = 21952 sites).
BenchCase setup3D()
{
    const double d = kD, r = d / 2;
    const int nl = 28;
    const double s3 = 1.05 * d;
    const double L = nl * s3;
    const int nc = int(std::ceil(L / d));
    const auto t1 = Clock::now();
    const auto xs = gradedSpacing(0, nc * d, nc);
    CellMesh mesh3(hexGridMesh(xs, xs, xs));
    const double tMesh3 = seconds(t1, Clock::now());
    std::vector<Vec3> x3;
    std::vector<double> r3;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(-0.01 * d, 0.01 * d);
    const double off = 0.5 * (nc * d - L) + 0.5 * s3;
    for (int k = 0; k < nl && label(x3.size()) < kGrains3D; ++k)
        for (int j = 0; j < nl && label(x3.size()) < kGrains3D; ++j)
            for (int i = 0; i < nl && label(x3.size()) < kGrains3D; ++i)
            {
                x3.emplace_back(off + i * s3 + U(rng), off + j * s3 + U(rng), off + k * s3 + U(rng));
                r3.push_back(r);
            }
    return BenchCase{std::move(mesh3), tMesh3, std::move(x3), std::move(r3)};
}

/// Case 2 run: time the 3D maps with the closed form for box cells, then
/// the same grains through the general `overlap` library path; print both.
Result3D run3D(const BenchCase& c, int reps)
{
    Result3D out;
    for (label k = 0; k < c.mesh.nCells(); ++k) out.nBox += c.mesh.isBox(k);
    out.closedForm = run(c.mesh, c.x, c.r, 0.005 * kD, std::max(5, reps / 2), 2);
    const Result& res3 = out.closedForm;
    std::printf("3D: %d spheres, %d cells (%d boxes; mesh build %.2f s): map median %.2f ms "
                "(min %.2f, max %.2f), PCM %.2f ms, %.2f entries/grain, "
                "%.2f evaluations/grain, max phi %.4f\n",
                res3.grains, res3.cells, out.nBox, c.meshSeconds, res3.msMedian, res3.msMin, res3.msMax,
                res3.msPcm, res3.entriesPerGrain, res3.evalsPerGrain, res3.phiMax);
    MappingSettings general;
    general.closedFormBoxes = false;
    out.general = run(c.mesh, c.x, c.r, 0.005 * kD, 5, 2, general, false);
    const Result& gen3 = out.general;
    std::printf("3D general path (overlap library, closedFormBoxes = false): map median %.2f ms "
                "(min %.2f, max %.2f): closed form %.1fx faster\n",
                gen3.msMedian, gen3.msMin, gen3.msMax, gen3.msMedian / res3.msMedian);
    return out;
}

/// Write the JSON result file @p out; false if it cannot be opened.
bool writeJson(const std::string& out, int reps, const Result& res2, const Result3D& r3, double wall,
               double rss)
{
    std::ofstream f(out);
    if (!f)
    {
        std::cerr << "overlapMapBench: cannot write " << out << "\n";
        return false;
    }
    const Result& res3 = r3.closedForm;
    const Result& gen3 = r3.general;
    f.precision(6);
    f << "{\n"
      << "  \"benchmark\": \"overlapMap\",\n"
      << "  \"wall_seconds_total\": " << wall << ",\n"
      << "  \"seconds_per_step_median\": " << res2.msMedian * 1e-3 << ",\n"
      << "  \"milliseconds_per_map_median\": " << res2.msMedian << ",\n"
      << "  \"milliseconds_per_map_min\": " << res2.msMin << ",\n"
      << "  \"milliseconds_per_map_max\": " << res2.msMax << ",\n"
      << "  \"milliseconds_per_map_pcm_median\": " << res2.msPcm << ",\n"
      << "  \"grains\": " << res2.grains << ",\n"
      << "  \"cells\": " << res2.cells << ",\n"
      << "  \"entries_per_grain\": " << res2.entriesPerGrain << ",\n"
      << "  \"overlap_evaluations_per_grain\": " << res2.evalsPerGrain << ",\n"
      << "  \"repetitions\": " << reps << ",\n"
      << "  \"grain_diameter_m\": " << kD << ",\n"
      << "  \"h_over_d\": 2,\n"
      << "  \"mesh_2d\": \"" << cells2D(kW) << "x" << cells2D(kH)
      << " squares split into right triangles (edge h = 2d, legs), 56 x 68 mm, depth 2.3 mm\",\n"
      << "  \"layout\": \"monodisperse grains on a jittered lattice (2D triangular, spacing 1.04 d; "
         "3D simple cubic, spacing 1.05 d), non-overlapping, re-jittered by +-0.005 d before each map; "
         "centroids computed; median over repetitions after one warm-up map\",\n"
      << "  \"peak_rss_mb\": " << rss << ",\n"
      << "  \"machine\": \"" << machineNote() << "\",\n"
      << "  \"3d\": {\n"
      << "    \"milliseconds_per_map_median\": " << res3.msMedian << ",\n"
      << "    \"milliseconds_per_map_pcm_median\": " << res3.msPcm << ",\n"
      << "    \"grains\": " << res3.grains << ",\n"
      << "    \"cells\": " << res3.cells << ",\n"
      << "    \"entries_per_grain\": " << res3.entriesPerGrain << ",\n"
      << "    \"overlap_evaluations_per_grain\": " << res3.evalsPerGrain << ",\n"
      << "    \"h_over_d\": 1,\n"
      << "    \"box_cells\": " << r3.nBox << ",\n"
      << "    \"milliseconds_per_map_median_general_path\": " << gen3.msMedian << ",\n"
      << "    \"speedup_closed_form_vs_general_path\": " << gen3.msMedian / res3.msMedian << ",\n"
      << "    \"before_after\": \"before = the general sphere/hexahedron routine of the overlap "
         "library for every cell (MappingSettings::closedFormBoxes = false, 5 maps, same grains "
         "and machine state); after = closed-form sphere/box overlaps for the axis-aligned hex "
         "cells (default)\"\n"
      << "  },\n"
      << "  \"command\": \"tests/bench/overlapMap " << reps << "\"\n"
      << "}\n";
    std::printf("wrote %s\n", out.c_str());
    return true;
}

} // namespace

int main(int argc, char** argv)
{
    const std::string out = argc > 1 ? argv[1] : "tests/bench/results/overlapMap.json";
    const int reps = argc > 2 ? std::max(3, std::atoi(argv[2])) : 21;
    const auto tStart = Clock::now();
    const std::string only = argc > 3 ? argv[3] : ""; // profiling aid: "2d" or "3d"

    const BenchCase case2 = setup2D();
    if (label(case2.x.size()) != kGrains2D)
    {
        std::cerr << "overlapMapBench: could only place " << case2.x.size() << " discs\n";
        return 1;
    }
    const Result res2 = only == "3d" ? Result() : run2D(case2, reps);
    if (!only.empty() && only != "3d")
    {
        return 0; // profiling aid: 2D case only, no JSON
    }

    const BenchCase case3 = setup3D();
    const Result3D res3 = run3D(case3, reps);
    if (only == "3d")
    {
        return 0; // profiling aid: 3D case only, no JSON
    }

    const double wall = seconds(tStart, Clock::now());
    const double rss = peakRssMb();
    std::printf("peak RSS %.1f MB, total %.1f s\n", rss, wall);
    return writeJson(out, reps, res2, res3, wall, rss) ? 0 : 1;
}
