// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::System::removeGrains: grains leaving the system (e.g. through an
// outlet of the fluid domain), with their per-grain state and contacts.
#include "SystemImpl.H"

#include <algorithm>
#include <iterator>
#include <sstream>

namespace nscd
{

std::vector<std::size_t> System::removeGrains(const std::vector<std::size_t>& indices)
{
    Impl& I = *impl_;
    const std::size_t N = I.x.size();
    std::vector<std::size_t> sorted(indices);
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k)
    {
        if (sorted[k] >= N)
        {
            std::ostringstream os;
            os << "nscd::System::removeGrains: grain " << sorted[k] << " does not exist (" << N << " grains)";
            throw InputError(os.str());
        }
        if (k > 0 && sorted[k] == sorted[k - 1])
            throw InputError("nscd::System::removeGrains: grain " + std::to_string(sorted[k])
                             + " given twice");
    }
    if (sorted.empty()) return sorted;

    // old grain index -> new one (-1: removed); the map is increasing, so the
    // contact records (sorted by i, then j) stay sorted
    std::vector<char> keep(N, 1);
    for (std::size_t i : sorted) keep[i] = 0;
    std::vector<int> newIndex(N, -1);
    int n = 0;
    for (std::size_t i = 0; i < N; ++i)
        if (keep[i]) newIndex[i] = n++;
    const int removed = int(N) - n;

    I.columns.compact(keep);      // every per-grain column
    for (Droplet& d : I.droplets) // per-grain output of the last step
        if (d.grainImpulse.size() == N) compactRows(d.grainImpulse, keep);

    // internal order (slot -> grain): the slots of the remaining grains
    // keep their order; old slot -> new slot (-1: removed), increasing
    std::vector<int> newSlot(N, -1);
    {
        int ns = 0;
        for (std::size_t s = 0; s < N; ++s)
        {
            const int g = I.order[s];
            if (!keep[g]) continue;
            newSlot[s] = ns;
            I.order[ns++] = newIndex[g];
        }
        I.order.resize(ns);
        releaseSpare(I.order);
        I.rebuildSlotOf();
        releaseSpare(I.slotOf);
        I.verlet.invalidate();
    }

    I.syncKeptContacts();
    // contacts (by slot): body j is grain slot j (j < N) or wall j - N;
    // droplet contacts are not kept between steps (storeImpulses); the
    // slot map is increasing, so the records (sorted by i) stay sorted
    std::size_t m = 0;
    for (const Contact& c : I.contacts)
    {
        if (c.i < 0 || std::size_t(c.i) >= N || newSlot[c.i] < 0) continue;
        if (c.j < int(N) && newSlot[c.j] < 0) continue;
        Contact d = c;
        d.i = newSlot[c.i];
        d.j = c.j < int(N) ? newSlot[c.j] : c.j - removed;
        I.contacts[m++] = d;
    }
    I.contacts.resize(m);
    releaseSpare(I.contacts);
    return sorted;
}

} // namespace nscd
