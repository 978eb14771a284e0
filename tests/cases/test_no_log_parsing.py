# SPDX-License-Identifier: GPL-3.0-or-later
"""No Python of the repository reads numbers from a solver log (issue 56):
the per-step numbers are in postProcessing/<name>/<startTime>/<name>.dat
(src/grainCloud/stepDataFile.H; nscdpost.read_step_data, step_timing), and
the messages a user reads (fatal errors, start-up and end-of-run reports)
are checked through foamcase.log_message.

Scanned: the Python of tests/ (benches included), tutorials/ and
src/python/: .py files, Python scripts without the extension and the
Python here-documents (<<'PY' ... PY) of the bench shell scripts, parsed
with ast.  Flagged:
  - a regular-expression call (re.findall, re.search, ...) or a
    log_message pattern holding a per-step log line that a .dat file holds
    (STEP_LINES);
  - a regular-expression call on a run's output (p.stdout, p.stderr or a
    variable named log, e.g. log = open("log.vansFoam").read()).
Opening a log to look for a message ("Stop signal .. received" in it) is
not flagged.  ALLOWED lists the exceptions, each with its reason."""

import ast
import os
import re
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# fragments of per-step log lines (as written in a pattern) -> the file
# that holds their numbers
STEP_LINES = {
    "Time = ": "stepTiming (Time, executionTime, clockTime)",
    "Timing": "stepTiming (mapping, fluid, contacts)",
    "deltaT = ": "stepTiming (deltaT)",
    "inside-mesh checks": "stepTiming (insideMeshChecks)",
    "NSCD:": "grainStatistics",
    "sub-steps": "grainStatistics",
    "sweeps": "grainStatistics, grainDepositSettle",
    "settling:": "grainDepositSettle",
    "displacement": "gates",
    "cohesi": "cohesion",
    "fluid torque": "rotationCoupling",
    "lost by the fluid": "rotationCoupling",
    "pressure diffusion": "continuityErrors",
    "continuity errors": "continuityErrors",
    "droplet-grain force": "droplet",
    "droplet: Q_f": "droplet",
    "heat:": "heatBudget, grainHeat",
    "heat budget": "heatBudget",
    "heat patch": "heatBudget",
    "water volume": "waterVolume",
    "water out": "waterVolume",
    "voidFraction min/max": "couplingStatistics",
    "grain Reynolds": "couplingStatistics",
    "grainOutlets:": "grainOutlets",
    "vapour: sum": "vapour",
}

# (path, what) -> why it may; what: "*", "re-output" or "step-line:<fragment>"
ALLOWED = {
    ("tests/cases/test_step_files.py", "*"): (
        "the test of the .dat files against the log lines they stand beside"
    ),
    ("tests/cases/test_no_log_parsing.py", "*"): "this test's own patterns",
    ("tests/bench/rainDeposit", "re-output"): (
        "grainDeposit's one-off 'Static load:' report (a message, no per-step number)"
    ),
    ("tests/bench/granularCollapseDecomposed", "re-output"): (
        "the start-up report 'grains decomposed over N ranks (owned per rank"
        " ...)' (a message, no per-step number; no file holds it)"
    ),
    ("tests/bench/granularCollapse3DDecomposed", "re-output"): (
        "the same start-up report as granularCollapseDecomposed's"
    ),
    ("tests/cases/test_faults_boundaries.py", "step-line:grainOutlets:"): (
        "the removal message names the removed grains' ids, which no file holds"
    ),
    ("tests/cases/test_restart_columns.py", "step-line:grainOutlets:"): (
        "the removal message naming grain id 0 (grainOutlets.dat has no ids)"
    ),
}

RE_FUNCS = {"findall", "search", "finditer", "match", "fullmatch", "split", "compile", "sub"}


def python_sources():
    """{path: [python source, ...]} of the scanned files."""
    files = subprocess.run(
        ["git", "ls-files", "tests", "tutorials", "src/python"],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout.split()
    out = {}
    for f in files:
        path = os.path.join(ROOT, f)
        if "/results/" in f or not os.path.isfile(path):
            continue
        try:
            text = open(path).read()
        except UnicodeDecodeError:
            continue
        first = text.split("\n", 1)[0]
        if f.endswith(".py") or (first.startswith("#!") and "python" in first):
            out[f] = [text]
        elif first.startswith("#!") and ("bash" in first or "sh" in first):
            blocks = re.findall(r"<<\s*'?(\w+)'?\n(.*?)\n\1\n", text, re.S)
            blocks = [b for tag, b in blocks if tag.upper() in ("PY", "EOF", "PYTHON")]
            if blocks:
                out[f] = blocks
    return out


def strings(node):
    """The string constants inside node (f-strings' literal parts too)."""
    return [
        n.value for n in ast.walk(node) if isinstance(n, ast.Constant) and isinstance(n.value, str)
    ]


def findings(tree):
    """[(what, line, detail)] of one parsed source."""
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        is_re = (
            isinstance(f, ast.Attribute)
            and isinstance(f.value, ast.Name)
            and f.value.id == "re"
            and f.attr in RE_FUNCS
        )
        is_msg = isinstance(f, ast.Name) and f.id == "log_message"
        if is_re or is_msg:
            for s in strings(node):
                for frag, dat in STEP_LINES.items():
                    if frag in s or frag.replace(" ", r"\s") in s:
                        found.append((f"step-line:{frag}", node.lineno, f"{s!r}: read {dat}.dat"))
        if is_re:
            for arg in node.args[1:]:
                if (isinstance(arg, ast.Attribute) and arg.attr in ("stdout", "stderr")) or (
                    isinstance(arg, ast.Name) and arg.id == "log"
                ):
                    found.append(("re-output", node.lineno, ast.unparse(arg)))
    return found


@pytest.mark.fast
def test_no_python_parses_a_solver_log():
    sources = python_sources()
    assert "tests/bench/sedimentation" in sources and "src/python/nscdpost.py" in sources
    bad = []
    for path, blocks in sorted(sources.items()):
        if (path, "*") in ALLOWED:
            continue
        for src in blocks:
            for what, line, detail in findings(ast.parse(src)):
                if (path, what) not in ALLOWED:
                    bad.append(f"{path}:{line}: {what}: {detail}")
    assert not bad, "solver logs parsed (read the .dat files instead):\n" + "\n".join(bad)


@pytest.mark.fast
def test_the_guard_sees_log_parsing():
    """The checks flag the kinds of log reading they are for, and not a
    message check or the writing of a log."""
    src = (
        'log = open("log.vansFoam").read()\n'
        'm = re.findall(r"NSCD: contacts (\\d+)", p.stdout)\n'
        'n = re.search(r"anything", log)\n'
        'q = log_message(out, r"sweeps (\\d+)")\n'
        'assert "Stop signal 15" in log\n'
        'open(os.path.join(case, f"log.{app}"), "w")\n'
    )
    kinds = sorted(what for what, _, _ in findings(ast.parse(src)))
    assert kinds == ["re-output", "re-output", "step-line:NSCD:", "step-line:sweeps"], kinds
