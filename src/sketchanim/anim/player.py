"""Playback: every track evaluated at one time, written into the scene.

The continuous tracks are packed into flat arrays once (again only when the set of
tracks changes), and one compiled pass evaluates them all at a time: de Boor's
algorithm per track, orientations normalised. Discrete tracks step, and events fire
when playback passes them.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numba import njit

from sketchanim.anim.scene import Attribute, Scene
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Track
from sketchanim.errors import ArgumentError


@dataclass(frozen=True)
class _Packed:
    """The continuous tracks end to end: knots, coefficients (row-major) and values,
    with each track's offsets into them."""

    paths: list[str]
    attributes: list[Attribute]
    discrete: list[DiscreteTrack]
    span: tuple[float, ...]
    knots: np.ndarray
    kofs: np.ndarray
    coef: np.ndarray
    cofs: np.ndarray
    orders: np.ndarray
    dims: np.ndarray
    rotation: np.ndarray
    low: np.ndarray                                   # each track's bounds (±inf: unbounded)
    high: np.ndarray
    oofs: np.ndarray
    bounds: list[int]                                 # oofs as Python ints (fast to slice with)


@njit(cache=True)
def _evaluate(t: float, knots: np.ndarray, kofs: np.ndarray, coef: np.ndarray, cofs: np.ndarray,
              orders: np.ndarray, dims: np.ndarray, rotation: np.ndarray, low: np.ndarray, high: np.ndarray,
              oofs: np.ndarray, out: np.ndarray) -> None:
    """Every packed spline at ``t`` (clamped to its span) into ``out``, each channel
    clamped to its track's ``low`` and ``high`` (a bounded curve keeps them but for
    rounding)."""
    work = np.empty(32)
    for j in range(len(orders)):
        k = orders[j]
        deg = k - 1
        tk = knots[kofs[j] : kofs[j + 1]]
        n = len(tk) - k
        x = min(max(t, tk[deg]), tk[n])
        lo, hi = deg, n - 1                     # the span: tk[i] <= x < tk[i + 1], i <= n - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if tk[mid] <= x:
                lo = mid
            else:
                hi = mid - 1
        i = lo
        d = dims[j]
        c0 = cofs[j]
        norm = 0.0
        for ch in range(d):
            for r in range(k):
                work[r] = coef[c0 + (i - deg + r) * d + ch]
            for r in range(1, k):
                for s in range(deg, r - 1, -1):
                    idx = i - deg + s
                    alpha = (x - tk[idx]) / (tk[idx + k - r] - tk[idx])
                    work[s] = (1.0 - alpha) * work[s - 1] + alpha * work[s]
            out[oofs[j] + ch] = min(max(work[deg], low[j]), high[j])
            norm += work[deg] * work[deg]
        if rotation[j]:
            norm = np.sqrt(norm)
            for ch in range(d):
                out[oofs[j] + ch] /= norm


