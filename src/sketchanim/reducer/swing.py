"""The no-swing bound, checked exactly: how far a curve leaves the local range of its
samples anywhere between them.

Between samples ``i`` and ``i + 1`` a curve we keep must stay within the range of the four
samples around that interval (``i - 1 .. i + 2``) widened by the tolerance, and within the
attribute's bounds if it has them (:func:`local_ranges`). A check at a few points per
interval misses a cubic that dips between them; :func:`excess` finds the curve's extremes
on each interval exactly instead: the interval's ends, the knots inside it and the real
roots of each polynomial piece's derivative there.

>>> import numpy as np
>>> from scipy.interpolate import BSpline
>>> t = np.arange(5.0); x = np.c_[[0.0, 0.0, 1.0, 1.0, 1.0]]
>>> ring = BSpline(np.r_[[0.0] * 4, [4.0] * 4], np.c_[[0.0, -1.0, 2.0, 1.0]], 3)
>>> lo, hi = local_ranges(x, np.array([0.01]))
>>> swinging(ring, t, lo, hi).tolist()
[0, 1, 2, 3]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError

#: Bounds of an attribute's channels: (low, high), each of shape (d,) (±inf: unbounded).
Bounds = tuple[np.ndarray, np.ndarray]

#: Relative slack of the comparison (rounding of the curve's evaluation).
SLACK = 1e-9


def check_bounds(bounds: tuple[ArrayLike, ArrayLike] | None, dim: int) -> Bounds | None:
    """``bounds`` as two float arrays of shape (dim,) with ``low <= high`` (a scalar
    applies to every channel; ±inf: unbounded), or None; else
    :class:`~sketchanim.errors.ArgumentError`.

    >>> [b.tolist() for b in check_bounds((0, 1), 2)]
    [[0.0, 0.0], [1.0, 1.0]]
    """
    if bounds is None:
        return None
    try:
        low, high = (np.broadcast_to(np.asarray(b, dtype=float), (dim,)).copy() for b in bounds)
    except (TypeError, ValueError) as err:
        raise ArgumentError("bounds", f"needs (low, high), each a number or {dim} numbers, got {bounds!r}") from err
    if np.isnan(low).any() or np.isnan(high).any() or np.any(low > high):
        raise ArgumentError("bounds", f"needs low <= high in every channel, got low {low.tolist()}, high {high.tolist()}")
    return low, high


def outside(values: np.ndarray, bounds: Bounds | None) -> int | None:
    """Index of the first row of ``values`` (n, d) outside ``bounds``, or None.

    >>> outside(np.c_[[0.5, 1.5]], (np.array([0.0]), np.array([1.0])))
    1
    """
    if bounds is None or not len(values):
        return None
    bad = np.flatnonzero(np.any((values < bounds[0]) | (values > bounds[1]), axis=1))
    return int(bad[0]) if len(bad) else None


def local_ranges(values: np.ndarray, tol: np.ndarray, bounds: Bounds | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The range each sample interval's curve must stay in: per interval ``i`` and
    channel, the least and greatest of samples ``i - 1 .. i + 2`` (those that exist)
    widened by ``tol``, then cut to ``bounds``. Two arrays of shape (n - 1, d).

    >>> lo, hi = local_ranges(np.c_[[0.0, 1.0, 0.5, 2.0]], np.array([0.1]), (np.array([0.0]), np.array([1.5])))
    >>> lo[:, 0].tolist(), hi[:, 0].tolist()
    ([0.0, 0.0, 0.4], [1.1, 1.5, 1.5])
    """
    x = np.asarray(values, dtype=float).reshape(len(values), -1)
    n = len(x)
    near = [x[np.clip(np.arange(n - 1) + k, 0, n - 1)] for k in (-1, 0, 1, 2)]
    lo = np.minimum(np.minimum(near[0], near[1]), np.minimum(near[2], near[3])) - tol
    hi = np.maximum(np.maximum(near[0], near[1]), np.maximum(near[2], near[3])) + tol
    if bounds is not None:
        lo = np.maximum(lo, bounds[0])
        hi = np.minimum(hi, bounds[1])
    return lo, hi


