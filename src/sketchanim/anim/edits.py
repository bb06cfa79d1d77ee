"""Editing tracks: each edit is a function from a track to a new track (tracks are
never changed in place); :meth:`.history.History.edit` makes one an undoable step.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline

from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Track
from sketchanim.errors import ArgumentError
from sketchanim.reducer.splice import join, snapped, split
from sketchanim.spline import derivative, elevate_degree, insert_knots


def _curve(track: ContinuousTrack, spline: BSpline) -> ContinuousTrack:
    """``track`` with the curve ``spline``, edited by hand (composing it again from its
    takes drops the edit: :attr:`~.tracks.ContinuousTrack.edited`)."""
    return replace(track, spline=spline, edited=True)


def moved_points(track: ContinuousTrack, moves: Mapping[int, ArrayLike]) -> ContinuousTrack:
    """``track`` with control point ``index`` at ``value`` (dim numbers) for each
    ``index: value`` of ``moves``: the curve changes only on the spans of the points
    moved (``[t[i], t[i + order]]`` for point ``i``).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 1.0]], 1)
    >>> moved_points(ContinuousTrack("a.x", FLOAT, s, 0.01), {1: [3.0]}).evaluate([1.0]).tolist()
    [[3.0]]
    """
    c = np.array(track.spline.c, dtype=float)
    for index, value in moves.items():
        if not 0 <= index < len(c):
            raise ArgumentError("index", f"{track.path}: control point {index} of {len(c)}")
        c[index] = track.type.check(value, f"{track.path} point {index}")
    return _curve(track, BSpline(track.spline.t, c, track.spline.k))


def _active(spline: BSpline, t: float) -> np.ndarray:
    """The indices of the coefficients whose basis functions can be nonzero at ``t``."""
    k, knots = spline.k, np.asarray(spline.t)
    n = len(knots) - k - 1
    span = int(np.clip(np.searchsorted(knots, t, side="right") - 1, k, n - 1))
    return np.arange(span - k, span + 1)


def moved_key(track: ContinuousTrack, time: float, value: ArrayLike | None = None,
              slope: ArrayLike | None = None) -> ContinuousTrack:
    """``track`` whose curve takes ``value`` at ``time`` and / or has the derivative
    ``slope`` (per second) there: a key or its tangent handle dragged. The change is the
    least (in the control points' norm) that does it, made to the control points active at
    ``time`` only, so the curve changes only within ``order`` spans around it and keeps
    its knots (its continuity everywhere). An orientation takes a value only (a unit
    quaternion, played on the curve's side of the sphere).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> s = BSpline(np.r_[[0.0] * 4, 1.0, 2.0, [3.0] * 4], np.zeros((6, 1)), 3)
    >>> keyed = moved_key(ContinuousTrack("a.x", FLOAT, s, 0.01), 1.0, [1.0], [0.5])
    >>> round(float(keyed.evaluate([1.0])[0, 0]), 12), round(float(keyed.spline.derivative()(1.0)[0]), 12)
    (1.0, 0.5)
    """
    s = track.spline
    if not (np.isfinite(time) and track.start <= time <= track.end):
        raise ArgumentError("time", f"{track.path}: a key goes within [{track.start}, {track.end}], got {time!r}")
    if value is None and slope is None:
        raise ArgumentError("value", f"{track.path}: a key edit needs a value or a slope")
    if track.type.is_rotation and slope is not None:
        raise ArgumentError("slope", f"{track.path}: an orientation's key takes a value only")
    active = _active(s, time)
    unit = np.zeros((len(s.c), len(active)))
    unit[active, np.arange(len(active))] = 1.0
    basis = BSpline(s.t, unit, s.k)
    rows, wants = [], []
    if value is not None:
        target = np.asarray(track.type.check(value, f"{track.path} key at {time}"), dtype=float)
        now = s(time)
        if track.type.is_rotation and float(np.dot(target, now)) < 0:
            target = -target                                  # the same rotation, on the curve's side
        rows.append(basis(time))
        wants.append(target - now)
    if slope is not None:
        rate = np.asarray(slope, dtype=float).reshape(-1)
        if rate.shape != (track.type.dim,) or not np.all(np.isfinite(rate)):
            raise ArgumentError("slope", f"{track.path}: a slope needs {track.type.dim} finite numbers")
        rows.append(derivative(basis)(time))
        wants.append(rate - derivative(s)(time))
    change = np.linalg.pinv(np.array(rows)) @ np.array(wants)
    c = np.array(s.c, dtype=float)
    c[active] += change
    return _curve(track, BSpline(s.t, c, s.k))


def with_knots(track: ContinuousTrack, times: Sequence[float]) -> ContinuousTrack:
    """``track`` with knots inserted at ``times`` (the curve unchanged, a point more each).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 1.0]], 1)
    >>> with_knots(ContinuousTrack("a.x", FLOAT, s, 0.01), [0.25, 0.5]).n_coefficients
    4
    """
    for t in times:
        if not track.start < t < track.end:
            raise ArgumentError("time", f"{track.path}: a knot goes inside ({track.start}, {track.end}), got {t!r}")
    return _curve(track, insert_knots(track.spline, sorted(times)))


def without_knots(track: ContinuousTrack, indices: Sequence[int]) -> ContinuousTrack:
    """``track`` without the interior knots ``indices`` (into ``spline.t``): for each,
    the nearest curve without it by least squares over the spans its basis functions
    cover, only their control points changed (one point fewer each): knot ``t[j]``
    changes the curve on ``[t[j - order], t[j + order]]`` and nowhere else.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.r_[[0.0] * 4, np.arange(1.0, 8.0), [8.0] * 4]
    >>> s = BSpline(t, np.c_[np.sin(np.arange(11.0))], 3)
    >>> cut = without_knots(ContinuousTrack("a.x", FLOAT, s, 0.01), [9])       # the knot at 6
    >>> cut.n_coefficients, bool(np.allclose(cut.evaluate([0.5, 1.9]), s([0.5, 1.9])))
    (10, True)
    """
    s, k = track.spline, track.spline.k
    knots, c = np.asarray(s.t, dtype=float), np.array(s.c, dtype=float)
    for index in sorted(set(indices), reverse=True):
        if not (k + 1 <= index < len(knots) - k - 1 and knots[k] < knots[index] < knots[-k - 1]):
            raise ArgumentError("index", f"{track.path}: knot {index} is not an interior knot")
        old = BSpline(knots, c, k)
        fewer = np.delete(knots, index)
        free = np.arange(index - k - 1, index)               # the points of the spans the knot bounded
        fixed = np.r_[c[: index - k - 1], np.zeros((len(free), c.shape[1])), c[index + 1:]]
        lo, hi = fewer[max(index - k - 1, 0)], fewer[min(index + k, len(fewer) - 1)]
        edges = np.unique(fewer[(fewer >= lo) & (fewer <= hi)])
        x = np.unique(np.concatenate([np.linspace(a, b, 4 * (k + 1)) for a, b in zip(edges[:-1], edges[1:])]))
        design = BSpline.design_matrix(x, fewer, k).toarray()
        rest = old(x) - design @ fixed
        fixed[free] = np.linalg.lstsq(design[:, free], rest, rcond=None)[0]
        knots, c = fewer, fixed
    return _curve(track, BSpline(knots, c, k))


def with_key(track: DiscreteTrack, time: float, value: object) -> DiscreteTrack:
    """``track`` with ``value`` keyed at ``time``: an event is added (several may share a
    time); a bool or an enum value replaces the one keyed at that very time, if any.

    >>> from sketchanim.anim.attributes import BOOL, EVENT
    >>> on = with_key(with_key(DiscreteTrack("lamp.on", BOOL), 1.0, False), 1.0, True)
    >>> on.times, on.values
    ([1.0], [True])
    >>> with_key(with_key(DiscreteTrack("box.cue", EVENT), 1.0, "hit"), 1.0, None).values
    ['hit', None]
    """
    value = track.type.check(value, track.path)
    time = float(time)
    if not np.isfinite(time):
        raise ArgumentError("time", f"{track.path}: a key's time must be finite, got {time!r}")
    pairs = list(zip(track.times, track.values))
    if track.type.name != "event":
        pairs = [(t, v) for t, v in pairs if t != time]
    i = sum(1 for t, _ in pairs if t <= time)
    pairs.insert(i, (time, value))
    return replace(track, times=[t for t, _ in pairs], values=[v for _, v in pairs])


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

    >>> from scipy.interpolate import make_lsq_spline
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
