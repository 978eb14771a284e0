// SPDX-License-Identifier: GPL-3.0-or-later
// HDF5 state I/O: round trip, bit-exact restart, errors.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <string>
#include <thread>

using namespace nscd;

namespace
{
System makeBox(int dim, int n)
{
    System s(dim);
    const int m = s.addMaterial({2500, 0.4, 1e9, 0.25, 1.2, 840});
    const int m2 = s.addMaterial({1500, 0.2});
    std::mt19937 gen(2);
    std::uniform_real_distribution<double> U(0.004, 0.006);
    const double h = 0.013;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
            for (int c = 0; c < (dim == 3 ? 3 : 1); ++c)
            {
                const int k = s.addGrain(Vec3((a + 0.5) * h, (b + 0.5) * h, dim == 3 ? (c + 0.5) * h : 0),
                                         U(gen), (a + b) % 2 ? m : m2);
                s.velocities()[k] = Vec3(U(gen) - 0.005, 0, 0) * 100;
            }
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0.01, 0));
    s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
    s.addPlane(Vec3(n * h, 0, 0), Vec3(-1, 0, 0));
    if (dim == 2)
        s.addSegment(Vec3(0.02, 0.5, 0), Vec3(0.06, 0.4, 0));
    else
    {
        s.addTriangulatedSurface({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 2}});
        s.addPlane(Vec3(0, 0, 3 * h), Vec3(0, 0, -1));
    }
    s.setGravity(Vec3(0.5, -9.81, 0));
    s.setExternalForce(3, Vec3(1e-3, 2e-3, 0), Vec3(0, 0, 1e-7));
    s.setRotationLocked(5);
    s.settings().tolerance = 1e-5;
    return s;
}
} // namespace

TEST(HDF5, RoundTripEveryField)
{
    for (int dim : {2, 3})
    {
        System s = makeBox(dim, 6);
        for (int k = 0; k < 50; ++k) s.step(1e-3);
        const std::string f = "nscd_roundtrip.h5";
        s.writeHDF5(f);
        const System r = System::readHDF5(f);
        ASSERT_EQ(r.size(), s.size());
        EXPECT_EQ(r.dimension(), dim);
        EXPECT_EQ(r.time(), s.time());
        EXPECT_EQ(r.positions(), s.positions());
        EXPECT_EQ(r.velocities(), s.velocities());
        EXPECT_EQ(r.angularVelocities(), s.angularVelocities());
        EXPECT_EQ(r.radii(), s.radii());
        EXPECT_EQ(r.materials(), s.materials());
        for (std::size_t i = 0; i < s.size(); ++i)
        {
            EXPECT_EQ(r.orientations()[i].coeffs(), s.orientations()[i].coeffs());
            EXPECT_EQ(r.mass(i), s.mass(i));
            EXPECT_EQ(r.rotationLocked(i), s.rotationLocked(i));
        }
        EXPECT_EQ(r.material(0).youngModulus, 1e9);
        EXPECT_EQ(r.nWalls(), s.nWalls());
        EXPECT_EQ(r.wallDisplacement(0), s.wallDisplacement(0));
        EXPECT_EQ(r.gravity(), s.gravity());
        EXPECT_EQ(r.settings().tolerance, 1e-5);
        const auto a = s.contacts(), b = r.contacts();
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t k = 0; k < a.size(); ++k)
        {
            EXPECT_EQ(a[k].i, b[k].i);
            EXPECT_EQ(a[k].j, b[k].j);
            EXPECT_EQ(a[k].impulse, b[k].impulse);
        }
        std::remove(f.c_str());
    }
}

// Reference: restart contract, 2N steps == N steps + write + read + N steps,
// exact (bitwise) equality of positions, velocities and orientations.
TEST(HDF5, RestartIsBitIdentical)
{
    for (int dim : {2, 3})
    {
        const int N = 60;
        System a = makeBox(dim, 6);
        for (int k = 0; k < 2 * N; ++k) a.step(1e-3);
        System b = makeBox(dim, 6);
        for (int k = 0; k < N; ++k) b.step(1e-3);
        b.writeHDF5("nscd_restart.h5");
        System c = System::readHDF5("nscd_restart.h5");
        for (int k = 0; k < N; ++k) c.step(1e-3);
        EXPECT_EQ(a.positions(), c.positions()) << "dim " << dim;
        EXPECT_EQ(a.velocities(), c.velocities());
        EXPECT_EQ(a.angularVelocities(), c.angularVelocities());
        for (std::size_t i = 0; i < a.size(); ++i)
            EXPECT_EQ(a.orientations()[i].coeffs(), c.orientations()[i].coeffs());
        EXPECT_EQ(a.time(), c.time());
        std::remove("nscd_restart.h5");
    }
}

