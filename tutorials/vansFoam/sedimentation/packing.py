# SPDX-License-Identifier: GPL-3.0-or-later
"""Initial grain layers of the sedimentation tutorial and the measures of its
front, numpy only: shared by setupCase.py / postProcess.py (vansFoam) and
tests/bench/migflowSedimentation.py (MigFlow, run from its own venv).

Packings of discs r = 1.5 mm in the 0.4 x 0.6 m box, top of the layer 2 mm
below the lid, at rest:
- square: MigFlow's grid deposit, 133 columns x 50 rows of spacing d (6,650
  discs, layer 0.150 m), the tutorial's default;
- hexagonal: the thesis' packing (M. Henry, PhD thesis, UCLouvain, section
  3.2.2, Figure 3.9): rows sqrt(3) r apart, 133 and 132 discs in turn (odd
  rows shifted by r), 57 rows (7,553 discs, layer 56 sqrt(3) r + d =
  0.1485 m: the most rows within the square layer's 0.150 m).
Every disc touches its neighbours (diameter 2 r (1 - 1e-9)).
"""

import numpy as np

W, H = 0.4, 0.6  # box [m]
R = 1.5e-3  # disc radius [m]
TOP_GAP = 2e-3  # lid to the top of the layer [m]
ROWS = {"square": 50, "hexagonal": 57}
NCOL = int(W / (2 * R))  # 133


def lattice(packing="square", rows=None):
    """Disc centres (n, 2) [m], row by row from the top, and each disc's row
    index (n,)."""
    if packing not in ROWS:
        raise ValueError(f"unknown packing {packing!r} (use: {' | '.join(ROWS)})")
    rows = ROWS[packing] if rows is None else int(rows)
    x0 = 0.5 * (W - NCOL * 2 * R)
    ytop = H - TOP_GAP - R
    dy = np.sqrt(3.0) * R if packing == "hexagonal" else 2 * R
    xy, row = [], []
    for j in range(rows):
        shift = packing == "hexagonal" and j % 2 == 1
        for i in range(NCOL - 1 if shift else NCOL):
            xy.append((x0 + (2 * i + 1 + shift) * R, ytop - j * dy))
            row.append(j)
    return np.array(xy), np.array(row)


def perturb(xy, amplitude, seed=1, move=True):
    """Centres moved by independent uniform random offsets in [-a, a] d in x
    and y (a = amplitude; only when move) and the diameter factor 1 - 2 a,
    which keeps every pair of displaced lattice neighbours apart (their
    distance shrinks by at most 2 a d).  move=False: the smaller discs on the
    lattice, the control run that separates the displacement from the size."""
    rng = np.random.default_rng(seed)
    offset = rng.uniform(-amplitude, amplitude, xy.shape) * 2 * R
    return (xy + offset if move else xy.copy()), 1.0 - 2.0 * amplitude


def front_height(y, r=R):
    """Leading edge of the falling layer [m]: the 0.5 % quantile of the
    centre heights y minus r (robust to a few isolated grains)."""
    return float(np.percentile(y, 0.5) - r)


def rows_of(y0, gap=R):
    """Starting row index (0 = top) of each grain from its starting height
    y0: heights sorted from the top, a new row wherever two consecutive ones
    differ by more than gap (rows are >= sqrt(3) r apart, a perturbation
    moves a centre by much less)."""
    order = np.argsort(-y0)
    row = np.empty(len(y0), dtype=int)
    row[order] = np.concatenate(([0], np.cumsum(-np.diff(y0[order]) > gap)))
    return row


def row_spread(row, y, lowest=10, d=2 * R):
    """Coherence of the rows: the standard deviation of the centre heights y
    of the discs that started in one row (row: starting row index), in d.
    Returns (spread of the lowest starting row, median over the `lowest`
    lowest starting rows).  A row falling as a sheet keeps it below ~1; a
    row broken into fingers spreads over the fingers' length."""
    last = int(row.max())
    s = [np.std(y[row == j]) / d for j in range(last, max(last - lowest, -1), -1)]
    return float(s[0]), float(np.median(s))
