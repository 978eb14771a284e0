// SPDX-License-Identifier: GPL-3.0-or-later
// A state written in parts (one per rank of a decomposed run, each holding
// only its grains) and joined into one file by HDF5 virtual datasets (VDS,
// HDF5 >= 1.10, in the serial HDF5 build): the joined file holds the shared
// data (time, settings, walls) and, for every per-grain or per-contact
// dataset, a virtual dataset mapping rows [first, first + n) to the part
// that wrote them. Readers (readHDF5, h5py, ParaView through the XDMF) see
// one state; no writer ever holds more than its part. Also the small
// readers of one dataset (grainIdsHDF5, grainRadiiHDF5).
#include "ColumnsHDF5.H"
#include "IOStages.H"

#include <hdf5.h>

#include <memory>
#include <numeric>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace nscd
{

namespace
{
using h5::H5File;
using h5::openState;
using h5::Reader;
using h5::Writer;

/// The directory of file, with its trailing '/' ("" for a bare name).
std::string directoryOf(const std::string& file)
{
    const std::size_t s = file.rfind('/');
    return s == std::string::npos ? std::string() : file.substr(0, s + 1);
}

/// RAII set of HDF5 ids closed with their own function.
struct Ids
{
    std::vector<std::pair<hid_t, herr_t (*)(hid_t)>> ids;
    hid_t add(hid_t id, herr_t (*close)(hid_t))
    {
        if (id >= 0) ids.emplace_back(id, close);
        return id;
    }
    ~Ids()
    {
        for (auto it = ids.rbegin(); it != ids.rend(); ++it) it->second(it->first);
    }
};

/// The names of the datasets at the root of file f.
std::vector<std::string> datasetNames(hid_t f)
{
    H5G_info_t info;
    std::vector<std::string> names;
    if (H5Gget_info(f, &info) < 0) return names;
    for (hsize_t k = 0; k < info.nlinks; ++k)
    {
        const ssize_t n = H5Lget_name_by_idx(f, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
        std::string name(std::size_t(n > 0 ? n : 0), '\0');
        H5Lget_name_by_idx(f, ".", H5_INDEX_NAME, H5_ITER_INC, k, &name[0], name.size() + 1, H5P_DEFAULT);
        names.push_back(name);
    }
    return names;
}

/// Join dataset name of the open parts pf (relative names parts) into a
/// virtual dataset of file f.
void joinDataset(hid_t f, const std::string& file, const std::string& name, const std::vector<hid_t>& pf,
                 const std::vector<std::string>& parts)
{
    auto fail = [&](const std::string& why)
    { throw InputError("nscd::System::writeHDF5Joined: " + file + ": dataset '" + name + "': " + why); };
    Ids ids;
    std::vector<hsize_t> rows(pf.size());
    hsize_t cols = 0;
    int rank = 0;
    hid_t type = -1;
    for (std::size_t p = 0; p < pf.size(); ++p)
    {
        const hid_t ds = ids.add(H5Dopen2(pf[p], name.c_str(), H5P_DEFAULT), H5Dclose);
        if (ds < 0) fail("missing in " + parts[p]);
        const hid_t sp = ids.add(H5Dget_space(ds), H5Sclose);
        hsize_t d[2] = {0, 0};
        const int nd = H5Sget_simple_extent_dims(sp, d, nullptr);
        if (p == 0)
        {
            rank = nd;
            cols = d[1];
            type = ids.add(H5Dget_type(ds), H5Tclose);
        }
        if (nd != rank || nd < 1 || nd > 2 || d[1] != cols) fail("another shape in " + parts[p]);
        rows[p] = d[0];
    }
    const hsize_t total = std::accumulate(rows.begin(), rows.end(), hsize_t(0));
    const hsize_t dims[2] = {total, cols};
    const hid_t space = ids.add(H5Screate_simple(rank, dims, nullptr), H5Sclose);
    const hid_t dcpl = ids.add(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    H5Pset_obj_track_times(dcpl, 0);
    hsize_t first = 0;
    for (std::size_t p = 0; p < pf.size(); ++p)
    {
        if (rows[p] == 0) continue;
        const hsize_t n[2] = {rows[p], cols};
        const hsize_t at[2] = {first, 0};
        const hid_t src = ids.add(H5Screate_simple(rank, n, nullptr), H5Sclose);
        H5Sselect_hyperslab(space, H5S_SELECT_SET, at, nullptr, n, nullptr);
        if (H5Pset_virtual(dcpl, space, parts[p].c_str(), name.c_str(), src) < 0)
            fail("cannot map the rows of " + parts[p]);
        first += rows[p];
    }
    H5Sselect_all(space);
    const hid_t ds =
        ids.add(H5Dcreate2(f, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
    if (ds < 0) fail("cannot create the virtual dataset");
}
} // namespace

long System::nextGrainId() const { return impl_->nextId; }

std::vector<long> System::grainIdsHDF5(const std::string& file)
{
    H5File h;
    Reader r = openState(h, file);
    const long N = r.rows("radii", 0);
    if (H5Lexists(r.f, "grainIds", H5P_DEFAULT) > 0) return r.read<long>("grainIds", H5T_NATIVE_LONG, 0, N);
    std::vector<long> ids(N);
    for (long k = 0; k < N; ++k) ids[k] = k;
    return ids;
}

std::vector<double> System::grainRadiiHDF5(const std::string& file)
{
    H5File h;
    Reader r = openState(h, file);
    return r.d("radii", 0);
}

void System::writeHDF5Part(const std::string& file, const StatePart& part) const
{
    const Impl& I = *impl_;
    const bool byRows = !part.rowOf.empty();
    if (byRows ? part.rowOf.size() != I.x.size()
               : part.written > I.x.size() || part.written + part.otherRows.size() != I.x.size())
        throw InputError("nscd::System::writeHDF5Part: " + file + ": " + std::to_string(part.written) + " + "
                         + std::to_string(part.otherRows.size()) + " rows for " + std::to_string(I.x.size())
                         + " grains");
    H5File h;
    Writer w{io::createState(h, file, ""), file};
    writeColumns(w, I.columns, part.written, byRows ? &part.rows : nullptr);
    std::vector<int> order(byRows ? part.rows.size() : part.written);
    std::iota(order.begin(), order.end(), int(part.first));
    w.i("grainOrder", order, 0);
    io::writeContacts(w, I, &part);
    io::closeState(h, file, "");
}

void System::writeHDF5Joined(const std::string& file, const std::vector<std::string>& parts, long nextId,
                             const std::string& preamble) const
{
    const Impl& I = *impl_;
    if (parts.empty()) throw InputError("nscd::System::writeHDF5Joined: " + file + ": no parts");
    H5File h; // (silences HDF5's error printing until the parts are closed)
    Ids open;
    std::vector<hid_t> pf(parts.size());
    const std::string dir = directoryOf(file);
    for (std::size_t p = 0; p < parts.size(); ++p)
    {
        pf[p] = open.add(H5Fopen((dir + parts[p]).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
        if (pf[p] < 0)
            throw InputError("nscd::System::writeHDF5Joined: " + file + ": cannot open its part " + dir
                             + parts[p]);
    }
    Writer w{io::createState(h, file, preamble), file};
    io::writeHeader(w, I);
    io::writeWalls(w, I);
    io::writeHeat(w, I);
    const System::Settings& S = I.settings;
    w.write("reorder", std::vector<long>{S.reorderInterval, I.stepsSinceReorder}.data(), 2, 0,
            H5T_NATIVE_LONG);
    w.i("cohesionMinAge", {S.cohesionMinAge}, 0);
    w.write("nextGrainId", &nextId, 1, 0, H5T_NATIVE_LONG);
    for (const std::string& name : datasetNames(pf[0])) joinDataset(h.id, file, name, pf, parts);
    io::closeState(h, file, preamble);
}

namespace
{
/// The source files of the virtual dataset radii of file f (every part
/// holds every dataset: radii stands for them); empty if it is not virtual.
std::vector<std::string> sourcesOf(hid_t f)
{
    std::vector<std::string> out;
    if (H5Lexists(f, "radii", H5P_DEFAULT) <= 0) return out;
    Ids ids;
    const hid_t ds = ids.add(H5Dopen2(f, "radii", H5P_DEFAULT), H5Dclose);
    const hid_t dcpl = ds < 0 ? -1 : ids.add(H5Dget_create_plist(ds), H5Pclose);
    size_t count = 0;
    if (dcpl >= 0 && H5Pget_layout(dcpl) == H5D_VIRTUAL) H5Pget_virtual_count(dcpl, &count);
    for (size_t k = 0; k < count; ++k)
    {
        const ssize_t n = H5Pget_virtual_filename(dcpl, k, nullptr, 0);
        std::string name(std::size_t(n > 0 ? n : 0), '\0');
        H5Pget_virtual_filename(dcpl, k, &name[0], name.size() + 1);
        out.push_back(name);
    }
    return out;
}
} // namespace

std::vector<std::string> System::partsOfHDF5(const std::string& file)
{
    H5File h;
    if (H5Fis_hdf5(file.c_str()) <= 0) return {};
    h.id = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    return h.id < 0 ? std::vector<std::string>() : sourcesOf(h.id);
}

void io::checkParts(h5::Reader& r)
{
    const std::string dir = directoryOf(r.file);
    std::string missing;
    for (const std::string& name : sourcesOf(r.f))
    {
        struct stat st;
        const std::string path = !name.empty() && name[0] == '/' ? name : dir + name;
        if (missing.empty() && name != "." && ::stat(path.c_str(), &st) != 0) missing = path;
    }
    if (!missing.empty())
        r.fail("its part " + missing
               + " is missing (a state written in parts by a decomposed run: keep its directory"
                 " beside it)");
}

} // namespace nscd
