// SPDX-License-Identifier: GPL-3.0-or-later
// Bit-identity check of the contact solve across library versions (used for
// docs/validation/contactCompliance.md): pours a 300-grain 2D column and a
// 300-sphere 3D pile between planes with System::advance(5e-4, 0.1) for 400
// steps and prints every position and velocity component in hex (%a). Build
// it against two libraries (e.g. a git worktree of an earlier commit, built
// the same way) and cmp the outputs; env BETA sets Material::relativeCompliance.
// (BETA needs a library with the compliance fields.)
// usage: g++ -O2 -std=c++17 -Isrc/nscd/include -I/usr/include/eigen3
//        tests/bench/hardLawBitCheck.cpp -L<lib> -lnscd -Wl,-rpath,<lib> -o bitcheck
#include "benchBox.H"
#include "nscd/System.H"
#include <cstdio>
#include <cstdlib>
#include <random>
using namespace nscd;
int main()
{
    for (int dim : {2, 3})
    {
        System s(dim);
        Material mat{2500, 0.3};
        if (std::getenv("BETA")) mat.relativeCompliance = std::atof(std::getenv("BETA"));
        const int m = s.addMaterial(mat);
        std::mt19937_64 rng(3);
        std::uniform_real_distribution<double> u(0, 1);
        const double d = 1e-3, w = 10e-3, sp = 1.3 * d;
        int n = 0;
        for (int j = 0; n < 300; ++j)
            for (int i = 0; i < int(w / sp) && n < 300; ++i)
                for (int kz = 0; kz < (dim == 3 ? 3 : 1) && n < 300; ++kz, ++n)
                    s.addGrain(Vec3((i + 0.5) * sp + 0.1 * d * (2 * u(rng) - 1), (j + 0.5) * sp,
                                    dim == 3 ? (kz + 0.5) * sp : 0.0),
                               (0.9 * d + 0.1 * d * u(rng)) / 2, m);
        benchBox::addBoxPlanes(s, dim, w);
        s.setGravity(Vec3(0, -9.81, 0));
        for (int k = 0; k < 400; ++k) s.advance(5e-4, 0.1);
        for (std::size_t i = 0; i < s.size(); ++i)
            for (int c = 0; c < 3; ++c) std::printf("%a %a\n", s.positions()[i][c], s.velocities()[i][c]);
    }
}
