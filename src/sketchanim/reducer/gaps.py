"""Gaps and jumps: where a smooth curve through the samples would swing outside them
between samples, and the bridges the reducer puts there instead.

Between samples ``i`` and ``i + 1`` every curve :func:`sketchanim.reduce` returns stays
within the range of the four samples around that interval, widened by the tolerance and
cut to the attribute's bounds (:mod:`.swing`, checked exactly over the whole interval).
:func:`without_swing` reduces the take, finds the intervals where the curve leaves that
range and cuts the take there: each run of samples between cuts is reduced on its own,
and each cut interval is **bridged** from where one run ends to where the next begins.
The cut intervals are listed as features: a **jump** where the value steps over one
interval (a pen lifted and put down elsewhere, a spike: found beforehand by
:func:`find_jumps`, since a smooth curve through a step rings on both sides), a **gap**
at every other bridged interval (dropped frames, a tracker that lost its target: an
interval is a gap because the curve would swing across it, not because it is long;
:class:`~sketchanim.reducer.FeatureOptions` ``gap`` can also cut every interval over
that many median intervals beforehand, off by default).

A bridge is C1 where the two sides allow it: the cubic Hermite segment matching the two
runs' end values and end derivatives, if it stays within the bridged interval's range
(checked exactly); otherwise the straight segment between the end values. The loop adds
cuts until no interval swings; a bridge that still leaves its range (a run's end value
beyond a bound, within tolerance of a sample on it) cuts the intervals beside it too. At
worst every interval is bridged straight between the samples themselves: the
piecewise-linear interpolant, which never leaves the range, so the loop ends.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.interpolate import BSpline
from scipy.sparse.linalg import spsolve

from sketchanim.reducer.features import Feature
from sketchanim.reducer.splice import join
from sketchanim.reducer.swing import SLACK, excess, swinging
from sketchanim.spline import insertion_matrix

#: A run of samples reduced alone: (times, values) -> (spline, features).
ReducePart = Callable[[np.ndarray, np.ndarray], tuple[BSpline, tuple[Feature, ...]]]


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


def find_jumps(values: np.ndarray, tol: np.ndarray, times: np.ndarray | None = None) -> np.ndarray:
    """Indices ``i`` where some channel jumps from sample ``i`` to ``i + 1``: by over
    :data:`JUMP_TOLS` tolerances and :data:`JUMP_RATIO` times what it would change over
    that interval at its speed over either neighbouring interval (a pen lifted and put
    down elsewhere, a tracker re-locking; with ``times`` None, evenly sampled). A long
    interval (dropped frames) is no jump for covering more ground than a short one.
    A smooth curve through a step rings on both sides of it; a bridge does not.

    >>> find_jumps(np.c_[[0.0, 0.1, 0.2, 5.0, 5.1, 5.2]], np.array([0.01])).tolist()
    [2]
    >>> find_jumps(np.c_[[0.0, 0.1, 0.2, 5.0, 5.1, 5.2]], np.array([0.01]), np.r_[0.0, 1, 2, 50, 51, 52]).tolist()
    []
    """
    d = np.abs(np.diff(values, axis=0)) / tol
    if len(d) < 2:
        return np.zeros(0, dtype=int)
    steps = np.ones(len(d)) if times is None else np.diff(times)
    speed = d / steps[:, None]
    zero = np.zeros((1, d.shape[1]))
    beside = np.maximum(np.r_[zero, speed[:-1]], np.r_[speed[1:], zero]) * steps[:, None]
    return np.flatnonzero(np.any((d > JUMP_TOLS) & (d > JUMP_RATIO * beside), axis=1))


def _elevated(points: np.ndarray, order: int) -> np.ndarray:
    """Bezier control points (m, d) raised to ``order`` points (same curve)."""
    while len(points) < order:
        m = len(points)
        w = (np.arange(1, m) / m)[:, None]
        points = np.r_[points[:1], w * points[:-1] + (1 - w) * points[1:], points[-1:]]
    return points


def bridge(start: float, end: float, left: np.ndarray, right: np.ndarray, order: int,
           slopes: tuple[np.ndarray, np.ndarray] | None = None) -> BSpline:
    """The segment from value ``left`` at ``start`` to ``right`` at ``end``, as a clamped
    spline of ``order``: with ``slopes`` (the derivatives wanted at each end) and
    ``order >= 4``, the cubic Hermite segment; else straight.

    >>> s = bridge(1.0, 3.0, np.array([0.0]), np.array([4.0]), 4)
    >>> s(np.array([1.0, 2.0, 3.0]))[:, 0].tolist()
    [0.0, 2.0, 4.0]
    >>> c1 = bridge(0.0, 1.0, np.array([0.0]), np.array([1.0]), 5, (np.array([0.0]), np.array([3.0])))
    >>> [round(float(v), 12) for v in (c1(0.5)[0], c1.derivative()(0.0)[0], c1.derivative()(1.0)[0])]
    [0.125, 0.0, 3.0]
    """
    if slopes is None or order < 4:
        u = np.linspace(0.0, 1.0, order)[:, None]
        points = (1 - u) * left + u * right
    else:
        h = (end - start) / 3.0
        points = _elevated(np.array([left, left + h * slopes[0], right - h * slopes[1], right]), order)
    return BSpline(np.r_[[start] * order, [end] * order], points, order - 1)


def _end_slopes(spline: BSpline) -> tuple[np.ndarray, np.ndarray]:
    """A clamped spline's derivative at its first and its last knot."""
    d = spline.derivative()
    return (np.asarray(d(spline.t[0])).reshape(-1), np.asarray(d(spline.t[-1])).reshape(-1))


