// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::mpi::DecomposedSystem: values of the ghosts summed to their owners,
// and the whole system gathered on one rank (for writing a state).
#include "DecomposedSystemImpl.H"

#include <algorithm>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace nscd
{
namespace mpi
{
namespace
{
/// components doubles per local grain, checked on every rank (one refusing
/// alone would leave the others waiting); InputError naming the function
void checkGrainValues(const DecomposedSystem::Impl& I, const char* function,
                      const std::vector<double>& values, int components)
{
    int bad = components < 1 || values.size() != std::size_t(components) * I.sys.size();
    MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, I.comm);
    if (bad)
        throw InputError(std::string("nscd::mpi::DecomposedSystem::") + function + ": "
                         + std::to_string(values.size()) + " values for " + std::to_string(I.sys.size())
                         + " grains of " + std::to_string(components)
                         + " components here, or a size mismatch on another rank");
}

/// Send the values of the grains of from[r] to each rank r, which receives
/// them for its grains of to[r] (the lists of the two sides aligned: ghosts
/// and their owners' send lists) and applies combine(value here, received).
template <class Combine>
void passAlong(const DecomposedSystem::Impl& I, const std::vector<std::vector<int>>& from,
               const std::vector<std::vector<int>>& to, std::vector<double>& values, int components, int tag,
               Combine combine)
{
    std::vector<std::vector<double>> send(I.P), recv(I.P);
    for (int r = 0; r < I.P; ++r)
    {
        for (int i : from[r])
            send[r].insert(send[r].end(), values.begin() + std::ptrdiff_t(i) * components,
                           values.begin() + std::ptrdiff_t(i + 1) * components);
        recv[r].resize(to[r].size() * std::size_t(components));
    }
    exchangeKnown(I.comm, tag, send, recv);
    for (int r = 0; r < I.P; ++r)
        for (std::size_t k = 0; k < to[r].size(); ++k)
            for (int c = 0; c < components; ++c)
                combine(values[std::size_t(to[r][k]) * components + c], recv[r][k * components + c]);
}
} // namespace

void DecomposedSystem::sumToOwners(std::vector<double>& values, int components)
{
    Impl& I = *impl_;
    checkGrainValues(I, "sumToOwners", values, components);
    if (I.P == 1) return;
    passAlong(I, I.ghostFrom, I.sendTo, values, components, TagSums, [](double& v, double got) { v += got; });
}

void DecomposedSystem::copyToGhosts(std::vector<double>& values, int components)
{
    Impl& I = *impl_;
    checkGrainValues(I, "copyToGhosts", values, components);
    if (I.P == 1) return;
    passAlong(I, I.sendTo, I.ghostFrom, values, components, TagGhostValues,
              [](double& v, double got) { v = got; });
}

double DecomposedSystem::Impl::sumOverSubdomains(double value)
{
    CpuTimer t(counters.solveCommCpuSeconds);
    double out = value;
    MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_SUM, comm);
    return out;
}

void DecomposedSystem::Impl::weightedMeanOverSubdomains(std::vector<double>& values,
                                                        const std::vector<double>& weights)
{
    CpuTimer t(counters.solveCommCpuSeconds);
    const std::size_t n = values.size();
    if (P == 1 || n == 0) return;
    // every rank's (w v, w) gathered and summed in rank order: the same bits everywhere
    std::vector<double> mine(2 * n), all(2 * n * std::size_t(P));
    for (std::size_t j = 0; j < n; ++j)
    {
        mine[2 * j] = weights[j] * values[j];
        mine[2 * j + 1] = weights[j];
    }
    MPI_Allgather(mine.data(), int(2 * n), MPI_DOUBLE, all.data(), int(2 * n), MPI_DOUBLE, comm);
    counters.bytesSent += long(2 * n * sizeof(double)) * (P - 1);
    for (std::size_t j = 0; j < n; ++j)
    {
        double wv = 0, w = 0;
        for (int r = 0; r < P; ++r)
        {
            wv += all[2 * n * std::size_t(r) + 2 * j];
            w += all[2 * n * std::size_t(r) + 2 * j + 1];
        }
        if (w > 0) values[j] = wv / w;
    }
}

void DecomposedSystem::Impl::sumGhostsToOwners(std::vector<double>& values)
{
    CpuTimer t(counters.solveCommCpuSeconds);
    if (P == 1) return;
    passAlong(*this, ghostFrom, sendTo, values, 1, TagSums, [](double& v, double got) { v += got; });
}

void DecomposedSystem::Impl::copyOwnersToGhosts(std::vector<double>& values)
{
    CpuTimer t(counters.solveCommCpuSeconds);
    if (P == 1) return;
    passAlong(*this, sendTo, ghostFrom, values, 1, TagGhostValues, [](double& v, double got) { v = got; });
}

std::vector<ContactRecord> DecomposedSystem::Impl::solvedContacts() const
{
    // a grain pair: the owner of the smaller id; a wall: the grain's owner
    std::vector<ContactRecord> contacts;
    for (const System::ContactView& c : sys.contacts())
    {
        const bool mine = c.j < 0 ? bool(owned[c.i]) : bool(owned[gid[c.i] < gid[c.j] ? c.i : c.j]);
        if (!mine) continue;
        ContactRecord k;
        k.grain = gid[c.i];
        k.partner = c.j >= 0 ? gid[c.j] : long(c.j);
        put(k.n, c.normal);
        put(k.impulse, c.impulse);
        k.age = c.age;
        contacts.push_back(k);
    }
    return contacts;
}

