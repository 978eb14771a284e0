// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::mpi::DecomposedSystem: construction (from nothing or by decomposing
// a whole system), grains added, the step and the sub-stepped advance.
#include "DecomposedSystemImpl.H"
#include "nscd/ComplianceStepScope.H"

#include <utility>

#include <algorithm>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace nscd
{
namespace mpi
{

DecomposedSystem::DecomposedSystem(int dimension, MPI_Comm comm, OwnerFunction ownerOf, double halo)
    : impl_(std::make_unique<Impl>(dimension))
{
    impl_->init(comm, std::move(ownerOf), halo);
}

DecomposedSystem::DecomposedSystem(System&& whole, MPI_Comm comm, OwnerFunction ownerOf, double halo)
    : DecomposedSystem(std::move(whole), -1, comm, std::move(ownerOf), halo)
{
}

DecomposedSystem::DecomposedSystem(System&& part, long wholeSize, MPI_Comm comm, OwnerFunction ownerOf,
                                   double halo)
    : impl_(std::make_unique<Impl>(std::move(part)))
{
    Impl& I = *impl_;
    I.init(comm, std::move(ownerOf), halo);
    const std::size_t N = I.sys.size();
    I.gid = I.sys.grainIds();
    I.owned.assign(N, 1);
    // keep the grains owned here and those that will be ghosts here (within
    // halo of the owned centres' box), with the contacts among them: the
    // contact impulses warm-start the first step, at the interfaces too
    // (exchange() then refreshes the ghosts in place)
    // owner: the lowest rank that claims the centre (by grain id, as the
    // ranks may hold different parts)
    long idEnd = 0;
    for (long id : I.gid) idEnd = std::max(idEnd, id + 1);
    MPI_Allreduce(MPI_IN_PLACE, &idEnd, 1, MPI_LONG, MPI_MAX, I.comm);
    long expected = wholeSize;
    if (wholeSize < 0) expected = long(N); // the whole system on every rank
    std::vector<int> claim(idEnd, std::numeric_limits<int>::max());
    for (std::size_t i = 0; i < N; ++i)
        if (I.checkedOwner(I.sys.positions()[i], I.gid[i]) == I.rank) claim[I.gid[i]] = I.rank;
    if (idEnd > 0) MPI_Allreduce(MPI_IN_PLACE, claim.data(), int(idEnd), MPI_INT, MPI_MIN, I.comm);
    const long claimed = long(std::count_if(claim.begin(), claim.end(),
                                            [](int r) { return r != std::numeric_limits<int>::max(); }));
    if (claimed != expected)
    {
        // the grains held here that no rank claims, named (a part read: a
        // grain outside every rank's part is only counted)
        std::string lost;
        int named = 0;
        for (std::size_t i = 0; i < N && named < 5; ++i)
            if (claim[I.gid[i]] == std::numeric_limits<int>::max())
            {
                const Vec3& x = I.sys.positions()[i];
                lost += "\n    grain " + std::to_string(I.gid[i]) + " at (" + std::to_string(x.x()) + ", "
                        + std::to_string(x.y()) + ", " + std::to_string(x.z()) + ")";
                ++named;
            }
        throw InputError("nscd::mpi::DecomposedSystem: " + std::to_string(expected - claimed) + " of "
                         + std::to_string(expected) + " grain(s) in no rank's region (outside the domain?)"
                         + (wholeSize >= 0 ? ", or outside every rank's part of the state" : "") + lost);
    }
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (std::size_t i = 0; i < N; ++i)
    {
        const Vec3& x = I.sys.positions()[i];
        I.owned[i] = claim[I.gid[i]] == I.rank;
        if (I.owned[i])
        {
            lo = lo.cwiseMin(x);
            hi = hi.cwiseMax(x);
        }
    }
    claim = {};
    std::vector<char> drop(N, 0);
    for (std::size_t i = 0; i < N; ++i)
        drop[i] = !I.owned[i] && distance2(I.sys.positions()[i], lo, hi) > I.halo * I.halo;
    I.removeFlagged(drop);
    exchange();
}

DecomposedSystem::~DecomposedSystem() = default;

System& DecomposedSystem::system() { return impl_->sys; }
const System& DecomposedSystem::system() const { return impl_->sys; }
int DecomposedSystem::rank() const { return impl_->rank; }
int DecomposedSystem::nRanks() const { return impl_->P; }
const std::vector<char>& DecomposedSystem::owned() const { return impl_->owned; }
const std::vector<long>& DecomposedSystem::globalIds() const { return impl_->gid; }
const ExchangeCounters& DecomposedSystem::counters() const { return impl_->counters; }

void DecomposedSystem::Impl::reportSubStepCause(StepReport& rep, const SubStepChoice& local, double nHalo,
                                                double fastestSpeed)
{
    using Cause = StepReport::SubStepCause;
    // the rank whose own rule asked for the most sub-steps (lowest rank on a tie)
    struct
    {
        double count;
        int rank;
    } mine{local.count, rank};
    {
        CpuTimer t(counters.solveCommCpuSeconds);
        MPI_Allreduce(MPI_IN_PLACE, &mine, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm);
    }
    if (nHalo > mine.count) // (mine.count: the largest rule count, need[3] of advance)
    {
        rep.substepCause = Cause::Halo;
        rep.substepBody = -3;
        rep.substepSpeed = fastestSpeed;
        return;
    }
    double what[3] = {double(int(local.cause)), double(local.body), local.speed}; // (body: global id)
    {
        CpuTimer t(counters.solveCommCpuSeconds);
        MPI_Bcast(what, 3, MPI_DOUBLE, mine.rank, comm);
    }
    rep.substepCause = Cause(int(what[0]));
    rep.substepBody = long(what[1]);
    rep.substepSpeed = what[2];
}

StepReport DecomposedSystem::advance(double dt, double fraction)
{
    Impl& I = *impl_;
    if (!(dt > 0) || !(fraction > 0))
        throw InputError("nscd::mpi::DecomposedSystem::advance: dt and fraction must be > 0, got dt = "
                         + std::to_string(dt) + ", fraction = " + std::to_string(fraction));
    const System::Settings& set = I.sys.settings();
    // the reach of the fastest grain must stay within the halo: r_max, the
    // margin and the alert distance of a pair of such grains (bounds over
    // every rank)
    double bounds[2] = {0, -1e300}; // r_max, -r_min
    const Vec3 g = I.sys.gravity();
    for (std::size_t i = 0; i < I.sys.size(); ++i)
    {
        const double r = I.sys.radii()[i];
        bounds[0] = std::max(bounds[0], r);
        bounds[1] = std::max(bounds[1], -r);
    }
    StepReport total;
    double remaining = dt;
    const ComplianceStepScope lawStep(I.sys, dt); // the sub-steps keep relativeCompliance's law of dt
    while (remaining > 0)
    {
        double speed = 0;
        const std::vector<Vec3>& force = std::as_const(I.sys).column<Vec3>("forces");
        for (std::size_t i = 0; i < I.sys.size(); ++i)
        {
            if (I.sys.fixed(i)) continue;
            const Vec3 vFree = I.sys.velocities()[i] + dt * (g + force[i] / I.sys.mass(i));
            speed = std::max(speed, vFree.norm() + I.sys.radii()[i] * I.sys.angularVelocities()[i].norm());
        }
        // sub-steps: System::subStep's rule on each rank, and the halo's
        const SubStepChoice local = I.sys.subStepChoice(dt, fraction);
        double need[4] = {bounds[0], bounds[1], speed, local.count};
        {
            CpuTimer t(I.counters.solveCommCpuSeconds);
            MPI_Allreduce(MPI_IN_PLACE, need, 4, MPI_DOUBLE, MPI_MAX, I.comm);
        }
        const double rMax = need[0], rMin = need[1] > -1e300 ? -need[1] : 0.0; // (no grain anywhere: 0)
        const double spare = I.halo - 2 * rMax - set.alertMargin * std::max(rMin, 0.0);
        if (!(spare > 0))
            throw InputError("nscd::mpi::DecomposedSystem::advance: the halo " + std::to_string(I.halo)
                             + " m does not exceed 2 r_max + the alert margin ("
                             + std::to_string(2 * rMax + set.alertMargin * rMin) + " m)");
        const double nHalo = std::ceil(2 * set.alertDistanceFactor * need[2] * dt / spare * (1 - 1e-12));
        const double n = std::max({1.0, need[3], nHalo});
        double h = std::min(remaining, dt / n);
        if (h >= remaining * (1 - 1e-12)) h = remaining;
        const double needed = total.substeps + std::ceil(remaining / h * (1 - 1e-12));
        if (needed > double(set.maxSubSteps))
            throw StepError("nscd::mpi::DecomposedSystem::advance: the step of " + std::to_string(dt)
                            + " s needs about " + std::to_string(needed)
                            + " sub-steps, more than maxSubSteps = " + std::to_string(set.maxSubSteps)
                            + " (fastest grain: free speed " + std::to_string(need[2]) + " m/s; halo "
                            + std::to_string(I.halo) + " m)");
        if (total.substeps == 0 && n > 1) I.reportSubStepCause(total, local, nHalo, need[2]);
        total.addSubStep(step(h));
        remaining = (h == remaining) ? 0.0 : remaining - h;
    }
    return total;
}

const std::vector<int>& DecomposedSystem::unclaimed() const { return impl_->unclaimed; }

std::vector<std::size_t> DecomposedSystem::removeOwned(const std::vector<std::size_t>& indices)
{
    try
    {
        return impl_->removeOwned(indices);
    }
    catch (const std::exception& e)
    {
        impl_->abortAll("removeOwned", e);
    }
}

void DecomposedSystem::setRegionBox(const Vec3& lo, const Vec3& hi)
{
    impl_->regionLo = lo;
    impl_->regionHi = hi;
}

std::size_t DecomposedSystem::nOwned() const
{
    return std::size_t(std::count(impl_->owned.begin(), impl_->owned.end(), 1));
}

std::size_t DecomposedSystem::addGrain(long id, const Vec3& centre, double radius, int material, bool fixed)
{
    Impl& I = *impl_;
    if (I.checkedOwner(centre, id) != I.rank) return std::size_t(-1);
    const std::size_t i = std::size_t(I.sys.addGrain(centre, radius, material, fixed));
    I.sub.setGrainId(i, id);
    I.gid.push_back(id);
    I.owned.push_back(1);
    I.data.resize(I.gid.size() * std::size_t(I.dataWidth), 0.0);
    return i;
}

void DecomposedSystem::setGrainDataWidth(int width)
{
    Impl& I = *impl_;
    if (width < 0)
        throw InputError("nscd::mpi::DecomposedSystem::setGrainDataWidth: negative width "
                         + std::to_string(width));
    if (width != I.dataWidth) I.data.assign(I.gid.size() * std::size_t(width), 0.0);
    I.dataWidth = width;
}

int DecomposedSystem::grainDataWidth() const { return impl_->dataWidth; }
std::vector<double>& DecomposedSystem::grainData() { return impl_->data; }
const std::vector<double>& DecomposedSystem::grainData() const { return impl_->data; }

void DecomposedSystem::exchange()
{
    impl_->counters = ExchangeCounters{};
    try
    {
        impl_->exchange();
    }
    catch (const std::exception& e)
    {
        impl_->abortAll("exchange", e);
    }
}

StepReport DecomposedSystem::step(double dt)
{
    Impl& I = *impl_;
    I.counters = ExchangeCounters{};
    try
    {
        const StepReport rep = I.sub.step(dt, I.owned, I.gid);
        I.exchange();
        return rep;
    }
    catch (const InputError&)
    {
        throw; // refused by the collective input check: every rank throws it
    }
    catch (const std::exception& e)
    {
        I.abortAll("step", e);
    }
}

} // namespace mpi
} // namespace nscd
