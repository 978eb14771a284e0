// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::mpi::DecomposedSystem: migration of the grains that left a rank's
// region (their owner found by asking every rank when the owner function is
// local), the ghost refresh, and the warm start of migrated contacts.
#include "DecomposedSystemImpl.H"

#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace nscd
{
namespace mpi
{

void DecomposedSystem::Impl::exchange()
{
    CpuTimer t(counters.exchangeCpuSeconds);
    counters.migratedOut = counters.ghostsSent = counters.ghostsAdded = counters.ghostsDropped = 0;
    counters.renumbered = 0;
    counters.unclaimed = 0;
    unclaimed.clear();
    if (P == 1)
    {
        // one rank owns everything: no migration, no ghost; a grain outside
        // the region (a local owner function) is reported
        for (int i = 0; i < int(owned.size()); ++i)
            if (checkedOwner(sys.positions()[i], gid[i]) == notHere) unclaimed.push_back(i);
        counters.unclaimed = long(unclaimed.size());
        renumberAlongSlots();
        return;
    }
    const std::vector<std::vector<ContactRecord>> contacts = migrate();
    refreshGhosts();
    seedMigratedContacts(contacts);
    renumberAlongSlots();
}

std::vector<int> DecomposedSystem::Impl::migrationDestinations()
{
    const int N0 = int(owned.size());
    std::vector<int> dest(N0, -1);
    std::vector<int> leaving; // owner unknown here (a local owner function)
    for (int i = 0; i < N0; ++i)
    {
        if (!owned[i]) continue;
        const int r = checkedOwner(sys.positions()[i], gid[i]);
        if (r == notHere)
            leaving.push_back(i);
        else if (r != rank)
            dest[i] = r;
    }
    const std::vector<int> claimed = claimLeavers(leaving);
    for (std::size_t k = 0; k < leaving.size(); ++k)
    {
        if (claimed[k] < 0)
            unclaimed.push_back(leaving[k]);
        else
            dest[leaving[k]] = claimed[k];
    }
    counters.unclaimed = long(unclaimed.size());
    return dest;
}

void DecomposedSystem::Impl::migratingContacts(const std::vector<int>& dest,
                                               std::vector<std::vector<ContactRecord>>& sendC) const
{
    for (const System::ContactView& c : sys.contacts())
    {
        // as seen from grain a (the migrant): partner b (grain id, or a wall -(w+1))
        for (int side = 0; side < 2; ++side)
        {
            const int a = side == 0 ? c.i : c.j;
            const int b = side == 0 ? c.j : c.i;
            if (a < 0 || dest[a] < 0) continue;
            if (b >= 0 && !(gid[a] < gid[b])) continue; // the partner's owner keeps it
            ContactRecord k;
            k.grain = gid[a];
            k.partner = b >= 0 ? gid[b] : long(b);
            const double sgn = side == 0 ? 1.0 : -1.0;
            put(k.n, sgn * c.normal);
            put(k.impulse, sgn * c.impulse);
            k.age = c.age;
            sendC[dest[a]].push_back(k);
        }
    }
}

std::vector<std::vector<ContactRecord>> DecomposedSystem::Impl::migrate()
{
    const std::vector<int> dest = migrationDestinations();
    const std::size_t bytes = recordBytes(ColumnMigrate);
    std::vector<std::vector<char>> send(P), recv;
    std::vector<std::vector<double>> sendD(P), recvD;
    std::vector<std::vector<ContactRecord>> sendC(P), recvC;
    bool any = false;
    for (int i = 0; i < int(dest.size()); ++i)
    {
        if (dest[i] < 0) continue;
        appendRecord(i, ColumnMigrate, send[dest[i]]);
        appendData(i, sendD[dest[i]]);
        owned[i] = 0;
        any = true;
        ++counters.migratedOut;
    }
    if (any) migratingContacts(dest, sendC);
    counters.bytesSent += exchangeLists(comm, TagRecords, send, recv);
    counters.bytesSent += exchangeData(sendD, recv, bytes, recvD);
    counters.bytesSent += exchangeLists(comm, TagContacts, sendC, recvC);
    std::unordered_map<long, int> local; // the ghosts here (a migrant may be one)
    for (int i = 0; i < int(gid.size()); ++i)
        if (!owned[i]) local[gid[i]] = i;
    for (int r = 0; r < P; ++r)
        for (std::size_t k = 0; k < recv[r].size() / bytes; ++k)
        {
            const char* g = recv[r].data() + k * bytes;
            auto it = local.find(recordId(g)); // a ghost here becomes owned (keeps its contacts)
            place(it == local.end() ? -1 : it->second, g, ColumnMigrate,
                  recvD[r].data() + k * std::size_t(travelWidth()), true);
        }
    return recvC;
}

std::vector<double> DecomposedSystem::Impl::ownedBoxes() const
{
    double box[6] = {1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
    for (int i = 0; i < int(owned.size()); ++i)
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
    std::vector<double> boxes(6 * P);
    MPI_Allgather(box, 6, MPI_DOUBLE, boxes.data(), 6, MPI_DOUBLE, comm);
    return boxes;
}

void DecomposedSystem::Impl::refreshGhosts()
{
    const int N = int(owned.size());
    const std::vector<double> boxes = ownedBoxes();
    std::vector<std::vector<char>> send(P), recv;
    std::vector<std::vector<double>> sendD(P), recvD;
    sendTo.assign(P, {});
    const std::size_t bytes = recordBytes(ColumnGhost);
    const double h2 = halo * halo;
    for (int i = 0; i < N; ++i)
    {
        if (!owned[i]) continue;
        const Vec3& x = sys.positions()[i];
        for (int r = 0; r < P; ++r)
        {
            if (r == rank) continue;
            const double* b = &boxes[6 * r];
            if (distance2(x, Vec3(b[0], b[1], b[2]), Vec3(b[3], b[4], b[5])) > h2) continue;
            sendTo[r].push_back(i);
            appendRecord(i, ColumnGhost, send[r]);
            appendData(i, sendD[r]);
            ++counters.ghostsSent;
        }
    }
    counters.bytesSent += exchangeLists(comm, TagRecords, send, recv);
    counters.bytesSent += exchangeData(sendD, recv, bytes, recvD);
    std::unordered_map<long, int> local; // the ghosts here (refreshed in place)
    for (int i = 0; i < N; ++i)
        if (!owned[i]) local[gid[i]] = i;
    std::vector<char> keep(N, 0);
    for (int i = 0; i < N; ++i) keep[i] = owned[i];
    ghostFrom.assign(P, {});
    for (int r = 0; r < P; ++r)
        for (std::size_t k = 0; k < recv[r].size() / bytes; ++k)
        {
            const char* g = recv[r].data() + k * bytes;
            auto it = local.find(recordId(g));
            const int i = place(it == local.end() ? -1 : it->second, g, ColumnGhost,
                                recvD[r].data() + k * std::size_t(travelWidth()), false);
            if (i >= N)
            {
                keep.push_back(1);
                ++counters.ghostsAdded;
            }
            else
                keep[i] = 1;
            ghostFrom[r].push_back(i);
        }
    dropStaleGhosts(keep);
}

void DecomposedSystem::Impl::dropStaleGhosts(const std::vector<char>& keep)
{
    std::vector<char> drop(keep.size());
    std::vector<int> newIndex(keep.size(), -1);
    int n = 0;
    for (std::size_t i = 0; i < keep.size(); ++i)
    {
        drop[i] = !keep[i];
        counters.ghostsDropped += drop[i];
        if (keep[i]) newIndex[i] = n++;
    }
    removeFlagged(drop);
    for (auto& L : ghostFrom)
        for (int& i : L) i = newIndex[i];
    for (auto& L : sendTo)
        for (int& i : L) i = newIndex[i];
    for (int& i : unclaimed) i = newIndex[i]; // owned: kept
}

std::vector<std::size_t> DecomposedSystem::Impl::removeOwned(const std::vector<std::size_t>& indices)
{
    const std::size_t N = owned.size();
    std::vector<char> drop(N, 0);
    for (std::size_t i : indices)
    {
        if (i >= N || !owned[i])
            throw InputError("nscd::mpi::DecomposedSystem::removeOwned: local grain " + std::to_string(i)
                             + (i >= N ? " out of range" : " is a ghost here (remove it on its owner)"));
        drop[i] = 1;
    }
    // the ranks holding a ghost of a removed grain (its send lists) drop it
    std::vector<std::vector<long>> send(P), recv(P);
    for (int r = 0; r < P; ++r)
        for (int i : sendTo[r])
            if (drop[i]) send[r].push_back(gid[i]);
    if (P > 1) counters.bytesSent += exchangeLists(comm, TagRemoved, send, recv);
    std::unordered_set<long> gone;
    for (const auto& L : recv) gone.insert(L.begin(), L.end());
    for (int r = 0; r < P && !gone.empty(); ++r)
        for (int i : ghostFrom[r])
            if (gone.count(gid[i])) drop[i] = 1;
    std::vector<int> newIndex(N, -1);
    std::vector<std::size_t> removed;
    int n = 0;
    for (std::size_t i = 0; i < N; ++i)
    {
        if (drop[i])
            removed.push_back(i);
        else
            newIndex[i] = n++;
    }
    removeFlagged(drop);
    // the lists keep the remaining grains in their order (the two sides of
    // each ghost list stay aligned)
    auto remap = [&newIndex](std::vector<int>& L)
    {
        std::size_t m = 0;
        for (int i : L)
            if (newIndex[i] >= 0) L[m++] = newIndex[i];
        L.resize(m);
    };
    for (auto& L : ghostFrom) remap(L);
    for (auto& L : sendTo) remap(L);
    remap(unclaimed);
    counters.unclaimed = long(unclaimed.size());
    // (the last solve's interface lists: rebuilt by the next step)
    ifaceGhost.assign(P, {});
    ifaceOwned.assign(P, {});
    ownedShared.clear();
    copies.clear();
    return removed;
}

std::vector<int> DecomposedSystem::Impl::claimLeavers(const std::vector<int>& leaving)
{
    struct Leaver
    {
        double x[3];
        long id;
    };
    std::vector<Leaver> mine(leaving.size());
    for (std::size_t k = 0; k < leaving.size(); ++k)
    {
        put(mine[k].x, sys.positions()[leaving[k]]);
        mine[k].id = gid[leaving[k]];
    }
    const int n = int(mine.size() * sizeof(Leaver));
    std::vector<int> bytes(P), offs(P, 0);
    MPI_Allgather(&n, 1, MPI_INT, bytes.data(), 1, MPI_INT, comm);
    std::partial_sum(bytes.begin(), bytes.end() - 1, offs.begin() + 1);
    const std::size_t total = std::size_t(offs.back() + bytes.back()) / sizeof(Leaver);
    if (total == 0) return {};
    std::vector<Leaver> all(total);
    MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), bytes.data(), offs.data(), MPI_BYTE, comm);
    counters.bytesSent += long(n) * (P - 1);
    const std::size_t first = std::size_t(offs[rank]) / sizeof(Leaver);
    std::vector<int> claim(total, std::numeric_limits<int>::max());
    for (std::size_t k = 0; k < total; ++k)
    {
        if (k >= first && k < first + mine.size()) continue; // not in this region: asked already
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
    auto key = [](int i, int j) // a pair either way round (j < 0: a wall)
    {
        if (j >= 0 && j < i) std::swap(i, j);
        return (static_cast<unsigned long long>(unsigned(i)) << 32) | unsigned(j);
    };
    std::unordered_set<unsigned long long> known; // the pairs with a record here already
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
                if (it == local.end()) continue; // the partner is not within the halo any more
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

} // namespace mpi
} // namespace nscd