def reduce_across(times: np.ndarray, values: np.ndarray, cuts: np.ndarray, order: int, reduce_part: ReducePart,
                  jumps: np.ndarray, lo: np.ndarray, hi: np.ndarray, normalised: bool = False
                  ) -> tuple[BSpline, list[Feature]]:
    """Reduce each run of samples between the cuts (after samples ``cuts``, sorted) with
    ``reduce_part`` and bridge them; one spline (each run's own curve on its span) and
    the features: a ``"jump"`` at the cuts in ``jumps``, a ``"gap"`` at the others.
    A bridge is C1 where that stays within ``lo``, ``hi`` (per interval, as from
    :func:`~sketchanim.reducer.swing.local_ranges`) on its interval, else straight.
    A run of one sample is a point two straight bridges meet on.

    >>> t = np.r_[np.linspace(0, 1, 11), np.linspace(5, 6, 11)]
    >>> x = np.c_[t]
    >>> def part(t, x):
    ...     return BSpline(np.r_[[t[0]] * 2, [t[-1]] * 2], x[[0, -1]], 1), ()
    >>> lo, hi = np.full((21, 1), -np.inf), np.full((21, 1), np.inf)
    >>> s, found = reduce_across(t, x, np.array([10]), 2, part, np.zeros(0, int), lo, hi)
    >>> found, float(s(3.0)[0])
    ([Feature(kind='gap', start=1.0, end=5.0)], 3.0)
    """
    edges = np.r_[0, cuts + 1, len(times)]
    smooth_at: list[float] = []
    pieces: list[BSpline] = []
    found: list[Feature] = []
    end: tuple[np.ndarray, np.ndarray | None] | None = None        # the last run's end value and slope
    for a, b in zip(edges[:-1], edges[1:]):
        if b - a >= 2:
            spline, features = reduce_part(times[a:b], values[a:b])
            c = np.asarray(spline.c).reshape(len(spline.c), -1)
            spline = BSpline(spline.t, c, spline.k)
            first, last = c[0], c[-1]
            slopes: tuple[np.ndarray | None, np.ndarray | None] = _end_slopes(spline)
        else:
            spline, features = None, ()
            first = last = values[a]
            slopes = (None, None)
        if end is not None:
            t0, t1 = float(times[a - 1]), float(times[a])
            piece = bridge(t0, t1, end[0], first, order)
            if end[1] is not None and slopes[0] is not None and order >= 4:
                smooth = bridge(t0, t1, end[0], first, order, (end[1], slopes[0]))
                room = excess(smooth, times[a - 1 : a + 1], lo[a - 1 : a], hi[a - 1 : a], normalised=normalised)
                if np.all(room <= SLACK * _magnitude(lo[a - 1], hi[a - 1])):
                    piece = smooth
                    # one knot fewer at each C1 join, but beside a pause (kept exactly still)
                    smooth_at += [at for at, v in ((t0, end[1]), (t1, slopes[0])) if np.any(v != 0)]
            pieces.append(piece)
            found.append(Feature("jump" if a - 1 in jumps else "gap", t0, t1))
        if spline is not None:
            pieces.append(spline)
        found.extend(features)
        end = (last, slopes[1])
    return _c1(join(pieces), smooth_at), found


