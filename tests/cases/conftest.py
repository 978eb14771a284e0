"""Shared fixtures for the case tests: build small OpenFOAM cases in a tmp dir
and run the project's applications on them (environment from etc/bashrc)."""
import os
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "src", "python"))
sys.path.insert(0, os.path.dirname(__file__))


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