// The same state written twice, more than a second apart (HDF5 object
// modification times have a resolution of one second), gives the same bytes:
// a rerun or a restart can be compared with cmp (consistency check of the
// writer, no physics).
TEST(HDF5, SameStateSameBytes)
{
    System s = makeBox(2, 6);
    for (int k = 0; k < 20; ++k) s.step(1e-3);
    s.writeHDF5("nscd_bytes_a.h5");
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    s.writeHDF5("nscd_bytes_b.h5");
    auto bytes = [](const char* f)
    {
        std::ifstream in(f, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    const std::string a = bytes("nscd_bytes_a.h5"), b = bytes("nscd_bytes_b.h5");
    EXPECT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << "the two writes of one state differ";
    std::remove("nscd_bytes_a.h5");
    std::remove("nscd_bytes_b.h5");
}

TEST(HDF5, MissingAndCorruptFiles)
{
    EXPECT_THROW(System::readHDF5("does/not/exist.h5"), InputError);
    {
        std::ofstream o("nscd_garbage.h5");
        o << "this is not hdf5";
    }
    EXPECT_THROW(System::readHDF5("nscd_garbage.h5"), InputError);
    // a valid HDF5 file without the expected datasets
    System s = makeBox(2, 3);
    s.writeHDF5("nscd_ok.h5");
    {
        // truncate the file: corrupt
        std::ifstream in("nscd_ok.h5", std::ios::binary);
        std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream o("nscd_trunc.h5", std::ios::binary);
        o.write(data.data(), std::streamsize(data.size() / 2));
    }
    EXPECT_THROW(System::readHDF5("nscd_trunc.h5"), InputError);
    try
    {
        System::readHDF5("nscd_garbage.h5");
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("nscd_garbage.h5"), std::string::npos);
    }
    EXPECT_THROW(s.writeHDF5("no/such/dir/x.h5"), InputError);
    std::remove("nscd_garbage.h5");
    std::remove("nscd_ok.h5");
    std::remove("nscd_trunc.h5");
}

TEST(HDF5, EmptySystemRoundTrip)
{
    System s(3);
    s.writeHDF5("nscd_empty.h5");
    const System r = System::readHDF5("nscd_empty.h5");
    EXPECT_EQ(r.size(), 0u);
    EXPECT_EQ(r.dimension(), 3);
    std::remove("nscd_empty.h5");
}

// A preamble (e.g. an OpenFOAM FoamFile header) in the HDF5 user block: the
// file starts with it, HDF5 skips it and the restart stays bit-identical.
TEST(HDF5, PreambleInUserBlock)
{
    System a = makeBox(2, 4);
    for (int k = 0; k < 20; ++k) a.step(1e-3);
    const std::string header = "FoamFile\n{\n    class nscdGrainState;\n}\n";
    a.writeHDF5("nscd_preamble.h5", header);
    {
        std::ifstream in("nscd_preamble.h5", std::ios::binary);
        std::string start(header.size(), '\0');
        in.read(&start[0], std::streamsize(start.size()));
        EXPECT_EQ(start, header);
    }
    System b = System::readHDF5("nscd_preamble.h5");
    std::remove("nscd_preamble.h5");
    for (int k = 0; k < 20; ++k)
    {
        a.step(1e-3);
        b.step(1e-3);
    }
    EXPECT_EQ(a.positions(), b.positions());
    EXPECT_EQ(a.velocities(), b.velocities());
    // a preamble longer than 512 bytes: the next power of two
    a.writeHDF5("nscd_preamble.h5", std::string(700, '#'));
    EXPECT_EQ(System::readHDF5("nscd_preamble.h5").size(), a.size());
    std::remove("nscd_preamble.h5");
}

namespace
{
/// Contacts of s by the ids of their grains (wall j: -(wall+1)) -> impulse.
std::map<std::pair<long, long>, Vec3> contactsById(const System& s)
{
    std::map<std::pair<long, long>, Vec3> out;
    const auto& id = s.grainIds();
    for (const System::ContactView& c : s.contacts())
    {
        const long a = id[c.i], b = c.j >= 0 ? id[c.j] : c.j;
        if (c.j >= 0 && b < a)
            out[{b, a}] = -c.impulse;
        else
            out[{a, b}] = c.impulse;
    }
    return out;
}

/// Check that part is the grains of whole whose centre keep accepts, in the
/// file's order, with their state, ids and the contacts among them.
void expectPartOf(const System& whole, const System& part,
                  const std::function<bool(const Vec3&, double)>& keep)
{
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < whole.size(); ++i)
        if (keep(whole.positions()[i], whole.radii()[i])) kept.push_back(i);
    ASSERT_EQ(part.size(), kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k)
    {
        const std::size_t i = kept[k];
        ASSERT_EQ(part.grainIds()[k], whole.grainIds()[i]);
        EXPECT_EQ(part.positions()[k], whole.positions()[i]);
        EXPECT_EQ(part.velocities()[k], whole.velocities()[i]);
        EXPECT_EQ(part.angularVelocities()[k], whole.angularVelocities()[i]);
        EXPECT_EQ(part.radii()[k], whole.radii()[i]);
        EXPECT_EQ(part.mass(k), whole.mass(i));
        EXPECT_EQ(part.temperatures()[k], whole.temperatures()[i]);
        EXPECT_EQ(part.rotationLocked(k), whole.rotationLocked(i));
    }
    EXPECT_EQ(part.nWalls(), whole.nWalls());
    EXPECT_EQ(part.time(), whole.time());
    std::set<long> ids(part.grainIds().begin(), part.grainIds().end());
    std::map<std::pair<long, long>, Vec3> expected;
    for (const auto& [pair, impulse] : contactsById(whole))
        if (ids.count(pair.first) && (pair.second < 0 || ids.count(pair.second))) expected[pair] = impulse;
    EXPECT_EQ(contactsById(part), expected);
}
} // namespace

