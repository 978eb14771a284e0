# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared helpers of the fault tests (test_faults_control.py,
test_faults_state.py, test_faults_boundaries.py): a small 2D box case, edits
of controlDict, digests of the earlier results (the failure check is
foamcase.fails_with)."""

import hashlib
import os
import re
import subprocess

from foamcase import add_fluid, make_box_case, run, uniform_inflow

G = 9.81
MAT = {"glass": {"density": 2500, "friction": 0.4}}


def box(tmp_path, name, grains, end=0.02, dt=1e-3, write_interval=0.01, **kw):
    case = str(tmp_path / name)
    make_box_case(
        case,
        (0, 0, 0),
        (0.1, 0.1, 0.01),
        (4, 4, 1),
        (0, -G, 0),
        MAT,
        grains=grains,
        end_time=end,
        dt=dt,
        write_interval=write_interval,
        **kw,
    )
    return case


def set_control(case, **entries):
    """Replace `key value;` entries of system/controlDict."""
    path = os.path.join(case, "system", "controlDict")
    txt = open(path).read()
    for k, v in entries.items():
        txt, n = re.subn(rf"\b{k} [^;]*;", f"{k} {v};", txt)
        assert n == 1, k
    open(path, "w").write(txt)


def digest(case, time_name):
    """Hashes of every file of a time directory (the 'earlier results')."""
    out = {}
    root = os.path.join(case, time_name)
    for d, _, files in os.walk(root):
        for f in files:
            p = os.path.join(d, f)
            out[os.path.relpath(p, root)] = hashlib.sha1(open(p, "rb").read()).hexdigest()
    assert out, root
    return out


def times(case):
    return sorted((t for t in os.listdir(case) if re.fullmatch(r"[0-9.e-]+", t)), key=float)


def stack(tmp_path, name, **kw):
    # a 2 x 3 stack of touching discs on the floor
    d = 0.01
    grains = [
        (0.04 + d * 1.0001 * i, d / 2 * 1.0001 + d * j * 1.0001, 0, d)
        for i in range(2)
        for j in range(3)
    ]
    return box(tmp_path, name, grains, **kw)


def open_bottom_cube(case, env, grains, end, write_interval, outlet=False):
    """A 40 mm cube of water at rest (4 x 4 x 4 cells, vansFoam) whose
    bottom is the open patch `inlet` (foamcase.uniform_inflow with 0 m/s:
    p fixed at the top `outlet`), grains (x, y, z, d) of MAT; outlet: grains
    may leave through `inlet` (grainProperties outletPatches).  Runs
    blockMesh and grainDeposit."""
    make_box_case(
        case,
        (0, 0, 0),
        (0.04, 0.04, 0.04),
        (4, 4, 4),
        (0, -G, 0),
        MAT,
        grains=grains,
        end_time=end,
        dt=1e-3,
        write_interval=write_interval,
        two_d=False,
        extra_props="outletPatches (inlet);\n" if outlet else "",
    )
    add_fluid(case, 1000, 1e-6, max_dt=1e-3)
    uniform_inflow(case, 0.0)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)


def mount_small_disk(path, size):
    """Mount a tmpfs of `size` (e.g. "2m") at path, a file system that fills
    up as a real disk does (ENOSPC); skips the calling test when it cannot
    be mounted (mount needs root, or CAP_SYS_ADMIN in a container).  The
    caller unmounts it (umount_small_disk)."""
    import pytest

    os.makedirs(path, exist_ok=True)
    p = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", path],
        capture_output=True,
        text=True,
    )
    if p.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs to fill ({p.stderr.strip()}): needs root")


def umount_small_disk(path):
    subprocess.run(["umount", "-l", path], check=True)


def fill_disk(path, free):
    """Fill the file system of path with the file path/filler, leaving
    `free` bytes (rounded by the file system to its pages)."""
    filler = os.path.join(path, "filler")
    with open(filler, "wb", buffering=0) as f:
        chunk = b"\0" * (1 << 16)
        try:
            while True:
                f.write(chunk)
        except OSError:
            pass
    size = os.path.getsize(filler)
    os.truncate(filler, max(0, size - free))
    return filler
