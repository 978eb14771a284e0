# SPDX-License-Identifier: GPL-3.0-or-later
"""nscdpost: read nscdFoam case output from Python (tutorial post-processing, tests).

Needs numpy, foamlib (PyPI; OpenFOAM files, ascii or binary) and h5py
(the HDF5 grain state).  Installed
with the other tools of src/python by `pip install -e src/python`
(etc/installDependencies).  Functions:
  time_dirs(case)              -> sorted list of (float time, str name) with grains
  read_internal_field(path)    -> internal field of an ascii vol field (numpy; scalar
                                or N x 3), uniform fields as 0-d/3-vectors
  read_grains(case, time_name) -> dict with 'x' (N x 3 [m]), 'd' (N [m]), 'U' (N x 3 [m/s]),
                                'fixed' (N bool)
  write_json(path, obj)        -> results.json writer (sorted keys, floats as-is)
  instantiate_case(base, case, subs) -> copy a template case, replacing @KEYS@
  copy_grain_state(src, dst)   -> copy 0/grainState.h5 and 0/lagrangian of a settled case
  read_contacts(case, time_name) -> the saved contact list and impulses (h5py)
  read_h5(path, dataset)       -> one dataset of an HDF5 file (grainState.h5) with h5py
  write_xdmf(h5path)           -> XDMF 3 file of the grains and contacts of one
                                grainState.h5 for ParaView
  read_droplet_history(case), heat_history(case) -> droplet.dat / vansFoam
                                heatBudget.dat of a run continued from its writes, joined
  read_step_data(case, name)   -> a solver's run-time file postProcessing/<name>/
                                <start>/<name>.dat (columns by name, restarts joined)
  step_timing(case)            -> steps, CPU/clock/split totals of stepTiming.dat
"""

import importlib.util
import json
import os
import re
import shutil
import subprocess

import numpy as np
from foamlib import FoamCase, FoamFieldFile, FoamFile
from grainstate import read_contacts, read_h5, read_state_contacts, write_xdmf, xdmf_grids  # noqa: F401

_FLOAT = r"[-+0-9.eE]+"


def _read_positions(path):
    """Grain centres (n, 3) [m] of a lagrangian `positions` file in the
    legacy format OpenFOAM v1912 writes next to `coordinates`: a list of
    `(x y z) celli` entries.  Read here, not with foamlib: foamlib 1.7.10
    parses this mixed list in a time quadratic in its length (2.2 s for 40
    grains) and rejects it from ~80 grains on (measured 2026-11-23)."""
    text = _read_file(path)
    i = text.find("FoamFile")
    if i >= 0:  # skip the header's braces
        text = text[text.find("}", i) + 1 :]
    start, end = text.find("("), text.rfind(")")
    if start < 0 or end < 0:
        raise ValueError(f"{path}: no list found")
    head = text[:start].strip().split()
    n = int(head[-1]) if head and head[-1].isdigit() else None
    vals = re.findall(
        r"\(\s*(%s)\s+(%s)\s+(%s)\s*\)" % (_FLOAT, _FLOAT, _FLOAT), text[start + 1 : end]
    )
    arr = np.array(vals, dtype=float).reshape(-1, 3)
    if n is not None and len(arr) != n:
        raise ValueError(f"{path}: expected {n} positions, read {len(arr)}")
    return arr


def _read_file(path):
    with open(path) as f:
        return f.read()


def _foam_class(path):
    """`class` of the FoamFile header of path ("" if none), from the file's
    first 2000 characters (foamlib would parse the whole file)."""
    with open(path, errors="replace") as f:
        m = re.search(r"\bclass\s+([^;\s]+)\s*;", f.read(2000))
    return m.group(1) if m else ""


def _foam_file(path):
    """foamlib.FoamFile of path; FileNotFoundError if it does not exist
    (foamlib would create it on write access)."""
    if not os.path.isfile(path):
        raise FileNotFoundError(path)
    return FoamFile(path)


