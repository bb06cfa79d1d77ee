"""Gaps, jumps and overshoot: where a smooth curve through the samples would swing
outside them between samples.

A **gap** is an interval far longer than the take's usual sampling interval (a tracker
that lost its target, a logger that paused): a curve fitted across one is free to swing
anywhere inside it, since no sample holds it there. A **jump** is a step in value over
one interval (a pen lifted and put down elsewhere, a spike): a smooth curve through it
rings on both sides. The take is cut there, each side reduced on its own, and the cut
bridged by a straight segment from where one side ends to where the next begins: it
stays between the two sides' values (a corner at each end, as at a pause's edges).

:func:`without_overshoot` then checks every sample interval: at its midpoint the curve
must lie within the range of the four samples around it, widened by the tolerance.
Intervals that fail are cut and bridged too (and listed as jumps), until none fails: at
worst every interval is bridged, the piecewise-linear interpolant, which never
overshoots, so this ends. :func:`sketchanim.reduce` does all this for both methods.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.reducer.features import Feature
from sketchanim.reducer.splice import join

def find_gaps(times: np.ndarray, gap: float) -> np.ndarray:
    """Indices ``i`` where ``times[i + 1] - times[i]`` is over ``gap`` times the median
    interval (increasing times).

    >>> find_gaps(np.array([0.0, 0.1, 0.2, 0.3, 2.0, 2.1]), 5.0).tolist()
    [3]
    """
    steps = np.diff(times)
    if len(steps) < 2:
        return np.zeros(0, dtype=int)
    return np.flatnonzero(steps > gap * np.median(steps))


#: A jump: a change over one interval of more than this many tolerances ...
JUMP_TOLS = 20.0
#: ... and more than this many times the changes over the intervals beside it.
JUMP_RATIO = 5.0


def find_jumps(values: np.ndarray, tol: np.ndarray) -> np.ndarray:
    """Indices ``i`` where some channel jumps from sample ``i`` to ``i + 1``: by over
    :data:`JUMP_TOLS` tolerances and :data:`JUMP_RATIO` times its change over either
    neighbouring interval (a pen lifted and put down elsewhere, a tracker re-locking).
    A smooth curve through a step rings on both sides of it; a straight bridge does not.

    >>> find_jumps(np.c_[[0.0, 0.1, 0.2, 5.0, 5.1, 5.2]], np.array([0.01])).tolist()
    [2]
    """
    d = np.abs(np.diff(values, axis=0)) / tol
    if len(d) < 2:
        return np.zeros(0, dtype=int)
    zero = np.zeros((1, d.shape[1]))
    beside = np.maximum(np.r_[zero, d[:-1]], np.r_[d[1:], zero])
    return np.flatnonzero(np.any((d > JUMP_TOLS) & (d > JUMP_RATIO * beside), axis=1))


def overshooting(spline: BSpline, times: np.ndarray, values: np.ndarray, tol: np.ndarray,
                 chunk: int = 1 << 18) -> np.ndarray:
    """Intervals ``i`` (between samples ``i`` and ``i + 1``) at whose midpoint the curve
    is outside the range of samples ``i - 1 .. i + 2`` widened by the tolerance
    (checked ``chunk`` intervals at a time, so memory stays bounded on long takes).

    >>> t = np.arange(5.0); x = np.c_[[0.0, 0.0, 1.0, 1.0, 1.0]]
    >>> ring = BSpline(np.r_[[0.0] * 4, [4.0] * 4], np.c_[[0.0, -1.0, 2.0, 1.0]], 3)
    >>> overshooting(ring, t, x, np.array([0.01])).tolist(), overshooting(ring, t, x, np.array([0.01]), 2).tolist()
    ([0, 3], [0, 3])
    """
    n = len(times)
    slack = tol * (1 + 1e-9)
    found = []
    for a in range(0, n - 1, chunk):
        b = min(a + chunk, n - 1)                              # intervals a .. b - 1
        near = [values[np.clip(np.arange(a, b) + k, 0, n - 1)] if a + k < 0 or b + k > n - 1 else values[a + k : b + k]
                for k in (-1, 0, 1, 2)]
        lo = np.minimum(np.minimum(near[0], near[1]), np.minimum(near[2], near[3]))
        hi = np.maximum(np.maximum(near[0], near[1]), np.maximum(near[2], near[3]))
        mid = np.asarray(spline(0.5 * (times[a + 1 : b + 1] + times[a:b]))).reshape(b - a, -1)
        found.append(a + np.flatnonzero(np.any((mid > hi + slack) | (mid < lo - slack), axis=1)))
    return np.concatenate(found) if found else np.zeros(0, dtype=int)


def bridge(start: float, end: float, left: np.ndarray, right: np.ndarray, order: int) -> BSpline:
    """The straight segment from value ``left`` at ``start`` to ``right`` at ``end``, as
    a clamped spline of ``order`` (control points evenly spaced along it).

    >>> s = bridge(1.0, 3.0, np.array([0.0]), np.array([4.0]), 4)
    >>> s(np.array([1.0, 2.0, 3.0]))[:, 0].tolist()
    [0.0, 2.0, 4.0]
    """
    u = np.linspace(0.0, 1.0, order)[:, None]
    return BSpline(np.r_[[start] * order, [end] * order], (1 - u) * left + u * right, order - 1)


def reduce_across(times: np.ndarray, values: np.ndarray, cuts: np.ndarray, order: int,
                  reduce_part: Callable[[np.ndarray, np.ndarray], tuple[BSpline, tuple[Feature, ...]]],
                  jumps: np.ndarray = np.zeros(0, dtype=int)) -> tuple[BSpline, list[Feature]]:
    """Reduce each run of samples between the cuts (after samples ``cuts``, sorted) with
    ``reduce_part(times, values) -> (spline, features)`` and bridge them; one spline
    (each run's own curve on its span) and the features: a ``"jump"`` at the cuts in
    ``jumps``, a ``"gap"`` at the others.

    A run of one sample is a point the two bridges meet on.

    >>> t = np.r_[np.linspace(0, 1, 11), np.linspace(5, 6, 11)]
    >>> x = np.c_[t ** 2]
    >>> def part(t, x):
    ...     return BSpline(np.r_[[t[0]] * 2, [t[-1]] * 2], x[[0, -1]], 1), ()
    >>> s, found = reduce_across(t, x, find_gaps(t, 5.0), 2, part)
    >>> found, float(s(3.0)[0])
    ([Feature(kind='gap', start=1.0, end=5.0)], 13.0)
    """
    bounds = np.r_[0, cuts + 1, len(times)]
    pieces: list[BSpline] = []
    found: list[Feature] = []
    end_value: np.ndarray | None = None
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a >= 2:
            spline, features = reduce_part(times[a:b], values[a:b])
            c = np.asarray(spline.c).reshape(len(spline.c), -1)
            spline = BSpline(spline.t, c, spline.k)
            first, last = c[0], c[-1]
        else:
            spline, features = None, ()
            first = last = values[a]
        if end_value is not None:
            pieces.append(bridge(float(times[a - 1]), float(times[a]), end_value, first, order))
            found.append(Feature("jump" if a - 1 in jumps else "gap", float(times[a - 1]), float(times[a])))
        if spline is not None:
            pieces.append(spline)
        found.extend(features)
        end_value = last
    return join(pieces), found


def without_overshoot(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int, gap: float,
                      whole: Callable[[], tuple[BSpline, list[Feature]]],
                      reduce_part: Callable[[np.ndarray, np.ndarray], tuple[BSpline, tuple[Feature, ...]]]
                      ) -> tuple[BSpline, list[Feature]]:
    """The take reduced with ``whole()`` (no cuts) or, cut at its gaps and jumps, run by
    run with ``reduce_part``; then cut and bridged further wherever it overshoots
    (:func:`overshooting`), until it does not. Runs already reduced are not reduced again.

    >>> t = np.linspace(0, 1, 11); x = np.c_[(t > 0.5) * 1.0]      # a step
    >>> def part(t, x):
    ...     return BSpline(np.r_[[t[0]] * 2, [t[-1]] * 2], x[[0, -1]], 1), ()
    >>> s, found = without_overshoot(t, x, np.array([0.01]), 2, 5.0, None, part)
    >>> [f.kind for f in found], bool(np.all(s(t) == x))
    (['jump'], True)
    """
    gaps = find_gaps(times, gap)
    jumps = np.setdiff1d(find_jumps(values, tol), gaps)          # a step across a gap is the gap
    cuts = np.union1d(gaps, jumps)
    done: dict[tuple[float, float, int], tuple[BSpline, tuple[Feature, ...]]] = {}

    def part(t: np.ndarray, x: np.ndarray) -> tuple[BSpline, tuple[Feature, ...]]:
        key = (float(t[0]), float(t[-1]), len(t))
        if key not in done:
            done[key] = reduce_part(t, x)
        return done[key]

    while True:
        spline, found = reduce_across(times, values, cuts, order, part, jumps) if len(cuts) else whole()
        more = np.setdiff1d(overshooting(spline, times, values, tol), cuts)
        if not more.size:
            return spline, found
        cuts = np.union1d(cuts, more)
        jumps = np.union1d(jumps, more)
