"""Straight pieces where a curve swings: the streaming reducer's last resort for the
no-swing rule (:mod:`.swing`).

Where no smooth curve through a window's knots stays in an interval's range (a cubic
through a step rings on both sides of it), the curve between those two samples becomes
the straight line between its values there: the interval's ends get knots of
multiplicity ``order - 1`` (a C0 join, by knot insertion, so nothing else moves) and its
inner coefficients go on the line between the two nodal ones. A line between two points
of a box stays in the box; a nodal value outside the ranges of the straight intervals
beside it is moved into them, which only brings it closer to its sample. Moving a nodal
value changes the interval on its other side, so the check runs again until nothing
swings.

>>> from scipy.interpolate import make_interp_spline
>>> from sketchanim.reducer.swing import local_ranges
>>> t = np.arange(8.0); x = np.c_[[0.0, 0, 0, 0, 1, 1, 1, 1]]
>>> s = make_interp_spline(t, x, k=3)
>>> lo, hi = local_ranges(x, np.array([0.01]))
>>> int(window_kernel.interval_excess(s.t, 4, s.c, t, lo, hi, 0, window_kernel.power_form(4)).max() > 0.01)
1
>>> knots, coef, count = straightened(s.t, s.c, 4, t, lo, hi, 7, ())
>>> float(window_kernel.interval_excess(knots, 4, coef, t, lo, hi, 0, window_kernel.power_form(4)).max())
0.0
"""

from __future__ import annotations

from collections.abc import Collection

import numpy as np
from scipy.interpolate import BSpline, insert

from sketchanim.reducer import window_kernel


def straightened(knots: np.ndarray, coef: np.ndarray, order: int, times: np.ndarray, lo: np.ndarray,
                 hi: np.ndarray, n_final: int, fixed: Collection[float], *, movable: bool = True
                 ) -> tuple[np.ndarray, np.ndarray, int]:
    """The spline ``(knots, coef)`` of ``order`` with every interval ``times[s] ..
    times[s + 1]``, ``s < n_final``, that leaves ``[lo[s], hi[s]]`` (beyond
    :data:`window_kernel.SWING_SLACK`) made straight (see the module). Nodal values at
    the times in ``fixed`` are never moved (a value a neighbour already has), none
    without ``movable`` (a quaternion's: the line between two is the shortest turn
    between their rotations, and moving one component would change its rotation). Returns the
    new knots and coefficients (the same arrays if nothing swings) and the number of
    intervals made straight.

    ``times`` must not hold knots strictly inside an interval (every knot is a sample
    time in the reducer).
    """
    k = order
    straight: set[int] = set()
    while True:
        ex = window_kernel.interval_excess(knots, k, coef, times, lo, hi, 0, window_kernel.power_form(k))[:n_final]
        new = [s for s in np.flatnonzero(ex > window_kernel.SWING_SLACK) if s not in straight]
        if not new:
            return knots, coef, len(straight)
        straight.update(int(s) for s in new)
        extra = []
        for s in new:
            for at in (times[s], times[s + 1]):
                have = int(np.count_nonzero(knots == at)) + extra.count(at)
                extra += [at] * max(0, k - 1 - have)
        spline = BSpline(knots, coef, k - 1)
        for at in sorted(set(extra)):
            spline = insert(at, spline, m=extra.count(at))
        knots = np.asarray(spline.t)
        coef = np.array(spline.c[: len(knots) - k], dtype=float)     # scipy pads c to len(t)
        _place(knots, coef, k, times, lo, hi, sorted(straight), fixed if movable else times)


def _place(knots: np.ndarray, coef: np.ndarray, k: int, times: np.ndarray, lo: np.ndarray, hi: np.ndarray,
           straight: list[int], fixed: Collection[float]) -> None:
    """Move the nodal coefficients of the ``straight`` intervals into the ranges of the
    straight intervals beside them (unless ``fixed``), then put each interval's inner
    coefficients on the line between its two nodal ones, in place."""
    node_lo: dict[int, np.ndarray] = {}
    node_hi: dict[int, np.ndarray] = {}
    pieces = []
    for s in straight:
        r = int(np.searchsorted(knots, times[s], side="right"))   # the piece on [t_s, t_s+1] is span r - 1
        first, last = r - k, r - 1                                  # its nodal coefficients
        pieces.append((first, last))
        for node, at in ((first, times[s]), (last, times[s + 1])):
            if at in fixed:
                continue
            node_lo[node] = np.maximum(node_lo.get(node, lo[s]), lo[s])
            node_hi[node] = np.minimum(node_hi.get(node, hi[s]), hi[s])
    for node, low in node_lo.items():
        coef[node] = np.clip(coef[node], low, np.maximum(low, node_hi[node]))
    w = np.arange(1, k - 1)[:, None] / (k - 1)
    for first, last in pieces:
        coef[first + 1 : last] = coef[first] + w * (coef[last] - coef[first])

