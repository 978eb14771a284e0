#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: the thesis' semi-implicit scheme for every grain
(couplingProperties `resolvedCellsPerDiameter 0;`) against vansFoam's
default on the unresolved tutorials (issue 59, item 1;
docs/validation/resolvedGrains.md, "Implicit scheme for every grain").

Each case is the one its tests use (or the tutorial where a test does),
set up by the tutorial's own setupCase.py and measured by its own
postProcess.py; SCHEME implicit appends `resolvedCellsPerDiameter 0;` to
its couplingProperties (implicitNoPenalty: with `rigidViscosityRatio 0;`
too), nothing else changes:
  sedimentation     tutorial, overlap, 2 s: leading edge, top of the layer
  meshIndependence  test_meshIndependence's 120 discs at h/d 0.5, 1, 2, 4
  fluidisation      test_heave_under_rising_pressure's 400 discs
  settling3D        tutorial on hexahedra to 0.25 s (test_settling3D_meshes)
  fluidisedBed3D    test_fluidisedBed3D's 2,000 spheres, serial, 0.5 s
  rayleighTaylor    tutorial (70,000 discs) to RT_END (default 0.1 s)
CPU: vansFoam's user + system time.  Writes
tests/bench/results/implicitAllGrains.json (one entry per case and scheme,
merged into the file).  ~15 CPU-min, most of it rayleighTaylor.

usage: implicitAllGrains.py [--workdir DIR] [--rt-end T] CASE:SCHEME ...
       (SCHEME default | implicit | implicitNoPenalty)
"""

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
sys.path[:0] = [os.path.join(ROOT, "tests", "cases"), os.path.join(ROOT, "src", "python")]
from foamcase import copy_tutorial, run, tutorial_modules  # noqa: E402

TUT = os.path.join(ROOT, "tutorials", "vansFoam")
OUT = os.path.join(ROOT, "tests", "bench", "results", "implicitAllGrains.json")
ENV = dict(os.environ)


class Runner:
    def __init__(self, scheme):
        self.scheme, self.cpu = scheme, {}

    def opt(self, case):
        """The scheme's couplingProperties entries."""
        if self.scheme == "default":
            return
        with open(os.path.join(case, "constant", "couplingProperties"), "a") as f:
            f.write("\nresolvedCellsPerDiameter 0;\n")
            if self.scheme == "implicitNoPenalty":
                f.write("rigidViscosityRatio 0;\n")

    def timed(self, case, key):
        r0, t0 = resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
        p = run("vansFoam", case, ENV, check=False)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime
        self.cpu[key] = {"cpu_s": round(cpu, 1), "wall_s": round(time.time() - t0, 1)}
        self.cpu[key]["exit_status"] = p.returncode
        print(key, self.cpu[key], flush=True)


def sedimentation(r, w, _):
    case = os.path.join(w, "overlap")
    cmd = ["python3", "setupCase.py", case, "overlap", "2", "50"]
    subprocess.run(cmd, cwd=os.path.join(TUT, "sedimentation"), check=True)
    r.opt(case)
    run("blockMesh", case, ENV)
    run("grainDeposit", case, ENV)
    r.timed(case, "vansFoam")
    _, post = tutorial_modules("vansFoam", "sedimentation")
    return dict([post.measure(case)])["overlap"]


def mesh_independence(r, w, _):
    import test_meshIndependence as tm

    plain = tm.run

    def hooked(app, case, env, *a, **k):
        if app == "blockMesh":
            r.opt(case)
        if app == "vansFoam":
            return r.timed(case, os.path.basename(case))
        return plain(app, case, env, *a, **k)

    tm.run = hooked
    res = {hd: tm.cloud_case(os.path.join(w, f"hd{hd}"), ENV, hd) for hd in (0.5, 1, 2, 4)}
    tm.run = plain
    return {str(k): {"com_drop": c, "edge_drop": e} for k, (c, e) in res.items()}


