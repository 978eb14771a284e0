# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-rank cost model of a coupled vansFoam/vansInterFoam step with the
grains decomposed, from 64 to 1,024 ranks (issue 57 item 5).

Every constant is a measured figure of this repository (the source named
beside it) or a stated assumption (marked ASSUMED); the model and its
limits are described in docs/validation/decomposedGrains.md, "Scaling model
for 64-1,024 ranks".  Prints the markdown tables and writes
tests/bench/results/scalingModel.json.

    python3 tests/bench/scalingModel.py
"""

import json
import math
import os

# --- measured (this machine, one core per figure) -----------------------------
# 100,000 spheres at rest, x slabs (results/nscdDecomposed3D100000.json):
W_REST = 0.0639 / 100_000  # s per sphere-step, undecomposed System::step
C_D = 1.047  # decomposed path on one rank / System::step
GHOSTS_8 = (1630, 12_500)  # ghosts, owned of the busiest rank at 8 ranks
WORK_8 = 0.166  # its NSCD work / undecomposed
BYTES_PER_GHOST_AVERAGING = 1_145_630 / 1630 / 15  # sent per ghost per averaging
A_SLABS = 16  # averagings per step at 4-8 ranks (15-17)
# fluidisedBed3D on 4 ranks (tutorial README, "Cost"): contacts 333 s and
# mapping 54 s of rank 0's clock over 1,000 steps of ~25,000 flowing spheres,
# 4 ranks sharing 2 cores (x 0.5 for one core per rank)
W_FLOW = 0.5 * 0.333 / 25_000  # s per sphere-step, contacts, flowing bed
W_MAP = 0.5 * 0.054 / 25_000  # s per sphere-step, overlap mapping and sums
# rayleighTaylor serial (tutorial README): fluid 364 s over 4,576 steps of
# 18,056 cells
W_FLUID = 364 / 4576 / 18_056  # s per cell-step (PIMPLE, 2 correctors)
FCC_DENSITY = 1.41  # spheres per d^3 (fcc; random packing 1.15)

# --- assumed ------------------------------------------------------------------
ALLREDUCE_PER_STAGE = 2e-6  # s, small all-reduce, per log2(P) stage (InfiniBand class) ASSUMED
NEIGHBOUR_LATENCY = 5e-6  # s per neighbour exchange (InfiniBand class) ASSUMED
NEIGHBOUR_BANDWIDTH = 5e9  # B/s per rank ASSUMED
FLUID_REDUCTIONS = (
    100  # all-reduces of the fluid per step (p: 2 correctors x ~25 CG/GAMG iterations x 2) ASSUMED
)
COUPLING_EXCHANGES = (
    6  # neighbour exchanges of the coupling per step (mapping sums over copies) ASSUMED
)
CELLS_PER_SPHERE = (
    0.25  # fluid cells per sphere (cells of ~2 d, water and air above the bed) ASSUMED
)
BED_DEPTH = 100  # spheres (pencils' height) ASSUMED


def interface_factor():
    """k of work = C_D w n (1 + k f), f = ghosts/owned, fitted on the 8-rank slab run."""
    f = GHOSTS_8[0] / GHOSTS_8[1]
    return (WORK_8 * 8 / C_D - 1) / f


def halo_depth():
    """Ghost layer depth delta [d] of the 8-rank slab run: 815 ghosts per
    interface; the bed is 100,000 fcc spheres in 8 layers (layer spacing
    sqrt(2/3) d, areal density FCC_DENSITY^(2/3) per d^2) on a square
    footprint, so an interface is 8 sqrt(2/3) d high and one footprint side
    long."""
    side = math.sqrt(100_000 / 8 / FCC_DENSITY ** (2 / 3))
    area = 8 * math.sqrt(2 / 3) * side
    return GHOSTS_8[0] / 2 / (area * FCC_DENSITY)


def ghost_share(n, shape, delta):
    """Ghosts/owned of a subdomain of n spheres: 'cube' or 'pencil' (full
    bed depth BED_DEPTH, square cross-section)."""
    if shape == "cube":
        s = (n / FCC_DENSITY) ** (1 / 3)
        return ((s + 2 * delta) / s) ** 3 - 1
    a = math.sqrt(n / (FCC_DENSITY * BED_DEPTH))
    return ((a + 2 * delta) / a) ** 2 - 1


def rank_step(n, p, shape, k, delta, solves_grow=False):
    """Per-rank seconds of one coupled step: (work, communication, parts).
    solves_grow: the interface's extra local solves grow with the number of
    averagings (k x A/A_SLABS), the pessimistic bound for cubes."""
    f = ghost_share(n, shape, delta)
    # averagings: chains do not cross pencils' cuts; in cubes a vertical
    # chain crosses p^(1/3) subdomains, one per averaging (Visseq et al. 2012)
    a = A_SLABS * (1 if shape == "pencil" else round(p ** (1 / 3)))
    k_eff = k * a / A_SLABS if solves_grow else k
    grains = C_D * (W_FLOW + W_MAP) * n * (1 + k_eff * f)
    fluid = W_FLUID * CELLS_PER_SPHERE * n
    stages = math.ceil(math.log2(p))
    allreduce = ALLREDUCE_PER_STAGE * stages
    ghosts = f * n
    exchange = NEIGHBOUR_LATENCY + ghosts * BYTES_PER_GHOST_AVERAGING / NEIGHBOUR_BANDWIDTH
    comm = a * (allreduce + exchange) + FLUID_REDUCTIONS * allreduce
    comm += COUPLING_EXCHANGES * exchange
    return grains + fluid, comm, dict(ghost_share=f, averagings=a)


def table(label, runs, k, delta):
    rows = []
    serial = None
    for total, p, shape in runs:
        n = total / p
        work, comm, parts = rank_step(n, p, shape, k, delta)
        work_grow, comm_grow, _ = rank_step(n, p, shape, k, delta, solves_grow=True)
        if serial is None or total != serial[0]:
            serial = (total, (W_FLOW + W_MAP) * total + W_FLUID * CELLS_PER_SPHERE * total)
        eff = serial[1] / (p * (work + comm))
        eff_grow = serial[1] / (p * (work_grow + comm_grow))
        rows.append(
            dict(
                run=label,
                spheres=total,
                ranks=p,
                shape=shape,
                spheres_per_rank=round(n),
                ghost_share=round(parts["ghost_share"], 3),
                averagings=parts["averagings"],
                work_ms=round(1e3 * work, 2),
                communication_ms=round(1e3 * comm, 3),
                efficiency=round(eff, 2),
                efficiency_if_solves_grow=round(eff_grow, 2),
            )
        )
    return rows


def main():
    k, delta = interface_factor(), halo_depth()
    runs = []
    for shape in ("pencil", "cube"):
        runs += table("strong, 1e7 spheres", [(1e7, p, shape) for p in (64, 256, 1024)], k, delta)
        runs += table(
            "weak, 1e5 spheres per rank", [(1e5 * p, p, shape) for p in (64, 256, 1024)], k, delta
        )
    print(f"interface factor k = {k:.2f}, halo depth {delta:.2f} d")
    print(
        "| run | ranks | subdomains | spheres per rank | ghosts/owned | averagings | work [ms] |"
        " communication [ms] | efficiency | if the extra solves grow with the averagings |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in runs:
        print(
            f"| {r['run']} | {r['ranks']} | {r['shape']} | {r['spheres_per_rank']:,} | {r['ghost_share']} | "
            f"{r['averagings']} | {r['work_ms']} | {r['communication_ms']} | {r['efficiency']} |"
            f" {r['efficiency_if_solves_grow']} |"
        )
    out = dict(
        benchmark="scalingModel",
        what="per-rank cost model of a coupled step, grains decomposed (docs/validation/decomposedGrains.md)",
        interface_factor=k,
        halo_depth_d=delta,
        measured=dict(
            w_rest=W_REST,
            c_d=C_D,
            w_flow=W_FLOW,
            w_map=W_MAP,
            w_fluid=W_FLUID,
            averagings_slabs=A_SLABS,
        ),
        assumed=dict(
            allreduce_per_stage=ALLREDUCE_PER_STAGE,
            neighbour_latency=NEIGHBOUR_LATENCY,
            neighbour_bandwidth=NEIGHBOUR_BANDWIDTH,
            fluid_reductions=FLUID_REDUCTIONS,
            coupling_exchanges=COUPLING_EXCHANGES,
            cells_per_sphere=CELLS_PER_SPHERE,
            bed_depth=BED_DEPTH,
        ),
        runs=runs,
    )
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "scalingModel.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
