// SPDX-License-Identifier: GPL-3.0-or-later
// HDF5 state I/O (C API) for bit-exact restarts.
#include "ColumnsHDF5.H"
#include "IOStages.H"
#include "SystemImpl.H"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

namespace nscd
{

using h5::H5File;
using h5::openState;
using h5::Reader;
using h5::Writer;

namespace
{
void put3(std::vector<double>& a, const Vec3& v)
{
    a.push_back(v.x());
    a.push_back(v.y());
    a.push_back(v.z());
}
Vec3 get3(const std::vector<double>& a, std::size_t k) { return Vec3(a[k], a[k + 1], a[k + 2]); }
} // namespace

namespace io
{
/// writeHDF5 stage: format version, dimension, time, last dt, cohesion force
/// [s, s, N], gravity [m/s^2], solver settings and materials (SI).
void writeHeader(Writer& w, const System::Impl& I)
{
    w.i("format", {formatVersion}, 0);
    w.i("dimension", {I.dim}, 0);
    w.d("time", {I.time, I.lastDt, I.cohesionForce}, 0);
    w.d("complianceStep", {I.lastComplianceDt}, 0); // relativeCompliance's T of the last step
    std::vector<double> g;
    put3(g, I.g);
    w.d("gravity", g, 0);
    const System::Settings& S = I.settings;
    w.d("settings",
        {S.tolerance, double(S.maxIterations), S.overlapTolerance, S.alertDistanceFactor, S.alertMargin,
         S.cohesionDistance, S.warmStart ? 1.0 : 0.0, double(int(S.ordering)), S.overlapSlop, S.relaxation},
        0);
    std::vector<double> m;
    for (const Material& a : I.materials)
        for (double v :
             {a.density, a.friction, a.youngModulus, a.poissonRatio, a.conductivity, a.heatCapacity})
            m.push_back(v);
    w.d("materials", m, 6);
    // contact compliance [m/N] and relative compliance [-] per material
    // (a dataset of its own: files without it read as 0, the hard law)
    std::vector<double> cm;
    for (const Material& a : I.materials)
        for (double v : {a.compliance, a.relativeCompliance}) cm.push_back(v);
    w.d("materialCompliance", cm, 2);
}

/// writeHDF5 stage: every ColumnRestart grain column (external order;
/// System's: positions [m], velocities [m/s], angular velocities [rad/s],
/// orientations (x y z w), forces [N], torques [N m], radii [m], materials,
/// fixed/rotation-locked flags, persistent ids, heat state) and the next id.
void writeGrains(Writer& w, const System::Impl& I)
{
    writeColumns(w, I.columns, I.x.size());
    w.write("nextGrainId", &I.nextId, 1, 0, H5T_NATIVE_LONG);
}

/// writeHDF5 stage: the walls (type; point, normal, end, velocity,
/// displacement [m, m/s]; vertices [m] and triangles of triangulated
/// surfaces) and their friction.
void writeWalls(Writer& w, const System::Impl& I)
{
    std::vector<int> wt;
    std::vector<double> wd;
    for (std::size_t k = 0; k < I.walls.size(); ++k)
    {
        const Wall& W = I.walls[k];
        wt.push_back(W.type);
        put3(wd, W.p);
        put3(wd, W.n);
        put3(wd, W.b);
        put3(wd, W.velocity);
        put3(wd, W.displacement);
        if (W.type == TriangleWall)
        {
            std::vector<double> vv;
            for (const Vec3& a : W.vertices) put3(vv, a);
            std::vector<int> tt;
            for (const auto& a : W.triangles)
                for (int c : a) tt.push_back(c);
            w.d("wallVertices_" + std::to_string(k), vv, 3);
            w.i("wallTriangles_" + std::to_string(k), tt, 3);
        }
    }
    w.i("wallTypes", wt, 0);
    w.d("walls", wd, 15);
    std::vector<double> wf;
    for (const Wall& W : I.walls) wf.push_back(W.friction);
    w.d("wallFriction", wf, 0);
}

/// writeHDF5 stage: the persistent contacts (bodies in the external grain
/// order, as rows of the whole state with part, normal, impulses [N s],
/// Delassus terms, gap [m], ages).
void writeContacts(Writer& w, const System::Impl& I, const System::StatePart* part)
{
    const long N = long(I.x.size());
    const bool byRows = part && !part->rowOf.empty();
    auto row = [&](long b) -> long
    {
        if (!part) return b;
        if (b >= N) return part->nGrains + (b - N); // a wall
        if (byRows) return part->rowOf.at(std::size_t(b));
        if (b < long(part->written)) return part->first + b;
        return part->otherRows.at(std::size_t(b) - part->written);
    };
    // byRows: the contacts of the written grains of smaller id, both rows known
    std::vector<char> written(byRows ? std::size_t(N) : 0, 0);
    if (byRows)
        for (std::size_t i : part->rows) written.at(i) = 1;
    std::vector<const Contact*> kept;
    for (const Contact& c : I.contacts)
    {
        const long a = I.grainOf(c.i), b = I.grainOf(I.keptBody(c));
        const long first = b >= N || I.ids[a] < I.ids[b] ? a : b;
        if (!byRows || (written[first] && row(a) >= 0 && row(b) >= 0)) kept.push_back(&c);
    }
    std::vector<int> ij;
    std::vector<double> cd;
    for (const Contact* k : kept) // slots to grains (external order)
    {
        const Contact& c = *k;
        ij.push_back(row(I.grainOf(c.i)));
        ij.push_back(row(I.grainOf(I.keptBody(c))));
        put3(cd, c.n);
        put3(cd, c.rt);
        for (double a : {c.rn, c.wnn, c.wtt, c.bias, c.mu, c.coh, c.gap, c.change}) cd.push_back(a);
    }
    w.i("contactBodies", ij, 2);
    w.d("contactData", cd, 14);
    // contact ages (optional dataset: files without it read with age 0)
    std::vector<int> age;
    age.reserve(kept.size());
    for (const Contact* c : kept) age.push_back(c->age);
    w.i("contactAge", age, 0);
}

/// writeHDF5 stage: the internal grain order (slot -> grain), the reorder
/// state and cohesionMinAge (optional datasets: files without them read with
/// the order of the grains, never reordered, and cohesionMinAge 0).
void writeOrder(Writer& w, const System::Impl& I)
{
    const System::Settings& S = I.settings;
    w.i("grainOrder", I.order, 0);
    w.write("reorder", std::vector<long>{S.reorderInterval, I.stepsSinceReorder}.data(), 2, 0,
            H5T_NATIVE_LONG);
    w.i("cohesionMinAge", {S.cohesionMinAge}, 0);
}

/// writeHDF5 stage: wall temperatures [K] (NaN adiabatic), default
/// temperature [K] and heat solver settings (the grains' heat state is in
/// their columns, writeGrains).
void writeHeat(Writer& w, const System::Impl& I)
{
    const System::Settings& S = I.settings;
    std::vector<double> wT;
    for (const Wall& W : I.walls) wT.push_back(W.temperature); // NaN: adiabatic
    w.d("wallTemperature", wT, 0);
    w.d("heatSettings", {I.temperatureColumn().defaultValue(), S.heatTolerance, double(S.heatMaxIterations)},
        0);
}

hid_t createState(H5File& h, const std::string& file, const std::string& preamble)
{
    hid_t fcpl = H5P_DEFAULT;
    if (!preamble.empty())
    {
        hsize_t block = 512; // HDF5 user blocks: 0 or a power of 2 >= 512
        while (block < preamble.size()) block *= 2;
        fcpl = H5Pcreate(H5P_FILE_CREATE);
        H5Pset_userblock(fcpl, block);
    }
    h.id = H5Fcreate(file.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    if (fcpl != H5P_DEFAULT) H5Pclose(fcpl);
    if (h.id < 0) throw InputError("nscd::System::writeHDF5: cannot create " + file);
    return h.id;
}

void closeState(H5File& h, const std::string& file, const std::string& preamble)
{
    if (H5Fflush(h.id, H5F_SCOPE_LOCAL) < 0)
        throw InputError("nscd::System::writeHDF5: cannot flush " + file);
    if (preamble.empty()) return;
    // the user block, after HDF5 has closed the file
    const herr_t closed = H5Fclose(h.id);
    h.id = -1;
    std::FILE* fp = closed < 0 ? nullptr : std::fopen(file.c_str(), "r+b");
    const bool ok = fp && std::fwrite(preamble.data(), 1, preamble.size(), fp) == preamble.size();
    if (!(fp && std::fclose(fp) == 0 && ok))
        throw InputError("nscd::System::writeHDF5: cannot write the preamble of " + file);
}
} // namespace io

void System::writeHDF5(const std::string& file, const std::string& preamble) const
{
    const Impl& I = *impl_;
    H5File h;
    Writer w{io::createState(h, file, preamble), file};
    io::writeHeader(w, I);
    io::writeGrains(w, I);
    io::writeWalls(w, I);
    io::writeContacts(w, I, nullptr);
    io::writeOrder(w, I);
    io::writeHeat(w, I);
    io::closeState(h, file, preamble);
}

namespace
{
/// readHDF5 stage: time, last dt, cohesion force [s, s, N], gravity [m/s^2]
/// and the solver settings, from r into I.
void readHeader(Reader& r, System::Impl& I)
{
    const auto tm = r.d("time", 0, 3);
    I.time = tm[0];
    I.lastDt = tm[1];
    I.cohesionForce = tm[2];
    // (optional: files written before it existed read the law of lastDt)
    I.lastComplianceDt =
        H5Lexists(r.f, "complianceStep", H5P_DEFAULT) > 0 ? r.d("complianceStep", 0, 1)[0] : 0.0;
    I.g = get3(r.d("gravity", 0, 3), 0);
    const auto st = r.d("settings", 0, 10);
    I.settings.tolerance = st[0];
    I.settings.maxIterations = int(st[1]);
    I.settings.overlapTolerance = st[2];
    I.settings.alertDistanceFactor = st[3];
    I.settings.alertMargin = st[4];
    I.settings.cohesionDistance = st[5];
    I.settings.warmStart = st[6] != 0;
    I.settings.ordering =
        st[7] == 1.0 ? System::Settings::Ordering::Fifo : System::Settings::Ordering::Symmetric;
    I.settings.overlapSlop = st[8];
    I.settings.relaxation = st[9];
}

/// readHDF5 stage: the materials (SI, see Material) added to s, validated by
/// System::addMaterial.
void readMaterials(Reader& r, System& s)
{
    const auto m = r.d("materials", 6);
    // contact compliance (optional: files written before it existed are hard)
    std::vector<double> cm;
    if (H5Lexists(r.f, "materialCompliance", H5P_DEFAULT) > 0)
        cm = r.d("materialCompliance", 2, long(m.size() / 6));
    for (std::size_t k = 0; k < m.size() / 6; ++k)
    {
        Material a{m[6 * k], m[6 * k + 1], m[6 * k + 2], m[6 * k + 3], m[6 * k + 4], m[6 * k + 5]};
        if (!cm.empty())
        {
            a.compliance = cm[2 * k];
            a.relativeCompliance = cm[2 * k + 1];
        }
        try
        {
            s.addMaterial(a);
        }
        catch (const InputError& e)
        {
            r.fail(std::string("bad material: ") + e.what());
        }
    }
}

/// readHDF5 stage: the values of grain k of the file (k: the k-th read)
/// checked: radius, material, finite vectors, temperature.
void checkGrain(Reader& r, const System::Impl& I, long k, long inFile)
{
    const std::string g = "grain " + std::to_string(inFile) + ": ";
    // std::isfinite first: an ordered comparison with a NaN raises
    // FE_INVALID (SIGFPE under OpenFOAM's FPE trapping)
    if (!std::isfinite(I.rad[k]) || !(I.rad[k] > 0))
        r.fail(g + "radius " + std::to_string(I.rad[k]) + " (radii must be finite and > 0)");
    if (I.mat[k] < 0 || I.mat[k] >= int(I.materials.size()))
        r.fail(g + "material id " + std::to_string(I.mat[k]) + " (the file has "
               + std::to_string(I.materials.size()) + " materials)");
    const std::pair<const char*, const std::vector<Vec3>*> vec3[] = {{"position", &I.x},
                                                                     {"velocity", &I.v},
                                                                     {"angular velocity", &I.w},
                                                                     {"force", &I.force},
                                                                     {"torque", &I.torque}};
    // (std::isfinite by component: Eigen's allFinite computes a - a, which
    // raises FE_INVALID on an infinity)
    auto finite = [](const auto& a)
    { return std::all_of(a.data(), a.data() + a.size(), [](double c) { return std::isfinite(c); }); };
    for (const auto& e : vec3)
    {
        const Vec3& a = (*e.second)[k];
        if (!finite(a))
            r.fail(g + "non-finite " + e.first + " (" + std::to_string(a.x()) + ", " + std::to_string(a.y())
                   + ", " + std::to_string(a.z()) + ")");
    }
    if (!finite(I.q[k].coeffs())) r.fail(g + "non-finite orientation");
    if (!std::isfinite(I.T[k]) || I.T[k] < 0)
        r.fail("grain " + std::to_string(inFile) + ": temperature " + std::to_string(I.T[k])
               + " K (must be finite and >= 0)");
}

/// readHDF5 stage: every ColumnRestart grain column (see writeGrains) into
/// I (materials already read; a column's default where an optional dataset
/// is absent): the N grains of the file, or (pick) those listed (ascending
/// grain numbers of the file; ids: the file's, else the grain numbers);
/// then masses and inertias, the order of addition. Returns N.
long readGrains(Reader& r, System::Impl& I, const std::vector<long>* pick)
{
    const long N = r.rows("radii", 0);
    const std::vector<std::string> missing = readColumns(r, I.columns, N, pick);
    const long NK = long(I.x.size());
    for (long k = 0; k < NK; ++k)
    {
        checkGrain(r, I, k, pick ? (*pick)[k] : k);
        I.setMassInertia(std::size_t(k));
    }
    I.order.resize(NK);
    std::iota(I.order.begin(), I.order.end(), 0);
    I.rebuildSlotOf();
    if (std::find(missing.begin(), missing.end(), "grainIds") == missing.end())
    {
        I.nextId = r.read<long>("nextGrainId", H5T_NATIVE_LONG, 0, 1)[0];
        std::vector<long> sortedIds(I.ids);
        std::sort(sortedIds.begin(), sortedIds.end());
        for (long k = 0; k < NK; ++k)
            if (sortedIds[k] < 0 || sortedIds[k] >= I.nextId || (k > 0 && sortedIds[k] == sortedIds[k - 1]))
                r.fail("grain ids are not unique values in [0, nextGrainId)");
    }
    else
    {
        // the grain numbers of the file (the ids a whole read gives)
        if (pick)
            I.ids = *pick;
        else
            std::iota(I.ids.begin(), I.ids.end(), 0L);
        I.nextId = N;
    }
    return N;
}

/// readHDF5 stage: the walls (geometry [m], velocity [m/s], displacement [m],
/// triangulated surfaces with their trees) and their friction, into I.
void readWalls(Reader& r, System::Impl& I)
{
    const auto wt = r.i("wallTypes", 0);
    const auto wd = r.d("walls", 15, long(wt.size()));
    for (std::size_t k = 0; k < wt.size(); ++k)
    {
        Wall W;
        W.type = wt[k];
        if (W.type < PlaneWall || W.type > TriangleWall) r.fail("bad wall type");
        W.p = get3(wd, 15 * k);
        W.n = get3(wd, 15 * k + 3);
        W.b = get3(wd, 15 * k + 6);
        W.velocity = get3(wd, 15 * k + 9);
        W.displacement = get3(wd, 15 * k + 12);
        if (W.type == TriangleWall)
        {
            const auto vv = r.d("wallVertices_" + std::to_string(k), 3);
            const auto tt = r.i("wallTriangles_" + std::to_string(k), 3);
            for (std::size_t a = 0; a < vv.size() / 3; ++a) W.vertices.push_back(get3(vv, 3 * a));
            for (std::size_t a = 0; a < tt.size() / 3; ++a)
            {
                W.triangles.push_back({tt[3 * a], tt[3 * a + 1], tt[3 * a + 2]});
                for (int c = 0; c < 3; ++c)
                    if (tt[3 * a + c] < 0 || tt[3 * a + c] >= int(W.vertices.size()))
                        r.fail("bad triangle index");
            }
            if (W.triangles.empty()) r.fail("empty triangulated wall");
            W.tree = buildTriangleTree(W.vertices, W.triangles);
            buildTriangleFeatures(W);
        }
        I.walls.push_back(std::move(W));
        linkSegment(I.walls, int(I.walls.size()) - 1);
    }
    // per-wall friction (optional: files written before it existed use the grains')
    if (H5Lexists(r.f, "wallFriction", H5P_DEFAULT) > 0)
    {
        const auto wf = r.d("wallFriction", 0, long(I.walls.size()));
        for (std::size_t k = 0; k < I.walls.size(); ++k) I.walls[k].friction = wf[k];
    }
}

/// readHDF5 stage: the contact records (bodies as grain numbers in the
/// external order and wall N + id, normal, impulses [N s], Delassus terms,
/// gap [m], ages) into I.contacts, N grains of the file and the walls
/// already read; pick (the grains read, see readGrains): only the contacts
/// among them and with the walls, their bodies numbered as read.
void readContacts(Reader& r, System::Impl& I, long N, const std::vector<long>* pick)
{
    const long NB = N + long(I.walls.size());
    std::vector<int> ij;
    std::vector<long> cpick; // pick: the contacts kept (numbers in the file)
    long NC = 0;
    auto check = [&](long k, int i, int j)
    {
        if (i < 0 || i >= N || j < 0 || j >= NB) r.fail("bad contact " + std::to_string(k));
        if (i == j) r.fail("bad contact " + std::to_string(k) + " (a grain with itself)");
    };
    if (!pick)
    {
        ij = r.i("contactBodies", 2);
        NC = long(ij.size() / 2);
        for (long k = 0; k < NC; ++k) check(k, ij[2 * k], ij[2 * k + 1]);
    }
    else
    {
        // the grains read, by their number in the file
        std::vector<int> readAs(N, -1);
        const long NK = long(pick->size());
        for (long k = 0; k < NK; ++k) readAs[(*pick)[k]] = int(k);
        r.visit<int>("contactBodies", H5T_NATIVE_INT, 2, -1,
                     [&](long a, long n, const int* b)
                     {
                         for (long k = 0; k < n; ++k)
                         {
                             const int i = b[2 * k], j = b[2 * k + 1];
                             check(a + k, i, j);
                             const int jr = j >= N ? int(NK + (j - N)) : readAs[j];
                             if (readAs[i] < 0 || jr < 0) continue;
                             cpick.push_back(a + k);
                             ij.push_back(readAs[i]);
                             ij.push_back(jr);
                         }
                         NC = a + n;
                     });
    }
    const auto cd = r.d("contactData", 14, NC, pick ? &cpick : nullptr);
    const long NCK = long(ij.size() / 2);
    I.contacts.resize(NCK);
    for (long k = 0; k < NCK; ++k)
    {
        Contact& c = I.contacts[k];
        c.i = ij[2 * k];
        c.j = ij[2 * k + 1];
        c.n = get3(cd, 14 * k);
        c.rt = get3(cd, 14 * k + 3);
        const double* p = &cd[14 * k + 6];
        c.rn = p[0];
        c.wnn = p[1];
        c.wtt = p[2];
        c.bias = p[3];
        c.mu = p[4];
        c.coh = p[5];
        c.gap = p[6];
        c.change = p[7];
    }
    // contact ages (optional: files written before they existed read with age 0)
    if (H5Lexists(r.f, "contactAge", H5P_DEFAULT) > 0)
    {
        const auto age = r.i("contactAge", 0, NC, pick ? &cpick : nullptr);
        for (long k = 0; k < NCK; ++k)
        {
            if (age[k] < 0) r.fail("negative contact age " + std::to_string(pick ? cpick[k] : k));
            I.contacts[k].age = age[k];
        }
    }
}

/// readHDF5 stage: the internal grain order and reorder state (optional;
/// a part of the file (pick) keeps the reorder interval only: its grains are
/// sorted again at its first step), then the contacts' grain numbers mapped
/// to slots (i < j for grain pairs) and sorted by i.
void readOrder(Reader& r, System::Impl& I, long N, bool part)
{
    if (part && H5Lexists(r.f, "reorder", H5P_DEFAULT) > 0)
    {
        const auto ro = r.read<long>("reorder", H5T_NATIVE_LONG, 0, 2);
        if (ro[0] < 0 || ro[0] > std::numeric_limits<int>::max())
            r.fail("bad reorder dataset (interval " + std::to_string(ro[0]) + ")");
        I.settings.reorderInterval = int(ro[0]);
    }
    else if (H5Lexists(r.f, "grainOrder", H5P_DEFAULT) > 0)
    {
        const auto ord = r.i("grainOrder", 0, N);
        std::vector<char> seen(N, 0);
        for (long k = 0; k < N; ++k)
        {
            if (ord[k] < 0 || ord[k] >= N || seen[ord[k]])
                r.fail("grainOrder is not a permutation of the grains (entry " + std::to_string(k) + ")");
            seen[ord[k]] = 1;
        }
        I.order = ord;
        I.rebuildSlotOf();
        const auto ro = r.read<long>("reorder", H5T_NATIVE_LONG, 0, 2);
        if (ro[0] < 0 || ro[0] > std::numeric_limits<int>::max() || ro[1] < -1)
            r.fail("bad reorder dataset (interval " + std::to_string(ro[0]) + ", steps "
                   + std::to_string(ro[1]) + ")");
        I.settings.reorderInterval = int(ro[0]);
        I.stepsSinceReorder = ro[1];
    }
    N = long(I.x.size());
    for (Contact& c : I.contacts)
    {
        c.i = I.slotOf[c.i];
        if (c.j >= N) continue;
        c.j = I.slotOf[c.j];
        if (c.j < c.i)
        {
            std::swap(c.i, c.j);
            c.n = -c.n;
            c.rt = -c.rt;
        }
    }
    std::stable_sort(I.contacts.begin(), I.contacts.end(),
                     [](const Contact& a, const Contact& b) { return a.i < b.i; });
    I.keptContactsN = -1; // written for the grains read
}

/// readHDF5 stage: heat settings (optional datasets: default temperature
/// [K], heat solver settings, wall temperatures [K], NaN adiabatic) into I;
/// the grains' heat state is in their columns (readGrains). Files written
/// before they existed keep the defaults (adiabatic walls).
void readHeat(Reader& r, System::Impl& I)
{
    auto has = [&](const char* name) { return H5Lexists(r.f, name, H5P_DEFAULT) > 0; };
    if (has("heatSettings"))
    {
        const auto hs = r.d("heatSettings", 0, 3);
        I.temperatureColumn().setDefault(hs[0]);
        I.settings.heatTolerance = hs[1];
        I.settings.heatMaxIterations = int(hs[2]);
    }
    if (has("wallTemperature"))
    {
        const auto wT = r.d("wallTemperature", 0, long(I.walls.size()));
        for (std::size_t k = 0; k < I.walls.size(); ++k) I.walls[k].temperature = wT[k];
    }
}
} // namespace

System System::readHDF5(const std::string& file) { return readHDF5(file, nullptr); }

Reader h5::openState(H5File& h, const std::string& file)
{
    if (H5Fis_hdf5(file.c_str()) <= 0)
        throw InputError("nscd::System::readHDF5: " + file
                         + " is missing or not an HDF5 file"
                           " (damaged or truncated?)");
    h.id = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (h.id < 0)
        throw InputError("nscd::System::readHDF5: cannot open " + file
                         + ": the file is damaged or truncated"
                           " (e.g. a write cut by a full disk or a kill)");
    Reader r{h.id, file};
    if (r.i("format", 0, 1)[0] != io::formatVersion) r.fail("unsupported format version");
    io::checkParts(r);
    return r;
}

// Memory of a partial read: the part, plus the radii and one chunk of 65,536
// rows while the grains are picked, and one int per grain of the file while
// the contacts are.
System System::readHDF5(const std::string& file, const std::function<bool(const Vec3&, double)>& keep,
                        const std::function<void(System&)>& declare)
{
    H5File h;
    Reader r = openState(h, file);
    const int dim = r.i("dimension", 0, 1)[0];
    if (dim != 2 && dim != 3) r.fail("bad dimension");
    System s(dim);
    Impl& I = *s.impl_;
    readHeader(r, I);
    readMaterials(r, s);
    if (declare) declare(s);
    // keep: the grain numbers whose centre it accepts (a pass over the positions)
    std::vector<long> pick;
    if (keep)
    {
        const auto rad = r.d("radii", 0);
        r.visit<double>(
            "positions", H5T_NATIVE_DOUBLE, 3, long(rad.size()),
            [&](long a, long n, const double* x)
            {
                for (long k = 0; k < n; ++k)
                    if (keep(Vec3(x[3 * k], x[3 * k + 1], dim == 2 ? 0.0 : x[3 * k + 2]), rad[a + k]))
                        pick.push_back(a + k);
            });
    }
    const std::vector<long>* part = keep ? &pick : nullptr;
    const long N = readGrains(r, I, part);
    readWalls(r, I);
    readContacts(r, I, N, part);
    readOrder(r, I, N, part);
    if (H5Lexists(r.f, "cohesionMinAge", H5P_DEFAULT) > 0)
    {
        I.settings.cohesionMinAge = r.i("cohesionMinAge", 0, 1)[0];
        if (I.settings.cohesionMinAge < 0) r.fail("negative cohesionMinAge");
    }
    readHeat(r, I);
    return s;
}

} // namespace nscd
