// SPDX-License-Identifier: GPL-3.0-or-later
// nscdMPIBench: per-rank cost of the decomposed NSCD step on a saved bed
// (not a test; driven by tests/bench/nscdDecomposed).
//   mpirun -np N nscdMPIBench state.h5 steps out.json [serial]
// Every rank reads the whole state (System::readHDF5) and keeps the grains
// of its slab (equal grain counts along x), or with NSCD_PARTREAD=1 reads
// only its slab grown by the halo (System::readHDF5(file, keep), after a
// pass over the centres for the slab bounds); the bed is stepped `steps`
// times (dt of the state's last step) after 3 untimed steps. Per rank:
// owned grains, ghosts, contacts, thread CPU of the step split into the
// solve's collectives, the exchange (migration and ghosts) and the rest
// (NSCD work), bytes sent, averagings per step, resident memory and
// proportional set size after the steps, and the peak resident memory
// (which includes the whole state every rank reads at the start, or its
// part with NSCD_PARTREAD=1). With `serial` and one rank, System::step of
// the same state is timed as well, with the resident memory and
// proportional set size while it holds the state.
#include "nscdMPI/DecomposedSystem.H"

#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace nscd;

namespace
{
double threadCpu()
{
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// Resident memory of the process [MB]: now (VmRSS) or its peak (VmHWM)
/// from /proc/self/status; with file "/proc/self/smaps_rollup" and field
/// "Pss:", the proportional set size (pages shared with other processes,
/// e.g. the other ranks' copies of the MPI and system libraries and the MPI
/// shared-memory segments, counted as 1/n of a page each).
double rssMB(const char* field = "VmRSS:", const char* file = "/proc/self/status")
{
    std::ifstream f(file);
    std::string line;
    const std::size_t n = std::string(field).size();
    while (std::getline(f, line))
        if (line.rfind(field, 0) == 0) return std::atof(line.c_str() + n) / 1024.0;
    return 0;
}

double median(std::vector<double> v)
{
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

template <class T>
std::string list(const std::vector<T>& v)
{
    std::ostringstream os;
    os << "[";
    for (std::size_t k = 0; k < v.size(); ++k) os << (k ? ", " : "") << v[k];
    os << "]";
    return os.str();
}

std::vector<double> gather(double x, int P)
{
    std::vector<double> all(P);
    MPI_Gather(&x, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    return all;
}
/// System::step of the whole state: median thread CPU per step, resident
/// memory and proportional set size while it holds the state.
struct Undecomposed
{
    double cpu = 0, rss = 0, pss = 0;
};

Undecomposed timeUndecomposed(const std::string& state, int steps)
{
    Undecomposed U;
    System S = System::readHDF5(state);
    const double dt = S.lastStepDt() > 0 ? S.lastStepDt() : 1e-4;
    for (int n = 0; n < 3; ++n) S.step(dt);
    std::vector<double> t;
    for (int n = 0; n < steps; ++n)
    {
        const double t0 = threadCpu();
        const StepReport rep = S.step(dt);
        t.push_back(threadCpu() - t0);
        if (std::getenv("NSCD_VERBOSE"))
            std::printf("undecomposed step %d: sweeps %d (relax solve %d), local solves %ld, contacts "
                        "%d, residual %.3g, cpu %.4f s\n",
                        n, rep.sweeps, rep.relaxSolves, rep.localSolves, rep.contacts, rep.residual,
                        t.back());
    }
    U.cpu = median(t);
    U.rss = rssMB(); // (the undecomposed system held, after its steps)
    U.pss = rssMB("Pss:", "/proc/self/smaps_rollup");
    return U;
}

/// The state decomposed on P x slabs of equal grain counts (this rank's
/// slab), read whole or (NSCD_PARTREAD=1) as the slab grown by the halo;
/// N: the grains of the state, dt: its last step's.
std::unique_ptr<mpi::DecomposedSystem> decompose(const std::string& state, int P, int rank, std::size_t& N,
                                                 double& dt)
{
    const bool partRead = std::getenv("NSCD_PARTREAD") && std::string(std::getenv("NSCD_PARTREAD")) == "1";
    // the centres along x and the largest radius: from the whole state, or
    // (partRead) from a pass over the file that keeps no grain
    std::vector<double> xs;
    double rmax = 0;
    System whole(2);
    if (partRead)
        System::readHDF5(state,
                         [&](const Vec3& x, double r)
                         {
                             xs.push_back(x.x());
                             rmax = std::max(rmax, r);
                             return false;
                         });
    else
    {
        whole = System::readHDF5(state);
        for (std::size_t i = 0; i < whole.size(); ++i)
        {
            xs.push_back(whole.positions()[i].x());
            rmax = std::max(rmax, whole.radii()[i]);
        }
    }
    N = xs.size();
    std::sort(xs.begin(), xs.end());
    std::vector<double> cut(P + 1); // slab bounds at the grain-count quantiles
    cut[0] = -1e300;
    cut[P] = 1e300;
    for (int r = 1; r < P; ++r) cut[r] = 0.5 * (xs[N * r / P - 1] + xs[N * r / P]);
    xs = {};
    auto ownerOf = [cut, P](const Vec3& x, long)
    { return int(std::upper_bound(cut.begin() + 1, cut.begin() + P, x.x()) - (cut.begin() + 1)); };
    const double halo = 3 * rmax;
    if (partRead)
        whole = System::readHDF5(state, [&](const Vec3& x, double)
                                 { return x.x() >= cut[rank] - halo && x.x() < cut[rank + 1] + halo; });
    dt = whole.lastStepDt() > 0 ? whole.lastStepDt() : 1e-4;
    std::unique_ptr<mpi::DecomposedSystem> decomposed(
        partRead ? new mpi::DecomposedSystem(std::move(whole), long(N), MPI_COMM_WORLD, ownerOf, halo)
                 : new mpi::DecomposedSystem(std::move(whole), MPI_COMM_WORLD, ownerOf, halo));
    return decomposed;
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
        if (rank == 0) std::fprintf(stderr, "usage: nscdMPIBench state.h5 steps out.json [serial]\n");
        MPI_Finalize();
        return 1;
    }
    const std::string state = argv[1];
    const int steps = std::atoi(argv[2]);
    const bool serial = argc > 4 && std::string(argv[4]) == "serial" && P == 1;

    Undecomposed U;
    if (serial) U = timeUndecomposed(state, steps);
    malloc_trim(0);

    std::size_t N = 0;
    double dt = 0;
    std::unique_ptr<mpi::DecomposedSystem> decomposed = decompose(state, P, rank, N, dt);
    mpi::DecomposedSystem& D = *decomposed;
    malloc_trim(0);

    const int warmup = std::getenv("NSCD_WARMUP") ? std::atoi(std::getenv("NSCD_WARMUP")) : 3;
    for (int n = 0; n < warmup; ++n) D.step(dt);
    std::vector<double> cpu, comm, exch, work, avg, bytes, contacts;
    bool converged = true;
    for (int n = 0; n < steps; ++n)
    {
        const double t0 = threadCpu();
        const StepReport rep = D.step(dt);
        const double c = threadCpu() - t0;
        const mpi::ExchangeCounters& k = D.counters();
        cpu.push_back(c);
        comm.push_back(k.solveCommCpuSeconds);
        exch.push_back(k.exchangeCpuSeconds);
        work.push_back(c - k.solveCommCpuSeconds - k.exchangeCpuSeconds);
        avg.push_back(k.averagings);
        bytes.push_back(double(k.bytesSent));
        contacts.push_back(rep.contacts);
        converged = converged && rep.converged;
        if (std::getenv("NSCD_VERBOSE") && (rank == 0 || std::getenv("NSCD_ALLRANKS")))
            std::printf("rank %d step %d: averagings %d (relax solve %d), local solves %ld, contacts %d, "
                        "residual %.3g, work %.4f s, migrated %ld, ghosts sent %ld added %ld dropped %ld\n",
                        rank, n, k.averagings, rep.relaxSolves, rep.localSolves, rep.contacts, rep.residual,
                        work.back(), k.migratedOut, k.ghostsSent, k.ghostsAdded, k.ghostsDropped);
    }
    const auto owned = gather(double(D.nOwned()), P);
    const auto ghosts = gather(double(D.system().size() - D.nOwned()), P);
    const auto mCpu = gather(median(cpu), P), mComm = gather(median(comm), P),
               mExch = gather(median(exch), P), mWork = gather(median(work), P),
               mAvg = gather(median(avg), P), mBytes = gather(median(bytes), P),
               mContacts = gather(median(contacts), P), rss = gather(rssMB(), P),
               peak = gather(rssMB("VmHWM:"), P), pss = gather(rssMB("Pss:", "/proc/self/smaps_rollup"), P);
    if (rank == 0)
    {
        std::ofstream o(argv[3]);
        o << "{\n  \"ranks\": " << P << ",\n  \"grains\": " << N << ",\n  \"dt\": " << dt
          << ",\n  \"timed_steps\": " << steps
          << ",\n  \"converged_every_step\": " << (converged ? "true" : "false")
          << ",\n  \"owned_grains\": " << list(owned) << ",\n  \"ghost_grains\": " << list(ghosts)
          << ",\n  \"contacts\": " << list(mContacts) << ",\n  \"cpu_seconds_per_step\": " << list(mCpu)
          << ",\n  \"nscd_work_cpu_seconds_per_step\": " << list(mWork)
          << ",\n  \"solve_collectives_cpu_seconds_per_step\": " << list(mComm)
          << ",\n  \"exchange_cpu_seconds_per_step\": " << list(mExch)
          << ",\n  \"averagings_per_step\": " << list(mAvg)
          << ",\n  \"bytes_sent_per_step\": " << list(mBytes) << ",\n  \"rss_mb\": " << list(rss)
          << ",\n  \"peak_rss_mb\": " << list(peak) << ",\n  \"pss_mb\": " << list(pss);
        if (serial)
            o << ",\n  \"undecomposed_cpu_seconds_per_step\": " << U.cpu
              << ",\n  \"undecomposed_rss_mb\": " << U.rss << ",\n  \"undecomposed_pss_mb\": " << U.pss;
        o << "\n}\n";
        std::printf(
            "np %d: owned %s, work CPU %s s/step, collectives %s, exchange %s, averagings %s, rss %s MB\n", P,
            list(owned).c_str(), list(mWork).c_str(), list(mComm).c_str(), list(mExch).c_str(),
            list(mAvg).c_str(), list(rss).c_str());
        if (serial) std::printf("undecomposed System::step: %.4f CPU s/step\n", U.cpu);
    }
    MPI_Finalize();
    return 0;
}