std::unique_ptr<System> DecomposedSystem::Impl::systemOf(const std::vector<char>& records,
                                                         const std::vector<ContactRecord>& contacts) const
{
    const std::size_t bytes = recordBytes(ColumnMigrate);
    auto whole = std::make_unique<System>(Subdomain::withoutGrains(sys));
    struct NoCoupling : SubdomainCoupling
    {
        double maxOverSubdomains(double v) override { return v; }
        void countCopies(const std::vector<char>& in, std::vector<int>& out) override
        {
            out.assign(in.size(), 1);
        }
        void averageCopies(std::vector<Vec3>&, std::vector<Vec3>&) override {}
    } none;
    Subdomain access(*whole, none);
    std::unordered_map<long, int> index;
    for (std::size_t k = 0; k < records.size() / bytes; ++k)
    {
        const char* g = &records[k * bytes];
        const std::size_t i = access.addGrain(ColumnMigrate, g + sizeof(long));
        access.setGrainId(i, recordId(g));
        index[recordId(g)] = int(i);
    }
    if (sys.lastStepDt() > 0 && !contacts.empty())
    {
        std::vector<System::ContactView> views;
        views.reserve(contacts.size());
        for (const ContactRecord& k : contacts)
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
        whole->setContactImpulses(views, sys.lastStepDt());
    }
    return whole;
}

std::unique_ptr<System> DecomposedSystem::gatherWhole(int root) const
{
    const Impl& I = *impl_;
    // this rank's owned grains (records of every migrating column) and the
    // contacts it solves
    const std::size_t bytes = I.recordBytes(ColumnMigrate);
    std::vector<char> grains;
    for (int i = 0; i < int(I.owned.size()); ++i)
        if (I.owned[i]) I.appendRecord(i, ColumnMigrate, grains);
    const std::vector<ContactRecord> contacts = I.solvedContacts();
    auto gather = [&](const auto& mine, auto& all)
    {
        using T = typename std::decay_t<decltype(mine)>::value_type;
        const int n = int(mine.size() * sizeof(T));
        std::vector<int> bytes(I.P), offs(I.P, 0);
        MPI_Gather(&n, 1, MPI_INT, bytes.data(), 1, MPI_INT, root, I.comm);
        if (I.rank == root)
        {
            std::partial_sum(bytes.begin(), bytes.end() - 1, offs.begin() + 1);
            all.resize(std::size_t(offs.back() + bytes.back()) / sizeof(T));
        }
        MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), bytes.data(), offs.data(), MPI_BYTE, root, I.comm);
    };
    std::vector<char> allGrains;
    std::vector<ContactRecord> allContacts;
    gather(grains, allGrains);
    gather(contacts, allContacts);
    if (I.rank != root) return nullptr;

    std::vector<std::pair<long, std::size_t>> byId(allGrains.size() / bytes); // (id, record)
    for (std::size_t k = 0; k < byId.size(); ++k) byId[k] = {recordId(&allGrains[k * bytes]), k};
    std::sort(byId.begin(), byId.end());
    std::vector<char> sorted(allGrains.size());
    for (std::size_t k = 0; k < byId.size(); ++k)
        std::copy_n(&allGrains[byId[k].second * bytes], bytes, &sorted[k * bytes]);
    allGrains.clear();
    allGrains.shrink_to_fit();
    return I.systemOf(sorted, allContacts);
}

System::StatePart DecomposedSystem::statePart(long& nextId) const
{
    Impl& I = *impl_;
    // owned grains in ascending id: rows first, first + 1, ... of the whole
    std::vector<std::pair<long, std::size_t>> mine; // (id, local index)
    for (std::size_t i = 0; i < I.owned.size(); ++i)
        if (I.owned[i]) mine.emplace_back(I.gid[i], i);
    std::sort(mine.begin(), mine.end());
    long n = long(mine.size());
    std::vector<long> counts(I.P);
    MPI_Allgather(&n, 1, MPI_LONG, counts.data(), 1, MPI_LONG, I.comm);
    System::StatePart part;
    part.written = mine.size();
    part.first = std::accumulate(counts.begin(), counts.begin() + I.rank, 0L);
    part.nGrains = std::accumulate(counts.begin(), counts.end(), 0L);
    nextId = I.sys.nextGrainId();
    MPI_Allreduce(MPI_IN_PLACE, &nextId, 1, MPI_LONG, MPI_MAX, I.comm);
    // the rows of the ghosts, from their owners (exact in a double below 2^53)
    std::vector<double> rows(I.sys.size(), -1.0);
    for (std::size_t k = 0; k < mine.size(); ++k) rows[mine[k].second] = double(part.first + long(k));
    I.copyOwnersToGhosts(rows);
    part.rows.reserve(mine.size());
    for (const auto& g : mine) part.rows.push_back(g.second);
    part.rowOf.assign(rows.begin(), rows.end());
    return part;
}

} // namespace mpi
} // namespace nscd
