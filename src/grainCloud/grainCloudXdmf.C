/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud XDMF output (see grainCloud.H)
  SPDX-License-Identifier: GPL-3.0-or-later

Description
    The grains and their contacts for ParaView, read straight from the HDF5
    state: <case>/grainState.xmf, an XDMF 3 temporal collection with, per
    written time, a Polyvertex grid of the grains and a Polyline grid of
    the grain-grain contacts, every array pointing into
    <time>/grainState.h5 (no copy of the state).

    The state written by nscd (src/nscd/src/IO.cpp) holds no index list
    for the vertices, mixes grain-grain and wall contacts in /contactBodies
    (second body = nGrains + wall index for a wall) and stores impulses, so
    four small datasets are added to each state file before it is renamed
    into place (addXdmfDatasets; a decomposed run's parts each get theirs,
    joined with the rest, grainCloudStateParts.C):
      xdmfVertices        (N)     int    0 ... N-1
      xdmfContactPairs    (m, 2)  int    the grain-grain rows of /contactBodies
      xdmfNormalForce     (m, 3)  double rn n / dt   [N; 2D: N/m]
      xdmfTangentialForce (m, 3)  double rt / dt     [N; 2D: N/m]
    with dt = /time[1], the last sub-step's length; a state that has not
    stepped (dt = 0, grainDeposit without settling) stores the impulses
    [N s] instead and the XDMF names them normalImpulse/tangentialImpulse.
    Wall contacts are left out (the state holds no point of the wall).
    nscd's reader ignores these datasets.

    Also startStateHas: whether the start state holds a dataset.

    The .xmf lives in the case directory, not beside each grainState.h5:
    a file without a FoamFile header in a time directory makes foamToVTK,
    decomposePar and reconstructPar warn, and XML cannot carry that header.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "Time.H"
#include "OSspecific.H"
#include "writeCheck.H"

#include <hdf5.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{

//- HDF5 frees the library at exit (atexit): a file it could not close (a
//  write that failed on a full disk, then reported by a FatalError) makes
//  it loop there ("HDF5: infinite loop closing library") and crash at the
//  exit of the run.  Every HDF5 file of the project is closed by its
//  handle, so that clean-up is not needed: turned off when the library is
//  loaded, before any HDF5 call.
[[maybe_unused]] const bool hdf5NoAtExit = (H5dont_atexit() >= 0);

