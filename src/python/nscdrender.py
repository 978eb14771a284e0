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

Force chains (`--chains`): the grains as discs and every grain-grain
contact that carries a normal force as a segment between the two centres,
its width and colour proportional to that force, drawn with matplotlib
from the grain state <time>/grainState.h5 itself (no foamToVTK needed):

    python3 -m nscdrender --chains CASE [-n N | -t T1,T2] [-o DIR]

writes DIR/<case name>_forceChains_t<time>.png for times whose state has
stepped (the state grainDeposit writes at 0 holds no contacts).

pyplot gives the tutorials' and benches' plotting scripts matplotlib in
the Agg backend (or None where it is not installed), save_plot finishes and
writes their one-axes line plots (labels, legend, grid, layout), the same on
every figure.
"""

import argparse
import json
import os
import sys

import nscdpost
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


#: colour map of the normal contact force in a force-chain picture
CHAIN_CMAP = "inferno_r"
#: line width of the largest force, as a fraction of the mean grain diameter
CHAIN_WIDTH = 0.5


def read_force_chains(h5):
    """The grains and the force-carrying grain-grain contacts of one grain
    state file (nscd's layout, src/nscd/src/IO.cpp, read with h5py through
    nscdpost): dict with 'x' (N x 3 centres [m]), 'r' (N radii [m]),
    'fixed' (N bool), 'pairs' (m x 2 grain indices), 'fn' (m normal forces
    rn / dt [N; 2D: N per unit depth]), 'time' [s], 'dim' (2 or 3) and
    'unit' (the force's unit).  Kept: the grain-grain rows of
    /contactBodies (wall contacts have no second centre) whose normal
    impulse rn is positive; dt is the last sub-step's (/time[1]).  A state
    that has not stepped (dt = 0) holds no contacts."""
    r = nscdpost.read_h5(h5, "/radii").astype(float)
    x = nscdpost.read_h5(h5, "/positions", 3).astype(float)
    try:
        fixed = nscdpost.read_h5(h5, "/fixed") > 0
    except KeyError:  # optional: no fixed grain
        fixed = np.zeros(len(r), dtype=bool)
    try:
        dim = int(nscdpost.read_h5(h5, "/dimension")[0])
    except KeyError:
        dim = 3
    c = nscdpost.read_state_contacts(h5)
    keep = (c["j"] >= 0) & (c["rn"] > 0)
    dt = c["dt"] if c["dt"] > 0 else 1.0
    return {
        "x": x,
        "r": r,
        "fixed": fixed,
        "pairs": np.column_stack((c["i"][keep], c["j"][keep])),
        "fn": c["rn"][keep] / dt,
        "time": float(nscdpost.read_h5(h5, "/time")[0]),
        "dim": dim,
        "unit": "N/m" if dim == 2 else "N",
    }


def draw_force_chains(h5, png, title=None, width=1200, dpi=100):
    """Write the force-chain picture of the grain state file h5 to png (see
    the module doc), seen from +z (a 3D state is projected on z = const),
    framed on the grains, `width` pixels wide.  Returns the number of
    segments drawn (the force-carrying grain-grain contacts of
    read_force_chains)."""
    from matplotlib.collections import EllipseCollection, LineCollection
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    s = read_force_chains(h5)
    x, r, fn = s["x"][:, :2], s["r"], s["fn"]
    lo, hi = (x - r[:, None]).min(axis=0), (x + r[:, None]).max(axis=0)
    pad = 0.02 * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    lx, ly = hi - lo
    # axes: the full width, the height of the grains' extent (at most 1.6
    # x the width); BAR_PX below for the colour bar, TITLE_PX above
    ax_w = width / dpi
    ax_h = min(ax_w * ly / lx, 1.6 * ax_w)
    fig_h = ax_h + (BAR_PX + TITLE_PX) / dpi
    fig = Figure(figsize=(ax_w, fig_h), dpi=dpi)
    ax = fig.add_axes((0.0, BAR_PX / dpi / fig_h, 1.0, ax_h / fig_h))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal", adjustable="box")
    ax.set_axis_off()
    faces = np.where(s["fixed"][:, None], [[0.55, 0.55, 0.55, 1.0]], [[0.86, 0.86, 0.86, 1.0]])
    ax.add_collection(
        EllipseCollection(
            2 * r,
            2 * r,
            np.zeros(len(r)),
            units="xy",
            offsets=x,
            offset_transform=ax.transData,
            facecolors=faces,
            edgecolors=(0.6, 0.6, 0.6, 1.0),
            linewidths=0.3,
        )
    )
    fmax = float(fn.max()) if len(fn) else 1.0
    # width of the largest force: CHAIN_WIDTH of the mean diameter [points]
    pt_per_m = min(ax_w / lx, ax_h / ly) * 72.0
    chains = LineCollection(
        x[s["pairs"]].reshape(-1, 2, 2),
        linewidths=CHAIN_WIDTH * 2 * float(np.mean(r)) * pt_per_m * fn / fmax,
        cmap=CHAIN_CMAP,
        norm=Normalize(0.0, fmax),
        capstyle="round",
    )
    chains.set_array(fn)
    ax.add_collection(chains)
    cax = fig.add_axes((0.3, 0.45 * BAR_PX / dpi / fig_h, 0.4, 0.15 * BAR_PX / dpi / fig_h))
    bar = fig.colorbar(chains, cax=cax, orientation="horizontal")
    bar.set_label(f"normal contact force [{s['unit']}]")
    fig.text(
        0.01,
        1.0 - 0.7 * TITLE_PX / dpi / fig_h,
        f"{title or ''}   t = {s['time']:.4g} s   {len(fn)} force-carrying contacts".strip(),
        fontsize=10,
    )
    fig.savefig(png, dpi=dpi, facecolor="white")
    return len(chains.get_segments())


def pyplot(png):
    """matplotlib.pyplot in the Agg backend (files only, no display) for a
    script about to draw png; None, after printing "matplotlib missing: no
    <png>", where matplotlib is not installed (the script then skips the
    figure, its numbers are written all the same)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(f"matplotlib missing: no {png}")
        return None
    return plt


