# SPDX-License-Identifier: GPL-3.0-or-later
"""nscdrender: snapshot PNGs of a case from its foamToVTK output, like the
figures of M. Henry, PhD thesis, UCLouvain: the grains, coloured by their
speed |U| [m/s] or temperature T [K], over a cell field (void fraction,
alpha.water or temperature).  Rendered offscreen with PyVista (VTK's EGL
window, no X server), one shared script for every tutorial's Allrun:

    python3 -m nscdrender CASE [-f FIELD] [-g speed|T] [-n N | -t T1,T2] [-o DIR]

CASE must hold VTK/ written by `foamToVTK` (VTK/<case>.vtm.series and, with
grains, VTK/lagrangian/grains/grains.vtp.series).  Writes
DIR/<case name>_<field>_t<time>.png (DIR defaults to CASE), one per time.

2D cases (grains in one plane) are seen from +z with a parallel projection;
3D cases are cut by the plane z = mid-depth, on which the field is drawn
with the grains that cut that plane, seen from +z too.
"""

import argparse
import json
import os
import sys

import numpy as np

#: cell fields tried in this order when none is asked for
FIELD_ORDER = ("alpha.water", "T", "voidFraction")
#: colour maps: fields and grain colourings (matplotlib names)
CMAPS = {
    "alpha.water": "Blues",
    "voidFraction": "bone",
    "T": "inferno",
    "speed": "turbo",
    "grainT": "coolwarm",
}


def _series(path):
    """[(time, file path)] of a ParaView .series file (JSON), in time order."""
    with open(path) as f:
        files = json.load(f)["files"]
    base = os.path.dirname(path)
    return sorted((float(e["time"]), os.path.join(base, e["name"])) for e in files)


def vtk_series(case):
    """(mesh series, grain series) of CASE/VTK: lists of (time, file); the
    grain series is [] for a case without grains.  Raises FileNotFoundError
    naming the file and the fix (run foamToVTK)."""
    vtk = os.path.join(case, "VTK")
    mesh = (
        [f for f in sorted(os.listdir(vtk)) if f.endswith(".vtm.series")]
        if os.path.isdir(vtk)
        else []
    )
    if not mesh:
        raise FileNotFoundError(f"{vtk}/*.vtm.series: not found; run foamToVTK in {case} first")
    grains = os.path.join(vtk, "lagrangian", "grains", "grains.vtp.series")
    return (_series(os.path.join(vtk, mesh[0])), _series(grains) if os.path.isfile(grains) else [])


def pick_times(times, n=None, wanted=None):
    """Indices into `times` of n evenly spaced times (first and last
    included; n = 1: the last), or of the times nearest to each of `wanted` [s]."""
    if wanted:
        return sorted({int(np.argmin(np.abs(np.asarray(times) - w))) for w in wanted})
    n = min(n or 3, len(times))
    if n == 1:
        return [len(times) - 1]
    return sorted(set(np.linspace(0, len(times) - 1, n).round().astype(int).tolist()))


def _internal(pv, vtm):
    """The `internal` block (cells) of one time's .vtm."""
    mb = pv.read(vtm)
    block = mb["internal"] if "internal" in mb.keys() else mb[0]
    return block.cell_data_to_point_data(pass_cell_data=True) if block.n_cells else block


#: pixels kept below the domain for the colour bars, and above it for the title
BAR_PX, TITLE_PX = 110, 36


def _grains_on_cut(pv, gfile, zmid, z_front, grains):
    """Glyphs (spheres of the grains' diameters) of the grains of gfile that
    cut the plane z = zmid (all of them in a 2D case), moved to z_front in
    front of the cut; (None, None, None) if there are none.  Returns
    (glyphs, colour-bar title, colour map)."""
    g = pv.read(gfile)
    if not g.n_points:
        return None, None, None
    d = np.asarray(g.point_data["d"])
    mask = np.abs(g.points[:, 2] - zmid) <= 0.5 * d
    if np.ptp(g.points[:, 2]) <= 1e-9 * np.max(d):  # 2D: all in one plane
        mask[:] = True
    if not mask.any():
        return None, None, None
    pts = g.points[mask].copy()
    pts[:, 2] = z_front
    on = pv.PolyData(pts)
    if grains == "T":
        if "T" not in g.point_data.keys():  # e.g. grainDeposit's write
            label, cmap = None, None
        else:
            on.point_data["colour"] = np.asarray(g.point_data["T"])[mask]
            label, cmap = "grain T [K]", CMAPS["grainT"]
    else:
        on.point_data["colour"] = np.linalg.norm(np.asarray(g.point_data["U"])[mask], axis=1)
        label, cmap = "grain speed [m/s]", CMAPS["speed"]
    on.point_data["diameter"] = d[mask]
    balls = on.glyph(
        geom=pv.Sphere(radius=0.5, theta_resolution=16, phi_resolution=12),
        scale="diameter",
        orient=False,
    )
    return balls, label, cmap


