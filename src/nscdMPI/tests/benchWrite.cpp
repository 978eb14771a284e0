// SPDX-License-Identifier: GPL-3.0-or-later
// nscdMPIWriteBench: peak memory of writing a state (not a test; driven by
// tests/bench/grainStateWrite).
//   mpirun -np N nscdMPIWriteBench state.h5 outdir out.json
// One rank: the state read whole and written whole (System::writeHDF5), as
// a serial run writes: once as read, once after one step (the figure
// compared, as a serial run holds its step's data when it writes). N ranks:
// each rank reads its x slab of equal grain counts grown by the halo
// (System::readHDF5 with keep, as grainFoam
// starts), makes one step, then writes the state in parts joined by
// virtual datasets (DecomposedSystem::statePart, System::writeHDF5Part,
// System::writeHDF5Joined: the grainCloud writer without OpenFOAM) and, for
// comparison, gathered on rank 0 (gatherWhole, System::writeHDF5: the
// writer before). Per rank: the resident memory before each write and its
// peak during it (VmHWM reset through /proc/self/clear_refs before the
// write), and the peak of the read and step before; rank 0 checks that the joined
// file reads back with every grain.
#include "nscdMPI/DecomposedSystem.H"

#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace nscd;

namespace
{
double statusMB(const char* field)
{
    std::ifstream f("/proc/self/status");
    std::string line;
    const std::size_t n = std::string(field).size();
    while (std::getline(f, line))
        if (line.rfind(field, 0) == 0) return std::atof(line.c_str() + n) / 1024.0;
    return 0;
}

/// Reset the peak resident memory (VmHWM) to the current one.
void resetPeak() { std::ofstream("/proc/self/clear_refs") << "5"; }

std::vector<double> gather(double v, int P)
{
    std::vector<double> all(P);
    MPI_Gather(&v, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    return all;
}

std::string list(const std::vector<double>& v)
{
    std::ostringstream o;
    o << "[";
    for (std::size_t k = 0; k < v.size(); ++k) o << (k ? ", " : "") << v[k];
    o << "]";
    return o.str();
}

/// Resident memory before, and peak during, write() [MB].
template <class Write>
std::pair<double, double> measure(Write write)
{
    malloc_trim(0);
    MPI_Barrier(MPI_COMM_WORLD);
    resetPeak();
    const double before = statusMB("VmRSS:");
    write();
    const double peak = statusMB("VmHWM:");
    MPI_Barrier(MPI_COMM_WORLD);
    return {before, peak};
}
} // namespace

int main(int argc, char** argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, P = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &P);
    if (argc < 4)
    {
        if (rank == 0) std::fprintf(stderr, "usage: nscdMPIWriteBench state.h5 outdir out.json\n");
        MPI_Finalize();
        return 1;
    }
    const std::string state = argv[1], dir = argv[2];
    std::ofstream o;
    if (rank == 0) o.open(argv[3]);
    if (P == 1)
    {
        // written as read, then after one step, as a serial run writes (its
        // step's contact records, solver rows and lists held)
        System S = System::readHDF5(state);
        const auto read = measure([&] { S.writeHDF5(dir + "/whole.h5"); });
        S.step(S.lastStepDt() > 0 ? S.lastStepDt() : 1e-4);
        const auto m = measure([&] { S.writeHDF5(dir + "/whole.h5"); });
        o << "{\n  \"ranks\": 1,\n  \"grains\": " << S.size() << ",\n  \"rss_before_write_mb\": " << m.first
          << ",\n  \"peak_rss_during_write_mb\": " << m.second
          << ",\n  \"without_step_rss_before_write_mb\": " << read.first
          << ",\n  \"without_step_peak_rss_during_write_mb\": " << read.second
          << ",\n  \"peak_rss_of_process_mb\": " << statusMB("VmHWM:") << "\n}\n";
        std::printf("serial: %zu grains, after a step: rss %.1f MB, peak during write %.1f MB; "
                    "as read: %.1f, %.1f MB\n",
                    S.size(), m.first, m.second, read.first, read.second);
        MPI_Finalize();
        return 0;
    }
    // x slabs of equal grain counts, each rank reading its slab grown by the halo
    std::vector<double> xs;
    double rmax = 0;
    System::readHDF5(state,
                     [&](const Vec3& x, double r)
                     {
                         xs.push_back(x.x());
                         rmax = std::max(rmax, r);
                         return false;
                     });
    const std::size_t N = xs.size();
    std::sort(xs.begin(), xs.end());
    std::vector<double> cut(P + 1);
    cut[0] = -1e300;
    cut[P] = 1e300;
    for (int r = 1; r < P; ++r) cut[r] = 0.5 * (xs[N * r / P - 1] + xs[N * r / P]);
    xs = {};
    const double halo = 3 * rmax;
    System part = System::readHDF5(state, [&](const Vec3& x, double)
                                   { return x.x() >= cut[rank] - halo && x.x() < cut[rank + 1] + halo; });
    const double dt = part.lastStepDt() > 0 ? part.lastStepDt() : 1e-4;
    auto ownerOf = [cut, P](const Vec3& x, long)
    { return int(std::upper_bound(cut.begin() + 1, cut.begin() + P, x.x()) - (cut.begin() + 1)); };
    mpi::DecomposedSystem D(std::move(part), long(N), MPI_COMM_WORLD, ownerOf, halo);
    D.step(dt);
    const double readAndStep = statusMB("VmHWM:"); // (before the resets)

