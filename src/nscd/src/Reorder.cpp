// SPDX-License-Identifier: GPL-3.0-or-later
// Internal grain order along a space-filling curve (System::Settings::
// reorderInterval): the slots of a step (bodies, detection records, solver
// rows, persistent contacts) follow the Morton (Z-order) curve over the grid
// cells of the grain centres, so that neighbours in space are neighbours in
// memory. The per-grain arrays of the interface keep the external order,
// unless a caller that owns the grain indices renumbers them along the
// internal one (System::renumberAlongInternalOrder).
#include "Reorder.H"
#include "SystemImpl.H"
#include "nscd/Permutation.H"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <utility>

namespace nscd
{

namespace
{
/// Spread the low 21 bits of a so that bit k moves to bit 3k.
std::uint64_t spread3(std::uint64_t a)
{
    a &= 0x1fffffULL;
    a = (a | a << 32) & 0x1f00000000ffffULL;
    a = (a | a << 16) & 0x1f0000ff0000ffULL;
    a = (a | a << 8) & 0x100f00f00f00f00fULL;
    a = (a | a << 4) & 0x10c30c30c30c30c3ULL;
    a = (a | a << 2) & 0x1249249249249249ULL;
    return a;
}

/// Spread the low 32 bits of a so that bit k moves to bit 2k.
std::uint64_t spread2(std::uint64_t a)
{
    a &= 0xffffffffULL;
    a = (a | a << 16) & 0x0000ffff0000ffffULL;
    a = (a | a << 8) & 0x00ff00ff00ff00ffULL;
    a = (a | a << 4) & 0x0f0f0f0f0f0f0f0fULL;
    a = (a | a << 2) & 0x3333333333333333ULL;
    a = (a | a << 1) & 0x5555555555555555ULL;
    return a;
}
} // namespace

std::uint64_t mortonKey2(std::uint32_t i, std::uint32_t j) { return spread2(i) | spread2(j) << 1; }

std::uint64_t mortonKey3(std::uint32_t i, std::uint32_t j, std::uint32_t k)
{
    return spread3(i) | spread3(j) << 1 | spread3(k) << 2;
}

std::vector<int> mortonOrder(const std::vector<Vec3>& x, int dim, double cell)
{
    const int N = int(x.size());
    std::vector<int> out(N);
    std::iota(out.begin(), out.end(), 0);
    if (N < 2) return out;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Vec3& p : x)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    // cells per axis below 2^21 (3D) / 2^32 (2D): coarser cells for huge extents
    const double maxCells = dim == 3 ? double((1u << 21) - 1) : 4294967295.0;
    double h = cell > 0 && std::isfinite(cell) ? cell : 0.0;
    for (int d = 0; d < dim; ++d) h = std::max(h, (hi[d] - lo[d]) / maxCells);
    if (!(h > 0)) return out; // all centres at one point
    const double ih = 1.0 / h;
    std::vector<std::pair<std::uint64_t, int>> key(N);
    for (int i = 0; i < N; ++i)
    {
        std::uint32_t c[3] = {0, 0, 0};
        for (int d = 0; d < dim; ++d)
            c[d] = std::uint32_t(std::min(maxCells, std::max(0.0, std::floor((x[i][d] - lo[d]) * ih))));
        key[i] = {dim == 3 ? mortonKey3(c[0], c[1], c[2]) : mortonKey2(c[0], c[1]), i};
    }
    std::sort(key.begin(), key.end()); // ties (one cell): by grain index
    for (int s = 0; s < N; ++s) out[s] = key[s].second;
    return out;
}

void System::Impl::rebuildSlotOf()
{
    slotOf.resize(order.size());
    for (int s = 0; s < int(order.size()); ++s) slotOf[order[s]] = s;
}

void System::Impl::applyOrder(std::vector<int> newOrder)
{
    const int N = int(x.size());
    const std::vector<int> oldOrder = std::move(order);
    order = std::move(newOrder);
    rebuildSlotOf();
    verlet.invalidate(); // the list is by slot
    // persistent contacts: old slot -> grain -> new slot; grain pairs kept
    // with i < j (as detect() makes them), so that the next step matches them
    for (Contact& c : contacts)
    {
        c.i = slotOf[oldOrder[c.i]];
        if (c.j >= N) continue;
        c.j = slotOf[oldOrder[c.j]];
        if (c.j < c.i)
        {
            std::swap(c.i, c.j); // B becomes A: same normal impulse, opposite n and tangential impulse
            c.n = -c.n;
            c.rt = -c.rt;
        }
    }
    std::stable_sort(contacts.begin(), contacts.end(),
                     [](const Contact& a, const Contact& b) { return a.i < b.i; });
}

bool orderIsScattered(const std::vector<int>& curve, const std::vector<int>& slotOf)
{
    const int N = int(curve.size());
    if (N < 2) return false;
    const int window = std::min(reorderWindow, std::max(1, N / 8));
    long far = 0;
    for (int k = 0; k + 1 < N; ++k)
        if (std::abs(slotOf[curve[k]] - slotOf[curve[k + 1]]) > window) ++far;
    return double(far) > reorderFarFraction * (N - 1);
}

std::vector<std::size_t> System::renumberAlongInternalOrder()
{
    Impl& I = *impl_;
    const int N = int(I.x.size());
    if (N < 2 || int(I.order.size()) != N) return {};
    // scattered: consecutive slots whose grains are far apart in index (the
    // test of orderIsScattered with the grain index in place of the slot)
    const int window = std::min(reorderWindow, std::max(1, N / 8));
    long far = 0;
    for (int s = 0; s + 1 < N; ++s)
        if (std::abs(I.order[s + 1] - I.order[s]) > window) ++far;
    if (double(far) <= reorderFarFraction * (N - 1)) return {};

    // new grain s is the grain of slot s: the slots keep their order, so the
    // bodies, detection records, Verlet list and contact records (all by
    // slot) stay as they are
    const std::vector<std::size_t> oldOf(I.order.begin(), I.order.end());
    I.columns.permute(oldOf);     // every per-grain column
    for (Droplet& d : I.droplets) // (per-grain output of the last step, when sized)
        if (d.grainImpulse.size() == oldOf.size()) permuteInPlace(oldOf, d.grainImpulse);
    std::iota(I.order.begin(), I.order.end(), 0);
    I.rebuildSlotOf();
    return oldOf;
}

void System::Impl::maybeReorder()
{
    const int K = settings.reorderInterval;
    const int N = int(x.size());
    if (K <= 0 || N < 2) return;
    if (stepsSinceReorder < 0 || stepsSinceReorder >= K)
    {
        std::vector<int> curve = mortonOrder(x, dim, 2 * rMax());
        if (orderIsScattered(curve, slotOf)) applyOrder(std::move(curve));
        stepsSinceReorder = 0;
    }
    ++stepsSinceReorder;
}

} // namespace nscd