def _frame(bounds, width):
    """Window size and parallel camera (position, focal point, view up,
    parallel scale) that show the x-y extent of bounds at the largest scale
    fitting `width` (height at most 1.6 x width), with BAR_PX below and
    TITLE_PX above."""
    x0, x1, y0, y1, z0, z1 = bounds
    lx, ly = max(x1 - x0, 1e-30), max(y1 - y0, 1e-30)
    s = min((width - 20) / lx, 1.6 * width / ly)  # pixels per metre
    height = int(round(ly * s)) + BAR_PX + TITLE_PX
    focal = (0.5 * (x0 + x1), y0 + (0.5 * height - BAR_PX) / s, 0.5 * (z0 + z1))
    position = (focal[0], focal[1], z1 + 10 * max(lx, ly))
    return (width, height), [position, focal, (0, 1, 0)], 0.5 * height / s


def _bar(p, title, x):
    """Horizontal colour bar of the actor titled `title`, at x (fraction of
    the window) below the domain, its labels under it."""
    return dict(
        title=title,
        color="black",
        n_labels=3,
        fmt="%.3g",
        vertical=False,
        position_x=x,
        position_y=0.01,
        width=0.4,
        height=BAR_PX / p.window_size[1] * 0.8,
        title_font_size=14,
        label_font_size=12,
    )


def render_case(case, field=None, grains="speed", n=3, times=None, out=None, width=900):
    """Write snapshot PNGs of CASE (see the module doc); returns their paths.
    field: cell field name (default: the first of FIELD_ORDER present);
    grains: "speed" (|U| [m/s]) or "T" [K] for the grains' colour; n: number
    of evenly spaced times, or times: list of times [s] (nearest written);
    out: output directory (default CASE); width: image width [pixels].
    Raises FileNotFoundError (no VTK output), KeyError (the field asked for
    is not written)."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    pv.OFF_SCREEN = True
    mesh_series, grain_series = vtk_series(case)
    out = out or case
    os.makedirs(out, exist_ok=True)
    name = os.path.basename(os.path.abspath(case))
    # the field is chosen on the last write (the initial one may not hold
    # the solver's fields, e.g. voidFraction); a time without it is grey, as
    # is a case without any (grainFoam)
    last = _internal(pv, mesh_series[-1][1]).cell_data.keys()
    f = field or next((k for k in FIELD_ORDER if k in last), None)
    if field and field not in last:
        raise KeyError(f"{mesh_series[-1][1]}: no cell field {field}; fields written: {list(last)}")
    gtimes = np.array([g for g, _ in grain_series])
    written = []
    for i in pick_times([t for t, _ in mesh_series], n, times):
        t, vtm = mesh_series[i]
        cells = _internal(pv, vtm)
        b = cells.bounds
        size, camera, scale = _frame(b, width)
        p = pv.Plotter(off_screen=True, window_size=size)
        p.set_background("white")
        cut = cells.slice(normal="z", origin=cells.center)
        if f and f in cut.cell_data.keys():
            p.add_mesh(
                cut,
                scalars=f,
                preference="cell",
                lighting=False,
                cmap=CMAPS.get(f, "viridis"),
                clim=(0.0, 1.0) if f in ("alpha.water", "voidFraction") else None,
                scalar_bar_args=_bar(p, f, 0.05),
            )
        else:
            p.add_mesh(cut, color="lightgrey", lighting=False)
        p.add_mesh(cut.outline() if cut.n_points else cells.outline(), color="black")
        if len(gtimes):  # the nearest grain write
            gfile = grain_series[int(np.argmin(np.abs(gtimes - t)))][1]
            balls, label, cmap = _grains_on_cut(
                pv, gfile, cells.center[2], b[5] + 1e-3 * (b[1] - b[0]), grains
            )
            if balls is not None and label is None:
                p.add_mesh(balls, color="grey")
            elif balls is not None:
                p.add_mesh(balls, scalars="colour", cmap=cmap, scalar_bar_args=_bar(p, label, 0.55))
        p.add_text(
            f"{name}   t = {t:.4g} s",
            font_size=10,
            color="black",
            position=(8, size[1] - TITLE_PX + 8),
        )
        p.enable_parallel_projection()
        p.camera_position = camera
        p.camera.parallel_scale = scale
        for bar in p.scalar_bars.values():  # labels under the bar, title above
            bar.SetTextPositionToPrecedeScalarBar()
        png = os.path.join(out, f"{name}_{f or 'grains'}_t{t:.4g}.png")
        p.screenshot(png)
        p.close()
        written.append(png)
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m nscdrender", description=__doc__.split("\n\n")[0])
    ap.add_argument("cases", nargs="+", help="case directories holding VTK/ (foamToVTK)")
    ap.add_argument(
        "-f", "--field", help=f"cell field (default: first of {', '.join(FIELD_ORDER)})"
    )
    ap.add_argument(
        "-g",
        "--grains",
        choices=("speed", "T"),
        default="speed",
        help="grain colour: speed |U| or temperature T (default speed)",
    )
    ap.add_argument("-n", type=int, default=3, help="number of evenly spaced times (default 3)")
    ap.add_argument("-t", "--times", help="comma-separated times [s] (nearest written)")
    ap.add_argument("-o", "--out", help="output directory (default: each case)")
    a = ap.parse_args(argv)
    times = [float(v) for v in a.times.split(",")] if a.times else None
    for case in a.cases:
        try:
            for png in render_case(case, a.field, a.grains, a.n, times, a.out):
                print(png)
        except (FileNotFoundError, KeyError) as e:  # bad input: say which and why
            print(f"nscdrender: {case}: {e}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