def read_vector_field(path):
    """Values of a lagrangian vectorField file (ascii or binary, `N(...)`
    or uniform `N{(x y z)}` list) as an (n, 3) float array; the legacy
    `positions` file of a cloud as its (n, 3) centres [m]; the internal
    field of a volVectorField (a uniform one as one row).  Raises
    FileNotFoundError, ValueError if the list is not of 3-vectors."""
    cls = _foam_class(path)
    if "Cloud<" in cls:
        return _read_positions(path)
    if cls.startswith("vol"):  # a volVectorField: its internal field
        return np.asarray(read_internal_field(path), dtype=float).reshape(-1, 3)
    arr = np.asarray(_foam_file(path)[None], dtype=float)
    if arr.size == 0:
        return arr.reshape(0, 3)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{path}: not a list of 3-vectors (shape {arr.shape})")
    return arr


def read_scalar_field(path):
    """Values of a lagrangian scalarField / labelField file (ascii or binary,
    `N(...)` or uniform `N{v}` list) as an (n,) float array.  Raises
    FileNotFoundError, ValueError if the list is not of scalars."""
    if _foam_class(path).startswith("vol"):  # a volScalarField: its internal field
        return np.asarray(read_internal_field(path), dtype=float).reshape(-1)
    arr = np.asarray(_foam_file(path)[None], dtype=float)
    if arr.ndim != 1:
        raise ValueError(f"{path}: not a list of scalars (shape {arr.shape})")
    return arr


def numeric_dirs(path):
    """(t, name) of the entries of PATH whose name is a number (time
    directories, postProcessing/<fo>/<start time>), sorted by t; [] if PATH
    is not a directory.  foamlib's FoamCase lists them."""
    if not os.path.isdir(path):
        return []
    return [(t.time, t.name) for t in FoamCase(path)]


def time_dirs(case):
    """Time directories of a case that hold a grains cloud, sorted by time
    (foamlib's FoamCase)."""
    if not os.path.isdir(case):
        return []
    return [
        (t.time, t.name)
        for t in FoamCase(case)
        if os.path.isfile(os.path.join(t.path, "lagrangian", "grains", "positions"))
    ]


#: optional per-grain fields written by the coupled solvers (vansCloud):
#: fluid force [N] (2D: per mesh depth), fluid velocity at the grain [m/s],
#: grain and fluid temperature [K], fluid torque [N m] (rotationCoupling);
#: and the grains' persistent index grainId (grainCloud; the written order
#: changes between times and with the decomposition: sort by it to follow a
#: grain)
OPTIONAL_GRAIN_FIELDS = ("Ffluid", "Ufluid", "T", "Tfluid", "torqueFluid", "grainId")


def read_grains(case, time_name):
    """Grain centres `x`, diameters `d`, velocities `U` and `fixed` flags
    written at one time, plus each field of OPTIONAL_GRAIN_FIELDS present
    (vectors as (n, 3), scalars as (n,) arrays, by the file's class)."""
    cdir = os.path.join(case, time_name, "lagrangian", "grains")
    x = read_vector_field(os.path.join(cdir, "positions"))
    d = read_scalar_field(os.path.join(cdir, "d"))
    U = read_vector_field(os.path.join(cdir, "U"))
    fixed = np.zeros(len(d), dtype=bool)
    if os.path.isfile(os.path.join(cdir, "fixed")):
        fixed = read_scalar_field(os.path.join(cdir, "fixed")) > 0.5
    if not (len(x) == len(d) == len(U) == len(fixed)):
        raise ValueError(f"{cdir}: inconsistent grain field sizes")
    out = {"x": x, "d": d, "U": U, "fixed": fixed}
    for name in OPTIONAL_GRAIN_FIELDS:
        path = os.path.join(cdir, name)
        if not os.path.isfile(path):
            continue
        vector = _foam_class(path).startswith("vector")
        arr = (read_vector_field if vector else read_scalar_field)(path)
        if len(arr) != len(d):
            raise ValueError(f"{path}: {len(arr)} values for {len(d)} grains")
        out[name] = arr
    return out


