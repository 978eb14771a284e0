# SPDX-License-Identifier: GPL-3.0-or-later
"""The XDMF 3 files of the grains (nscdpost.write_xdmf, write_xdmf_series),
read back with VTK's XDMF reader (vtkXdmfReader, the reader ParaView offers
as "XDMF Reader"; meshio 5.3 reads only files of one uniform grid, these
hold a grains and a contacts grid).

Independent reference: the datasets of the same grainState.h5 read with
h5py directly (src/nscd/src/IO.cpp layout), not through nscdpost: grain
count, positions, radii, velocities, ids; the grain-grain contact pairs and
the normal contact force rn n / dt.  Case: the 2 x 3 stack of discs of the
fault tests on the floor of a 4 x 4 box, grainFoam to 0.02 s (a few s)."""
import os

import h5py
import numpy as np
import pytest

import nscdpost
from faultcase import stack
from foamcase import run

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def _blocks(path, time=None):
    """{grid name: vtkUnstructuredGrid} of an XDMF file read by VTK (at
    `time` for a temporal collection), and the file's time steps."""
    r = vtk.vtkXdmfReader()
    r.SetFileName(path)
    r.UpdateInformation()
    steps = r.GetOutputInformation(0).Get(vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    if time is None:
        r.Update()
    else:
        r.UpdateTimeStep(time)
    out = r.GetOutputDataObject(0)
    names = {}
    for b in range(out.GetNumberOfBlocks()):
        # in a temporal collection the reader numbers the grids: grains[2]
        name = out.GetMetaData(b).Get(vtk.vtkCompositeDataSet.NAME()).split("[")[0]
        names[name] = out.GetBlock(b)
    return names, steps


def _arr(data, name):
    a = data.GetArray(name)
    assert a is not None, name
    return vtk_to_numpy(a)


def _check_grains(g, h5):
    with h5py.File(h5, "r") as f:
        x, r, v = f["positions"][()], f["radii"][()], f["velocities"][()]
        w, ids = f["angularVelocities"][()], f["grainIds"][()]
    assert g.GetNumberOfPoints() == len(r) == 6
    assert g.GetNumberOfCells() == len(r)          # one vertex per grain
    np.testing.assert_array_equal(vtk_to_numpy(g.GetPoints().GetData()), x)
    pd = g.GetPointData()
    np.testing.assert_array_equal(_arr(pd, "radius"), r)
    np.testing.assert_array_equal(_arr(pd, "velocity"), v)
    np.testing.assert_array_equal(_arr(pd, "angularVelocity"), w)
    np.testing.assert_array_equal(_arr(pd, "id"), ids)


@pytest.fixture(scope="module")
def settled(tmp_path_factory, env):
    case = stack(tmp_path_factory.mktemp("xdmf"), "stack")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    return case


def test_xdmf_of_one_state_reads_back(settled):
    h5 = os.path.join(settled, "0.02", "grainState.h5")
    xmf = nscdpost.write_xdmf(h5)
    assert xmf == os.path.join(settled, "0.02", "grainState.xmf")
    grids, _ = _blocks(xmf)
    _check_grains(grids["grains"], h5)

    with h5py.File(h5, "r") as f:
        n = len(f["radii"])
        ij, cd, dt = f["contactBodies"][()], f["contactData"][()], f["time"][1]
    gg = ij[:, 1] < n                                # grain-grain rows
    assert 0 < gg.sum() < len(ij)                    # the stack has both kinds
    c = grids["contacts"]
    assert c.GetNumberOfCells() == gg.sum()
    cells = vtk_to_numpy(c.GetCells().GetConnectivityArray()).reshape(-1, 2)
    np.testing.assert_array_equal(cells, ij[gg])
    fn = _arr(c.GetCellData(), "normalForce")
    np.testing.assert_allclose(fn, cd[gg, 6:7] * cd[gg, 0:3] / dt, rtol=1e-15, atol=0)
    # the stack's weight goes through its vertical contacts: the force is
    # finite, non-zero and of the order of the grains' weight per depth
    assert np.abs(fn).max() > 0


def test_xdmf_series_of_a_case(settled):
    xmf = nscdpost.write_xdmf_series(settled)
    assert xmf == os.path.join(settled, "grainState.xmf")
    grids, steps = _blocks(xmf, 0.02)
    assert list(steps) == [0.0, 0.01, 0.02]
    _check_grains(grids["grains"], os.path.join(settled, "0.02", "grainState.h5"))
    grids0, _ = _blocks(xmf, 0.0)
    _check_grains(grids0["grains"], os.path.join(settled, "0", "grainState.h5"))


def test_xdmf_names_a_bad_file(tmp_path):
    bad = tmp_path / "grainState.h5"
    bad.write_text("not HDF5\n")
    with pytest.raises(OSError, match=str(bad)):
        nscdpost.write_xdmf(str(bad))
