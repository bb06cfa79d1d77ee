"""Editing tracks, every edit undoable.

Each edit is a function from a track to a new track (tracks are never changed in
place), and :class:`History` applies edits to a player's tracks, keeping what each one
replaced so that it can be undone and redone. Recording a take is an edit too.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline, make_lsq_spline

from sketchanim.anim.player import Player
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


#: A change to the scene in a History step: (do, undo), two calls without arguments.
SceneChange = tuple[Callable[[], object], Callable[[], object]]


@dataclass(frozen=True)
class Edit:
    """One undoable step: the tracks it replaced and the ones it put (None: no track),
    and the scene changes made with them, in order.

    ``merge`` is the step's merge key: a step applied with the same key as the last one
    joins it (three.js's updatable commands: a run of nudges, the passes of a loop
    recording), so one undo goes back to before the first.
    """

    label: str
    before: Mapping[str, Track | None]
    after: Mapping[str, Track | None]
    scene: tuple[SceneChange, ...] = ()
    merge: str | None = None


class History:
    """Apply edits to a player's tracks and changes to its scene, with undo and redo.

    ``on_change`` is called with the history after every step applied, undone or
    redone (e.g. to tell clients the labels and whether undo and redo are possible).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> from sketchanim.anim.scene import Scene
    >>> scene = Scene(); obj = scene.add("a"); _ = obj.add("x", FLOAT)
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 1.0]], 1)
    >>> player = Player(scene, [ContinuousTrack("a.x", FLOAT, s, 0.01)])
    >>> history = History(player)
    >>> history.edit("a.x", "move point", moved_point, 1, [5.0])
    >>> float(player.tracks["a.x"].evaluate([1.0])[0, 0]), history.undo(), float(player.tracks["a.x"].evaluate([1.0])[0, 0])
    (5.0, 'move point', 1.0)
    >>> history.set("a.x", [2.0], "nudge", merge="nudge"); history.set("a.x", [3.0], "nudge", merge="nudge")
    >>> history.labels, history.undo(), scene.get("a.x").tolist()
    ((['nudge'], []), 'nudge', [0.0])
    """

    def __init__(self, player: Player, limit: int = 1000,
                 on_change: Callable[[History], object] | None = None) -> None:
        self.player = player
        self.limit = limit
        self.on_change = on_change
        self.done: list[Edit] = []
        self.undone: list[Edit] = []

    @property
    def labels(self) -> tuple[list[str], list[str]]:
        """The labels of the steps to undo (oldest first) and of those to redo (the next
        redo last)."""
        return [e.label for e in self.done], [e.label for e in self.undone]

    def apply(self, label: str, tracks: Mapping[str, Track | None], scene: tuple[SceneChange, ...] = (),
              merge: str | None = None) -> None:
        """Put ``tracks`` (path -> new track, or None to remove it) and make the scene
        changes ``scene`` (each ``(do, undo)``) as one step: removals first, then the
        scene changes, then the tracks put (so a track can follow its object)."""
        before = {path: self.player.tracks.get(path) for path in tracks}
        self._put(tracks, [do for do, _ in scene])
        step = Edit(label, before, dict(tracks), tuple(scene), merge)
        if merge is not None and self.done and self.done[-1].merge == merge:
            last = self.done.pop()
            step = Edit(label, {**before, **last.before}, {**last.after, **step.after}, last.scene + step.scene, merge)
        self.done.append(step)
        del self.done[: -self.limit]
        self.undone.clear()
        self._changed()

    def edit(self, path: str, label: str, change: Callable[..., Track], *args: object) -> None:
        """Replace the track at ``path`` by ``change(track, *args)`` as one step."""
        if path not in self.player.tracks:
            raise ArgumentError("path", f"no track for {path!r}")
        self.apply(label, {path: change(self.player.tracks[path], *args)})

    def set(self, path: str, value: object, label: str | None = None, merge: str | None = None) -> None:
        """Set the scene's value at ``path`` as one step (checked first: a bad value
        raises and changes nothing)."""
        scene = self.player.scene
        old, new = scene.get(path), scene.type(path).check(value, path)
        self.apply(label or f"set {path}", {}, ((lambda: scene.set(path, new), lambda: scene.set(path, old)),), merge)

    def undo(self) -> str | None:
        """Undo the last step; its label, or None if there is none."""
        return self._move(self.done, self.undone, "before")

    def redo(self) -> str | None:
        """Redo the last undone step; its label, or None if there is none."""
        return self._move(self.undone, self.done, "after")

    def _move(self, source: list[Edit], target: list[Edit], side: str) -> str | None:
        """Take the last step of ``source``, put its ``side`` tracks and make its scene
        changes (undone in reverse), keep it on ``target``."""
        if not source:
            return None
        step = source.pop()
        calls = [do for do, _ in step.scene] if side == "after" else [undo for _, undo in reversed(step.scene)]
        self._put(getattr(step, side), calls)
        target.append(step)
        self._changed()
        return step.label

    def _changed(self) -> None:
        if self.on_change is not None:
            self.on_change(self)

    def _put(self, tracks: Mapping[str, Track | None], calls: list[Callable[[], object]] = ()) -> None:
        for path, track in tracks.items():
            if track is None and path in self.player.tracks:
                self.player.remove(path)
        for call in calls:
            call()
        for track in tracks.values():
            if track is not None:
                self.player.add(track)