def read_droplet(case, time_name="0"):
    """postProcessing/droplet/<time_name>/droplet.dat of a vansFoam case with
    a vapourDroplet (src/dropletCoupling/README.md for the columns) as an
    (n, ncol) array; raises FileNotFoundError."""
    return np.loadtxt(
        os.path.join(case, "postProcessing", "droplet", time_name, "droplet.dat"), ndmin=2
    )


def read_dat_history(case, name, file_name):
    """The whole history of a function object's file
    postProcessing/<name>/<start time>/<file_name> (droplet.dat,
    surfaceFieldValue.dat, ...), restarts included: a run restarted at t_r
    writes postProcessing/<name>/<t_r>/; the parts are joined in time order,
    each cut at the next one's start time.  Returns an (n, ncol) array (the
    first column the time); raises FileNotFoundError."""
    root = os.path.join(case, "postProcessing", name)
    parts = numeric_dirs(root) or [(0.0, "0")]
    out = []
    for k, (_t0, time_name) in enumerate(parts):
        a = np.loadtxt(_dat_path(root, time_name, file_name), ndmin=2)
        if k + 1 < len(parts):
            a = a[a[:, 0] <= parts[k + 1][0] * (1 + 1e-12)]
        out.append(a)
    return np.concatenate(out)


def _dat_path(root, time_name, file_name):
    """root/time_name/file_name, or the <stem>_<time_name>.dat that
    OpenFOAM's functionObjects::writeFile writes beside it when a second run
    starts from the same time, whichever is newer; FileNotFoundError if
    neither exists."""
    stem = file_name[:-4] if file_name.endswith(".dat") else file_name
    paths = [
        os.path.join(root, time_name, file_name),
        os.path.join(root, time_name, f"{stem}_{time_name}.dat"),
    ]
    paths = [p for p in paths if os.path.isfile(p)]
    if not paths:
        raise FileNotFoundError(os.path.join(root, time_name, file_name))
    return max(paths, key=os.path.getmtime)


def dat_columns(path):
    """Column names of a .dat file: the words of its last "#" header line
    (OpenFOAM's function-object files and the solvers' run-time files,
    src/grainCloud/stepDataFile.H: "# Time <name> ...")."""
    names = []
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            names = line[1:].split()
    return names


def read_step_data(case, name):
    """A run-time file of the solvers, postProcessing/<name>/<start time>/
    <name>.dat (src/grainCloud/stepDataFile.H: heatBudget,
    continuityErrors, waterVolume, vapour, grainStatistics, grainOutlets,
    grainHeat; the columns and units in the solvers' README.md), restarts
    joined (read_dat_history), as a dict mapping each column name of the
    header ("Time" first) to an (n,) array.  Raises FileNotFoundError."""
    root = os.path.join(case, "postProcessing", name)
    parts = numeric_dirs(root) or [(0.0, "0")]
    cols = dat_columns(_dat_path(root, parts[0][1], name + ".dat"))
    a = read_dat_history(case, name, name + ".dat")
    if a.shape[1] != len(cols):
        raise ValueError(f"{root}: {a.shape[1]} columns, header names {len(cols)}")
    return {c: a[:, k] for k, c in enumerate(cols)}