def save_plot(fig, ax, png, xlabel, ylabel=None, legend_size=8, dpi=120):
    """Finish the one-axes matplotlib figure of a tutorial's postProcess.py
    and write it to png: the axis labels (no ylabel when the legend says
    what is plotted), the legend (font size legend_size), a light grid and
    a tight layout, at dpi."""
    ax.set_xlabel(xlabel)
    if ylabel is not None:
        ax.set_ylabel(ylabel)
    ax.legend(fontsize=legend_size)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=dpi)


def render_force_chains(case, n=3, times=None, out=None, width=1200):
    """Force-chain PNGs (draw_force_chains) of n evenly spaced times of CASE
    whose grain state has stepped, or of the times nearest to `times` [s];
    returns their paths.  Raises FileNotFoundError when no time directory
    of CASE holds a stepped grainState.h5."""
    states = [
        (t, os.path.join(case, name, "grainState.h5"))
        for t, name in nscdpost.numeric_dirs(case)
        if os.path.isfile(os.path.join(case, name, "grainState.h5"))
    ]
    states = [(t, h5) for t, h5 in states if nscdpost.read_h5(h5, "/time")[1] > 0]
    if not states:
        raise FileNotFoundError(
            f"{case}: no <time>/grainState.h5 of a stepped state; run the solver (grainFoam, ...) first"
        )
    out = out or case
    os.makedirs(out, exist_ok=True)
    name = os.path.basename(os.path.abspath(case))
    written = []
    for i in pick_times([t for t, _ in states], n, times):
        t, h5 = states[i]
        png = os.path.join(out, f"{name}_forceChains_t{t:.4g}.png")
        draw_force_chains(h5, png, name, width)
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
    ap.add_argument(
        "-c",
        "--chains",
        action="store_true",
        help="force chains from <time>/grainState.h5 instead of the VTK snapshots",
    )
    a = ap.parse_args(argv)
    times = [float(v) for v in a.times.split(",")] if a.times else None
    for case in a.cases:
        try:
            if a.chains:
                pngs = render_force_chains(case, a.n, times, a.out)
            else:
                pngs = render_case(case, a.field, a.grains, a.n, times, a.out)
            for png in pngs:
                print(png)
        except (FileNotFoundError, KeyError) as e:  # bad input: say which and why
            print(f"nscdrender: {case}: {e}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
