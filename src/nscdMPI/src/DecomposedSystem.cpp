// nscd::mpi::DecomposedSystem: ownership, migration and ghosts of a grain
// system decomposed over MPI ranks, and the collectives of the
// interface-averaged step (nscd::SubdomainCoupling) over MPI.
#include "nscdMPI/DecomposedSystem.H"

#include "Messages.H"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace nscd
{
namespace mpi
{

namespace
{
/// A grain sent to its new owner or as a ghost (plain data).
struct GrainRecord
{
    long id;
    int material;
    int flags;  ///< 1: fixed, 2: rotation locked
    double radius;
    double x[3], v[3], w[3], q[4], f[3], t[3], u[3];
    double T, c;
};

/// A contact sent with a migrating grain (its warm start), seen from that grain.
struct ContactRecord
{
    long grain;      ///< the migrating grain's global id
    long partner;    ///< the other grain's global id, or a wall -(w+1)
    double n[3];     ///< unit normal from the partner to the grain
    double impulse[3];  ///< impulse on the grain [N s]
    int age;
};

void put(double* a, const Vec3& v) { a[0] = v.x(); a[1] = v.y(); a[2] = v.z(); }
Vec3 get(const double* a) { return Vec3(a[0], a[1], a[2]); }

/// The state a record carries.
Subdomain::GrainState stateOf(const GrainRecord& g)
{
    Subdomain::GrainState s;
    s.x = get(g.x); s.v = get(g.v); s.w = get(g.w);
    s.q = Eigen::Quaterniond(g.q[0], g.q[1], g.q[2], g.q[3]);
    s.force = get(g.f); s.torque = get(g.t); s.fluidVelocity = get(g.u);
    s.temperature = g.T;
    s.dragCoefficient = g.c;
    return s;
}

/// Squared distance from p to the box [lo, hi] (inverted box: infinite).
double distance2(const Vec3& p, const Vec3& lo, const Vec3& hi)
{
    double d2 = 0;
    for (int k = 0; k < 3; ++k)
    {
        if (lo[k] > hi[k]) return std::numeric_limits<double>::infinity();
        const double e = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
        d2 += e*e;
    }
    return d2;
}

/// Thread CPU time [s] (CLOCK_THREAD_CPUTIME_ID).
double threadCpu()
{
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9*double(t.tv_nsec);
}

/// Adds the thread CPU time of its scope to a counter.
struct CpuTimer
{
    double& sum;
    const double t0 = threadCpu();
    explicit CpuTimer(double& s) : sum(s) {}
    ~CpuTimer() { sum += threadCpu() - t0; }
};

} // namespace

struct DecomposedSystem::Impl : public SubdomainCoupling
{
    MPI_Comm comm = MPI_COMM_NULL;
    int rank = 0, P = 1;
    System sys;
    OwnerFunction ownerOf;
    double halo = 0;
    /// setRegionBox (inverted: none)
    Vec3 regionLo = Vec3::Constant(1e300), regionHi = Vec3::Constant(-1e300);
    /// owned grains that left the region and no rank claimed (last exchange)
    std::vector<int> unclaimed;
    std::vector<char> owned;
    std::vector<long> gid;
    /// ghosts: local indices of the grains received from each rank (in its send order)
    std::vector<std::vector<int>> ghostFrom;
    /// owned grains sent to each rank as ghosts (local indices, in order)
    std::vector<std::vector<int>> sendTo;
    /// of this step's solve: ghosts in a contact here (by source rank) and
    /// owned grains in a contact of each rank (aligned with that rank's list)
    std::vector<std::vector<int>> ifaceGhost, ifaceOwned;
    std::vector<int> ownedShared;  ///< owned grains with copies elsewhere (each once)
    std::vector<int> copies;
    /// per local grain, 2 entries: interface impulses of its copy (Subdomain::step)
    std::vector<Vec3> lambda;
    ExchangeCounters counters;
    Subdomain sub{sys, *this};  ///< the step (after sys: it keeps a reference)

    explicit Impl(int dim) : sys(dim) {}
    explicit Impl(System&& whole) : sys(std::move(whole)) {}

    void init(MPI_Comm c, OwnerFunction f, double h)
    {
        if (!(h > 0) || !std::isfinite(h))
            throw InputError("nscd::mpi::DecomposedSystem: halo must be > 0 (at least 2 r_max + the alert"
                             " distance), got " + std::to_string(h));
        if (!f) throw InputError("nscd::mpi::DecomposedSystem: no owner function");
        MPI_Comm_dup(c, &comm);
        MPI_Comm_rank(comm, &rank);
        MPI_Comm_size(comm, &P);
        ownerOf = std::move(f);
        halo = h;
        ghostFrom.assign(P, {});
        sendTo.assign(P, {});
    }
    ~Impl() override
    {
        int done = 0;
        MPI_Finalized(&done);
        if (comm != MPI_COMM_NULL && !done) MPI_Comm_free(&comm);
    }

    // ---- SubdomainCoupling ----
    double maxOverSubdomains(double value) override
    {
        CpuTimer t(counters.solveCommCpuSeconds);
        double out = value;
        MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, comm);
        return out;
    }

    void countCopies(const std::vector<char>& inContact, std::vector<int>& copiesOut) override
    {
        CpuTimer t(counters.solveCommCpuSeconds);
        // ghosts in a contact here tell their owner; owners count and answer
        std::vector<std::vector<char>> flags(P), got(P);
        ifaceGhost.assign(P, {});
        ifaceOwned.assign(P, {});
        for (int r = 0; r < P; ++r)
        {
            for (int i : ghostFrom[r])
            {
                flags[r].push_back(inContact[i] ? 1 : 0);
                if (inContact[i]) ifaceGhost[r].push_back(i);
            }
            got[r].resize(sendTo[r].size());
        }
        counters.bytesSent += exchangeKnown(comm, TagFlags, flags, got);
        copiesOut.assign(owned.size(), 1);
        ownedShared.clear();
        for (int r = 0; r < P; ++r)
            for (std::size_t k = 0; k < got[r].size(); ++k)
                if (got[r][k])
                {
                    const int i = sendTo[r][k];
                    if (copiesOut[i]++ == 1) ownedShared.push_back(i);
                    ifaceOwned[r].push_back(i);
                }
        std::vector<std::vector<int>> answer(P), counts(P);
        for (int r = 0; r < P; ++r)
        {
            for (int i : ifaceOwned[r]) answer[r].push_back(copiesOut[i]);
            counts[r].resize(ifaceGhost[r].size());
        }
        counters.bytesSent += exchangeKnown(comm, TagCopies, answer, counts);
        for (int r = 0; r < P; ++r)
            for (std::size_t k = 0; k < counts[r].size(); ++k) copiesOut[ifaceGhost[r][k]] = counts[r][k];
        copies = copiesOut;
    }

    void averageCopies(std::vector<Vec3>& v, std::vector<Vec3>& w) override
    {
        CpuTimer t(counters.solveCommCpuSeconds);
        struct VW { double a[6]; };
        // per rank: (v, w) of the grains of lists[r], and a receive buffer of n(r)
        auto pack = [&](const std::vector<std::vector<int>>& lists, const std::vector<std::vector<int>>& from,
                        std::vector<std::vector<VW>>& out, std::vector<std::vector<VW>>& in)
        {
            out.assign(P, {});
            in.assign(P, {});
            for (int r = 0; r < P; ++r)
            {
                for (int i : lists[r])
                {
                    VW m;
                    put(m.a, v[i]);
                    put(m.a + 3, w[i]);
                    out[r].push_back(m);
                }
                in[r].resize(from[r].size());
            }
        };
        std::vector<std::vector<VW>> toOwner, atOwner;
        pack(ifaceGhost, ifaceOwned, toOwner, atOwner);
        counters.bytesSent += exchangeKnown(comm, TagToOwner, toOwner, atOwner);
        // owners: the mean of the copies (equal masses), sent back
        for (int r = 0; r < P; ++r)
            for (std::size_t k = 0; k < atOwner[r].size(); ++k)
            {
                const int i = ifaceOwned[r][k];
                v[i] += get(atOwner[r][k].a);
                w[i] += get(atOwner[r][k].a + 3);
            }
        for (int i : ownedShared) { v[i] /= copies[i]; w[i] /= copies[i]; }
        std::vector<std::vector<VW>> fromOwner, back;
        pack(ifaceOwned, ifaceGhost, fromOwner, back);
        counters.bytesSent += exchangeKnown(comm, TagFromOwner, fromOwner, back);
        for (int r = 0; r < P; ++r)
            for (std::size_t k = 0; k < back[r].size(); ++k)
            {
                const int i = ifaceGhost[r][k];
                v[i] = get(back[r][k].a);
                w[i] = get(back[r][k].a + 3);
            }
        ++counters.averagings;
    }

    // ---- grains ----
    GrainRecord record(int i) const
    {
        const Subdomain::GrainState s = sub.state(i);
        GrainRecord g;
        g.id = gid[i];
        g.material = sys.materials()[i];
        g.flags = (sys.fixed(i) ? 1 : 0) | (sys.rotationLocked(i) ? 2 : 0);
        g.radius = sys.radii()[i];
        put(g.x, s.x); put(g.v, s.v); put(g.w, s.w);
        g.q[0] = s.q.w(); g.q[1] = s.q.x(); g.q[2] = s.q.y(); g.q[3] = s.q.z();
        put(g.f, s.force); put(g.t, s.torque); put(g.u, s.fluidVelocity);
        g.T = s.temperature;
        g.c = s.dragCoefficient;
        return g;
    }

    /// Set local grain i from g (added first if i < 0); returns its index.
    int place(int i, const GrainRecord& g, bool isOwned)
    {
        if (i < 0)
        {
            i = int(sys.addGrain(get(g.x), g.radius, g.material, g.flags & 1));
            sub.setGrainId(std::size_t(i), g.id);
            gid.push_back(g.id);
            owned.push_back(0);
            lambda.resize(2*gid.size(), Vec3::Zero());
        }
        sys.setRotationLocked(i, g.flags & 2);
        sub.setState(i, stateOf(g));
        owned[i] = isOwned ? 1 : 0;
        return i;
    }

    /// Remove the local grains flagged in drop (System and the per-grain lists).
    void removeFlagged(const std::vector<char>& drop)
    {
        std::vector<std::size_t> idx;
        for (std::size_t i = 0; i < drop.size(); ++i) if (drop[i]) idx.push_back(i);
        if (idx.empty()) return;
        sys.removeGrains(idx);
        std::size_t n = 0;
        lambda.resize(2*drop.size(), Vec3::Zero());
        for (std::size_t i = 0; i < drop.size(); ++i)
            if (!drop[i])
            {
                gid[n] = gid[i];
                owned[n] = owned[i];
                lambda[2*n] = lambda[2*i];
                lambda[2*n + 1] = lambda[2*i + 1];
                ++n;
            }
        gid.resize(n);
        owned.resize(n);
        lambda.resize(2*n);
    }

    /// ownerOf, checked: a rank or notHere
    int checkedOwner(const Vec3& x, long id) const
    {
        const int r = ownerOf(x, id);
        if (r == notHere) return r;
        if (r < 0 || r >= P)
            throw InputError("nscd::mpi::DecomposedSystem: the owner function gives rank " + std::to_string(r)
                             + " for the point (" + std::to_string(x.x()) + ", " + std::to_string(x.y()) + ", "
                             + std::to_string(x.z()) + "); ranks are 0 to " + std::to_string(P - 1)
                             + " (or notHere)");
        return r;
    }

    /// For the owned grains `leaving` (left this rank's region, owner not
    /// known here): the lowest rank whose owner function claims each one,
    /// or -1 if none does (collective: every rank asks its function about
    /// the leavers of all ranks).
    std::vector<int> claimLeavers(const std::vector<int>& leaving);

    void exchange();

    /// A fault on this rank inside a collective (a StepError, an owner
    /// outside the ranks): the other ranks wait for it, so stop them all,
    /// as OpenFOAM's FatalError does, rather than hang.
    [[noreturn]] void abortAll(const char* where, const std::exception& e) const
    {
        std::fprintf(stderr, "nscd::mpi::DecomposedSystem::%s, rank %d: %s\n", where, rank, e.what());
        std::fflush(stderr);
        MPI_Abort(comm, 1);
        std::abort();  // MPI_Abort does not return
    }

    /// Add the contacts received with migrated grains to the warm start.
    void seedMigratedContacts(const std::vector<std::vector<ContactRecord>>& recvC);
};

void DecomposedSystem::Impl::exchange()
{
    CpuTimer t(counters.exchangeCpuSeconds);
    counters.migratedOut = counters.ghostsSent = counters.ghostsAdded = counters.ghostsDropped = 0;
    counters.unclaimed = 0;
    unclaimed.clear();
    if (P == 1)
    {
        // one rank owns everything: no migration, no ghost; a grain outside
        // the region (a local owner function) is reported
        for (int i = 0; i < int(owned.size()); ++i)
            if (checkedOwner(sys.positions()[i], gid[i]) == notHere) unclaimed.push_back(i);
        counters.unclaimed = long(unclaimed.size());
        return;
    }
    // 1. migration: owned grains whose centre left the region go to their
    // owner; here they stay as ghosts (with their contacts) until the ghost
    // refresh below keeps or drops them. The contacts the new owner will
    // solve (the grain's walls, and its grain pairs where it has the smaller
    // id) go with it, so that their warm start is not lost: a contact of a
    // deep bed restarted from zero costs the solve the sweeps that carry the
    // weight of the grains above it down again.
    const int N0 = int(owned.size());
    std::vector<std::vector<GrainRecord>> send(P), recv;
    std::vector<std::vector<ContactRecord>> sendC(P), recvC;
    std::vector<int> dest(N0, -1);
    std::vector<int> leaving;  // owner unknown here (a local owner function)
    for (int i = 0; i < N0; ++i)
    {
        if (!owned[i]) continue;
        const int r = checkedOwner(sys.positions()[i], gid[i]);
        if (r == notHere) leaving.push_back(i);
        else if (r != rank) dest[i] = r;
    }
    const std::vector<int> claimed = claimLeavers(leaving);
    for (std::size_t k = 0; k < leaving.size(); ++k)
    {
        if (claimed[k] < 0) unclaimed.push_back(leaving[k]);
        else dest[leaving[k]] = claimed[k];
    }
    counters.unclaimed = long(unclaimed.size());
    bool any = false;
    for (int i = 0; i < N0; ++i)
    {
        if (dest[i] < 0) continue;
        send[dest[i]].push_back(record(i));
        owned[i] = 0;
        any = true;
        ++counters.migratedOut;
    }
    if (any)
        for (const System::ContactView& c : sys.contacts())
        {
            // as seen from grain a (the migrant): partner b (grain id, or a wall -(w+1))
            for (int side = 0; side < 2; ++side)
            {
                const int a = side == 0 ? c.i : c.j;
                const int b = side == 0 ? c.j : c.i;
                if (a < 0 || dest[a] < 0) continue;
                if (b >= 0 && !(gid[a] < gid[b])) continue;  // the partner's owner keeps it
                ContactRecord k;
                k.grain = gid[a];
                k.partner = b >= 0 ? gid[b] : long(b);
                const double sgn = side == 0 ? 1.0 : -1.0;
                put(k.n, sgn*c.normal);
                put(k.impulse, sgn*c.impulse);
                k.age = c.age;
                sendC[dest[a]].push_back(k);
            }
        }
    counters.bytesSent += exchangeLists(comm, TagRecords, send, recv);
    counters.bytesSent += exchangeLists(comm, TagContacts, sendC, recvC);
    {
        std::unordered_map<long, int> local;  // the ghosts here (a migrant may be one)
        for (int i = 0; i < int(gid.size()); ++i) if (!owned[i]) local[gid[i]] = i;
        for (int r = 0; r < P; ++r)
            for (const GrainRecord& g : recv[r])
            {
                auto it = local.find(g.id);  // a ghost here becomes owned (keeps its contacts)
                place(it == local.end() ? -1 : it->second, g, true);
            }
    }

    // 2. ghosts: owned grains within halo of another rank's owned box
    const int N = int(owned.size());
    double box[6] = {1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
    for (int i = 0; i < N; ++i)
        if (owned[i])
            for (int k = 0; k < 3; ++k)
            {
                box[k] = std::min(box[k], sys.positions()[i][k]);
                box[3 + k] = std::max(box[3 + k], sys.positions()[i][k]);
            }
    for (int k = 0; k < 3; ++k)
        if (regionLo[k] <= regionHi[k])
        {
            box[k] = std::min(box[k], regionLo[k]);
            box[3 + k] = std::max(box[3 + k], regionHi[k]);
        }
    std::vector<double> boxes(6*P);
    MPI_Allgather(box, 6, MPI_DOUBLE, boxes.data(), 6, MPI_DOUBLE, comm);
    sendTo.assign(P, {});
    send.assign(P, {});
    const double h2 = halo*halo;
    for (int i = 0; i < N; ++i)
    {
        if (!owned[i]) continue;
        const Vec3& x = sys.positions()[i];
        for (int r = 0; r < P; ++r)
        {
            if (r == rank) continue;
            const double* b = &boxes[6*r];
            if (distance2(x, Vec3(b[0], b[1], b[2]), Vec3(b[3], b[4], b[5])) > h2) continue;
            sendTo[r].push_back(i);
            send[r].push_back(record(i));
            ++counters.ghostsSent;
        }
    }
    counters.bytesSent += exchangeLists(comm, TagRecords, send, recv);
    std::unordered_map<long, int> local;  // the ghosts here (refreshed in place)
    for (int i = 0; i < N; ++i) if (!owned[i]) local[gid[i]] = i;
    std::vector<char> keep(N, 0);
    for (int i = 0; i < N; ++i) keep[i] = owned[i];
    ghostFrom.assign(P, {});
    for (int r = 0; r < P; ++r)
        for (const GrainRecord& g : recv[r])
        {
            auto it = local.find(g.id);
            const int i = place(it == local.end() ? -1 : it->second, g, false);
            if (i >= N) { keep.push_back(1); ++counters.ghostsAdded; } else keep[i] = 1;
            ghostFrom[r].push_back(i);
        }
    // ghosts not refreshed are dropped; the indices kept shift down
    std::vector<char> drop2(keep.size());
    std::vector<int> newIndex(keep.size(), -1);
    int n = 0;
    for (std::size_t i = 0; i < keep.size(); ++i)
    {
        drop2[i] = !keep[i];
        counters.ghostsDropped += drop2[i];
        if (keep[i]) newIndex[i] = n++;
    }
    removeFlagged(drop2);
    for (auto& L : ghostFrom) for (int& i : L) i = newIndex[i];
    for (auto& L : sendTo) for (int& i : L) i = newIndex[i];
    for (int& i : unclaimed) i = newIndex[i];  // owned: kept
    seedMigratedContacts(recvC);
}

std::vector<int> DecomposedSystem::Impl::claimLeavers(const std::vector<int>& leaving)
{
    struct Leaver { double x[3]; long id; };
    std::vector<Leaver> mine(leaving.size());
    for (std::size_t k = 0; k < leaving.size(); ++k)
    {
        put(mine[k].x, sys.positions()[leaving[k]]);
        mine[k].id = gid[leaving[k]];
    }
    const int n = int(mine.size()*sizeof(Leaver));
    std::vector<int> bytes(P), offs(P, 0);
    MPI_Allgather(&n, 1, MPI_INT, bytes.data(), 1, MPI_INT, comm);
    std::partial_sum(bytes.begin(), bytes.end() - 1, offs.begin() + 1);
    const std::size_t total = std::size_t(offs.back() + bytes.back())/sizeof(Leaver);
    if (total == 0) return {};
    std::vector<Leaver> all(total);
    MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), bytes.data(), offs.data(), MPI_BYTE, comm);
    counters.bytesSent += long(n)*(P - 1);
    const std::size_t first = std::size_t(offs[rank])/sizeof(Leaver);
    std::vector<int> claim(total, std::numeric_limits<int>::max());
    for (std::size_t k = 0; k < total; ++k)
    {
        if (k >= first && k < first + mine.size()) continue;  // not in this region: asked already
        if (checkedOwner(get(all[k].x), all[k].id) == rank) claim[k] = rank;
    }
    MPI_Allreduce(MPI_IN_PLACE, claim.data(), int(total), MPI_INT, MPI_MIN, comm);
    std::vector<int> out(mine.size());
    for (std::size_t k = 0; k < mine.size(); ++k)
        out[k] = claim[first + k] == std::numeric_limits<int>::max() ? -1 : claim[first + k];
    return out;
}

