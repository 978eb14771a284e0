// SPDX-License-Identifier: GPL-3.0-or-later
// Per-grain columns (GrainColumns.H): a column declared by a caller keeps
// one value per grain through addGrain, removeGrains, the renumbering along
// the internal order and an HDF5 restart; the System's own arrays are
// columns of the same registry.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfenv>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <string>

using namespace nscd;

namespace
{
/// 2D discs on a 15-wide lattice, added in a shuffled order (their indices
/// scattered along the Morton order), resting on a floor; reorder every 5 steps.
System shuffledBed(int n)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4, 1e9, 0.25, 1.2, 840});
    std::vector<int> perm(n);
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), std::mt19937(11));
    for (int k : perm)
        s.addGrain(Vec3(1.1e-3 + 2.2e-3 * (k % 15) + 1.1e-3 * ((k / 15) % 2), 1.1e-3 + 2.05e-3 * (k / 15), 0),
                   1e-3 * (0.9 + 0.02 * (k % 5)), m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -9.81, 0));
    s.settings().reorderInterval = 5;
    return s;
}

/// The caller's columns of the tests: every element type.
void declareColumns(System& s, unsigned extra = 0)
{
    s.addColumn<double>("wetness", ColumnRestart | ColumnMigrate | extra, -1.0);
    s.addColumn<Vec3>("slip", ColumnRestart | ColumnMigrate | ColumnGhost | extra, Vec3(1, 2, 3));
    s.addColumn<Eigen::Quaterniond>("frame", ColumnRestart | extra, Eigen::Quaterniond::Identity());
    s.addColumn<int>("cell", ColumnRestart | extra, -7);
    s.addColumn<long>("tag", ColumnRestart | extra, 42L);
    s.addColumn<char>("inside", ColumnRestart | extra, char(1));
}

/// Values of grain id g in the columns of declareColumns.
double wetness(long g) { return 0.25 * double(g) + 1e-3; }
Vec3 slip(long g) { return Vec3(double(g), -double(g), 0.5); }

void setValues(System& s)
{
    auto& a = s.column<double>("wetness");
    auto& b = s.column<Vec3>("slip");
    auto& q = s.column<Eigen::Quaterniond>("frame");
    auto& c = s.column<int>("cell");
    auto& t = s.column<long>("tag");
    auto& d = s.column<char>("inside");
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        const long g = s.grainIds()[i];
        a[i] = wetness(g);
        b[i] = slip(g);
        q[i] = Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * double(g), Vec3::UnitZ()));
        c[i] = int(3 * g + 1);
        t[i] = 1000000000000L + g;
        d[i] = char(g % 2);
    }
}

/// Every grain holds the values of its id (setValues), bit for bit.
void expectValues(const System& s, const std::string& where)
{
    const auto& a = s.column<double>("wetness");
    const auto& b = s.column<Vec3>("slip");
    const auto& q = s.column<Eigen::Quaterniond>("frame");
    const auto& c = s.column<int>("cell");
    const auto& t = s.column<long>("tag");
    const auto& d = s.column<char>("inside");
    ASSERT_EQ(a.size(), s.size()) << where;
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        const long g = s.grainIds()[i];
        ASSERT_EQ(a[i], wetness(g)) << where << ", grain " << i;
        ASSERT_EQ(b[i], slip(g)) << where << ", grain " << i;
        ASSERT_EQ(q[i].coeffs(),
                  Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * double(g), Vec3::UnitZ())).coeffs())
            << where << ", grain " << i;
        ASSERT_EQ(c[i], int(3 * g + 1)) << where;
        ASSERT_EQ(t[i], 1000000000000L + g) << where;
        ASSERT_EQ(d[i], char(g % 2)) << where;
    }
}

std::string tmpFile(const char* name) { return ::testing::TempDir() + name; }
} // namespace

