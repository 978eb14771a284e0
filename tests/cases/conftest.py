# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared fixtures for the case tests: build small OpenFOAM cases in a tmp dir
and run the project's applications on them (environment from etc/bashrc)."""
import os
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# src/python is an installable package (`pip install -e src/python[render]`,
# done by etc/installDependencies, brings foamlib and PyVista); its modules
# are taken from this checkout (here for the tests, PYTHONPATH of etc/bashrc
# for the applications and scripts they run), so that two checkouts on one
# machine each test their own.  This directory's modules (foamcase) are
# importable because pytest puts the test directory on sys.path.
sys.path.insert(0, os.path.join(ROOT, "src", "python"))
try:
    import nscdpost as _nscdpost
except ImportError as e:
    raise pytest.UsageError(
        f"nscdpost is not installed ({e}): run `python3 -m pip install -e {ROOT}/src/python` "
        "(or etc/installDependencies)")
if os.path.dirname(os.path.realpath(_nscdpost.__file__)) != os.path.realpath(
        os.path.join(ROOT, "src", "python")):
    raise pytest.UsageError(
        f"nscdpost is imported from {_nscdpost.__file__}, not from this checkout: run "
        f"`python3 -m pip install -e {ROOT}/src/python` (or etc/installDependencies)")


def foam_env():
    """Environment of `source etc/bashrc`, computed once."""
    out = subprocess.run(
        ["bash", "-c", f"source {ROOT}/etc/bashrc >/dev/null 2>&1; env -0"],
        check=True, capture_output=True).stdout
    env = {}
    for item in out.split(b"\0"):
        if b"=" in item:
            k, v = item.split(b"=", 1)
            env[k.decode()] = v.decode()
    return env


_ENV = None


@pytest.fixture(scope="session")
def env():
    global _ENV
    if _ENV is None:
        _ENV = foam_env()
    return _ENV


# -- test tiers -----------------------------------------------------------------
# `./Alltest fast` runs `-m fast`: every test not listed below (each < 5 s
# here, the whole tier with ctest under 3 minutes).  `slow`: the tests
# measured over that with the 2 vCPUs shared (pytest --durations,
# 2026-11-23), and whole modules where a module fixture runs the tutorial
# once for several tests.  `mpi`: the test runs mpirun (also fast
# or slow by its own duration).  Update the lists when a test's cost moves.
SLOW_MODULES = {"test_lituyaBay.py", "test_dropletDigging.py", "test_granularCollapse.py",
                "test_tutorialAllruns.py", "test_grainFoam_decomposed.py",
                "test_fluidisedBed3D.py"}
SLOW_TESTS = {
    "test_resolvedRegime.py::test_falling_cylinder_terminal_velocity",
    "test_resolvedRegime.py::test_free_fixed_disc_galilean_consistency",
    "test_resolvedRegime.py::test_dkt_kissing",
    "test_resolvedRegime.py::test_fixed_disc_between_walls_faxen",
    "test_resolvedRegime.py::test_released_disc_added_mass",
    "test_resolvedRegime.py::test_free_disc_settling_faxen",
    "test_grainFoam_physics.py::test_dense_pile_stays_at_rest",
    "test_grainFoam_physics.py::test_restart_is_bit_identical",
    "test_fluidisation.py::test_heave_under_rising_pressure",
    "test_packedBedHeat.py::test_poured_bed_nusselt",
    "test_drag.py::test_lone_sphere_lab_frame_velocity",
    "test_columnCollapse.py::test_column_collapse_runout",
    "test_meshIndependence.py::test_sedimentation_front_mesh_independent",
    "test_droplet_grains.py::test_dense_suspension_settles_steadily",
    # > 4.5 s each in the fast tier, measured under load (pytest --durations=0,
    # 2026-11-23): moved so that `./Alltest fast` stays under 3 minutes
    "test_grainDeposit_replicate.py::test_copies_keep_the_column_packing",
    "test_grainDeposit_replicate.py::test_replicate_warm_start_converges_fast",
    "test_grainDeposit_replicate.py::test_frictionless_side_walls_carry_no_weight",
    "test_grainDeposit_replicate.py::test_copies_of_a_frictionless_column_stay_at_rest",
    "test_grainDeposit_replicate.py::test_noisy_settle_names_the_contact_tolerance",
    "test_drag.py::test_fluidised_bed_expansion",
    "test_snapshots.py::test_sedimentation_allrun_renders_snapshots",
    "test_droplet_heat.py::test_tutorial_skeleton_runs",
    "test_droplet_grains.py::test_porous_grains_pressure_gradient",
    "test_cohesion.py::test_parallel_same_decision",
    "test_cohesion.py::test_parallel_contact_point_across_the_cut",
    "test_boussinesq.py::test_heated_cavity_de_vahl_davis",
    "test_vapour.py::test_front_against_ogata_banks",
    "test_vansInterFoam.py::test_grain_falling_from_air_into_water",
    "test_vansInterFoam.py::test_dam_break_martin_moyce",
    "test_droplet_motion.py::test_falling_droplet_added_mass",
}
MPI_TESTS = {
    "test_cohesion.py::test_parallel_same_decision",
    "test_cohesion.py::test_dry_cohesion_decomposed",
    "test_cohesion.py::test_parallel_contact_point_across_the_cut",
    "test_droplet_restart.py::test_parallel_matches_serial",
    "test_faults_state.py::test_reconstructPar_carries_grain_state",
    "test_fluidisedBed3D.py::test_decomposed_bed_exchanges_momentum_and_keeps_its_grains",
    "test_faults_state.py::test_sigusr1_to_mpirun_writes_and_stops",
    "test_freeSurfaceFunctionObjects.py::test_wave_gauges_parallel_equals_serial",
    "test_grainFoam_decomposed.py::test_decomposed_collapse_matches_serial",
    "test_grainFoam_decomposed.py::test_pile_at_rest_across_ranks_and_restart",
    "test_grainFoam_decomposed.py::test_decomposition_refused_with_heat",
    "test_grainFoam_decomposed.py::test_grain_leaving_the_mesh_stops_a_decomposed_run",
    "test_overlapAdapter.py::test_parallel_matches_serial",
    "test_scotchDecomp.py::test_scotch_parallel_run_keeps_every_grain",
    "test_vansFoam.py::test_parallel_matches_serial",
    "test_vansFoam_decomposed.py::test_sedimentation_matches_serial",
    "test_vansFoam_decomposed.py::test_restart_on_4_ranks_continues_a_2_rank_run",
    "test_vansFoam_decomposed.py::test_rotation_coupling_keeps_every_grain_on_every_rank",
    "test_vansFoam_decomposed.py::test_bed_at_rest_across_ranks_matches_serial",
    "test_vansFoam_sources.py::test_parallel_heat_matches_serial",
}


def pytest_configure(config):
    config.addinivalue_line("markers", "fast: quick tier, each test < 30 s (./Alltest fast)")
    config.addinivalue_line("markers", "slow: > 20 s on this machine")
    config.addinivalue_line("markers", "mpi: runs mpirun")


def pytest_collection_modifyitems(config, items):
    for item in items:
        module = os.path.basename(str(item.fspath))
        name = f"{module}::{item.originalname}"
        slow = module in SLOW_MODULES or name in SLOW_TESTS
        item.add_marker(pytest.mark.slow if slow else pytest.mark.fast)
        if name in MPI_TESTS:
            item.add_marker(pytest.mark.mpi)