    const auto partOnly = measure( // (the part made, not written)
        [&]
        {
            long nextId = 0;
            D.statePart(nextId);
        });
    const auto parts = measure(
        [&]
        {
            long nextId = 0;
            const System::StatePart sp = D.statePart(nextId);
            D.system().writeHDF5Part(dir + "/rank" + std::to_string(rank) + ".h5", sp);
            MPI_Barrier(MPI_COMM_WORLD);
            if (rank == 0)
            {
                std::vector<std::string> names;
                for (int r = 0; r < P; ++r) names.push_back("rank" + std::to_string(r) + ".h5");
                D.system().writeHDF5Joined(dir + "/joined.h5", names, nextId);
            }
        });
    const auto gathered = measure(
        [&]
        {
            const std::unique_ptr<System> whole = D.gatherWhole(0);
            if (whole) whole->writeHDF5(dir + "/gathered.h5");
        });
    const auto before = gather(parts.first, P), peak = gather(parts.second, P),
               gBefore = gather(gathered.first, P), gPeak = gather(gathered.second, P),
               owned = gather(double(D.nOwned()), P), held = gather(double(D.system().size()), P),
               process = gather(readAndStep, P), partPeak = gather(partOnly.second, P);
    if (rank == 0)
    {
        const std::size_t back = System::grainIdsHDF5(dir + "/joined.h5").size();
        o << "{\n  \"ranks\": " << P << ",\n  \"grains\": " << N << ",\n  \"joined_file_grains\": " << back
          << ",\n  \"owned_grains\": " << list(owned) << ",\n  \"held_grains\": " << list(held)
          << ",\n  \"rss_before_write_mb\": " << list(before)
          << ",\n  \"peak_rss_during_write_mb\": " << list(peak)
          << ",\n  \"peak_rss_making_the_part_only_mb\": " << list(partPeak)
          << ",\n  \"gathered_rss_before_write_mb\": " << list(gBefore)
          << ",\n  \"gathered_peak_rss_during_write_mb\": " << list(gPeak)
          << ",\n  \"peak_rss_read_and_step_mb\": " << list(process) << "\n}\n";
        std::printf(
            "np %d: peak during the parts' write %s MB; gathered %s MB; joined file %zu of %zu grains\n", P,
            list(peak).c_str(), list(gPeak).c_str(), back, N);
    }
    MPI_Finalize();
    return 0;
}
