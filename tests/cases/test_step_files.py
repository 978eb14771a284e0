# SPDX-License-Identifier: GPL-3.0-or-later
"""The solvers' run-time files (issue 56 item 3; src/grainCloud/stepDataFile.H):
postProcessing/<name>/<startTime>/<name>.dat, a row per time step, hold the
numbers of the log lines they stand beside, to the log's printed precision.
One short case per solver: grainFoam (grainStatistics, grainHeat,
grainOutlets), vansFoam (grainStatistics, continuityErrors, heatBudget),
vansInterFoam (waterVolume, continuityErrors).  The log lines are parsed
here because the test is of the files against them."""

import os
import re
import shutil
import subprocess

import nscdpost
import numpy as np
import pytest
from faultcase import box, set_control
from foamcase import run
from interfoamcase import dam_break
from test_faults_boundaries import outlet_case
from test_grainHeat import column_case
from test_vansFoam_sources import budget_box

NUM = r"([-+0-9.eEnaif]+)"


def steps(log):
    """The log split at its "Time =" lines: [(time name, text of the step)]."""
    parts = re.split(r"^Time = (\S+)\n", log, flags=re.M)
    return list(zip(parts[1::2], parts[2::2]))


def same(file_values, log_values):
    """Each file value printed with the log value's number of significant
    digits equals the log value (the log rounds, the file keeps 17 digits)."""
    assert len(file_values) == len(log_values)
    for f, s in zip(file_values, log_values):
        digits = len(re.sub(r"[^0-9]", "", s.split("e")[0].lstrip("-+0.")))
        assert float(f"{f:.{max(digits, 1)}g}") == pytest.approx(float(s), rel=1e-15, abs=0), (
            f,
            s,
        )


def column(d, name, rows):
    return [d[name][k] for k in rows]


def check_nscd(case, log):
    """grainStatistics.dat against the "NSCD:" lines, one row per step."""
    g = nscdpost.read_step_data(case, "grainStatistics")
    lines = []
    for t, text in steps(log):
        m = re.search(
            r"^NSCD: contacts (\d+), sub-steps (\d+), sweeps (\d+), residual (\S+?)"
            r"(?: \(NOT converged\))?, max overlap/d_min (\S+)$",
            text,
            re.M,
        )
        assert m, text[:500]
        lines.append((t,) + m.groups())
    assert len(g["Time"]) == len(lines) > 2
    assert [float(t) for t, *_ in lines] == list(g["Time"])
    for k, name in enumerate(("contacts", "subSteps", "sweeps", "residual", "maxOverlap")):
        same(g[name], [ln[k + 1] for ln in lines])
    assert set(g["converged"]) <= {0.0, 1.0}
    assert np.all(g["grains"] > 0) and np.all(g["kineticEnergy"] >= 0)
    # the rule that set the sub-steps (nscd::StepReport::substepCause): set
    # exactly when a step was sub-stepped, and named in the log then
    assert set(g["subStepCause"]) <= {0.0, 1.0, 2.0, 3.0, 4.0}
    assert list(g["subStepCause"] > 0) == list(g["subSteps"] > 1)
    named = [bool(re.search(r"^NSCD sub-steps set by: \S", text, re.M)) for _, text in steps(log)]
    assert named == list(g["subSteps"] > 1)
    return g


