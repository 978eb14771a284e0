#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Consistency check (not a physics test): nscdpost's readers (foamlib
underneath since issue 28) return the same arrays (values, dtype, shape) as
a former nscdpost, on every case output found under the given directories
(grain sets read with read_grains, ascii vol fields with read_internal_field).

usage: git show 803a9e1:src/python/nscdpost.py > /tmp/nscdpost_old.py
       compareReaders.py /tmp/nscdpost_old.py DIR [DIR ...]

Prints the counts, the CPU time of each reader and every difference.
Measured 2026-11-23 on the tutorial outputs of /work/main (rayleighTaylor,
settling3D, fluidisation, dropletDigging/reduced, sedimentation,
granularCollapse, lituyaBay/reduced): 353 grain sets, 1,355 vol fields,
no difference; CPU 12.4 s (hand-written) vs 5.3 s (foamlib)."""

import glob
import importlib.util
import os
import re
import sys
import time

import nscdpost as new
import numpy as np

if len(sys.argv) < 3:
    sys.exit(__doc__)
spec = importlib.util.spec_from_file_location("old", sys.argv[1])
old = importlib.util.module_from_spec(spec)
spec.loader.exec_module(old)
roots = sys.argv[2:]
n_grain = n_field = 0
t_old = t_new = 0.0
bad = []


def same(a, b):
    a = np.asarray(a)
    b = np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b, equal_nan=True)


for root in roots:
    for case in sorted(
        set(
            os.path.dirname(os.path.dirname(p))
            for p in glob.glob(os.path.join(root, "**", "system", "controlDict"), recursive=True)
        )
    ):
        for _t, name in old.numeric_dirs(case):
            tdir = os.path.join(case, name)
            if os.path.isfile(os.path.join(tdir, "lagrangian", "grains", "positions")):
                a0 = time.process_time()
                go = old.read_grains(case, name)
                a1 = time.process_time()
                gn = new.read_grains(case, name)
                a2 = time.process_time()
                t_old += a1 - a0
                t_new += a2 - a1
                n_grain += 1
                if set(go) != set(gn) or not all(same(go[k], gn[k]) for k in go):
                    bad.append((tdir, "grains"))
            for f in sorted(os.listdir(tdir)):
                p = os.path.join(tdir, f)
                if not os.path.isfile(p) or f in ("grainState.h5",) or f.startswith("phi"):
                    continue
                text = open(p, errors="replace").read()
                head = text[:1500]
                if "class       vol" not in head and "class vol" not in head:
                    continue
                if "format      binary" in head:
                    continue
                if re.search(r"@[A-Z0-9_]+@", text):
                    continue  # a tutorial's case template (setupCase.py fills @KEY@), not a field
                a0 = time.process_time()
                fo = old.read_internal_field(p)
                a1 = time.process_time()
                fn = new.read_internal_field(p)
                a2 = time.process_time()
                t_old += a1 - a0
                t_new += a2 - a1
                n_field += 1
                if not same(fo, fn):
                    bad.append(
                        (p, np.asarray(fo).dtype, np.shape(fo), np.asarray(fn).dtype, np.shape(fn))
                    )
print(f"grain sets {n_grain}, vol fields {n_field}, CPU old {t_old:.2f} s new {t_new:.2f} s")
print("differences:", len(bad))
[print(" ", b) for b in bad[:20]]