//- HDF5 file handle that silences HDF5's own error printing while open
//  (the errors are reported as exceptions naming the file)
struct h5Handle
{
    hid_t id = -1;
    H5E_auto2_t oldFunc = nullptr;
    void* oldData = nullptr;
    h5Handle()
    {
        H5Eget_auto2(H5E_DEFAULT, &oldFunc, &oldData);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~h5Handle()
    {
        if (id >= 0) H5Fclose(id);
        H5Eset_auto2(H5E_DEFAULT, oldFunc, oldData);
    }
};


//- Dimensions of dataset name in file f (empty if it does not exist)
std::vector<hsize_t> datasetDims(hid_t f, const std::string& name)
{
    if (H5Lexists(f, name.c_str(), H5P_DEFAULT) <= 0)
    {
        return {};
    }
    const hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    if (ds < 0)
    {
        return {};
    }
    const hid_t space = H5Dget_space(ds);
    const int nd = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> d(nd > 0 ? nd : 0);
    if (nd > 0)
    {
        H5Sget_simple_extent_dims(space, d.data(), nullptr);
    }
    H5Sclose(space);
    H5Dclose(ds);
    return d;
}


//- The whole dataset name of file (path: for the error) as T values
template<class T>
std::vector<T> readDataset
(
    hid_t f,
    const std::string& path,
    const std::string& name,
    hid_t type,
    std::size_t width
)
{
    const std::vector<hsize_t> d = datasetDims(f, name);
    if (d.empty() || (width > 1 && (d.size() != 2 || d[1] != width)))
    {
        throw std::runtime_error
        (
            path + ": dataset '" + name + "' missing or not of "
          + std::to_string(width) + " column(s)"
        );
    }
    std::vector<T> out(d[0]*width);
    const hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    const herr_t st =
        out.empty()
      ? 0
      : H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
    H5Dclose(ds);
    if (st < 0)
    {
        throw std::runtime_error(path + ": cannot read dataset '" + name + "'");
    }
    return out;
}


//- Write dataset name (rows x cols; cols 0: 1D) into file f, without
//  modification times (the same state gives the same bytes, as nscd's own
//  datasets)
void writeDataset
(
    hid_t f,
    const std::string& path,
    const std::string& name,
    const void* data,
    hsize_t rows,
    hsize_t cols,
    hid_t type
)
{
    const hsize_t dims[2] = {rows, cols};
    const hid_t space = H5Screate_simple(cols > 0 ? 2 : 1, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_obj_track_times(dcpl, 0);
    const hid_t ds = H5Dcreate2
    (
        f, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT
    );
    H5Pclose(dcpl);
    herr_t st = ds >= 0 ? 0 : -1;
    if (ds >= 0 && rows > 0)
    {
        st = H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
    }
    if (ds >= 0)
    {
        H5Dclose(ds);
    }
    H5Sclose(space);
    if (st < 0)
    {
        throw std::runtime_error
        (
            path + ": cannot write dataset '" + name + "'"
        );
    }
}


//- One XDMF DataItem pointing into an HDF5 file: ref is "file:/dataset",
//  number "Float" or "Int", precision the bytes per value in the file
std::string dataItem
(
    const std::string& ref,
    const std::string& dims,
    const char* number,
    const char* precision = "8"
)
{
    return
        "<DataItem Dimensions=\"" + dims + "\" NumberType=\"" + number
      + "\" Precision=\"" + precision + "\" Format=\"HDF\">" + ref
      + "</DataItem>";
}

const char* const gridMark = "<Grid Name=\"t=";


//- The XDMF grids of the state h5 (path relative to the case) at time
//  timeName (value time), on one line: the grains (nGrains; their
//  temperature if withTemperature) and, if any, the nPairs grain-grain
//  contacts (forces if the last sub-step dt > 0, else impulses)
std::string timeLine
(
    const std::string& h5,
    const Foam::word& timeName,
    const double time,
    const hsize_t nGrains,
    const hsize_t nPairs,
    const bool withTemperature,
    const double dt
)
{
    const std::string N(std::to_string(nGrains));
    const std::string M(std::to_string(nPairs));
    std::ostringstream line;
    line<< std::setprecision(15)
        << gridMark << timeName
        << "\" GridType=\"Collection\" CollectionType=\"Spatial\">"
        << "<Time Value=\"" << time << "\"/>"
        << "<Grid Name=\"grains\" GridType=\"Uniform\">"
        << "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << N
        << "\" NodesPerElement=\"1\">"
        << dataItem(h5 + ":/xdmfVertices", N, "Int", "4") << "</Topology>"
        << "<Geometry GeometryType=\"XYZ\">"
        << dataItem(h5 + ":/positions", N + " 3", "Float") << "</Geometry>";
    const char* nodeAttrs[][4] =
    {
        {"radius", "Scalar", "radii", "Float"},
        {"velocity", "Vector", "velocities", "Float"},
        {"angularVelocity", "Vector", "angularVelocities", "Float"},
        {"id", "Scalar", "grainIds", "Int"},
        {"temperature", "Scalar", "temperatures", "Float"}
    };
    for (const auto& a : nodeAttrs)
    {
        if (std::string(a[0]) == "temperature" && !withTemperature)
        {
            continue;
        }
        const bool vec = std::string(a[1]) == "Vector";
        line<< "<Attribute Name=\"" << a[0] << "\" AttributeType=\"" << a[1]
            << "\" Center=\"Node\">"
            << dataItem(h5 + ":/" + a[2], vec ? N + " 3" : N, a[3])
            << "</Attribute>";
    }
    line<< "</Grid>";
    // no contacts grid without contacts: VTK's XDMF reader fails on an
    // empty grid
    if (nPairs > 0)
    {
        const std::string unit(dt > 0 ? "Force" : "Impulse");
        line<< "<Grid Name=\"contacts\" GridType=\"Uniform\">"
            << "<Topology TopologyType=\"Polyline\" NumberOfElements=\"" << M
            << "\" NodesPerElement=\"2\">"
            << dataItem(h5 + ":/xdmfContactPairs", M + " 2", "Int", "4")
            << "</Topology>"
            << "<Geometry GeometryType=\"XYZ\">"
            << dataItem(h5 + ":/positions", N + " 3", "Float") << "</Geometry>"
            << "<Attribute Name=\"normal" << unit
            << "\" AttributeType=\"Vector\" Center=\"Cell\">"
            << dataItem(h5 + ":/xdmfNormalForce", M + " 3", "Float")
            << "</Attribute>"
            << "<Attribute Name=\"tangential" << unit
            << "\" AttributeType=\"Vector\" Center=\"Cell\">"
            << dataItem(h5 + ":/xdmfTangentialForce", M + " 3", "Float")
            << "</Attribute></Grid>";
    }
    line<< "</Grid>";
    return line.str();
}


//- The lines of the time grids of the file xmf kept by a write at time
//  timeName (value time): those whose state file exists and that
//  precede this time (a restart from an earlier time drops the lines of
//  the times it rewrites)
std::vector<std::string> keptTimeLines
(
    const Foam::fileName& xmf,
    const Foam::fileName& caseDir,
    const Foam::word& timeName,
    const double time
)
{
    using namespace Foam;
    std::vector<std::string> kept;
    {
        std::ifstream in(xmf);
        std::string l;
        while (std::getline(in, l))
        {
            if (l.rfind(gridMark, 0) != 0)
            {
                continue;
            }
            const std::size_t a = std::char_traits<char>::length(gridMark);
            const std::string name(l.substr(a, l.find('"', a) - a));
            const std::size_t v = l.find("<Time Value=\"");
            double value = 0;
            if
            (
                v == std::string::npos || name == timeName
             || !isFile(caseDir/name/grainCloud::stateFileName)
             || !readScalar
                (
                    l.substr(v + 13, l.find('"', v + 13) - v - 13),
                    value
                )
             || value > time
            )
            {
                continue;
            }
            kept.push_back(l);
        }
    }
    return kept;
}

} // End anonymous namespace


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainCloud::addXdmfDatasets
(
    const std::string& path,
    const long first,
    const long nGrains,
    const double partDt
)
{
    h5Handle h;
    h.id = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (h.id < 0)
    {
        throw std::runtime_error(path + ": cannot open for the XDMF datasets");
    }
    const std::vector<hsize_t> r = datasetDims(h.id, "radii");
    if (r.size() != 1)
    {
        throw std::runtime_error(path + ": dataset 'radii' missing or not 1D");
    }
    const long n = long(r[0]);
    const long whole = nGrains < 0 ? n : nGrains;  // (a part: its rows)
    const std::vector<int> ij =
        readDataset<int>(h.id, path, "contactBodies", H5T_NATIVE_INT, 2);
    const std::vector<double> cd =
        readDataset<double>(h.id, path, "contactData", H5T_NATIVE_DOUBLE, 14);
    // (a part has no /time: the last sub-step's dt given)
    const std::vector<double> t =
        nGrains < 0
      ? readDataset<double>(h.id, path, "time", H5T_NATIVE_DOUBLE, 1)
      : std::vector<double>{0, partDt};
    if (cd.size() != 7*ij.size())
    {
        throw std::runtime_error
        (
            path + ": datasets 'contactBodies' and 'contactData' list"
            " different numbers of contacts"
        );
    }
    const double dt = t.size() > 1 && t[1] > 0 ? t[1] : 1.0;  // 1: impulses

    std::vector<int> vertices(n);
    for (long i = 0; i < n; ++i)
    {
        vertices[i] = int(first + i);
    }
    std::vector<int> pairs;
    std::vector<double> fn, ft;
    for (std::size_t k = 0; 2*k < ij.size(); ++k)
    {
        if (ij[2*k + 1] >= whole)
        {
            continue;  // wall contact
        }
        pairs.push_back(ij[2*k]);
        pairs.push_back(ij[2*k + 1]);
        // contactData row: normal (3), tangential impulse (3), rn, ...
        const double* c = &cd[14*k];
        for (int a = 0; a < 3; ++a)
        {
            fn.push_back(c[6]*c[a]/dt);
            ft.push_back(c[3 + a]/dt);
        }
    }
    const hsize_t m = pairs.size()/2;
    writeDataset
    (
        h.id, path, "xdmfVertices", vertices.data(), n, 0, H5T_NATIVE_INT
    );
    writeDataset
    (
        h.id, path, "xdmfContactPairs", pairs.data(), m, 2, H5T_NATIVE_INT
    );
    writeDataset
    (
        h.id, path, "xdmfNormalForce", fn.data(), m, 3, H5T_NATIVE_DOUBLE
    );
    writeDataset
    (
        h.id, path, "xdmfTangentialForce", ft.data(), m, 3, H5T_NATIVE_DOUBLE
    );
    if (H5Fflush(h.id, H5F_SCOPE_LOCAL) < 0)
    {
        throw std::runtime_error(path + ": cannot flush the XDMF datasets");
    }
}


void Foam::grainCloud::writeXdmf(const fileName& statePath) const
{
    const Time& runTime = mesh_.time();
    const fileName caseDir(statePath.path().path());
    const word timeName(statePath.path().name());
    const fileName xmf(caseDir/"grainState.xmf");
    const std::string h5(timeName + "/" + stateFileName);

    // sizes of this state, from the file just written
    std::vector<hsize_t> x, pairs, T;
    double dt = 0;
    {
        h5Handle h;
        h.id = H5Fopen(statePath.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
        if (h.id >= 0)
        {
            x = datasetDims(h.id, "positions");
            pairs = datasetDims(h.id, "xdmfContactPairs");
            T = datasetDims(h.id, "temperatures");
            try
            {
                const std::vector<double> t = readDataset<double>
                (
                    h.id, statePath, "time", H5T_NATIVE_DOUBLE, 1
                );
                dt = t.size() > 1 ? t[1] : 0;
            }
            catch (const std::runtime_error&)
            {
                x.clear();  // not a state file: no description below
            }
        }
    }
    if (x.size() != 2 || pairs.size() != 2)
    {
        WarningInFunction
            << "No XDMF description of " << statePath << " written to " << xmf
            << ": it cannot be read or lacks /positions, /time or"
            << " /xdmfContactPairs" << endl;
        return;
    }
    // this time's grids, on one line (the line is what the next write
    // keeps), after the earlier times' lines of the file
    const std::string line
    (
        timeLine
        (
            h5, timeName, runTime.value(), x[0], pairs[0],
            T.size() == 1 && T[0] == x[0], dt
        )
    );
    const std::vector<std::string> kept
    (
        keptTimeLines(xmf, caseDir, timeName, runTime.value())
    );

    const std::string tmp(xmf + ".tmp");
    {
        std::ofstream out(tmp);
        out << "<?xml version=\"1.0\" ?>\n"
            << "<!-- nscdFoam grains for ParaView (grainCloudXdmf.C): every"
            << " array is in <time>/grainState.h5; rewritten at each write"
               " -->\n"
            << "<Xdmf Version=\"3.0\">\n<Domain>\n"
            << "<Grid Name=\"grainState\" GridType=\"Collection\""
            << " CollectionType=\"Temporal\">\n";
        for (const std::string& l : kept)
        {
            out << l << '\n';
        }
        out << line << '\n'
            << "</Grid>\n</Domain>\n</Xdmf>\n";
        out.close();
        if (!out || std::rename(tmp.c_str(), xmf.c_str()) != 0)
        {
            std::remove(tmp.c_str());
            WarningInFunction
                << "Cannot write " << xmf << " (the grains for ParaView)"
                << noSpaceHint(fileName(xmf).path()).c_str()
                << "; the run continues" << endl;
        }
    }
}


bool Foam::grainCloud::startStateHas(const word& dataset) const
{
    if (startStatePath_.empty())
    {
        return false;
    }
    h5Handle h;
    h.id = H5Fopen(startStatePath_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    return h.id >= 0 && H5Lexists(h.id, dataset.c_str(), H5P_DEFAULT) > 0;
}

// ************************************************************************* //
