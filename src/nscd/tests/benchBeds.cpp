// SPDX-License-Identifier: GPL-3.0-or-later
// The beds of the nscdBench suites (benchBeds.H): dense polydisperse
// deposits built by a layered lattice construction and mirror tiling of a
// settled block (the construction: benchSuite.cpp's header), settling to
// rest, timers and the machine note of the JSON reports.
#include "benchBeds.H"
#include "benchMachine.H"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace nscd;

namespace nscdBench
{
double now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double cpu()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

double median(std::vector<double> v)
{
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string jsonList(const std::vector<double>& v)
{
    std::ostringstream o;
    o << "[";
    for (std::size_t k = 0; k < v.size(); ++k) o << (k ? ", " : "") << v[k];
    o << "]";
    return o.str();
}

System makeSystem(const Bed& b, double mu)
{
    System s(b.dim);
    const int m = s.addMaterial({rho, mu});
    for (std::size_t i = 0; i < b.x.size(); ++i) s.addGrain(b.x[i], b.r[i], m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
    s.addPlane(Vec3(b.W, 0, 0), Vec3(-1, 0, 0));
    if (b.dim == 3)
    {
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 0, 1));
        s.addPlane(Vec3(0, 0, b.D), Vec3(0, 0, -1));
    }
    s.setGravity(Vec3(0, -g, 0));
    // NSCD_SKIN: Settings::verletSkin (timing the Verlet list against the grid scan)
    if (const char* sk = std::getenv("NSCD_SKIN")) s.settings().verletSkin = std::atof(sk);
    return s;
}

/// A block to be tiled: frictionless side walls (a mirror plane carries no
/// tangential force), frictional floor.
System makeBlock(const Bed& b, double mu)
{
    System s = makeSystem(b, mu);
    for (int w = 1; w < s.nWalls(); ++w) s.setWallFriction(w, 0.0);
    return s;
}

/// Layered construction: lattice columns of spacing d_max (2D: hexagonal
/// rows of ncol discs; 3D: square layers ncol x ncol stacked in the hollows,
/// fcc), polydisperse radii (seed fixed), each grain lowered onto the grains of
/// the two layers below it (its height is the lowest one without overlap, so
/// it touches at least one grain below or the floor). Dense and close to rest;
/// the remaining motion (grains rolling into a second support) is small.
Bed lattice(int dim, int n, int ncol, unsigned seed)
{
    Bed b;
    b.dim = dim;
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> D(dMin, dMax);
    const double s = dMax * (1 + 1e-6);
    b.W = ncol * s;
    b.D = dim == 3 ? ncol * s : 0;
    std::vector<int> prev1, prev2, cur;
    for (int layer = 0; int(b.x.size()) < n; ++layer)
    {
        const int odd = layer % 2;
        cur.clear();
        auto place = [&](double px, double pz)
        {
            const double r = 0.5 * D(gen);
            double y = r * (1 + 1e-9);
            for (const std::vector<int>* L : {&prev1, &prev2})
                for (int j : *L)
                {
                    const double dx = px - b.x[j].x(), dz = pz - b.x[j].z();
                    const double h2 = dx * dx + dz * dz, rr = (r + b.r[j]) * (1 + 1e-9);
                    if (h2 < rr * rr) y = std::max(y, b.x[j].y() + std::sqrt(rr * rr - h2));
                }
            cur.push_back(int(b.x.size()));
            b.x.emplace_back(px, y, pz);
            b.r.push_back(r);
        };
        if (dim == 2)
            for (int a = 0; a < ncol - odd && int(b.x.size()) < n; ++a) place(s * (a + 0.5 + 0.5 * odd), 0.0);
        else
            for (int c = 0; c < ncol - odd && int(b.x.size()) < n; ++c)
                for (int a = 0; a < ncol - odd && int(b.x.size()) < n; ++a)
                    place(s * (a + 0.5 + 0.5 * odd), s * (c + 0.5 + 0.5 * odd));
        prev2 = prev1;
        prev1 = cur;
    }
    return b;
}

Bed fromSystem(const System& s, const Bed& shape)
{
    Bed b = shape;
    b.x = s.positions();
    b.r = s.radii();
    return b;
}

/// nx (x nz in 3D) mirrored copies of a settled block side by side.
Bed tile(const Bed& b, int nx, int nz)
{
    Bed t;
    t.dim = b.dim;
    t.W = nx * b.W;
    t.D = b.dim == 3 ? nz * b.D : 0;
    for (int a = 0; a < nx; ++a)
        for (int c = 0; c < (b.dim == 3 ? nz : 1); ++c)
            for (std::size_t i = 0; i < b.x.size(); ++i)
            {
                Vec3 p = b.x[i];
                p.x() = (a % 2) ? (a + 1) * b.W - p.x() : a * b.W + p.x();
                if (b.dim == 3) p.z() = (c % 2) ? (c + 1) * b.D - p.z() : c * b.D + p.z();
                t.x.push_back(p);
                t.r.push_back(b.r[i]);
            }
    return t;
}

/// Contact impulses of the settled block mapped onto the tiled bed (same
/// tile order and mirroring as tile()): grain pairs copied, floor contacts
/// kept, side-wall contacts become box-wall contacts on the outside and
/// grain-image contacts at the seams (the wall impulse is the image's).
std::vector<System::ContactView> tileContacts(const System& blk, int nx, int nz)
{
    const int dim = blk.dimension();
    const int nb = int(blk.size());
    const int nzz = dim == 3 ? nz : 1;
    std::vector<System::ContactView> out;
    const auto views = blk.contacts();
    for (int a = 0; a < nx; ++a)
        for (int c = 0; c < nzz; ++c)
        {
            const int off = (a * nzz + c) * nb;
            auto M = [&](Vec3 v)
            {
                if (a % 2) v.x() = -v.x();
                if (c % 2) v.z() = -v.z();
                return v;
            };
            for (const auto& v : views)
            {
                System::ContactView t = v;
                t.normal = M(v.normal);
                t.impulse = M(v.impulse);
                t.i = v.i + off;
                if (v.j >= 0)
                {
                    t.j = v.j + off;
                    out.push_back(t);
                    continue;
                }
                const int w = -v.j - 1;
                if (w == 0)
                {
                    out.push_back(t);
                    continue;
                }
                // side wall: which side of the tile, box wall or seam
                const bool xw = w <= 2;
                const int idx = xw ? a : c, n = xw ? nx : nzz;
                const bool low = (w == 1 || w == 3) != bool(idx % 2);
                const int nbIdx = low ? idx - 1 : idx + 1;
                if (nbIdx < 0 || nbIdx >= n)
                {
                    t.j = -((xw ? (low ? 1 : 2) : (low ? 3 : 4)) + 1);
                    out.push_back(t);
                }
                else if (nbIdx > idx)
                {
                    const int offB = xw ? (nbIdx * nzz + c) * nb : (a * nzz + nbIdx) * nb;
                    t.j = v.i + offB;
                    out.push_back(t);
                }
            }
        }
    return out;
}

double vmax(const System& s)
{
    double v = 0;
    for (const auto& a : s.velocities()) v = std::max(v, a.norm());
    return v;
}

/// Settle with the measured settings (tolerance 1e-6 d_min) and at most 1000
/// sweeps/step (the README's production cap), until max |v| < g dt for 20
/// consecutive steps, then until max |v| < g dt/10 for 50 more. maxSteps in total.
SettleResult settle(System& s, int maxSteps, const char* tag)
{
    SettleResult R;
    const System::Settings keep = s.settings();
    const double t0 = now(), c0 = cpu();
    long sw = 0;
    int calm = 0, phase = 1, builds = 0;
    s.settings().maxIterations = 1000;
    for (int k = 0; k < maxSteps; ++k)
    {
        const StepReport r = s.step(dt);
        sw += r.sweeps;
        builds += r.verletBuilds;
        R.steps = k + 1;
        const double v = vmax(s);
        calm = v < (phase == 1 ? 1.0 : 0.1) * g * dt ? calm + 1 : 0;
        if (k % 100 == 0)
            std::fprintf(stderr, "  [%s] settle step %d contacts %d sweeps %d vmax %.2e\n", tag, k,
                         r.contacts, r.sweeps, v);
        if (phase == 1 && calm >= 20)
        {
            phase = 2;
            calm = 0;
            R.coarseSteps = k + 1;
            s.settings() = keep;
            s.settings().maxIterations = 1000;
        }
        else if (phase == 2 && calm >= 50)
        {
            R.rest = true;
            break;
        }
    }
    s.settings() = keep;
    R.seconds = now() - t0;
    R.cpuSeconds = cpu() - c0;
    R.sweeps = double(sw) / R.steps;
    R.vmaxEnd = vmax(s);
    std::fprintf(stderr,
                 "  [%s] settled: %d steps (%d coarse), %.1f s (CPU %.2f s), %.1f sweeps/step, rest %d, "
                 "%d Verlet list builds\n",
                 tag, R.steps, R.coarseSteps, R.seconds, R.cpuSeconds, R.sweeps, int(R.rest), builds);
    return R;
}

std::string machineNote()
{
    std::ostringstream o;
    o << benchMachine::cpuModel()
      << ", 1 core (single-threaded, pinned with taskset when available; machine shared with other jobs), "
#ifdef __GNUC__
      << "GCC " << __GNUC__ << "." << __GNUC_MINOR__
#endif
      << " -O3";
    return o.str();
}
} // namespace nscdBench