def _c1(spline: BSpline, at: list[float]) -> BSpline:
    """``spline`` with one knot fewer at each time in ``at``, where it is C1 (joined on
    a Hermite bridge): the same curve, to rounding, one control point fewer each.
    Coefficients the removal does not touch are copied exactly (a pause beside a bridge
    stays exactly still).

    >>> s = BSpline(np.r_[[0.0] * 4, [1.0] * 3, [2.0] * 4], np.c_[[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]], 3)
    >>> c = _c1(s, [1.0])
    >>> len(c.c), bool(np.allclose(c(np.linspace(0, 2, 9)), s(np.linspace(0, 2, 9))))
    (6, True)
    """
    if not at or spline.k < 3:
        return spline
    order = spline.k + 1
    coarse = np.delete(spline.t, [int(np.searchsorted(spline.t, a)) for a in at])
    A = insertion_matrix(coarse, spline.t, order).tocsr()      # fine coefficients = A @ coarse ones
    fine = np.asarray(spline.c).reshape(A.shape[0], -1)
    x = np.full((A.shape[1], fine.shape[1]), np.nan)
    rows = np.flatnonzero(np.diff(A.indptr) == 1)
    rows = rows[A.data[A.indptr[rows]] == 1.0]                  # a coefficient kept as it is
    x[A.indices[A.indptr[rows]]] = fine[rows]
    unknown = np.isnan(x[:, 0])
    known = A[:, ~unknown] @ x[~unknown]
    Au = A[:, unknown]
    x[unknown] = spsolve((Au.T @ Au).tocsc(), Au.T @ (fine - known)).reshape(-1, fine.shape[1])
    return BSpline(coarse, x, spline.k)


def _magnitude(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The scale of a range's finite ends (what :data:`SLACK` is relative to)."""
    return np.maximum(np.abs(np.where(np.isfinite(lo), lo, 0.0)), np.abs(np.where(np.isfinite(hi), hi, 0.0)))


def without_swing(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int, jumps: bool,
                  gap: float | None, lo: np.ndarray, hi: np.ndarray, whole: Callable[[], tuple[BSpline, list[Feature]]],
                  reduce_part: ReducePart, normalised: bool = False) -> tuple[BSpline, list[Feature]]:
    """The take reduced with ``whole()`` (no cuts) or, cut at its jumps (with
    ``jumps``; and, with ``gap``, at intervals over ``gap`` median intervals), run by run with
    ``reduce_part``; then cut and bridged further wherever it leaves ``lo``, ``hi``
    between samples (:func:`~sketchanim.reducer.swing.swinging`; ``normalised``: a
    quaternion spline, checked as played), until it does not. Runs already reduced are
    not reduced again.

    >>> from sketchanim.reducer.swing import local_ranges
    >>> t = np.linspace(0, 1, 11); x = np.c_[(t > 0.5) * 1.0]      # a step
    >>> def part(t, x):
    ...     return BSpline(np.r_[[t[0]] * 2, [t[-1]] * 2], x[[0, -1]], 1), ()
    >>> lo, hi = local_ranges(x, np.array([0.01]))
    >>> s, found = without_swing(t, x, np.array([0.01]), 2, True, None, lo, hi, None, part)
    >>> [f.kind for f in found], bool(np.all(s(t) == x))
    (['jump'], True)
    """
    gaps = find_gaps(times, gap) if gap is not None else np.zeros(0, dtype=int)
    steps = find_jumps(values, tol, times) if jumps else np.zeros(0, dtype=int)
    steps = np.setdiff1d(steps, gaps)                             # a step across a gap is the gap
    cuts = np.union1d(gaps, steps)
    done: dict[tuple[float, float, int], tuple[BSpline, tuple[Feature, ...]]] = {}

    def part(t: np.ndarray, x: np.ndarray) -> tuple[BSpline, tuple[Feature, ...]]:
        key = (float(t[0]), float(t[-1]), len(t))
        if key not in done:
            done[key] = reduce_part(t, x)
        return done[key]

    last = len(times) - 2                                         # the last interval
    while True:
        spline, found = (reduce_across(times, values, cuts, order, part, steps, lo, hi, normalised) if len(cuts)
                         else whole())
        bad = swinging(spline, times, lo, hi, normalised)
        # A bridge beyond its range: the runs beside it end off the samples; cut them there.
        stuck = np.intersect1d(bad, cuts)
        more = np.setdiff1d(np.union1d(bad, np.clip(np.r_[stuck - 1, stuck + 1], 0, max(last, 0))), cuts)
        if not more.size:
            return spline, found
        cuts = np.union1d(cuts, more)
