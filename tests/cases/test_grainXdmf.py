# SPDX-License-Identifier: GPL-3.0-or-later
"""The grains for ParaView: <case>/grainState.xmf written by the solvers
(grainCloudXdmf.C, with its xdmf* datasets in each grainState.h5) and the
per-state file of nscdpost.write_xdmf, read back with VTK's XDMF reader
(vtkXdmfReader, the reader ParaView offers as "XDMF Reader"; meshio 5.3
reads only files of one uniform grid, these hold a grains and a contacts
grid per time).

Independent reference: the datasets nscd writes into the same
grainState.h5 (src/nscd/src/IO.cpp layout) read with h5py directly, not
through nscdpost: grain count, positions, radii, velocities, angular
velocities, ids; the grain-grain rows of /contactBodies and the contact
forces rn n / dt, rt / dt from /contactData and /time.  Case: the 2 x 3
stack of discs of the fault tests on the floor of a 4 x 4 box,
grainDeposit then grainFoam to 0.02 s (a few s)."""

import os
import shutil

import h5py
import nscdpost
import numpy as np
import pytest
from faultcase import set_control, stack
from foamcase import run

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

pytestmark = pytest.mark.fast


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
    assert g.GetNumberOfCells() == len(r)  # one vertex per grain
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


def _contacts_reference(h5):
    """Grain-grain pairs and normal, tangential contact forces [N per unit
    depth] of a state, from nscd's own datasets."""
    with h5py.File(h5, "r") as f:
        n = len(f["radii"])
        ij, cd, dt = f["contactBodies"][()], f["contactData"][()], f["time"][1]
    gg = ij[:, 1] < n  # grain-grain rows
    return gg, ij[gg], cd[gg, 6:7] * cd[gg, 0:3] / dt, cd[gg, 3:6] / dt


def _check_contacts(c, h5):
    gg, pairs, fn, ft = _contacts_reference(h5)
    assert 0 < gg.sum() < len(gg)  # the stack has both kinds
    assert c.GetNumberOfCells() == gg.sum()
    cells = vtk_to_numpy(c.GetCells().GetConnectivityArray()).reshape(-1, 2)
    np.testing.assert_array_equal(cells, pairs)
    np.testing.assert_allclose(_arr(c.GetCellData(), "normalForce"), fn, rtol=1e-15, atol=0)
    np.testing.assert_allclose(_arr(c.GetCellData(), "tangentialForce"), ft, rtol=1e-15, atol=0)
    # the stack's weight goes down through its vertical contacts
    assert np.abs(fn).max() > 0


def test_solver_writes_the_grains_of_every_time(settled):
    xmf = os.path.join(settled, "grainState.xmf")
    grids, steps = _blocks(xmf, 0.02)
    assert list(steps) == [0.0, 0.01, 0.02]
    h5 = os.path.join(settled, "0.02", "grainState.h5")
    _check_grains(grids["grains"], h5)
    _check_contacts(grids["contacts"], h5)
    # the deposit at 0 has not stepped: no contacts, no contacts grid
    grids0, _ = _blocks(xmf, 0.0)
    _check_grains(grids0["grains"], os.path.join(settled, "0", "grainState.h5"))
    assert "contacts" not in grids0
    # nothing of the .xmf in the time directories (OpenFOAM's tools read
    # every file there and warn about one without a FoamFile header)
    for t in ("0", "0.01", "0.02"):
        assert not [f for f in os.listdir(os.path.join(settled, t)) if f.endswith(".xmf")]


def test_restart_keeps_the_earlier_times(settled, tmp_path, env):
    """A run restarted from 0.01 rewrites 0.02 and keeps 0 and 0.01; one
    restarted from 0 to 0.01 drops 0.02 (a later time of an earlier run)."""
    case = str(tmp_path / "restart")
    shutil.copytree(settled, case)
    set_control(case, startFrom="startTime", startTime="0.01")
    run("grainFoam", case, env)
    grids, steps = _blocks(os.path.join(case, "grainState.xmf"), 0.02)
    assert list(steps) == [0.0, 0.01, 0.02]
    _check_grains(grids["grains"], os.path.join(case, "0.02", "grainState.h5"))
    set_control(case, startFrom="startTime", startTime="0")
    set_control(case, endTime="0.01")
    run("grainFoam", case, env)
    _, steps = _blocks(os.path.join(case, "grainState.xmf"))
    assert list(steps) == [0.0, 0.01]


def test_write_xdmf_of_one_state(settled, tmp_path):
    """nscdpost.write_xdmf: the same grids for one state, beside it (any
    state, also one written before the solvers wrote the XDMF datasets)."""
    h5 = str(tmp_path / "grainState.h5")
    shutil.copy(os.path.join(settled, "0.02", "grainState.h5"), h5)
    xmf = nscdpost.write_xdmf(h5)
    assert xmf == str(tmp_path / "grainState.xmf")
    grids, _ = _blocks(xmf)
    _check_grains(grids["grains"], h5)
    _check_contacts(grids["contacts"], h5)


def test_xdmf_names_a_bad_file(tmp_path):
    bad = tmp_path / "grainState.h5"
    bad.write_text("not HDF5\n")
    with pytest.raises(OSError, match=str(bad)):
        nscdpost.write_xdmf(str(bad))