class Player:
    """Evaluate tracks at any time and write the values into a scene.

    Parameters
    ----------
    scene : Scene
    tracks : iterable of ContinuousTrack or DiscreteTrack
        At most one per attribute path.

    Attributes
    ----------
    time : float
        The playhead, in seconds.
    speed : float
        Seconds of animation per second of playback (negative plays backwards).
    loop : bool
        Wrap around the animation's span instead of stopping at its ends.

    Examples
    --------
    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import POSITION
    >>> scene = Scene(); _ = scene.add("box")
    >>> line = BSpline(np.r_[[0.0] * 2, [2.0] * 2], np.array([[0.0, 0, 0], [2.0, 0, 0]]), 1)
    >>> player = Player(scene, [ContinuousTrack("box.position", POSITION, line, 0.005)])
    >>> player.seek(0.5); _ = player.apply()
    >>> scene.get("box.position").tolist()
    [0.5, 0.0, 0.0]
    >>> player.loop = True; _ = player.advance(2.0); round(player.time, 6)
    0.5
    """

    def __init__(self, scene: Scene, tracks: Iterable[Track] = ()) -> None:
        self.scene = scene
        self.tracks: dict[str, Track] = {}
        self.time = 0.0
        self.speed = 1.0
        self.loop = False
        self._last = 0.0                              # where events last fired
        self._packed: _Packed | None = None
        for track in tracks:
            self.add(track)

    # -- tracks --------------------------------------------------------------------------

    def add(self, track: Track) -> None:
        """Add or replace the track of ``track.path`` (its attribute must exist, of the
        same type)."""
        kind = self.scene.type(track.path)
        if kind != track.type:
            raise ArgumentError("track", f"{track.path} is {kind.name}, the track is {track.type.name}")
        self.tracks[track.path] = track
        self._packed = None

    def remove(self, path: str) -> None:
        """Drop the track of ``path``."""
        if self.tracks.pop(path, None) is None:
            raise ArgumentError("path", f"no track for {path!r}")
        self._packed = None

    @property
    def span(self) -> tuple[float, float]:
        """First and last time of any track (0, 0 without tracks)."""
        packed = self._pack()
        ends = list(packed.span)
        for track in packed.discrete:
            if track.times:
                ends += [track.times[0], track.times[-1]]
        return (min(ends), max(ends)) if ends else (0.0, 0.0)

    def _pack(self) -> _Packed:
        if self._packed is None:
            curves = [t for t in self.tracks.values() if isinstance(t, ContinuousTrack)]
            knots = [np.asarray(c.spline.t, dtype=float) for c in curves]
            coef = [np.ascontiguousarray(c.spline.c, dtype=float).reshape(-1) for c in curves]
            dims = np.array([c.type.dim for c in curves], dtype=np.int64)
            oofs = np.r_[0, np.cumsum(dims)].astype(np.int64)
            if any(c.spline.k + 1 > 32 for c in curves):
                raise ArgumentError("order", "tracks of order above 32 cannot be played")
            self._packed = _Packed(
                [c.path for c in curves],
                [self.scene.attribute(c.path) for c in curves],
                [t for t in self.tracks.values() if isinstance(t, DiscreteTrack)],
                (min(c.start for c in curves), max(c.end for c in curves)) if curves else (),
                np.concatenate(knots) if curves else np.zeros(0),
                np.r_[0, np.cumsum([len(k) for k in knots])].astype(np.int64),
                np.concatenate(coef) if curves else np.zeros(0),
                np.r_[0, np.cumsum([len(c) for c in coef])].astype(np.int64),
                np.array([c.spline.k + 1 for c in curves], dtype=np.int64),
                dims,
                np.array([c.type.is_rotation for c in curves], dtype=np.bool_),
                np.array([(c.type.bounds or (-np.inf, np.inf))[0] for c in curves], dtype=float),
                np.array([(c.type.bounds or (-np.inf, np.inf))[1] for c in curves], dtype=float),
                oofs,
                oofs.tolist(),
            )
        return self._packed

    # -- evaluation ----------------------------------------------------------------------

    def values(self, t: float) -> tuple[list[str], np.ndarray, np.ndarray]:
        """Every continuous track at ``t`` in one pass: the paths, the values of all of
        them end to end, and where each one's values start in that array."""
        p = self._pack()
        out = np.empty(int(p.oofs[-1]))
        _evaluate(float(t), p.knots, p.kofs, p.coef, p.cofs, p.orders, p.dims, p.rotation, p.low, p.high, p.oofs,
                  out)
        return p.paths, out, p.oofs

    def evaluate(self, t: float) -> dict[str, object]:
        """The value of every track at ``t``: arrays for continuous attributes, the
        holding value (or None before the first) for discrete ones."""
        paths, out, oofs = self.values(t)
        result: dict[str, object] = {p: out[oofs[i] : oofs[i + 1]] for i, p in enumerate(paths)}
        for path, track in self.tracks.items():
            if isinstance(track, DiscreteTrack):
                result[path] = track.value_at(t)
        return result

    # -- the playhead ---------------------------------------------------------------------

    def seek(self, t: float) -> None:
        """Move the playhead to ``t`` (scrubbing: no events fire on the way)."""
        if not np.isfinite(t):
            raise ArgumentError("time", f"must be finite, got {t!r}")
        self.time = self._last = float(t)

    def advance(self, seconds: float) -> float:
        """Move the playhead by ``seconds`` of playback (times ``speed``), wrapping when
        looping, else stopping at the span's ends; the new time."""
        start, end = self.span
        t = self.time + self.speed * float(seconds)
        if self.loop and end > start:
            t = start + (t - start) % (end - start)
        elif end > start:
            t = min(max(t, start), end)
        self.time = t
        return t

    def apply(self, skip: Iterable[str] = ()) -> list[tuple[str, float, object]]:
        """Write every track's value at the playhead into the scene, except at the paths
        in ``skip`` (those being manipulated: interaction has priority over playback).
        Returns the events passed since the last apply, as (path, time, label)."""
        skipped = set(skip)
        packed = self._pack()
        out = self.values(self.time)[1]
        bounds = packed.bounds
        for i, (path, attribute) in enumerate(zip(packed.paths, packed.attributes)):
            if not skipped or path not in skipped:
                attribute.value = out[bounds[i] : bounds[i + 1]]
        fired = []
        for track in packed.discrete:
            path = track.path
            if path in skipped:
                continue
            if track.type.name == "event":
                fired += [(path, t, v) for t, v in self._passed(track)]
            else:
                value = track.value_at(self.time)
                if value is not None:
                    self.scene.attribute(path).value = value
        self._last = self.time
        return fired

    def _passed(self, track: DiscreteTrack) -> list[tuple[float, object]]:
        """The events between the last apply and now, in playback order (across the
        wrap of a loop)."""
        a, b = self._last, self.time
        start, end = self.span
        if self.speed >= 0:
            if b >= a:
                return track.between(a, b)
            return track.between(a, end) + track.between(-np.inf, b) if self.loop else []
        if b <= a:
            return track.between(b, a)[::-1]
        return (track.between(-np.inf, a)[::-1] + track.between(b, end)[::-1]) if self.loop else []