def fluidisation(r, w, _):
    setup, post = tutorial_modules("vansFoam", "fluidisation")
    box = {"width": 20 * setup.D_MEAN, "height": 40 * setup.D_MEAN}
    setup.deposit(w, n_grains=400, **box)
    run("blockMesh", os.path.join(w, "deposit"), ENV)
    run("grainDeposit", os.path.join(w, "deposit"), ENV)
    res = {}
    for hd, dt in ((1, 1e-3), (4, 1e-3), (1, 1e-4)):
        key = f"hd{hd}_dt{dt:g}"
        case = os.path.join(w, key)
        setup.setup(case, hd, "0.32", w, max_delta_t=dt, ramp_time=0.25, **box)
        r.opt(case)
        run("blockMesh", case, ENV)
        r.timed(case, key)
        res[key] = post.measure(case)
    return res


def settling3d(r, w, _):
    case = copy_tutorial("vansFoam", "settling3D", os.path.join(w, "blockMesh"))
    cmd = ["foamDictionary", "-entry", "endTime", "-set", "0.25", "system/controlDict"]
    subprocess.run(cmd, cwd=case, check=True, capture_output=True)
    r.opt(case)
    run("blockMesh", case, ENV)
    run("grainDeposit", case, ENV)
    r.timed(case, "vansFoam")
    subprocess.run(["python3", "postProcess.py"], cwd=case, check=True, capture_output=True)
    res = json.load(open(os.path.join(case, "results.json")))
    return {k: res[k] for k in ("time", "mean_grain_velocity")}


def fluidised_bed3d(r, w, _):
    setup, post = tutorial_modules("vansFoam", "fluidisedBed3D")
    case = os.path.join(w, "np1")
    setup.setup(case, across=12, grains=2000, u0=0.07, end=0.5, ranks=1, write=0.1)
    r.opt(case)
    run("blockMesh", case, ENV)
    run("grainDeposit", case, ENV)
    r.timed(case, "vansFoam")
    a = post.analyse(case)
    late = [x for x in a["writes"] if x["time"] >= 0.2]
    return {
        "exchange_errors": [
            abs(x["pressure_drop_over_weight"] - x["fluid_force_minus_buoyancy_over_weight"])
            for x in late
        ],
        "pressure_drop_over_weight_second_half": a["pressure_drop_over_weight_second_half"],
    }


def rayleigh_taylor(r, w, end):
    case = os.path.join(w, "case")
    tut = os.path.join(TUT, "rayleighTaylor")
    subprocess.run(["python3", "setupCase.py", case, "1", end], cwd=tut, check=True)
    r.opt(case)
    run("blockMesh", case, ENV)
    run("grainDeposit", case, ENV)
    r.timed(case, "vansFoam")
    subprocess.run(["python3", os.path.join(tut, "postProcess.py"), case], cwd=w, check=True)
    res = json.load(open(os.path.join(w, "results.json")))
    return {k: res[k] for k in ("time", "mean_front_position", "finger_count")}


CASES = {
    "sedimentation": sedimentation,
    "meshIndependence": mesh_independence,
    "fluidisation": fluidisation,
    "settling3D": settling3d,
    "fluidisedBed3D": fluidised_bed3d,
    "rayleighTaylor": rayleigh_taylor,
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", help="CASE:SCHEME")
    ap.add_argument("--workdir", default="implicitAllGrains.work")
    ap.add_argument("--rt-end", default="0.1")
    args = ap.parse_args()
    out = json.load(open(OUT)) if os.path.exists(OUT) else {"benchmark": "implicitAllGrains"}
    for spec in args.runs:
        name, scheme = spec.split(":")
        w = os.path.abspath(os.path.join(args.workdir, f"{name}_{scheme}"))
        shutil.rmtree(w, ignore_errors=True)
        os.makedirs(w)
        r = Runner(scheme)
        res = CASES[name](r, w, args.rt_end)
        out.setdefault("runs", {})[spec] = {"cpu": r.cpu, "result": res}
        with open(OUT, "w") as f:
            json.dump(out, f, indent=1, default=float)
        print(spec, json.dumps(res, default=float)[:2000], flush=True)


if __name__ == "__main__":
    main()
