# SPDX-License-Identifier: GPL-3.0-or-later
"""Snapshot PNGs of a tutorial: the sedimentation
tutorial's own Allrun, on a copy with 2 rows of discs and 0.1 s, renders its
pictures with src/python/nscdrender.py (PyVista offscreen) after foamToVTK.

A smoke test of the pipeline, not of physics: the images exist, have the
requested size, and are not blank (several hundred distinct colours, pixel
spread well above zero, the grains' colour bar drawn)."""

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT

pytest.importorskip("pyvista")


def _pixels(path):
    """(h, w, 3) uint8 pixels of a PNG (matplotlib's reader, 0..1 floats)."""
    import matplotlib.image as mpimg

    img = mpimg.imread(path)
    return (np.asarray(img)[..., :3] * 255).round().astype(np.uint8)


@pytest.mark.slow
def test_sedimentation_allrun_renders_snapshots(tmp_path, env):
    tut = os.path.join(ROOT, "tutorials", "vansFoam", "sedimentation")
    work = str(tmp_path / "sedimentation")
    shutil.copytree(
        tut,
        work,
        ignore=shutil.ignore_patterns("overlap", "centroid", "results.json", "*.png", "log.*"),
    )
    p = subprocess.run(["./Allrun", "0.1", "2"], cwd=work, env=env, capture_output=True, text=True)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    # both methods run to the end: the centroid (PCM) case with the thesis'
    # artificial pressure diffusion and its void fraction floor
    # (setupCase.py METHODS)
    for case in ("overlap", "centroid"):
        assert "FOAM FATAL" not in open(os.path.join(work, case, "log.vansFoam")).read(), case
        pngs = sorted(f for f in os.listdir(os.path.join(work, case)) if f.endswith(".png"))
        # the writes of 0 and 0.1 s (writeInterval 0.1)
        assert pngs == sorted(f"{case}_voidFraction_t{t}.png" for t in ("0", "0.1")), pngs
        for name in pngs:
            px = _pixels(os.path.join(work, case, name))
            assert px.shape[1] == 900 and px.shape[0] > 400, (name, px.shape)
            colours = np.unique(px.reshape(-1, 3), axis=0)
            assert len(colours) > 200, (name, len(colours))
            assert px.std() > 20.0, (name, px.std())
    # the grains (turbo colour map) are drawn at the end time: pixels far
    # from grey (|r - b| large) exist in the domain
    px = _pixels(os.path.join(work, "overlap", "overlap_voidFraction_t0.1.png")).astype(int)
    assert (np.abs(px[..., 0] - px[..., 2]) > 80).sum() > 500


@pytest.mark.fast
def test_render_without_vtk_output_says_what_to_run(tmp_path, env):
    """Bad input: a case without VTK/ gives exit code 1 and names foamToVTK."""
    p = subprocess.run(
        [sys.executable, "-m", "nscdrender", str(tmp_path)], capture_output=True, text=True, env=env
    )
    assert p.returncode == 1
    assert "foamToVTK" in p.stderr and str(tmp_path) in p.stderr, p.stderr