// System::readHDF5(file, keep), the start of a decomposed run (each rank
// reads its region): the part read equals the whole read restricted to the
// grains kept (positions, velocities, ids, temperatures, the contacts among
// them with their impulses), on a small box (one chunk) and on a
// 72,000-disc lattice at rest (two chunks of rows, picks across the chunk
// boundary); keeping every grain gives the whole read. Consistency checks
// of the reader (no physics).
TEST(HDF5, PartReadKeepsTheGrainsAndTheirContacts)
{
    const std::string f = "nscd_part.h5";
    for (int dim : {2, 3})
    {
        System s = makeBox(dim, 6);
        for (int k = 0; k < 50; ++k) s.step(1e-3);
        s.writeHDF5(f);
        const System whole = System::readHDF5(f);
        const auto left = [](const Vec3& x, double r) { return x.x() < 0.04 && r > 0.0045; };
        expectPartOf(whole, System::readHDF5(f, left), left);
        const auto all = [](const Vec3&, double) { return true; };
        expectPartOf(whole, System::readHDF5(f, all), all);
        const auto none = [](const Vec3&, double) { return false; };
        EXPECT_EQ(System::readHDF5(f, none).size(), 0u);
        EXPECT_EQ(System::grainIdsHDF5(f), whole.grainIds());
        EXPECT_EQ(System::grainRadiiHDF5(f), whole.radii());
    }
    // touching discs on a floor: 300 columns x 240 rows
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    const double r = 5e-4;
    for (int b = 0; b < 240; ++b)
        for (int a = 0; a < 300; ++a) s.addGrain(Vec3((2 * a + 1) * r, (2 * b + 1) * r, 0), r, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -9.81, 0));
    s.settings().maxIterations = 3; // (contacts with impulses, not an equilibrium)
    s.step(1e-4);
    ASSERT_GT(s.contacts().size(), 100000u);
    s.writeHDF5(f);
    const System whole = System::readHDF5(f);
    // grains 0-65535 (rows 0-218) are the first chunk: a band of rows 210-229
    // of the left half, across its end
    const auto band = [r](const Vec3& x, double)
    { return x.y() > 420 * r && x.y() < 460 * r && x.x() < 300 * r; };
    expectPartOf(whole, System::readHDF5(f, band), band);
    std::remove(f.c_str());
}