void DecomposedSystem::Impl::seedMigratedContacts(const std::vector<std::vector<ContactRecord>>& recvC)
{
    std::size_t n = 0;
    for (const auto& L : recvC) n += L.size();
    if (n == 0 || !(sys.lastStepDt() > 0)) return;
    std::unordered_map<long, int> local;
    for (int i = 0; i < int(gid.size()); ++i) local[gid[i]] = i;
    std::vector<System::ContactView> views = sys.contacts();
    auto key = [](int i, int j)  // a pair either way round (j < 0: a wall)
    {
        if (j >= 0 && j < i) std::swap(i, j);
        return (static_cast<unsigned long long>(unsigned(i)) << 32) | unsigned(j);
    };
    std::unordered_set<unsigned long long> known;  // the pairs with a record here already
    for (const System::ContactView& c : views) known.insert(key(c.i, c.j));
    for (const auto& L : recvC)
        for (const ContactRecord& k : L)
        {
            auto a = local.find(k.grain);
            if (a == local.end()) continue;
            int b = int(k.partner);
            if (k.partner >= 0)
            {
                auto it = local.find(k.partner);
                if (it == local.end()) continue;  // the partner is not within the halo any more
                b = it->second;
            }
            if (!known.insert(key(a->second, b)).second) continue;
            System::ContactView c;
            c.point = Vec3::Zero();
            c.gap = 0;
            c.cohesive = false;
            c.i = a->second;
            c.j = b;
            c.normal = get(k.n);
            c.impulse = get(k.impulse);
            c.age = k.age;
            views.push_back(c);
        }
    sys.setContactImpulses(views, sys.lastStepDt());
}