@pytest.mark.fast
def test_grainFoam_files_match_log(tmp_path, env):
    case, _ = column_case(tmp_path, env, "heat")
    text = open(os.path.join(case, "system", "controlDict")).read()
    text = re.sub(r"endTime\s+\S+;", "endTime 0.02;", text)
    open(os.path.join(case, "system", "controlDict"), "w").write(text)
    log = run("grainFoam", case, env).stdout
    check_nscd(case, log)
    h = nscdpost.read_step_data(case, "grainHeat")
    heat = re.findall(
        rf"^heat: grain mean T = {NUM} K, wall heat = {NUM} J, bottom {NUM} W, right {NUM} W, "
        r"CG iterations (\d+)$",
        log,
        re.M,
    )
    assert len(heat) == len(h["Time"]) > 2
    for k, name in enumerate(("grainMeanT", "wallHeat", "bottom_rate", "right_rate")):
        same(h[name], [v[k] for v in heat])
    same(h["CGIterations"], [v[4] for v in heat])

    # outlets: a row per step, the removals of the "grainOutlets:" lines
    case = outlet_case(tmp_path, "outlet", env, end=0.1)
    log = run("grainFoam", case, env).stdout
    check_nscd(case, log)
    o = nscdpost.read_step_data(case, "grainOutlets")
    out = re.findall(
        r"^grainOutlets: (\d+) grains \(mass (\S+) kg\) left through bottom at time (\S+),"
        r" ids [\d ]+; total through bottom: (\d+) grains, (\S+) kg$",
        log,
        re.M,
    )
    rows = [k for k in range(len(o["Time"])) if o["bottom_grains"][k] > 0]
    assert len(rows) == len(out) == 3
    assert [o["Time"][k] for k in rows] == [float(v[2]) for v in out]
    same(column(o, "bottom_grains", rows), [v[0] for v in out])
    same(column(o, "bottom_mass", rows), [v[1] for v in out])
    same(column(o, "bottom_totalGrains", rows), [v[3] for v in out])
    same(column(o, "bottom_totalMass", rows), [v[4] for v in out])