def _critical_points(spline: BSpline, a: float, b: float) -> np.ndarray:
    """The knots of ``spline`` inside ``(a, b)`` and the real roots there of each
    polynomial piece's derivative, in every channel (unsorted)."""
    k = spline.k
    knots = np.unique(spline.t[(spline.t > a) & (spline.t < b)])
    edges = np.r_[a, knots, b]
    if k < 2:
        return knots
    left, width = edges[:-1], np.diff(edges)
    # The derivative on each piece in powers of s = t - left: sum_p d[p] s^p, p = 0 .. k - 1.
    d = np.stack([np.asarray(spline(left, nu=p + 1)).reshape(len(left), -1) / np.prod(np.arange(1, p + 1))
                  for p in range(k)], axis=-1)                        # (pieces, channels, k)
    rows = d.reshape(-1, k)
    starts = np.repeat(left, d.shape[1])
    widths = np.repeat(width, d.shape[1])
    roots = []
    if k == 2:                                                         # linear derivative
        with np.errstate(divide="ignore", invalid="ignore"):
            roots.append(-rows[:, 0] / rows[:, 1])
    elif k == 3:                                                       # quadratic
        c0, c1, c2 = rows[:, 0], rows[:, 1], rows[:, 2]
        disc = c1 * c1 - 4 * c2 * c0
        real = disc >= 0
        q = -0.5 * (c1 + np.copysign(np.sqrt(np.where(real, disc, 0.0)), c1))
        with np.errstate(divide="ignore", invalid="ignore"):
            for r in (q / c2, c0 / q):                                 # c2 = 0: the second is the root
                roots.append(np.where(real, r, np.nan))
    else:
        found = np.full((len(rows), k - 1), np.nan)
        for i, row in enumerate(rows):
            r = np.roots(row[::-1])
            r = r[np.abs(r.imag) <= 1e-12 * np.maximum(1.0, np.abs(r.real))].real
            found[i, : len(r)] = r
        roots.extend(found.T)
    s = np.concatenate([np.broadcast_to(r, starts.shape) for r in roots]) if roots else np.zeros(0)
    start = np.tile(starts, len(roots)) if roots else np.zeros(0)
    inside = np.isfinite(s) & (s > 0) & (s < np.tile(widths, len(roots)))
    return np.r_[knots, start[inside] + s[inside]]


def excess(spline: BSpline, times: np.ndarray, lo: np.ndarray, hi: np.ndarray, chunk: int = 1 << 16,
           normalised: bool = False) -> np.ndarray:
    """How far ``spline`` goes beyond ``[lo[i], hi[i]]`` anywhere on
    ``[times[i], times[i + 1]]``: per interval and channel, ``max(curve - hi, lo - curve)``
    over the interval where that is positive, else 0. Shape (n - 1, d); ``chunk``
    intervals are checked at a time, so memory stays bounded on long takes.

    With ``normalised`` the curve is a quaternion spline, played normalised: its values,
    normalised, are compared at the raw curve's extremes (where the normalised curve's
    extremes are, to second order in the norm's drift over the interval).

    >>> t = np.arange(3.0)
    >>> s = BSpline(np.r_[[0.0] * 3, [2.0] * 3], np.c_[[0.0, 2.0, 0.0]], 2)     # peaks at 1 in t = 1
    >>> excess(s, t, np.zeros((2, 1)), np.full((2, 1), 0.5))[:, 0].tolist()
    [0.5, 0.5]
    """
    times = np.asarray(times, dtype=float)
    n = len(times)
    out = np.zeros((n - 1, lo.shape[1]))
    for a in range(0, n - 1, chunk):
        b = min(a + chunk, n - 1)                                      # intervals a .. b - 1
        inner = _critical_points(spline, float(times[a]), float(times[b]))
        where = np.clip(np.searchsorted(times, inner, side="right") - 1, a, b - 1)
        points = np.r_[times[a : b + 1], inner]
        values = np.asarray(spline(points)).reshape(len(points), -1)
        if normalised:
            values = values / np.linalg.norm(values, axis=1, keepdims=True)
        # A sample time belongs to the intervals on both sides of it.
        owners = (np.r_[np.arange(a, b + 1), where], np.r_[np.arange(a - 1, b), where])
        for owner in owners:
            keep = (owner >= a) & (owner < b)
            i = owner[keep]
            v = values[keep]
            beyond = np.maximum(v - hi[i], lo[i] - v)
            np.maximum.at(out, i, np.maximum(beyond, 0.0))
    return out


def swinging(spline: BSpline, times: np.ndarray, lo: np.ndarray, hi: np.ndarray, normalised: bool = False
             ) -> np.ndarray:
    """Intervals ``i`` where ``spline`` leaves ``[lo[i], hi[i]]`` (:func:`local_ranges`)
    anywhere between ``times[i]`` and ``times[i + 1]``, beyond rounding (``normalised``:
    as :func:`excess`).

    >>> t = np.arange(3.0)
    >>> s = BSpline(np.r_[[0.0] * 3, [2.0] * 3], np.c_[[0.0, 2.0, 0.0]], 2)
    >>> swinging(s, t, np.zeros((2, 1)), np.full((2, 1), 1.0)).tolist()
    []
    """
    finite = np.maximum(np.abs(np.where(np.isfinite(lo), lo, 0.0)), np.abs(np.where(np.isfinite(hi), hi, 0.0)))
    return np.flatnonzero(np.any(excess(spline, times, lo, hi, normalised=normalised) > SLACK * finite, axis=1))