def step_timing(case):
    """Computing time of a solver run from its stepTiming.dat
    (src/grainCloud/stepTimingFile.H; the log's ExecutionTime, ClockTime and
    "Timing [s]:" lines): 'steps' (rows), for each column summed from the
    start of a run (executionTime, clockTime, insideMeshChecks; coupled:
    mapping, fluid, contacts) its total over the run and its restarts, and
    'cpu_per_step' (differences of executionTime within a run, the first
    step of each run left out)."""
    t = read_step_data(case, "stepTiming")
    exe = t["executionTime"]
    out = {"steps": len(exe), "cpu_per_step": np.diff(exe)[np.diff(exe) >= 0]}
    ends = np.append(np.nonzero(np.diff(exe) < 0)[0], len(exe) - 1)  # each run's last row
    for k in t:
        if k not in ("Time", "deltaT"):
            out[k] = float(t[k][ends].sum()) if len(exe) else 0.0
    return out


def read_droplet_history(case):
    """The whole droplet.dat history of a case, restarts included
    (`read_dat_history`); the same array as read_droplet(case) for a run
    that was not restarted."""
    return read_dat_history(case, "droplet", "droplet.dat")


HEAT_BUDGET_TERMS = (
    "fluidBoundary",
    "advected",
    "sources",
    "grainWalls",
    "fixedGrains",
    "continuityDefect",
)


def heat_history(case):
    """Per time step of a vansFoam run with heat on, from its heatBudget.dat
    (postProcessing/heatBudget/<start time>/heatBudget.dat, restarts
    joined; applications/solvers/vansFoam/README.md): dict of arrays `time`
    [s], `dt` [s] (the step), `grain_T`, `fluid_T` [K] (means), `Q` [J]
    (exchanged), `E` [J] (fluid + grains energy), `budget` (n, 6) [J]
    (HEAT_BUDGET_TERMS: fluid boundary, advected, sources, grain walls,
    fixed grains, continuity defect) and `patches`, a list with one dict
    per step mapping each budget patch to its (conduction, advected) rates
    [W].  Raises FileNotFoundError."""
    d = read_step_data(case, "heatBudget")
    names = [c[: -len("_conduction")] for c in d if c.endswith("_conduction")]
    n = len(d["Time"])
    return {
        "time": d["Time"],
        "dt": d["deltaT"],
        "grain_T": d["grainMeanT"],
        "fluid_T": d["fluidMeanT"],
        "Q": d["exchangedQ"],
        "E": d["energy"],
        "budget": np.column_stack([d[k] for k in HEAT_BUDGET_TERMS]).reshape(n, 6),
        "patches": [
            {p: (float(d[p + "_conduction"][i]), float(d[p + "_advected"][i])) for p in names}
            for i in range(n)
        ],
    }


def _unquote(text):
    """An OpenFOAM string as foamlib returns it ("..." with \\" and \\\\
    escapes) without its quotes and escapes."""
    text = str(text)
    if len(text) >= 2 and text[0] == text[-1] == '"':
        text = text[1:-1]
    return re.sub(r"\\(.)", r"\1", text)


def read_run_end(case):
    """How each run of a case ended, from the solvers'
    postProcessing/runEnd/<start time>/runEnd (src/grainCloud/
    grainRunControl.H), in start-time order: a list of dicts `start` [s],
    `reason` ("endTime", "stopSignal", "fatalError", or "running": not
    ended, killed, or a parallel run aborted by its error), `time` [s] (the
    last completed step) and `message` (the error's non-empty lines; [] but
    for fatalError).  [] if the case has none."""
    root = os.path.join(case, "postProcessing", "runEnd")
    out = []
    for t0, name in numeric_dirs(root):
        path = os.path.join(root, name, "runEnd")
        if not os.path.isfile(path):
            continue
        f = _foam_file(path)
        msg = f.get("message", [])
        msg = [msg] if isinstance(msg, str) else list(msg or [])
        out.append(
            {
                "start": t0,
                "reason": str(f["reason"]),
                "time": float(f["time"]),
                "message": [_unquote(m) for m in msg],
            }
        )
    return out


def trapezoid(y, x):
    """Trapezoidal integral of y(x) (numpy.trapezoid from numpy 2.0,
    numpy.trapz before: Debian 12's python3-numpy is 1.24)."""
    f = getattr(np, "trapezoid", None) or np.trapz
    return f(y, x)