@pytest.mark.fast
def test_substep_cause_in_log_and_file(tmp_path, env):
    """A sub-stepped step names the rule of nscd::System::advance that set
    its count, the grain and the speed, in the log and in grainStatistics'
    subStepCause: a grain of d 1 cm released at rest over steps of 0.1 s
    changes its velocity by g dt = 0.981 m/s a step (its free velocity, also
    once it rests on the floor), ceil(0.981 * 0.1 / (0.1 * 0.01)) = 99
    sub-steps by the velocity-change rule (System.H).  A consistency check of
    the report against the documented rule (a diagnostic, no physics model)."""
    case = box(tmp_path, "cause", [(0.05, 0.08, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    set_control(case, endTime=0.3, deltaT=0.1, writeInterval=0.1)
    log = run("grainFoam", case, env).stdout
    g = check_nscd(case, log)
    assert list(g["subSteps"]) == [99] * 3
    assert list(g["subStepCause"]) == [1] * 3
    assert (
        "NSCD sub-steps set by: the step's forces change the velocity of grain 0 by 0.981 m/s"
        in log
    )


def check_continuity(case, log):
    """continuityErrors.dat: the last "mixture continuity errors" line of each step."""
    c = nscdpost.read_step_data(case, "continuityErrors")
    last = []
    for t, text in steps(log):
        m = re.findall(
            r"^mixture continuity errors : sum local = (\S+), global = (\S+)$", text, re.M
        )
        assert m, text[:300]
        last.append((t,) + m[-1])
    assert [float(v[0]) for v in last] == list(c["Time"])
    same(c["sumLocal"], [v[1] for v in last])
    same(c["global"], [v[2] for v in last])


@pytest.mark.fast
def test_vansFoam_files_match_log(tmp_path, env):
    case = str(tmp_path / "budget")
    budget_box(case, env, end=0.01)
    log = run("vansFoam", case, env).stdout
    check_nscd(case, log)
    check_continuity(case, log)
    h = nscdpost.read_step_data(case, "heatBudget")
    heat = re.findall(
        rf"^heat: grain mean T = {NUM}, fluid mean T = {NUM}, exchanged Q = {NUM} J, "
        rf"energy fluid \+ grains = {NUM} J$",
        log,
        re.M,
    )
    budget = re.findall(
        rf"^heat budget: fluid boundary = {NUM} J, advected = {NUM} J, sources = {NUM} J, "
        rf"grain walls = {NUM} J, fixed grains = {NUM} J, continuity defect = {NUM} J$",
        log,
        re.M,
    )
    assert len(heat) == len(budget) == len(h["Time"]) > 2
    for k, name in enumerate(("grainMeanT", "fluidMeanT", "exchangedQ", "energy")):
        same(h[name], [v[k] for v in heat])
    terms = nscdpost.HEAT_BUDGET_TERMS
    for k, name in enumerate(terms):
        same(h[name], [v[k] for v in budget])
    patches = re.findall(
        rf"^heat patch (\S+): conduction = {NUM} W, advected = {NUM} W$", log, re.M
    )
    names = sorted({p for p, _, _ in patches})
    for p in names:
        rows = [v for v in patches if v[0] == p]
        same(h[p + "_conduction"], [v[1] for v in rows])
        same(h[p + "_advected"], [v[2] for v in rows])
    dts = re.findall(r"^deltaT = (\S+)$", log, re.M)
    same(h["deltaT"], dts[-len(h["Time"]) :])
    # nscdpost.heat_history: the same arrays from the file
    hh = nscdpost.heat_history(case)
    assert np.array_equal(hh["E"], h["energy"]) and hh["budget"].shape == (len(h["Time"]), 6)
    assert sorted(hh["patches"][0]) == names


@pytest.mark.fast
def test_vansInterFoam_files_match_log(tmp_path, env):
    case = str(tmp_path / "damBreak")
    dam_break(case, env, n=16, end=0.01)
    log = run("vansInterFoam", case, env).stdout
    check_continuity(case, log)
    w = nscdpost.read_step_data(case, "waterVolume")
    vol = re.findall(
        r"^water volume sum\(eps alpha V\) = (\S+) m\^3, alpha min/max = (\S+) (\S+)$", log, re.M
    )
    out = re.findall(r"^water out through the open boundaries = (\S+) m\^3", log, re.M)
    assert len(vol) == len(out) == len(w["Time"]) > 2
    for k, name in enumerate(("waterVolume", "alphaMin", "alphaMax")):
        same(w[name], [v[k] for v in vol])
    same(w["waterOut"], out)
    # the header: OpenFOAM's writeFile layout, the last "#" line the keys
    path = os.path.join(case, "postProcessing", "waterVolume", "0", "waterVolume.dat")
    assert nscdpost.read_run_end(case) == [
        {"start": 0.0, "reason": "endTime", "time": 0.01, "message": []}
    ]
    keys = ["Time", "waterVolume", "alphaMin", "alphaMax", "waterOut"]
    assert nscdpost.dat_columns(path) == keys
    assert foam_monitor_plot(path, env) == [(k, name) for k, name in enumerate(keys[1:], 2)]


def foam_monitor_plot(path, env):
    """Run OpenFOAM's own foamMonitor ($WM_PROJECT_DIR/bin) on the .dat file
    path and draw the gnuplot script it writes with the real gnuplot
    (gnuplot-nox, etc/installDependencies).  foamMonitor asks for the x11
    terminal and re-reads its script forever; headless, a wrapper first on
    PATH keeps the script and hands it to gnuplot once, in the dumb (text)
    terminal.  Returns the plotted curves [(column, title)] of the script
    (foamMonitor takes the keys from the last "#" line: "# Time <name> ..."
    and plots every column after the time against it); asserts that gnuplot
    drew them without an error, each title in the plot's key."""
    gnuplot = shutil.which("gnuplot", path=env["PATH"])
    assert gnuplot, "gnuplot not found: etc/installDependencies installs gnuplot-nox"
    bindir = os.path.join(os.path.dirname(path), "headlessGnuplot")
    os.makedirs(bindir)
    script = os.path.join(bindir, "plot.gp")
    drawn = os.path.join(bindir, "plot.txt")
    with open(os.path.join(bindir, "gnuplot"), "w") as f:
        f.write(
            "#!/bin/sh\n"
            f'sed -e "s/^set term x11.*/set term dumb size 120,40/" -e "/^pause/d" -e "/^reread/d" "$1" > "{script}"\n'
            f'exec "{gnuplot}" "{script}" > "{drawn}" 2>&1\n'
        )
    os.chmod(os.path.join(bindir, "gnuplot"), 0o755)
    monitor = os.path.join(env["WM_PROJECT_DIR"], "bin", "foamMonitor")
    e = dict(env, PATH=bindir + os.pathsep + env["PATH"])
    subprocess.run(
        [monitor, "-i", "2", "-r", "1", path], env=e, check=True, capture_output=True, timeout=60
    )
    plot = open(script).read()
    assert 'set xlabel "Time"' in plot  # the first key after "#"
    curves = [
        (int(c), t)
        for c, t in re.findall(rf'"{re.escape(path)}" using 1:(\d+) with lines title "(\S+)"', plot)
    ]
    picture = open(drawn).read()
    assert "Data Monitoring" in picture and "rror" not in picture, picture
    for _, title in curves:
        assert title in picture, f"{title} not in gnuplot's key:\n{picture}"
    return curves
