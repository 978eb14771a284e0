#!/usr/bin/env python3
"""Post-process the dropletDigging cases (issue 8): droplet depth vs time per
bed temperature (thesis Figure 4.14) and final depth vs bed temperature
(Figure 4.13), results.json (bed_temperature [C], final_depth [m], and per
temperature time [s], depth [m], mass [kg], mdot [kg/s]).

usage: postProcess.py CASE1 [CASE2 ...]   (cases made by setupCase.py)

The thesis curves are not digitised here: the plot marks the regime
thresholds the thesis reports (about 350 C and 500 C, maximum depth near
400 C, section 4.3.3) for orientation only.
"""
import json
import os
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))


def read_case(case):
    info = json.load(open(os.path.join(case, "case.json")))
    d = np.loadtxt(os.path.join(case, "postProcessing", "droplet", "0", "droplet.dat"), ndmin=2)
    return info, d


def main(cases):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    res = {"bed_temperature": [], "final_depth": [], "cases": {}}
    fig, ax = plt.subplots(figsize=(5, 4))
    for c in cases:
        info, d = read_case(os.path.join(here, c) if not os.path.isabs(c) else c)
        T = info["bed_temperature_C"]
        res["bed_temperature"].append(T)
        res["final_depth"].append(float(d[-1, 10]))
        res["cases"][str(T)] = {"time": d[:, 0].tolist(), "depth": d[:, 10].tolist(),
                                "mass": d[:, 5].tolist(), "mdot": d[:, 6].tolist()}
        ax.plot(d[:, 0], d[:, 10] / info["droplet_diameter"], label=f"{T:g} C")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("depth / D")
    ax.legend()
    ax.set_title("droplet depth (thesis Fig. 4.14)")
    fig.tight_layout()
    fig.savefig(os.path.join(here, "dropletDigging_depth.png"), dpi=120)
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(res["bed_temperature"], np.array(res["final_depth"]) * 1e3, "o-", label="nscdFoam")
    for t in (350, 500):
        ax.axvline(t, color="grey", ls="--")
    ax.set_xlabel("bed temperature [C]")
    ax.set_ylabel("final depth [mm]")
    ax.set_title("final depth (thesis Fig. 4.13; dashed: regime thresholds)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(here, "dropletDigging_finalDepth.png"), dpi=120)
    with open(os.path.join(here, "results.json"), "w") as f:
        json.dump(res, f, indent=1)
    print("bed temperature [C], final depth [m]:", list(zip(res["bed_temperature"], res["final_depth"])))


if __name__ == "__main__":
    main(sys.argv[1:])
