#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Observables of droplet runs on the thesis bed, beside the spread of
perturbed starts: do the contact settings that buy speed (compliance,
tolerance) move what the droplet does by more than where it lands on the bed
does?

Input: run directories kept by `tests/bench/dropletDigging` (KEEP_WORK=<dir>,
the case in <dir>/case), each with a label and a role:

    dropletDiggingSpread.py OUT.json ref:<label>:<dir>[:<json>] ... test:<label>:<dir>[:<json>] ...

`ref` runs are the perturbed starts of one setting (the same bed and contact
law, the droplet's centre moved by DROPLET_X_OFFSET): their range is the
spread (<json>: the run's bench JSON, tests/bench/results/<RESULT_NAME>.json,
for its cost).  `test` runs (another compliance, bed settled with it, or another
tolerance) are set beside it.  Observables, from the droplet's history
(postProcessing/droplet, thesis eq. 4.15-4.17, as the tutorial's
postProcess.summary): depth of the droplet's bottom below the bed top [m] at
0.05, 0.1, 0.15, 0.2 s; its highest lift (-min depth) [m] and when;
sinking speed over 0.1-0.2 s [m/s] (linear fit); grains inside the droplet
at the end; droplet mass at the end over its start; and the cost (CPU-h per
simulated second, sweeps, sub-steps per step, the largest overlap over d_min
from the bench JSON and grainStatistics).  A test run's observable is
`within` when it lies inside the reference range widened by half its width
on each side (the spread of n = 2-3 starts underestimates the population's);
a run stopped early is compared at the times it reached.  Depths, lift and
speed are printed in mm and mm/s.

Writes OUT.json (tests/bench/results/dropletDiggingSpread.json) and prints
the table of docs/validation/contactCompliance.md.
"""

import json
import os
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
sys.path.insert(0, os.path.join(root, "src", "python"))
import nscdpost  # noqa: E402

TIMES = (0.05, 0.1, 0.15, 0.2)
# droplet.dat's columns, as the tutorial's postProcess.py names them
COL = nscdpost.load_module(
    "dropletDigging_postProcess",
    os.path.join(root, "tutorials", "vansFoam", "dropletDigging", "postProcess.py"),
).COL


def observables(case):
    """The observables of one kept case directory (module docstring); raises
    FileNotFoundError without a droplet history."""
    d = nscdpost.read_droplet_history(case)
    t, depth = d[:, 0], d[:, COL["depth"]]
    out = {f"depth_{x:g}": float(np.interp(x, t, depth)) for x in TIMES if x <= t[-1] + 1e-9}
    k = int(np.argmin(depth))
    out["lift_max"] = float(-depth[k])
    out["lift_time"] = float(t[k])
    w = (t >= 0.1) & (t <= 0.2)
    out["sinking_speed_01_02"] = float(np.polyfit(t[w], depth[w], 1)[0]) if w.sum() > 2 else None
    out["grains_inside_end"] = int(d[-1, COL["nGrainsIn"]])
    out["mass_ratio_end"] = float(d[-1, COL["m"]] / d[0, COL["m"]])
    out["end_time"] = float(t[-1])
    return out


def cost(case, bench_json):
    """Cost figures of the run: from its bench JSON when given, and the
    largest overlap over d_min of grainStatistics (None if not written)."""
    out = {}
    if bench_json and os.path.isfile(bench_json):
        b = json.load(open(bench_json))
        for k in (
            "cpu_hours_per_simulated_second",
            "sweeps_per_step_median",
            "substeps_per_step_median",
            "steps",
            "contact",
            "droplet_x_offset_m",
        ):
            out[k] = b.get(k)
    g = nscdpost.read_step_data(case, "grainStatistics")
    if "maxOverlap" in g:
        out["max_overlap_over_dmin"] = float(max(float(v) for v in g["maxOverlap"]))
    out["steps_not_converged"] = (
        int(sum(1 for v in g["converged"] if int(float(v)) == 0)) if "converged" in g else None
    )
    return out


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    out_path, runs = argv[1], []
    for spec in argv[2:]:
        role, label, path, *bench = spec.split(":")
        if role not in ("ref", "test"):
            sys.exit(f"{spec}: the role must be ref or test")
        case = os.path.join(path, "case")
        bench = bench[0] if bench else None
        runs.append(
            {
                "label": label,
                "role": role,
                "dir": path,
                "observables": observables(case),
                **cost(case, bench),
            }
        )
    refs = [r for r in runs if r["role"] == "ref"]
    keys = [k for k in refs[0]["observables"] if k not in ("end_time", "lift_time")]
    spread = {}
    for k in keys:
        vals = [r["observables"][k] for r in refs if r["observables"].get(k) is not None]
        lo, hi = min(vals), max(vals)
        spread[k] = {"min": lo, "max": hi, "band": [lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo)]}
    for r in runs:
        if r["role"] == "test":
            r["within"] = {
                k: (
                    spread[k]["band"][0] <= r["observables"][k] <= spread[k]["band"][1]
                    if r["observables"].get(k) is not None
                    else None
                )
                for k in keys
            }
    res = {
        "benchmark": "dropletDiggingSpread",
        "reference": "perturbed starts (DROPLET_X_OFFSET) of the reference setting: their range",
        "spread": spread,
        "runs": runs,
    }
    json.dump(res, open(out_path, "w"), indent=2)
    head = "| run | role | " + " | ".join(keys) + " | CPU-h/s | sweeps | max overlap/d |"
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    for r in runs:
        o = r["observables"]
        cells = [
            "-"
            if o.get(k) is None
            else (
                f"{o[k] * 1e3:.3f}" if k.startswith(("depth", "lift", "sinking")) else f"{o[k]:.4g}"
            )
            for k in keys
        ]
        ov = r.get("max_overlap_over_dmin")
        ch = r.get("cpu_hours_per_simulated_second")
        print(
            f"| {r['label']} | {r['role']} | "
            + " | ".join(cells)
            + f" | {ch if ch is None else round(ch, 3)} | {r.get('sweeps_per_step_median')} |"
            + f" {ov if ov is None else round(ov, 4)} |"
        )


if __name__ == "__main__":
    main(sys.argv)