DecomposedSystem::DecomposedSystem(int dimension, MPI_Comm comm, OwnerFunction ownerOf, double halo)
: impl_(std::make_unique<Impl>(dimension))
{
    impl_->init(comm, std::move(ownerOf), halo);
}

DecomposedSystem::DecomposedSystem(System&& whole, MPI_Comm comm, OwnerFunction ownerOf, double halo)
: impl_(std::make_unique<Impl>(std::move(whole)))
{
    Impl& I = *impl_;
    I.init(comm, std::move(ownerOf), halo);
    const std::size_t N = I.sys.size();
    I.gid = I.sys.grainIds();
    I.owned.assign(N, 1);
    I.lambda.assign(2*N, Vec3::Zero());
    // keep the grains owned here and those that will be ghosts here (within
    // halo of the owned centres' box), with the contacts among them: the
    // contact impulses warm-start the first step, at the interfaces too
    // (exchange() then refreshes the ghosts in place)
    // owner: the lowest rank that claims the centre
    std::vector<int> claim(N, std::numeric_limits<int>::max());
    for (std::size_t i = 0; i < N; ++i)
        if (I.checkedOwner(I.sys.positions()[i], I.gid[i]) == I.rank) claim[i] = I.rank;
    if (N > 0) MPI_Allreduce(MPI_IN_PLACE, claim.data(), int(N), MPI_INT, MPI_MIN, I.comm);
    std::string lost;
    int nLost = 0;
    for (std::size_t i = 0; i < N; ++i)
        if (claim[i] == std::numeric_limits<int>::max() && nLost++ < 5)
        {
            const Vec3& x = I.sys.positions()[i];
            lost += "\n    grain " + std::to_string(I.gid[i]) + " at (" + std::to_string(x.x()) + ", "
                  + std::to_string(x.y()) + ", " + std::to_string(x.z()) + ")";
        }
    if (nLost > 0)
        throw InputError("nscd::mpi::DecomposedSystem: " + std::to_string(nLost)
                         + " grain(s) in no rank's region (outside the domain?):" + lost);
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (std::size_t i = 0; i < N; ++i)
    {
        const Vec3& x = I.sys.positions()[i];
        I.owned[i] = claim[i] == I.rank;
        if (I.owned[i]) { lo = lo.cwiseMin(x); hi = hi.cwiseMax(x); }
    }
    std::vector<char> drop(N, 0);
    for (std::size_t i = 0; i < N; ++i)
        drop[i] = !I.owned[i] && distance2(I.sys.positions()[i], lo, hi) > I.halo*I.halo;
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

const std::vector<int>& DecomposedSystem::unclaimed() const { return impl_->unclaimed; }

void DecomposedSystem::setRegionBox(const Vec3& lo, const Vec3& hi)
{
    impl_->regionLo = lo;
    impl_->regionHi = hi;
}

void DecomposedSystem::sumToOwners(std::vector<double>& values, int components)
{
    Impl& I = *impl_;
    // checked on every rank (one refusing alone would leave the others waiting)
    int bad = components < 1 || values.size() != std::size_t(components)*I.sys.size();
    MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, I.comm);
    if (bad)
        throw InputError("nscd::mpi::DecomposedSystem::sumToOwners: " + std::to_string(values.size())
                         + " values for " + std::to_string(I.sys.size()) + " grains of "
                         + std::to_string(components) + " components here, or a size mismatch on another rank");
    if (I.P == 1) return;
    // a ghost list of this rank is aligned with its owner's send list
    std::vector<std::vector<double>> send(I.P), recv(I.P);
    for (int r = 0; r < I.P; ++r)
    {
        for (int i : I.ghostFrom[r])
            send[r].insert(send[r].end(), values.begin() + std::ptrdiff_t(i)*components,
                           values.begin() + std::ptrdiff_t(i + 1)*components);
        recv[r].resize(I.sendTo[r].size()*std::size_t(components));
    }
    exchangeKnown(I.comm, TagSums, send, recv);
    for (int r = 0; r < I.P; ++r)
        for (std::size_t k = 0; k < I.sendTo[r].size(); ++k)
            for (int c = 0; c < components; ++c)
                values[std::size_t(I.sendTo[r][k])*components + c] += recv[r][k*components + c];
}

