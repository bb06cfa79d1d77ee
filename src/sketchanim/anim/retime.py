"""Retiming tracks and moving their motion in time: a whole track retimed (its curve and
its takes with it), a range copied out as a :class:`Piece` and pasted at another time.

Each is a function from a track to a new track (tracks are never changed in place), as
:mod:`.edits` are; :meth:`.history.History.edit` makes one an undoable step. Times are
numbers: snapping them to frames is the caller's choice.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from sketchanim.anim.edits import scaled, without_range
from sketchanim.anim.layers import recorded_over
from sketchanim.anim.take_edits import retimed_take
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take, Track, BLEND
from sketchanim.errors import ArgumentError
from sketchanim.reducer.splice import split

#: Samples per second a pasted curve is sampled at (the take it becomes; denser than any
#: frame rate the studio offers, so the paste keeps the piece's shape between frames).
PASTE_RATE = 240.0


def retimed(track: Track, factor: float = 1.0, pivot: float = 0.0, shift: float = 0.0) -> Track:
    """``track`` with time ``t`` moved to ``pivot + factor * (t - pivot) + shift``
    (``factor`` > 0), as a whole: a curve's knots and every take's sample times (and
    seconds of blend and smoothing, :func:`~.take_edits.retimed_take`), so that
    composing it again from its takes gives the retimed motion; whether it was
    :attr:`~.tracks.ContinuousTrack.edited` stays as it was. A discrete track's times.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> from sketchanim.anim.layers import recomposed
    >>> t = np.linspace(0, 1, 41)
    >>> track = recorded_over("a.x", FLOAT, None, Take(t, np.c_[np.sin(3 * t)]), 0.001, 4)
    >>> later = retimed(track, 2.0, pivot=0.0, shift=1.0)
    >>> later.start, later.end, later.takes[0].start, later.edited
    (1.0, 3.0, 1.0, False)
    >>> bool(np.abs(recomposed(later).evaluate(1 + 2 * t) - np.c_[np.sin(3 * t)]).max() <= 0.001)
    True
    """
    moved = scaled(track, factor, pivot, shift)
    if isinstance(track, DiscreteTrack):
        return moved
    takes = tuple(retimed_take(take, factor, pivot, shift) for take in track.takes)
    return replace(moved, takes=takes, edited=track.edited)


@dataclass(frozen=True)
class Piece:
    """A range of a track copied out (:func:`piece`): ``track`` starts at 0 (a curve on
    ``[0, length]``, a discrete track's values at times in ``(0, length)``), and
    ``length`` is the range's, in seconds."""

    track: Track
    length: float


def piece(track: Track, t0: float, t1: float) -> Piece:
    """The motion of ``track`` over ``(t0, t1)`` (within its span, for a curve) as a
    :class:`Piece` starting at 0: a curve cut exactly (knot insertion) at both ends, a
    discrete track's values strictly inside the range (those :func:`.edits.without_range`
    deletes). The piece has no takes.

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import BOOL, FLOAT
    >>> line = ContinuousTrack("a.x", FLOAT, BSpline(np.r_[[0.0] * 4, [4.0] * 4], np.c_[[0.0, 1, 2, 3]], 3), 0.01)
    >>> cut = piece(line, 1.0, 3.0)
    >>> cut.length, cut.track.start, cut.track.end, float(cut.track.evaluate([0.0])[0, 0])
    (2.0, 0.0, 2.0, 0.75)
    >>> piece(DiscreteTrack("a.on", BOOL, [0.5, 1.5, 2.5], [True, False, True]), 1.0, 3.0).track.times
    [0.5, 1.5]
    """
    if not (np.isfinite(t0) and np.isfinite(t1) and t0 < t1):
        raise ArgumentError("range", f"{track.path}: needs finite t0 < t1, got ({t0!r}, {t1!r})")
    if isinstance(track, DiscreteTrack):
        inside = [(t - t0, v) for t, v in zip(track.times, track.values) if t0 < t < t1]
        return Piece(DiscreteTrack(track.path, track.type, [t for t, _ in inside], [v for _, v in inside]),
                     float(t1 - t0))
    a, b = max(t0, track.start), min(t1, track.end)
    if not a < b:
        raise ArgumentError("range", f"{track.path}: ({t0}, {t1}) is outside its curve [{track.start}, {track.end}]")
    s = track.spline
    s = split(s, a)[1] if a > track.start else s
    s = split(s, b)[0] if b < track.end else s
    cut = ContinuousTrack(track.path, track.type, s, track.tol)
    return Piece(scaled(cut, 1.0, 0.0, -float(s.t[s.k])), float(s.t[-s.k - 1] - s.t[s.k]))


def pasted(track: Track, clip: Piece, at: float, order: int = 4, rate: float = PASTE_RATE) -> Track:
    """``track`` with the motion of ``clip`` put at time ``at`` (the piece's 0 there).

    A curve gets it as a replacing take (named "paste"): the piece sampled ``rate`` times
    a second, recorded over the track (:func:`.layers.recorded_over`), so it joins the
    motion around it smoothly (faded over up to :data:`~.tracks.BLEND` seconds at each
    seam, at most a quarter of the piece) and is kept within the track's tolerance; its
    ``order`` is the take's curve's. A discrete track gets the piece's values, those it
    had in ``(at, at + length)`` removed. The piece's attribute type must be the track's.

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import BOOL
    >>> lamp = DiscreteTrack("a.on", BOOL, [0.0, 2.0, 5.0], [True, False, True])
    >>> out = pasted(lamp, piece(DiscreteTrack("b.on", BOOL, [0.25], [True]), 0.0, 1.0), 1.5)
    >>> out.times, out.values                        # the False at 2 s was in the pasted second
    ([0.0, 1.75, 5.0], [True, True, True])
    """
    source = clip.track
    if source.type != track.type:
        raise ArgumentError("piece", f"a piece of {source.path} ({source.type.name}) cannot be pasted on "
                                     f"{track.path} ({track.type.name}): the types differ")
    if not np.isfinite(at):
        raise ArgumentError("at", f"{track.path}: must be finite, got {at!r}")
    if isinstance(track, DiscreteTrack):
        assert isinstance(source, DiscreteTrack)
        kept = without_range(track, at, at + clip.length) if clip.length > 0 else track
        out = replace(kept, times=list(kept.times), values=list(kept.values))
        for t, v in zip(source.times, source.values):
            out.add(at + t, v)
        return out
    assert isinstance(source, ContinuousTrack)
    n = max(2, int(np.ceil(clip.length * rate)) + 1)
    times = np.linspace(0.0, clip.length, n)
    take = Take(at + times, source.evaluate(times), "replace", blend=min(BLEND, clip.length / 4), name="paste")
    return recorded_over(track.path, track.type, track, take, track.tol, order)
