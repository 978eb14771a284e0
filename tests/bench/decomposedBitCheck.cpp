// SPDX-License-Identifier: GPL-3.0-or-later
// Bit-identity check of the decomposed step (nscd::Subdomain through
// nscd::mpi::DecomposedSystem) across library versions: the companion of
// hardLawBitCheck.cpp for a run on several ranks. A 2D column of 240 discs
// poured between walls on x slabs, with a heavy droplet falling on it, heat
// conduction (a hot floor, a source, an exchange with a bath), implicit drag
// on every third grain and cohesion; then a 3D pile of 240 spheres. Every
// step is DecomposedSystem::step; at the end the whole system is gathered on
// rank 0, which prints every position, velocity and temperature component,
// the droplet's centre and the step reports' counts in hex (%a). Build it
// against two libraries and cmp the outputs of the same rank count.
// usage: mpicxx -O2 -std=c++17 -Isrc/nscd/include -Isrc/nscdMPI/include
//        -I/usr/include/eigen3 tests/bench/decomposedBitCheck.cpp -L<lib>
//        -lnscdMPI -lnscd -Wl,-rpath,<lib> -o dbitcheck
//        mpirun -np 2 ./dbitcheck > out.txt
#include "benchBox.H"
#include "nscdMPI/DecomposedSystem.H"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

using namespace nscd;
using nscd::mpi::DecomposedSystem;

int main(int argc, char** argv)
{
    MPI_Init(&argc, &argv);
    int P = 1, me = 0;
    MPI_Comm_size(MPI_COMM_WORLD, &P);
    MPI_Comm_rank(MPI_COMM_WORLD, &me);
    for (int dim : {2, 3})
    {
        const double d = 1e-3, w = 10e-3, sp = 1.3 * d;
        auto owner = [=](const Vec3& x, long)
        { return std::clamp(int(std::floor(x.x() / w * P)), 0, P - 1); };
        DecomposedSystem D(dim, MPI_COMM_WORLD, owner, 3e-3);
        System& s = D.system();
        Material mat{2500, 0.3};
        mat.youngModulus = 1e9;
        mat.poissonRatio = 0.3;
        mat.conductivity = 1.0;
        mat.heatCapacity = 1.0;
        const int m = s.addMaterial(mat);
        benchBox::addBoxPlanes(s, dim, w);
        s.setWallTemperature(0, 400);
        s.setGravity(Vec3(0, -9.81, 0));
        s.setCohesion([](int a, int b) { return (a + b) % 5 == 0; }, 1e-4);
        if (dim == 2)
        {
            System::Droplet drop;
            drop.radius = 2e-3;
            drop.centre = Vec3(0.5 * w, 20e-3, 0);
            drop.mass = 1000 * M_PI * drop.radius * drop.radius;
            drop.force = Vec3(0, -9.81 * drop.mass, 0);
            drop.surfaceTension = 0.05;
            s.addDroplet(drop);
        }
        std::mt19937_64 rng(3);
        std::uniform_real_distribution<double> u(0, 1);
        const int n0 = 240;
        int n = 0;
        for (int j = 0; n < n0; ++j)
            for (int i = 0; i < int(w / sp) && n < n0; ++i)
                for (int kz = 0; kz < (dim == 3 ? 3 : 1) && n < n0; ++kz, ++n)
                {
                    const Vec3 x((i + 0.5) * sp + 0.1 * d * (2 * u(rng) - 1), (j + 0.5) * sp,
                                 dim == 3 ? (kz + 0.5) * sp : 0.0);
                    const double r = (0.9 * d + 0.1 * d * u(rng)) / 2;
                    const std::size_t k = D.addGrain(n, x, r, m);
                    if (k == std::size_t(-1)) continue;
                    s.temperatures()[k] = 300 + n % 7;
                    if (n % 11 == 0) s.setHeatSource(k, 1e-3);
                    if (n % 13 == 0) s.setHeatExchange(k, 1e-3, 350);
                    if (n % 3 == 0) s.setFluidDrag(k, 0.3 * s.mass(k) / 5e-4, Vec3(0.01, 0, 0));
                }
        D.exchange();
        long sweeps = 0, solves = 0, redetections = 0, relax = 0, converged = 0, heatIt = 0;
        for (int k = 0; k < 300; ++k)
        {
            const StepReport r = D.step(5e-4);
            sweeps += r.sweeps;
            solves += r.localSolves;
            redetections += r.redetections;
            relax += r.relaxSolves;
            converged += r.converged;
            heatIt += r.heatIterations;
        }
        long counts[6] = {sweeps, solves, redetections, relax, converged, heatIt};
        MPI_Allreduce(MPI_IN_PLACE, counts, 6, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
        std::unique_ptr<System> whole = D.gatherWhole(0);
        if (!whole) continue;
        std::printf("counts %ld %ld %ld %ld %ld %ld\n", counts[0], counts[1], counts[2], counts[3], counts[4],
                    counts[5]);
        for (std::size_t i = 0; i < whole->size(); ++i)
        {
            for (int c = 0; c < 3; ++c)
                std::printf("%a %a %a ", whole->positions()[i][c], whole->velocities()[i][c],
                            whole->angularVelocities()[i][c]);
            std::printf("%a\n", whole->temperatures()[i]);
        }
        for (int k = 0; k < whole->nDroplets(); ++k)
            std::printf("droplet %a %a %a\n", whole->droplet(k).centre.x(), whole->droplet(k).centre.y(),
                        whole->droplet(k).velocity.y());
    }
    MPI_Finalize();
}
