"""Editing tracks: each edit is a function from a track to a new track (tracks are
never changed in place); :meth:`.history.History.edit` makes one an undoable step.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline, make_lsq_spline

from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Track
from sketchanim.errors import ArgumentError
from sketchanim.reducer.splice import join, snapped, split
from sketchanim.spline import elevate_degree, insert_knots


def _curve(track: ContinuousTrack, spline: BSpline) -> ContinuousTrack:
    return replace(track, spline=spline)


def moved_point(track: ContinuousTrack, index: int, value: ArrayLike) -> ContinuousTrack:
    """``track`` with control point ``index`` at ``value`` (dim numbers).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 1.0]], 1)
    >>> moved_point(ContinuousTrack("a.x", FLOAT, s, 0.01), 1, [3.0]).evaluate([1.0]).tolist()
    [[3.0]]
    """
    c = np.array(track.spline.c, dtype=float)
    if not 0 <= index < len(c):
        raise ArgumentError("index", f"{track.path}: control point {index} of {len(c)}")
    c[index] = track.type.check(value, f"{track.path} point {index}")
    return _curve(track, BSpline(track.spline.t, c, track.spline.k))


def with_knot(track: ContinuousTrack, t: float) -> ContinuousTrack:
    """``track`` with a knot inserted at ``t`` (the curve is unchanged, one more point)."""
    if not track.start < t < track.end:
        raise ArgumentError("time", f"{track.path}: a knot goes inside ({track.start}, {track.end}), got {t!r}")
    return _curve(track, insert_knots(track.spline, [t]))


def without_knot(track: ContinuousTrack, index: int) -> ContinuousTrack:
    """``track`` without interior knot ``index`` (into ``spline.t``): the nearest curve
    on the remaining knots, by least squares over the track (one point fewer)."""
    s, k = track.spline, track.spline.k
    if not k + 1 <= index < len(s.t) - k - 1:
        raise ArgumentError("index", f"{track.path}: knot {index} is not an interior knot")
    knots = np.delete(s.t, index)
    x = np.unique(np.concatenate([np.linspace(a, b, 8) for a, b in zip(knots[k:-k - 1], knots[k + 1:-k])]))
    return _curve(track, make_lsq_spline(x, s(x), knots, k))


def shifted(track: Track, seconds: float) -> Track:
    """``track`` moved later by ``seconds`` (earlier if negative)."""
    return scaled(track, 1.0, 0.0, seconds)


def scaled(track: Track, factor: float, pivot: float = 0.0, shift: float = 0.0) -> Track:
    """``track`` with time ``t`` moved to ``pivot + factor * (t - pivot) + shift``.

    >>> from sketchanim.anim.attributes import BOOL
    >>> scaled(DiscreteTrack("a.on", BOOL, [1.0, 2.0], [True, False]), 2.0, pivot=1.0).times
    [1.0, 3.0]
    """
    if not (np.isfinite(factor) and factor > 0 and np.isfinite(pivot) and np.isfinite(shift)):
        raise ArgumentError("factor", f"{track.path}: time scale must be > 0 and finite, got {factor!r}")

    def move(t: ArrayLike) -> np.ndarray:
        return pivot + factor * (np.asarray(t, dtype=float) - pivot) + shift

    if isinstance(track, DiscreteTrack):
        return replace(track, times=move(track.times).tolist(), values=list(track.values))
    return _curve(track, BSpline(move(track.spline.t), track.spline.c, track.spline.k))


def without_range(track: Track, t0: float, t1: float) -> Track:
    """``track`` with its motion over ``(t0, t1)`` deleted: a discrete track loses the
    values there; a curve is bridged from its value and slope at ``t0`` to those at
    ``t1`` by a cubic (C1 at both ends), as deleting the keys of a range does in a
    keyframe editor. The rest keeps its timing.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 4, 9)
    >>> s = make_lsq_spline(t, np.sin(t), np.r_[[0.0] * 4, 2.0, [4.0] * 4], 3)
    >>> cut = without_range(ContinuousTrack("a.x", FLOAT, BSpline(s.t, s.c[:, None], 3), 0.01), 1.0, 3.0)
    >>> bool(np.allclose(cut.evaluate([0.5, 3.5])[:, 0], s([0.5, 3.5])))
    True
    """
    if not t0 < t1:
        raise ArgumentError("range", f"{track.path}: needs t0 < t1, got ({t0!r}, {t1!r})")
    if isinstance(track, DiscreteTrack):
        keep = [(t, v) for t, v in zip(track.times, track.values) if not t0 < t < t1]
        return replace(track, times=[t for t, _ in keep], values=[v for _, v in keep])
    s = track.spline
    k = s.k + 1
    if k < 4:
        raise ArgumentError("order", f"{track.path}: a range is bridged with a cubic; the track's order is {k}")
    t0, t1 = snapped(s, max(t0, track.start)), snapped(s, min(t1, track.end))
    if t0 >= t1:
        return track
    left = split(s, t0)[0] if t0 > track.start else None
    right = split(s, t1)[1] if t1 < track.end else None
    ends = [left(t0) if left else right(t0), right(t1) if right else left(t1)]
    slopes = [left.derivative()(t0) if left else 0 * ends[0], right.derivative()(t1) if right else 0 * ends[1]]
    # The cubic Hermite bridge as a Bezier piece, raised to the track's order if needed.
    h = (t1 - t0) / 3
    bezier = np.array([ends[0], ends[0] + h * slopes[0], ends[1] - h * slopes[1], ends[1]])
    bridge = elevate_degree(BSpline(np.r_[[t0] * 4, [t1] * 4], bezier, 3), k - 4)
    pieces = [p for p in (left, bridge, right) if p is not None]
    c = [np.array(p.c, dtype=float) for p in pieces]
    if left is not None:
        c[1][0] = c[0][-1]
    if right is not None:
        c[-1][0] = c[-2][-1]
    return _curve(track, join([BSpline(p.t, ci, p.k) for p, ci in zip(pieces, c)]))