// Declaration: grains there are and grains added take the default; the
// System's own arrays are columns of the same registry; a second
// declaration, an unknown name or the wrong type are InputErrors.
TEST(Columns, DeclaredColumnsTakeTheDefaultAndNameTheirErrors)
{
    System s(3);
    const int m = s.addMaterial({2500, 0.3});
    s.addGrain(Vec3(0, 0, 0), 1e-3, m);
    const int k = s.addColumn<double>("wetness", ColumnRestart, -1.0);
    EXPECT_EQ(s.columns()[k].name(), "wetness");
    EXPECT_EQ(s.columns()[k].type(), ColumnType::Double);
    EXPECT_EQ(s.column<double>("wetness"), std::vector<double>{-1.0});
    s.addGrain(Vec3(3e-3, 0, 0), 1e-3, m);
    EXPECT_EQ(s.column<double>("wetness"), (std::vector<double>{-1.0, -1.0}));
    // the System's own arrays are columns: the same vectors
    EXPECT_EQ(&s.column<Vec3>("positions"), &s.positions());
    EXPECT_EQ(&s.column<double>("temperatures"), &s.temperatures());
    s.setDefaultTemperature(350);
    s.addGrain(Vec3(6e-3, 0, 0), 1e-3, m);
    EXPECT_EQ(s.temperatures()[2], 350.0);
    auto message = [&](auto f)
    {
        try
        {
            f();
        }
        catch (const InputError& e)
        {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message([&] { s.addColumn<int>("wetness", 0, 0); }).find("'wetness' declared twice"),
              std::string::npos);
    EXPECT_NE(message([&] { s.addColumn<int>("positions", 0, 0); }).find("declared twice"),
              std::string::npos);
    EXPECT_NE(message([&] { s.column<double>("dryness"); }).find("no column 'dryness'"), std::string::npos);
    EXPECT_NE(message([&] { s.column<int>("wetness"); }).find("holds double, asked as int"),
              std::string::npos);
    EXPECT_THROW(s.addColumn<double>("", 0, 0.0), InputError);
}

// Removal compacts a declared column with the System's arrays.
TEST(Columns, ValuesSurviveRemoval)
{
    System s = shuffledBed(90);
    declareColumns(s);
    setValues(s);
    s.removeGrains({0, 17, 4, 89});
    ASSERT_EQ(s.size(), 86u);
    expectValues(s, "after removeGrains");
    for (int k = 0; k < 3; ++k) s.step(2e-4);
    s.removeGrains({5});
    expectValues(s, "after a step and a second removal");
}

// The renumbering along the internal (Morton) order permutes a declared
// column with the System's arrays.
TEST(Columns, ValuesSurviveReordering)
{
    System s = shuffledBed(300);
    declareColumns(s);
    setValues(s);
    for (int k = 0; k < 6; ++k) s.step(2e-4); // reordered at step 1 and 6
    const std::vector<std::size_t> oldOf = s.renumberAlongInternalOrder();
    ASSERT_EQ(oldOf.size(), s.size()) << "the shuffled bed is scattered";
    expectValues(s, "after renumberAlongInternalOrder");
    s.addGrain(Vec3(10e-3, 40e-3, 0), 1e-3, 0);
    EXPECT_EQ(s.column<double>("wetness").back(), -1.0);
    EXPECT_EQ(s.column<Vec3>("slip").back(), Vec3(1, 2, 3));
}

// HDF5 restart: the restart columns declared in readHDF5's callback read
// back bit for bit, whole or in part; a column missing from the file is its
// default when optional, else an InputError naming the file and dataset;
// a state read without declaring them reads as before.
TEST(Columns, ValuesSurviveAnHDF5Restart)
{
    System s = shuffledBed(120);
    declareColumns(s);
    setValues(s);
    for (int k = 0; k < 3; ++k) s.step(2e-4);
    s.removeGrains({3, 30});
    const std::string file = tmpFile("columns.h5");
    s.writeHDF5(file);

    System r = System::readHDF5(file, nullptr, [](System& t) { declareColumns(t); });
    expectValues(r, "read back");
    EXPECT_EQ(r.positions(), s.positions());
    // a part of the file (a subdomain's read)
    System part = System::readHDF5(
        file, [](const Vec3& x, double) { return x.x() < 15e-3; }, [](System& t) { declareColumns(t); });
    ASSERT_GT(part.size(), 10u);
    ASSERT_LT(part.size(), s.size());
    expectValues(part, "part read back");
    // without the declarations: the System's own columns only
    System plain = System::readHDF5(file);
    EXPECT_EQ(plain.velocities(), s.velocities());
    EXPECT_EQ(plain.columns().find("wetness"), -1);

    // a column the file lacks: optional takes its default, else an error
    System o = System::readHDF5(file, nullptr,
                                [](System& t)
                                { t.addColumn<double>("porosity", ColumnRestart | ColumnOptional, 0.4); });
    EXPECT_EQ(o.column<double>("porosity"), std::vector<double>(s.size(), 0.4));
    try
    {
        System::readHDF5(file, nullptr, [](System& t) { t.addColumn<int>("charge", ColumnRestart, 0); });
        ADD_FAILURE() << "a missing restart column read";
    }
    catch (const InputError& e)
    {
        const std::string w = e.what();
        EXPECT_NE(w.find(file), std::string::npos) << w;
        EXPECT_NE(w.find("missing dataset 'charge'"), std::string::npos) << w;
    }
    std::remove(file.c_str());
}

// A restart column declared after the state was read (a part of the program
// made later, e.g. an fvOption of the OpenFOAM side) reads its dataset with
// readColumnHDF5: each grain the row of its id, whole or partial read.
TEST(Columns, ColumnsDeclaredAfterTheReadReadTheirRowsById)
{
    System s = shuffledBed(60);
    declareColumns(s);
    setValues(s);
    for (int k = 0; k < 6; ++k) s.step(2e-4); // reordered at step 5
    s.removeGrains({2, 17});
    const std::string file = tmpFile("lateColumns.h5");
    s.writeHDF5(file);
    for (const bool part : {false, true})
    {
        System r = System::readHDF5(file, [part](const Vec3& x, double) { return !part || x.x() > 9e-3; });
        declareColumns(r);
        for (const char* c : {"wetness", "slip", "frame", "cell", "tag", "inside"})
            EXPECT_TRUE(r.readColumnHDF5(file, c)) << c;
        expectValues(r, part ? "late, part" : "late, whole");
        r.addColumn<double>("porosity", ColumnRestart | ColumnOptional, 0.4);
        EXPECT_FALSE(r.readColumnHDF5(file, "porosity"));
        EXPECT_EQ(r.column<double>("porosity"), std::vector<double>(r.size(), 0.4));
        EXPECT_THROW(r.readColumnHDF5(file, "masses"), InputError); // not a restart column
    }
    std::remove(file.c_str());
}

// Columns sharing a dataset (ColumnDataset), as the System's own "fixed"
// flags and "heatExchange" pairs do: each reads back its part.
TEST(Columns, ColumnsSharingADatasetReadBackTheirParts)
{
    System s = shuffledBed(20);
    auto& lo = s.column<double>("heatExchangeCoefficients");
    auto& hi = s.column<double>("bathTemperatures");
    s.addColumn<char>("flagA", ColumnRestart, char(0), {"flags", 0, 0, 0});
    s.addColumn<char>("flagB", ColumnRestart, char(0), {"flags", 0, 0, 3});
    s.addColumn<double>("pairA", ColumnRestart, 0.0, {"pairs", 2, 0});
    s.addColumn<double>("pairB", ColumnRestart, 0.0, {"pairs", 2, 1});
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        lo[i] = 0.1 * double(i);
        hi[i] = 300 + double(i);
        s.column<char>("flagA")[i] = char(i % 2);
        s.column<char>("flagB")[i] = char((i / 2) % 2);
        s.column<double>("pairA")[i] = double(i);
        s.column<double>("pairB")[i] = -double(i);
    }
    s.setRotationLocked(4);
    const std::string file = tmpFile("sharedColumns.h5");
    s.writeHDF5(file);
    System r = System::readHDF5(file, nullptr,
                                [](System& t)
                                {
                                    t.addColumn<char>("flagA", ColumnRestart, char(0), {"flags", 0, 0, 0});
                                    t.addColumn<char>("flagB", ColumnRestart, char(0), {"flags", 0, 0, 3});
                                    t.addColumn<double>("pairA", ColumnRestart, 0.0, {"pairs", 2, 0});
                                    t.addColumn<double>("pairB", ColumnRestart, 0.0, {"pairs", 2, 1});
                                });
    for (const char* c : {"flagA", "flagB"}) EXPECT_EQ(r.column<char>(c), s.column<char>(c)) << c;
    for (const char* c : {"pairA", "pairB", "heatExchangeCoefficients", "bathTemperatures"})
        EXPECT_EQ(r.column<double>(c), s.column<double>(c)) << c;
    EXPECT_TRUE(r.rotationLocked(4));
    EXPECT_FALSE(r.rotationLocked(3));
    std::remove(file.c_str());
}

// The values read are checked with floating-point traps on (OpenFOAM runs
// with FE_INVALID trapped): an infinite velocity or orientation in a state
// is an InputError naming the grain, not a SIGFPE.
TEST(Columns, NonFiniteValuesReadAreErrorsUnderFloatingPointTraps)
{
    for (int which = 0; which < 2; ++which)
    {
        System s = shuffledBed(10);
        if (which == 0)
            s.velocities()[2] = Vec3(std::numeric_limits<double>::infinity(), 0, 0);
        else
            s.column<Eigen::Quaterniond>("orientations")[2].coeffs()[1] =
                -std::numeric_limits<double>::infinity();
        const std::string file = tmpFile("nonFinite.h5");
        s.writeHDF5(file);
        std::string what;
#if defined(__GLIBC__)
        feenableexcept(FE_INVALID);
#endif
        try
        {
            System::readHDF5(file);
        }
        catch (const InputError& e)
        {
            what = e.what();
        }
#if defined(__GLIBC__)
        fedisableexcept(FE_INVALID);
#endif
        EXPECT_NE(what.find("grain 2: non-finite"), std::string::npos) << what;
        std::remove(file.c_str());
    }
}
