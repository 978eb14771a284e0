# SPDX-License-Identifier: GPL-3.0-or-later
"""grainstate: the nscd grain state file grainState.h5 from Python (h5py).

Needs numpy and h5py (python3-h5py).  Re-exported by nscdpost, where the
tutorials and tests find them:
  read_h5(path, dataset)       -> one dataset of an HDF5 file (grainState.h5)
  read_contacts(case, time_name), read_state_contacts(path)
                               -> the saved contact list and impulses
  xdmf_grids(h5path), write_xdmf(h5path)
                               -> XDMF 3 grids (grains, contacts as line cells
                                  with their forces) of one grainState.h5 for
                                  ParaView
"""

import os

import numpy as np


def read_h5(path, dataset, cols=None):
    """Dataset `dataset` (e.g. "/positions") of the HDF5 file `path` as a numpy
    array of the file's own type (float64 or int), read with h5py.  The nscd
    grain state grainState.h5 starts with a FoamFile header in its HDF5 user
    block; h5py (libhdf5) skips it.  cols: reshape to (n, cols), e.g. 1 for
    a column of a 1D dataset.  Raises FileNotFoundError when path does not
    exist, OSError naming path when it is not an HDF5 file, KeyError naming
    path when the dataset is missing."""
    import h5py

    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path}: no such HDF5 file")
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise OSError(f"{path}: cannot be read as HDF5 ({e})") from e
    with f:
        if dataset not in f:
            raise KeyError(f"{path}: no dataset '{dataset}' (has: {', '.join(sorted(f))})")
        a = f[dataset][()]
    a = np.asarray(a)
    return a.reshape(-1, cols) if cols else a


def read_contacts(case, time_name):
    """Contact list of the grain state case/time_name/grainState.h5 (the
    contacts of the last step and their impulses, the warm start of the
    next): 'i' (n, grain A), 'wall' (n, wall id or -1), 'j' (n, grain B or
    -1), 'normal' (n x 3, from B to A), 'rn' (n, normal impulse [N s],
    2D: per unit depth), 'rt' (n x 3, tangential impulse on A [N s]) and
    'dt' (the time step [s] of those impulses: the last sub-step's).
    In the file (src/nscd/src/IO.cpp): /contactBodies (n, 2) int, the second
    body a grain index or n_grains + wall index; /contactData (n, 14) float,
    normal (3), tangential impulse (3), normal impulse, then the Delassus
    terms, gap and state; /time = {time, last dt, cohesion force}.
    Raises the errors of read_h5 (naming the file) on a missing or bad file."""
    return read_state_contacts(os.path.join(case, time_name, "grainState.h5"))


def read_state_contacts(path):
    """read_contacts of the grain state file path (any name)."""
    n_grains = len(read_h5(path, "/radii"))
    ij = read_h5(path, "/contactBodies", 2).astype(int)
    cd = read_h5(path, "/contactData", 14).astype(float)
    j = ij[:, 1]
    wall = np.where(j >= n_grains, j - n_grains, -1)
    return {
        "i": ij[:, 0],
        "j": np.where(j < n_grains, j, -1),
        "wall": wall,
        "normal": cd[:, 0:3],
        "rt": cd[:, 3:6],
        "rn": cd[:, 6],
        "dt": float(read_h5(path, "/time")[1]),
    }


def _xdmf_item(dims, text, number="Float", precision=8, fmt="XML"):
    """One XDMF DataItem element: `text` is either "file.h5:/dataset" (fmt
    "HDF", data stay in the HDF5 file) or the values written inline (fmt
    "XML")."""
    d = " ".join(str(int(n)) for n in dims)
    return (
        f'<DataItem Dimensions="{d}" NumberType="{number}" Precision="{precision}" '
        f'Format="{fmt}">{text}</DataItem>'
    )


def _xdmf_values(a, integer=False):
    """Inline XDMF text of array a (row-major; 17 significant digits, so
    that float64 values read back exactly)."""
    a = np.asarray(a).reshape(-1)
    return " ".join(str(int(v)) for v in a) if integer else " ".join(f"{v:.17g}" for v in a)


