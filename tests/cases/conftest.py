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
        "(or etc/installDependencies)"
    ) from e
if os.path.dirname(os.path.realpath(_nscdpost.__file__)) != os.path.realpath(
    os.path.join(ROOT, "src", "python")
):
    raise pytest.UsageError(
        f"nscdpost is imported from {_nscdpost.__file__}, not from this checkout: run "
        f"`python3 -m pip install -e {ROOT}/src/python` (or etc/installDependencies)"
    )


def foam_env():
    """Environment of `source etc/bashrc`, computed once."""
    out = subprocess.run(
        ["bash", "-c", f"source {ROOT}/etc/bashrc >/dev/null 2>&1; env -0"],
        check=True,
        capture_output=True,
    ).stdout
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
# Every test carries its speed tier, exactly one of
#   @pytest.mark.fast   each test < 5 s here; `./Alltest fast` (-m fast), the
#                       whole tier with ctest under 3 minutes
#   @pytest.mark.slow   measured over that with the 2 vCPUs shared (pytest
#                       --durations=0), or in a module whose module fixture
#                       runs a tutorial once for several tests
# (`pytestmark = pytest.mark.fast` where a whole module is one tier), and in
# addition @pytest.mark.mpi when it runs mpirun (run_parallel, runParallel in
# an Allrun, ...).  Collection fails on a test without exactly one speed tier;
# a test without `mpi` that calls mpirun fails (see no_mpirun_unless_marked).
# Move a test between fast and slow when its cost moves.
TIERS = ("fast", "slow")


def pytest_configure(config):
    config.addinivalue_line("markers", "fast: quick tier, each test < 5 s here (./Alltest fast)")
    config.addinivalue_line("markers", "slow: over the fast tier's budget (./Alltest slow)")
    config.addinivalue_line("markers", "mpi: runs mpirun (./Alltest mpi); also fast or slow")


@pytest.hookimpl(tryfirst=True)  # before -m deselects: every collected test is checked
def pytest_collection_modifyitems(config, items):
    wrong = []
    for item in items:
        tiers = [m.name for m in item.iter_markers() if m.name in TIERS]
        if len(tiers) != 1:
            wrong.append(f"  {item.nodeid}: {', '.join(tiers) or 'no tier'}")
    if wrong:
        raise pytest.UsageError(
            "each test needs exactly one tier marker, @pytest.mark.fast or @pytest.mark.slow "
            "(tests/cases/conftest.py):\n" + "\n".join(wrong)
        )


@pytest.fixture(autouse=True)
def no_mpirun_unless_marked(request, tmp_path_factory):
    """For a test not marked mpi that uses the OpenFOAM environment, `mpirun`
    on its PATH is a guard script that fails saying so: a new parallel test
    cannot land outside `./Alltest mpi` unnoticed."""
    if "env" not in request.fixturenames or request.node.get_closest_marker("mpi"):
        yield
        return
    guard_dir = tmp_path_factory.getbasetemp() / "mpirunGuard"
    guard = guard_dir / "mpirun"
    if not guard.exists():
        guard_dir.mkdir(exist_ok=True)
        guard.write_text(
            "#!/bin/sh\necho 'mpirun called by a test not marked @pytest.mark.mpi: "
            "mark it (tests/cases/conftest.py)' >&2\nexit 3\n"
        )
        guard.chmod(0o755)
    env = request.getfixturevalue("env")
    path = env["PATH"]
    env["PATH"] = f"{guard_dir}:{path}"
    try:
        yield
    finally:
        env["PATH"] = path
