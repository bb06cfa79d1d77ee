"""Exact conversions of a B-spline to Bezier segments and of a cubic to Hermite keys.

Hermite keys are what keyframe tools store: per key a time, a value and the in- and
out-tangents (derivatives in value units per second). glTF's CUBICSPLINE sampler and
Blender's F-curves take them after scaling tangents by segment duration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError
from sketchanim.spline.knots import insert_knots


@dataclass(frozen=True)
class BezierSegments:
    """Piecewise Bezier form of a spline.

    Attributes
    ----------
    breaks : ndarray, shape (m + 1,)
        Segment ends in time.
    points : ndarray, shape (m, order, ...)
        Control points of each segment (trailing axes as the spline's coefficients).
    """

    breaks: np.ndarray
    points: np.ndarray


@dataclass(frozen=True)
class HermiteKeys:
    """Cubic Hermite keys: on ``[times[i], times[i+1]]`` the cubic with these end values
    and derivatives (``out_tangents[i]`` on the left, ``in_tangents[i+1]`` on the right).

    Attributes
    ----------
    times : ndarray, shape (m,)
    values : ndarray, shape (m, ...)
    in_tangents, out_tangents : ndarray, shape (m, ...)
        One-sided derivatives (per second); the first in-tangent and last out-tangent
        repeat the one-sided derivative there.
    """

    times: np.ndarray
    values: np.ndarray
    in_tangents: np.ndarray
    out_tangents: np.ndarray


def to_bezier(spline: BSpline) -> BezierSegments:
    """Split a spline into Bezier segments by raising every breakpoint to full multiplicity.

    >>> s = BSpline([0, 0, 0, 1, 2, 2, 2], [0.0, 2.0, 2.0, 0.0], 2)
    >>> b = to_bezier(s)
    >>> b.breaks, b.points.tolist()
    (array([0., 1., 2.]), [[0.0, 2.0, 2.0], [2.0, 2.0, 0.0]])
    """
    t = np.asarray(spline.t, dtype=float)
    order = spline.k + 1
    span = t[spline.k : len(t) - order + 1]
    breaks, counts = np.unique(span, return_counts=True)
    interior = breaks[1:-1]
    missing = np.repeat(interior, order - counts[1:-1])
    full = insert_knots(spline, missing) if missing.size else spline
    c = np.asarray(full.c)
    # With every interior breakpoint of multiplicity `order`, segment i owns coefficients
    # i*order .. i*order + order - 1.
    n_seg = len(breaks) - 1
    points = c[: n_seg * order].reshape((n_seg, order) + c.shape[1:])
    return BezierSegments(breaks, points)


def to_hermite(spline: BSpline) -> HermiteKeys:
    """Exact Hermite keys of a cubic B-spline, one key per breakpoint.

    Raises
    ------
    ArgumentError
        The spline is not cubic, or jumps in value at a breakpoint.

    Examples
    --------
    >>> s = BSpline([0, 0, 0, 0, 1, 1, 1, 1], [0.0, 1.0, 2.0, 3.0], 3)  # the line 3t
    >>> keys = to_hermite(s)
    >>> keys.values.tolist(), keys.out_tangents.tolist()
    ([0.0, 3.0], [3.0, 3.0])
    """
    if spline.k != 3:
        raise ArgumentError("spline", f"Hermite keys need a cubic (order 4), got order {spline.k + 1}")
    bez = to_bezier(spline)
    p = bez.points
    h = np.diff(bez.breaks).reshape((-1,) + (1,) * (p.ndim - 2))
    starts, ends = p[:, 0], p[:, 3]
    gaps = np.abs(starts[1:] - ends[:-1]) > 1e-9 * max(float(np.abs(p).max()), np.finfo(float).tiny)
    jumps = np.flatnonzero(np.any(gaps, axis=tuple(range(1, gaps.ndim))))
    if jumps.size:
        raise ArgumentError("spline", f"jumps in value at t={float(bez.breaks[jumps[0] + 1]):g}")
    out_t = 3.0 * (p[:, 1] - p[:, 0]) / h
    in_t = 3.0 * (p[:, 3] - p[:, 2]) / h
    values = np.concatenate([starts, ends[-1:]])
    in_tangents = np.concatenate([out_t[:1], in_t])
    out_tangents = np.concatenate([out_t, in_t[-1:]])
    return HermiteKeys(bez.breaks.copy(), values, in_tangents, out_tangents)


def from_hermite(keys: HermiteKeys) -> BSpline:
    """The cubic B-spline of Hermite keys (interior knots of multiplicity 3).

    >>> s = BSpline([0, 0, 0, 0, 1, 2, 2, 2, 2], [0.0, 1.0, -1.0, 2.0, 0.5], 3)
    >>> r = from_hermite(to_hermite(s))
    >>> bool(np.allclose(r(np.linspace(0, 2, 7)), s(np.linspace(0, 2, 7))))
    True
    """
    t = np.asarray(keys.times, dtype=float)
    if t.ndim != 1 or len(t) < 2 or np.any(np.diff(t) <= 0):
        raise ArgumentError("keys.times", "needs at least 2 strictly increasing times")
    v = np.asarray(keys.values, dtype=float)
    h = np.diff(t).reshape((-1,) + (1,) * (v.ndim - 1))
    p0, p3 = v[:-1], v[1:]
    p1 = p0 + np.asarray(keys.out_tangents, dtype=float)[:-1] * h / 3.0
    p2 = p3 - np.asarray(keys.in_tangents, dtype=float)[1:] * h / 3.0
    inner = np.stack([p0, p1, p2], axis=1).reshape((-1,) + v.shape[1:])
    coef = np.concatenate([inner, v[-1:]])
    knots = np.concatenate([[t[0]] * 4, np.repeat(t[1:-1], 3), [t[-1]] * 4])
    return BSpline(knots, coef, 3)