def xdmf_grids(h5path, h5ref=None):
    """The XDMF 3 grids of one grain state (grainState.h5, written by
    src/nscd/src/IO.cpp) as XML text, without the <Xdmf>/<Domain> frame:

    - "grains": a Polyvertex grid of the N grains, geometry /positions [m]
      (2D: the discs in the nscd plane z = 0, not the mesh mid-plane) and
      node attributes radius [m] (/radii), velocity [m/s] (/velocities),
      angularVelocity [rad/s] (/angularVelocities), id (/grainIds, the
      persistent grain id) and temperature [K] (/temperatures; in a run
      without heat the default temperature).  These point into the HDF5
      file (h5ref:/dataset, no copy); only the connectivity 0 ... N-1 is
      written inline (the state holds no such index list).
    - "contacts": the grain-grain contacts of the last step as Polyline
      cells of 2 points (the two grain centres), with cell attributes
      normalForce = rn n / dt and tangentialForce = rt / dt [N; 2D: N/m per
      unit depth], the impulses rn, rt [N s] of /contactData divided by the
      last sub-step's dt (/time[1]), and contactNormal (unit, from the
      second grain to the first).  A state with dt = 0 (not stepped yet,
      e.g. written by grainDeposit without settling) gives normalImpulse
      and tangentialImpulse [N s] instead.  Wall contacts are left out: the state
      gives no point of the wall.  The pairs and forces are computed here
      and written inline: the state lists grain-grain and wall contacts
      mixed, so no slice of it is the grain-grain list.  No contacts grid
      when there is no grain-grain contact.

    h5ref: how the XDMF file names the HDF5 file (default its base name:
    the .xmf beside it).  Raises the errors of read_h5 (naming the file)."""
    h5ref = h5ref or os.path.basename(h5path)
    x = read_h5(h5path, "/positions", 3)
    n = len(x)
    attrs = [
        ("radius", "Scalar", "/radii", (n,), "Float", 8),
        ("velocity", "Vector", "/velocities", (n, 3), "Float", 8),
        ("angularVelocity", "Vector", "/angularVelocities", (n, 3), "Float", 8),
        ("id", "Scalar", "/grainIds", (n,), "Int", 8),
    ]
    import h5py

    with h5py.File(h5path, "r") as f:
        for a in attrs:
            if a[2] not in f:
                raise KeyError(f"{h5path}: no dataset '{a[2]}' (not an nscd grain state?)")
            if f[a[2]].shape != a[3]:
                raise ValueError(
                    f"{h5path}: dataset '{a[2]}' has shape {f[a[2]].shape},"
                    f" expected {a[3]} for {n} grains"
                )
        if "temperatures" in f and f["temperatures"].shape == (n,):
            attrs.append(("temperature", "Scalar", "/temperatures", (n,), "Float", 8))
    out = [
        '<Grid Name="grains" GridType="Uniform">',
        f'<Topology TopologyType="Polyvertex" NumberOfElements="{n}" NodesPerElement="1">'
        + _xdmf_item((n,), _xdmf_values(np.arange(n), True), "Int", 8)
        + "</Topology>",
        '<Geometry GeometryType="XYZ">'
        + _xdmf_item((n, 3), f"{h5ref}:/positions", fmt="HDF")
        + "</Geometry>",
    ]
    for name, kind, ds, dims, number, prec in attrs:
        out.append(
            f'<Attribute Name="{name}" AttributeType="{kind}" Center="Node">'
            + _xdmf_item(dims, f"{h5ref}:{ds}", number, prec, "HDF")
            + "</Attribute>"
        )
    out.append("</Grid>")

    c = read_state_contacts(h5path)
    keep = c["j"] >= 0
    m = int(keep.sum())
    # forces need the step length; a state that has not stepped yet (dt 0,
    # e.g. a grainDeposit start without settling) gives the impulses
    dt = c["dt"]
    per, unit = (dt, "Force") if dt > 0 else (1.0, "Impulse")
    pairs = np.column_stack([c["i"][keep], c["j"][keep]])
    fn = c["rn"][keep, None] * c["normal"][keep] / per
    ft = c["rt"][keep] / per
    if m == 0:  # no contacts grid: an empty grid crashes VTK's XDMF reader
        return "\n".join(out)
    out += [
        '<Grid Name="contacts" GridType="Uniform">',
        f'<Topology TopologyType="Polyline" NumberOfElements="{m}" NodesPerElement="2">'
        + _xdmf_item((m, 2), _xdmf_values(pairs, True), "Int", 8)
        + "</Topology>",
        '<Geometry GeometryType="XYZ">'
        + _xdmf_item((n, 3), f"{h5ref}:/positions", fmt="HDF")
        + "</Geometry>",
    ]
    for name, a in (
        ("normal" + unit, fn),
        ("tangential" + unit, ft),
        ("contactNormal", c["normal"][keep]),
    ):
        out.append(
            f'<Attribute Name="{name}" AttributeType="Vector" Center="Cell">'
            + _xdmf_item((m, 3), _xdmf_values(a))
            + "</Attribute>"
        )
    out.append("</Grid>")
    return "\n".join(out)


def write_xdmf(h5path, xmf_path=None):
    """Write an XDMF 3 file that ParaView opens (File > Open, then the XDMF
    reader): the grains and grain-grain contacts of the grain state h5path
    (see xdmf_grids for what each grid holds, units and what is left out).
    xmf_path: default h5path with .xmf for .h5, i.e. <time>/grainState.xmf
    beside the state.  The solvers write <case>/grainState.xmf themselves
    (all times, src/grainCloud/grainCloudXdmf.C); this is for one state
    file, e.g. one written before they did.  OpenFOAM's utilities
    (foamToVTK, decomposePar, reconstructPar) warn about a file without a
    FoamFile header in a time directory: give xmf_path outside it when
    they still run on the case.  Returns the path written."""
    xmf_path = xmf_path or os.path.splitext(h5path)[0] + ".xmf"
    ref = os.path.relpath(os.path.abspath(h5path), os.path.dirname(os.path.abspath(xmf_path)))
    body = xdmf_grids(h5path, ref)
    with open(xmf_path, "w") as f:
        f.write(
            '<?xml version="1.0" ?>\n<Xdmf Version="3.0">\n<Domain>\n'
            '<Grid Name="grainState" GridType="Collection" CollectionType="Spatial">\n'
            + body
            + "\n</Grid>\n</Domain>\n</Xdmf>\n"
        )
    return xmf_path
