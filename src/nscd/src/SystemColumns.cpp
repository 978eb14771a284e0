// SPDX-License-Identifier: GPL-3.0-or-later
// The System's own per-grain columns (SystemColumns.H) and the
// HDF5 write/read of every ColumnRestart column of a registry.
#include "ColumnsHDF5.H"
#include "SystemImpl.H"

#include <algorithm>
#include <map>
#include <memory>
#include <utility>

namespace nscd
{

namespace
{
constexpr unsigned RMG = ColumnRestart | ColumnMigrate | ColumnGhost; // state of a grain
constexpr unsigned MG = ColumnMigrate | ColumnGhost;                  // travels, not in the file
constexpr unsigned ORMG = ColumnOptional | RMG;                       // added to the file later

/// Declare column name in c and return its vector.
template <class T>
std::vector<T>& declare(GrainColumns& c, const char* name, unsigned flags, const T& def,
                        ColumnDataset ds = {})
{
    return static_cast<TypedColumn<T>&>(c[c.add<T>(name, flags, def, 0, std::move(ds))]).data();
}
} // namespace

// The datasets are those of the files written before the registry existed
// (the flags of "fixed" packed in one int, "heatExchange" N x 2 of h, Tf).
SystemColumns::SystemColumns()
    : ids(declare<long>(columns, "grainIds", ColumnRestart | ColumnOptional, 0L)),
      x(declare<Vec3>(columns, "positions", RMG, Vec3::Zero())),
      v(declare<Vec3>(columns, "velocities", RMG, Vec3::Zero())),
      w(declare<Vec3>(columns, "angularVelocities", RMG, Vec3::Zero())),
      q(declare<Eigen::Quaterniond>(columns, "orientations", RMG, Eigen::Quaterniond::Identity(),
                                    {"orientations_xyzw"})),
      force(declare<Vec3>(columns, "forces", RMG, Vec3::Zero())),
      torque(declare<Vec3>(columns, "torques", RMG, Vec3::Zero())),
      rad(declare<double>(columns, "radii", RMG, 0.0)), mat(declare<int>(columns, "materialIds", RMG, 0)),
      fix(declare<char>(columns, "fixed", RMG, char(0), {"fixed", 0, 0, 0})),
      rotLock(declare<char>(columns, "rotationLocked", RMG, char(0), {"fixed", 0, 0, 1})),
      mass(declare<double>(columns, "masses", 0, 0.0)), inertia(declare<double>(columns, "inertias", 0, 0.0)),
      dragCoefficient(declare<double>(columns, "dragCoefficients", MG, 0.0)),
      dragVelocity(declare<Vec3>(columns, "fluidVelocities", MG, Vec3::Zero())),
      dragImpulse(declare<Vec3>(columns, "fluidDragImpulses", MG, Vec3::Zero())),
      T(declare<double>(columns, "temperatures", ORMG, 0.0)),
      heatQ(declare<double>(columns, "heatSources", ORMG, 0.0)),
      heatH(declare<double>(columns, "heatExchangeCoefficients", ORMG, 0.0, {"heatExchange", 2, 0})),
      heatTf(declare<double>(columns, "bathTemperatures", ORMG, 0.0, {"heatExchange", 2, 1})),
      fixT(declare<char>(columns, "fixedTemperature", ORMG, char(0)))
{
}

GrainColumns& System::columnRegistry() { return impl_->columns; }
const GrainColumns& System::columns() const { return impl_->columns; }

namespace
{
/// A dataset of the state and the restart columns stored in it.
struct DatasetColumns
{
    std::string name;
    int width = 1; ///< entries per row
    bool oneD = true;
    enum Storage
    {
        Real,
        Int,
        Long
    } storage = Real;
    std::vector<int> columns;
};

DatasetColumns::Storage storageOf(ColumnType t)
{
    if (t == ColumnType::Int || t == ColumnType::Char) return DatasetColumns::Int;
    if (t == ColumnType::Long) return DatasetColumns::Long;
    return DatasetColumns::Real;
}

/// The datasets of the ColumnRestart columns of c, in order of first use.
std::vector<DatasetColumns> restartDatasets(const GrainColumns& c, const std::string& where)
{
    std::vector<DatasetColumns> out;
    std::map<std::string, std::size_t> index;
    for (int k = 0; k < c.count(); ++k)
    {
        if (!c[k].has(ColumnRestart)) continue;
        const ColumnDataset& ds = c[k].dataset();
        auto it = index.find(ds.name);
        if (it == index.end())
        {
            DatasetColumns d;
            d.name = ds.name;
            d.width = ds.width > 0 ? ds.width : c[k].components();
            d.oneD = ds.width == 0 && c[k].components() == 1;
            d.storage = storageOf(c[k].type());
            it = index.emplace(ds.name, out.size()).first;
            out.push_back(d);
        }
        DatasetColumns& d = out[it->second];
        if (storageOf(c[k].type()) != d.storage || ds.offset + c[k].components() > d.width || ds.offset < 0)
            throw InputError(where + ": column '" + c[k].name() + "' does not fit dataset '" + ds.name
                             + "' (its storage type or width)");
        d.columns.push_back(k);
    }
    return out;
}

/// Value of entry e of row i of dataset d from its columns (integers).
long integerEntry(const GrainColumns& c, const DatasetColumns& d, std::size_t i, int e)
{
    long a = 0;
    for (int k : d.columns)
    {
        const ColumnDataset& ds = c[k].dataset();
        if (ds.offset != e) continue;
        if (ds.bit >= 0)
            a |= (c[k].integer(i) ? 1L : 0L) << ds.bit;
        else
            a = c[k].integer(i);
    }
    return a;
}

template <class S>
void writeDataset(h5::Writer& w, const GrainColumns& c, const DatasetColumns& d, std::size_t N, hid_t type,
                  const std::vector<std::size_t>* rows)
{
    if (rows) N = rows->size();
    std::vector<S> buf(N * std::size_t(d.width), S(0));
    for (std::size_t n = 0; n < N; ++n)
    {
        const std::size_t i = rows ? (*rows)[n] : n;
        S* row = &buf[n * d.width];
        if constexpr (std::is_same<S, double>::value)
            for (int k : d.columns)
                for (int e = 0; e < c[k].components(); ++e) row[c[k].dataset().offset + e] = c[k].real(i, e);
        else
            for (int e = 0; e < d.width; ++e) row[e] = S(integerEntry(c, d, i, e));
    }
    w.write(d.name, buf.data(), N, d.oneD ? 0 : hsize_t(d.width), type);
}

/// Rows 0 ... of col from the rows of buf (rows of dataset d).
template <class S>
void fillColumn(GrainColumn& col, const std::vector<S>& buf, const DatasetColumns& d)
{
    const std::size_t NK = buf.size() / std::size_t(d.width);
    const ColumnDataset& ds = col.dataset();
    for (std::size_t i = 0; i < NK; ++i)
    {
        const S* row = &buf[i * d.width];
        if constexpr (std::is_same<S, double>::value)
            for (int e = 0; e < col.components(); ++e) col.setReal(i, e, row[ds.offset + e]);
        else
            col.setInteger(i, ds.bit >= 0 ? (long(row[ds.offset]) >> ds.bit) & 1L : long(row[ds.offset]));
    }
}

template <class S>
void readDataset(h5::Reader& r, GrainColumns& c, const DatasetColumns& d, long N,
                 const std::vector<long>* pick, hid_t type)
{
    const std::vector<S> buf = r.read<S>(d.name, type, d.oneD ? 0 : hsize_t(d.width), N, pick);
    for (int k : d.columns) fillColumn(c[k], buf, d);
}

/// Rows pick (ascending) of dataset d into rows 0 ... of col.
void readPicked(h5::Reader& r, GrainColumn& col, const DatasetColumns& d, long N,
                const std::vector<long>& pick)
{
    const hsize_t cols = d.oneD ? 0 : hsize_t(d.width);
    if (d.storage == DatasetColumns::Real)
        fillColumn(col, r.read<double>(d.name, H5T_NATIVE_DOUBLE, cols, N, &pick), d);
    else if (d.storage == DatasetColumns::Int)
        fillColumn(col, r.read<int>(d.name, H5T_NATIVE_INT, cols, N, &pick), d);
    else
        fillColumn(col, r.read<long>(d.name, H5T_NATIVE_LONG, cols, N, &pick), d);
}
} // namespace

void writeColumns(h5::Writer& w, const GrainColumns& c, std::size_t N, const std::vector<std::size_t>* rows)
{
    for (const DatasetColumns& d : restartDatasets(c, "nscd::System::writeHDF5: " + w.file))
    {
        if (d.storage == DatasetColumns::Real)
            writeDataset<double>(w, c, d, N, H5T_NATIVE_DOUBLE, rows);
        else if (d.storage == DatasetColumns::Int)
            writeDataset<int>(w, c, d, N, H5T_NATIVE_INT, rows);
        else
            writeDataset<long>(w, c, d, N, H5T_NATIVE_LONG, rows);
    }
}

std::vector<std::string> readColumns(h5::Reader& r, GrainColumns& c, long N, const std::vector<long>* pick)
{
    c.grow(pick ? pick->size() : std::size_t(N));
    std::vector<std::string> missing;
    for (const DatasetColumns& d : restartDatasets(c, "nscd::System::readHDF5: " + r.file))
    {
        if (H5Lexists(r.f, d.name.c_str(), H5P_DEFAULT) <= 0)
        {
            for (int k : d.columns)
                if (!c[k].has(ColumnOptional))
                    r.fail("missing dataset '" + d.name + "' of the grain column '" + c[k].name()
                           + "' (declare the column optional to read such files with its default)");
            missing.push_back(d.name);
            continue;
        }
        if (d.storage == DatasetColumns::Real)
            readDataset<double>(r, c, d, N, pick, H5T_NATIVE_DOUBLE);
        else if (d.storage == DatasetColumns::Int)
            readDataset<int>(r, c, d, N, pick, H5T_NATIVE_INT);
        else
            readDataset<long>(r, c, d, N, pick, H5T_NATIVE_LONG);
    }
    return missing;
}

bool System::readColumnHDF5(const std::string& file, const std::string& name)
{
    const std::string where = "nscd::System::readColumnHDF5: " + file;
    GrainColumns& c = columnRegistry();
    const int k = c.find(name);
    if (k < 0 || !c[k].has(ColumnRestart))
        throw InputError(where + ": '" + name + "' is not a declared ColumnRestart column");
    DatasetColumns d;
    for (const DatasetColumns& e : restartDatasets(c, where))
        for (int j : e.columns)
            if (j == k) d = e;
    h5::H5File h;
    h5::Reader r = h5::openState(h, file);
    if (H5Lexists(r.f, d.name.c_str(), H5P_DEFAULT) <= 0) return false;
    // each grain's row in the file: the row of its grain id
    const std::vector<long> fileIds = grainIdsHDF5(file);
    std::map<long, long> rowOf;
    for (std::size_t i = 0; i < fileIds.size(); ++i) rowOf[fileIds[i]] = long(i);
    std::vector<std::pair<long, std::size_t>> at; // (row, grain), by row
    for (std::size_t g = 0; g < size(); ++g)
    {
        const auto it = rowOf.find(grainIds()[g]);
        if (it == rowOf.end())
            throw InputError(where + ": grain id " + std::to_string(grainIds()[g]) + " is not in the file");
        at.emplace_back(it->second, g);
    }
    std::sort(at.begin(), at.end());
    std::vector<long> pick(at.size());
    for (std::size_t j = 0; j < at.size(); ++j) pick[j] = at[j].first;
    std::unique_ptr<GrainColumn> rows = c[k].clone();
    rows->resize(pick.size());
    readPicked(r, *rows, d, long(fileIds.size()), pick);
    std::vector<char> buf(rows->elementBytes());
    for (std::size_t j = 0; j < at.size(); ++j)
    {
        rows->pack(j, buf.data());
        c[k].unpack(at[j].second, buf.data());
    }
    return true;
}

} // namespace nscd