def load_module(name, path):
    """Import the Python file `path` as a module named `name` without
    putting it on sys.path (tutorials share file names: setupCase.py,
    postProcess.py)."""
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def run_apps(case, apps):
    """Run each application of apps (names on PATH, etc/bashrc sourced) in
    case, one after the other, the output of each in case/log.<app>, as
    OpenFOAM's runApplication does; raises subprocess.CalledProcessError on
    the first that fails."""
    for app in apps:
        with open(os.path.join(case, f"log.{app}"), "w") as log:
            subprocess.run([app], cwd=case, stdout=log, stderr=subprocess.STDOUT, check=True)


def write_json_with_history(path, rec):
    """Write the record `rec` to `path`, the records the file held before
    kept under rec["earlier_measurements"] (the latest last)."""
    old = json.load(open(path)) if os.path.exists(path) else {}
    earlier = old.pop("earlier_measurements", [])
    if old:
        earlier.append(old)
    if earlier:
        rec["earlier_measurements"] = earlier
    with open(path, "w") as f:
        json.dump(rec, f, indent=1)
        f.write("\n")


def write_json(path, obj):
    with open(path, "w") as f:
        json.dump(obj, f, indent=2, sort_keys=True)
        f.write("\n")


def instantiate_case(base, case, subs):
    """Copy the template case directory `base` to `case` (replacing it;
    foamlib's FoamCase.copy) and substitute every key of `subs` (e.g.
    "@ENDTIME@") by its value in all files."""
    if os.path.exists(case):
        shutil.rmtree(case)
    FoamCase(base).copy(case)
    for root, _, files in os.walk(case):
        for f in files:
            p = os.path.join(root, f)
            with open(p) as fh:
                txt = fh.read()
            for k, v in subs.items():
                txt = txt.replace(k, v)
            with open(p, "w") as fh:
                fh.write(txt)


def read_internal_field(path):
    """Internal field of a volScalarField/volVectorField file (ascii or
    binary), or the values of a volScalarField::Internal (DimensionedField,
    keyword `value`), as a float numpy array: (n,) or (n, 3); a uniform field
    as a 0-d array or a 3-vector (broadcastable).  Raises FileNotFoundError,
    ValueError if the file has neither internalField nor value."""
    f = FoamFieldFile(path) if os.path.isfile(path) else None
    if f is None:
        raise FileNotFoundError(path)
    # a vol field's boundary patches have `value` entries too: internalField
    # is looked for first, `value` only in a file without it
    for key in ("internalField", "value"):
        if key in f:
            return np.asarray(f[key], dtype=float)
    raise ValueError(f"no internalField in {path}")


def copy_grain_state(src, dst, time_name="0"):
    """Copy the grain state (grainState.h5 and lagrangian/) of case src at
    time_name into case dst at time_name, e.g. a bed settled once by
    grainDeposit into each case that starts from it."""
    for item in ("grainState.h5", "lagrangian"):
        a = os.path.join(src, time_name, item)
        b = os.path.join(dst, time_name, item)
        (shutil.copytree if os.path.isdir(a) else shutil.copy)(a, b)


def power_law_fit(h, f, p_grid):
    """Least-squares fit f(h) = f_inf + C h^p over all levels: p scanned over
    p_grid, f_inf and C linear for each p (grid-convergence studies,
    tests/bench/*Convergence).  Returns (p, f_inf, C, rms misfit)."""
    h = np.asarray(h, float)
    f = np.asarray(f, float)
    best = None
    for p in p_grid:
        A = np.column_stack([np.ones_like(h), h**p])
        coef, *_ = np.linalg.lstsq(A, f, rcond=None)
        r = float(np.sqrt(np.mean((A @ coef - f) ** 2)))
        if best is None or r < best[3]:
            best = (float(p), float(coef[0]), float(coef[1]), r)
    return best
