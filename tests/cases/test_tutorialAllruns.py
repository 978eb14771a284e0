# SPDX-License-Identifier: GPL-3.0-or-later
"""Every tutorial's own Allrun runs to its end.

Each tutorial is copied (its files under version control only, so no
earlier output is reused) and its Allrun is run unchanged with the smallest
arguments it accepts (fewer grains, a shorter end time, a coarser mesh; the
`usage:` line of each Allrun): mesh, deposit, solver, foamToVTK,
post-processing and snapshot pictures, in the order a user runs them.

A smoke test of the whole chain, not of physics (the physics of each
tutorial is checked by its own test module): the Allrun exits 0, every log it
wrote ends without a FOAM FATAL message, and the results it promises
(a non-empty results.json, the PNGs) are written.  The sedimentation
tutorial's Allrun runs in test_snapshots.py, lituyaBay's (`./Allrun
reduced`) in test_lituyaBay.py and granularCollapse's (`./Allrun 0.02 0.5
0.25`) in test_granularCollapse.py::test_three_regimes, whose tests check
its results (foamcase.run_allrun: the same checks as here).
tests/bench/tutorialAllruns runs this module and records each Allrun's time
(4.3 min for the twelve on this machine, 2026-11-23).
"""

import pytest
from foamcase import copy_tutorial, run_allrun

pytestmark = pytest.mark.slow

# tutorial -> (Allrun arguments, results.json path relative to the tutorial,
#              PNG glob that must match at least once); smallest arguments
# each Allrun's usage line accepts
SMOKE = {
    "grainFoam/heatConduction": (["100"], "results.json", "case/case_grains_t*.png"),
    # builds its case with ../cylinderSedimentation/setupCase.py (copied beside it)
    "vansFoam/draftingKissingTumbling": (
        ["0.02", "4"],
        "results.json",
        "case/case_voidFraction_t*.png",
    ),
    "vansFoam/packedBedHeat": (["DiFeliceColburn", "1", "100"], "results.json", "Re*/Re*_T_t*.png"),
    "vansFoam/rayleighTaylor": (["0.1", "0.005"], "results.json", "case/case_voidFraction_t*.png"),
    "vansFoam/settling3D": (["0.02"], "results.json", "settling3D_voidFraction_t*.png"),
    "vansFoam/mergingClouds": (["0.05", "0.05"], "results.json", "merge/merge_voidFraction_t*.png"),
    # 100,000 spheres on 2 ranks for 20 steps
    "vansFoam/fluidisedBed3D": (
        ["0.02", "2"],
        "case/results.json",
        "case/case_voidFraction_t*.png",
    ),
    "vansInterFoam/damBreak": (["4"], "results.json", "case/case_alpha.water_t*.png"),
    # the five below pour a bed even at their smallest run (12-60 s each here)
    "grainFoam/columnCollapse": (["100"], "results.json", "a*/a*_grains_t*.png"),
    "vansFoam/bubblingBed": (["0.02", "5", "1.54"], "results.json", "v*/v*_voidFraction_t*.png"),
    "vansFoam/cylinderSedimentation": (
        ["0.02", "4", "yes", "1e-3", "0.02", "resolved", "4"],
        "results.json",
        "case/case_voidFraction_t*.png",
    ),
    "vansFoam/dropletDigging": (
        ["reduced", "0.01"],
        "reduced/results.json",
        "reduced/T*/T*_T_t*.png",
    ),
    "vansFoam/fluidisation": (["0.02", "1"], "results.json", "hd*/hd*_voidFraction_t*.png"),
}


# the Allruns above that run mpirun (runParallel)
PARALLEL = {"vansFoam/fluidisedBed3D"}


@pytest.mark.parametrize(
    "tutorial",
    [pytest.param(t, marks=pytest.mark.mpi) if t in PARALLEL else t for t in sorted(SMOKE)],
)
def test_allrun_runs_to_its_end(tutorial, tmp_path, env):
    args, results, pngs = SMOKE[tutorial]
    solver, case = tutorial.split("/")
    work = copy_tutorial(solver, case, str(tmp_path / case))
    if case == "draftingKissingTumbling":
        copy_tutorial(solver, "cylinderSedimentation", str(tmp_path / "cylinderSedimentation"))
    run_allrun(work, env, args, results, pngs)