std::unique_ptr<System> DecomposedSystem::gatherWhole(int root) const
{
    const Impl& I = *impl_;
    // this rank's owned grains, and the contacts it solves (a grain pair:
    // the owner of the smaller id; a wall: the grain's owner)
    std::vector<GrainRecord> grains;
    for (int i = 0; i < int(I.owned.size()); ++i)
        if (I.owned[i]) grains.push_back(I.record(i));
    std::vector<ContactRecord> contacts;
    for (const System::ContactView& c : I.sys.contacts())
    {
        const bool mine = c.j < 0 ? bool(I.owned[c.i])
                                  : bool(I.owned[I.gid[c.i] < I.gid[c.j] ? c.i : c.j]);
        if (!mine) continue;
        ContactRecord k;
        k.grain = I.gid[c.i];
        k.partner = c.j >= 0 ? I.gid[c.j] : long(c.j);
        put(k.n, c.normal);
        put(k.impulse, c.impulse);
        k.age = c.age;
        contacts.push_back(k);
    }
    auto gather = [&](const auto& mine, auto& all)
    {
        using T = typename std::decay_t<decltype(mine)>::value_type;
        const int n = int(mine.size()*sizeof(T));
        std::vector<int> bytes(I.P), offs(I.P, 0);
        MPI_Gather(&n, 1, MPI_INT, bytes.data(), 1, MPI_INT, root, I.comm);
        if (I.rank == root)
        {
            std::partial_sum(bytes.begin(), bytes.end() - 1, offs.begin() + 1);
            all.resize(std::size_t(offs.back() + bytes.back())/sizeof(T));
        }
        MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), bytes.data(), offs.data(), MPI_BYTE, root, I.comm);
    };
    std::vector<GrainRecord> allGrains;
    std::vector<ContactRecord> allContacts;
    gather(grains, allGrains);
    gather(contacts, allContacts);
    if (I.rank != root) return nullptr;

    std::sort(allGrains.begin(), allGrains.end(),
              [](const GrainRecord& a, const GrainRecord& b) { return a.id < b.id; });
    auto whole = std::make_unique<System>(Subdomain::withoutGrains(I.sys));
    struct NoCoupling : SubdomainCoupling
    {
        double maxOverSubdomains(double v) override { return v; }
        void countCopies(const std::vector<char>& in, std::vector<int>& out) override { out.assign(in.size(), 1); }
        void averageCopies(std::vector<Vec3>&, std::vector<Vec3>&) override {}
    } none;
    Subdomain access(*whole, none);
    std::unordered_map<long, int> index;
    for (const GrainRecord& g : allGrains)
    {
        const std::size_t i = std::size_t(whole->addGrain(get(g.x), g.radius, g.material, g.flags & 1));
        whole->setRotationLocked(i, g.flags & 2);
        access.setState(i, stateOf(g));
        access.setGrainId(i, g.id);
        index[g.id] = int(i);
    }
    if (I.sys.lastStepDt() > 0 && !allContacts.empty())
    {
        std::vector<System::ContactView> views;
        views.reserve(allContacts.size());
        for (const ContactRecord& k : allContacts)
        {
            System::ContactView c;
            c.point = Vec3::Zero();
            c.gap = 0;
            c.cohesive = false;
            c.i = index.at(k.grain);
            c.j = k.partner >= 0 ? index.at(k.partner) : int(k.partner);
            c.normal = get(k.n);
            c.impulse = get(k.impulse);
            c.age = k.age;
            views.push_back(c);
        }
        whole->setContactImpulses(views, I.sys.lastStepDt());
    }
    return whole;
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
    I.lambda.resize(2*I.gid.size(), Vec3::Zero());
    return i;
}

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
        const StepReport rep = I.sub.step(dt, I.owned, I.gid, I.lambda);
        I.exchange();
        return rep;
    }
    catch (const InputError&)
    {
        throw;  // refused by the collective input check: every rank throws it
    }
    catch (const std::exception& e)
    {
        I.abortAll("step", e);
    }
}

} // namespace mpi
} // namespace nscd
