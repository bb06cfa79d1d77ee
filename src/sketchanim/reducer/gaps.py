"""Gaps: intervals far longer than a take's usual sampling interval (a tracker that lost
its target, a logger that paused). A curve fitted across one is free to swing anywhere
inside it, since no sample holds it there, so the take is cut at its gaps, each side
reduced on its own, and the gap bridged by a straight segment from where one side ends
to where the next begins: it stays between the two sides' values, with no overshoot (a
corner at each end, as at a pause's edges). :func:`sketchanim.reduce` does this for
both methods; the gap is listed among the reduction's features.
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
