#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Run a command and record its CPU time and peak memory (the benches of
decomposed runs, tests/bench/decomposedRuns.sh; not a test).

usage: peakMemory.py OUT.json CMD [ARGS...]

Exact, from the child's resource usage (wait4, as GNU time -v): user +
system CPU seconds and the peak resident set size (ru_maxrss). Sampled every
0.1 s from /proc/<pid>/smaps_rollup, their maxima: Rss, Pss (a page shared
by n processes counts 1/n: what a process adds to the node; the shared
libraries' pages are counted once over the ranks), Anonymous (the process's
own heap and stacks, which RSS and PSS both count whole) and Pss_File
(file-backed pages: the libraries). A sample can miss a peak shorter than
0.1 s; ru_maxrss cannot. The command's exit code is returned."""

import json
import resource
import subprocess
import sys
import time

FIELDS = ("Rss", "Pss", "Anonymous", "Pss_File")


def sample(pid):
    """{field: MB} of /proc/pid/smaps_rollup, {} once the process is gone."""
    try:
        with open(f"/proc/{pid}/smaps_rollup") as f:
            text = f.read()
    except (FileNotFoundError, ProcessLookupError):
        return {}
    out = {}
    for line in text.splitlines()[1:]:
        key, _, value = line.partition(":")
        if key in FIELDS:
            out[key] = int(value.split()[0]) / 1024
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    start = time.time()
    proc = subprocess.Popen(sys.argv[2:])
    peak = dict.fromkeys(FIELDS, 0.0)
    while proc.poll() is None:
        for key, mb in sample(proc.pid).items():
            peak[key] = max(peak[key], mb)
        time.sleep(0.1)
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    rec = {
        "cpu_s": use.ru_utime + use.ru_stime,
        "peak_rss_mb": use.ru_maxrss / 1024,
        "wall_s": time.time() - start,
        "sampled_peak_mb": peak,
        "exit_code": proc.returncode,
    }
    with open(sys.argv[1], "w") as f:
        json.dump(rec, f, indent=1)
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main())
