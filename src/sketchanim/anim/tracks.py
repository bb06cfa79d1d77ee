"""Tracks: how an attribute changes over time.

A :class:`Take` is one recording of one attribute, raw (with the smoothing its curve is
reduced after, so that can be changed later). A :class:`ContinuousTrack` holds a reduced
B-spline of the attribute's channels (an orientation's is a quaternion spline, normalised
when evaluated, as glTF plays it); a :class:`DiscreteTrack` holds time-stamped values
with step semantics. Before its first time and after its last, a track holds its end
values.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import AttributeType
from sketchanim.errors import ArgumentError
from sketchanim.reducer.smoothing import check_sigma


MODES = ("replace", "additive")
#: Default fade at each seam of a punch-in, in seconds.
BLEND = 0.1


@dataclass(frozen=True)
class Take:
    """One recording of one attribute.

    Attributes
    ----------
    times : ndarray, shape (n,)
        Sample times in seconds, increasing.
    values : ndarray, shape (n, dim)
        The samples: values (``replace``), or offsets (``additive``: added to a vector,
        or scalar-last quaternions applied on top of an orientation).
    mode : {"replace", "additive"}
    blend : float
        Seconds of fade at each seam with existing motion.
    smoothing : float
        Seconds: the width its samples are smoothed over before they are reduced
        (:mod:`sketchanim.reducer.smoothing`; 0: not smoothed). ``values`` stay raw; the
        tolerance holds against the smoothed samples.
    name : str
        What the animator called it ("": not named).
    muted : bool
        Left out when the track's curve is composed (:func:`.layers.compose`).
    loop : str or None
        The loop recording it is part of (its passes share the key; one pass is kept, the
        others muted), or None.
    loop_pass : int
        Which pass of that loop recording (0, 1, ...; a pass may be several takes).
    """

    times: np.ndarray
    values: np.ndarray
    mode: str = "replace"
    blend: float = BLEND
    smoothing: float = 0.0
    name: str = ""
    muted: bool = False
    loop: str | None = None
    loop_pass: int = 0

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ArgumentError("mode", f"must be one of {', '.join(MODES)}, got {self.mode!r}")
        if not (np.isfinite(self.blend) and self.blend >= 0):
            raise ArgumentError("blend", f"must be >= 0 seconds, got {self.blend!r}")
        object.__setattr__(self, "smoothing", check_sigma(self.smoothing, "smoothing"))     # a float, 0.0 for None
        t = np.asarray(self.times, dtype=float)
        if t.ndim != 1 or len(t) < 2 or not np.all(np.diff(t) > 0):
            raise ArgumentError("times", f"a take needs 2 or more increasing times, got {len(t)}")

    @property
    def start(self) -> float:
        return float(self.times[0])

    @property
    def end(self) -> float:
        return float(self.times[-1])


def held_values(spline: BSpline, times: np.ndarray, rotation: bool) -> np.ndarray:
    """``spline`` at ``times``, holding its end values outside its span (normalised if
    ``rotation``), as tracks play.

    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 2.0]], 1)
    >>> held_values(s, np.array([-1.0, 0.5, 3.0]), False)[:, 0].tolist()
    [0.0, 1.0, 2.0]
    """
    k = spline.k
    v = spline(np.clip(times, spline.t[k], spline.t[-k - 1]))
    return v / np.linalg.norm(v, axis=1, keepdims=True) if rotation else v


@dataclass
class ContinuousTrack:
    """A continuous attribute's curve.

    Attributes
    ----------
    path : str
        The attribute ("object.attribute").
    type : AttributeType
    spline : BSpline
        Clamped, evaluating to (n, type.dim) values.
    tol : float
        The tolerance it was recorded with, in ``type.unit``.
    takes : tuple of Take
        The recordings it was made of, in order, raw (:func:`.layers.compose` rebuilds
        the curve from them at any tolerance); empty for a curve made otherwise.
    edited : bool
        Its curve was edited by hand (:mod:`.edits`) since it was composed from its takes:
        composing it again drops those edits.

    >>> from sketchanim.anim.attributes import POSITION
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> ContinuousTrack("box.position", POSITION, s, 0.005).evaluate([-1.0, 0.5, 2.0]).tolist()
    [[0.0, 0.0, 0.0], [0.5, 1.0, 1.5], [1.0, 2.0, 3.0]]
    """

    path: str
    type: AttributeType
    spline: BSpline
    tol: float
    takes: tuple[Take, ...] = ()
    edited: bool = False

    def __post_init__(self) -> None:
        c = np.asarray(self.spline.c)
        if not self.type.continuous or c.ndim != 2 or c.shape[1] != self.type.dim:
            raise ArgumentError("spline", f"{self.path}: needs {self.type.dim} channels, got coefficients {c.shape}")

    @property
    def start(self) -> float:
        return float(self.spline.t[self.spline.k])

    @property
    def end(self) -> float:
        return float(self.spline.t[-self.spline.k - 1])

    @property
    def n_coefficients(self) -> int:
        return int(np.asarray(self.spline.c).shape[0])

    def evaluate(self, times: ArrayLike) -> np.ndarray:
        """Values at ``times`` (n,), shape (n, dim); held outside the track's span."""
        return held_values(self.spline, np.asarray(times, dtype=float).reshape(-1), self.type.is_rotation)


@dataclass
class DiscreteTrack:
    """A discrete attribute's values at times, in time order (step semantics: a value
    holds from its time until the next).

    >>> from sketchanim.anim.attributes import BOOL
    >>> track = DiscreteTrack("lamp.on", BOOL)
    >>> track.add(1.0, False); track.add(2.0, True)
    >>> track.value_at(0.5), track.value_at(1.0), track.value_at(5.0)
    (None, False, True)
    """

    path: str
    type: AttributeType
    times: list[float] = field(default_factory=list)
    values: list[object] = field(default_factory=list)

    def __post_init__(self) -> None:
        if self.type.continuous:
            raise ArgumentError("type", f"{self.path}: a discrete track needs a discrete type, got {self.type.name}")
        if len(self.times) != len(self.values):
            raise ArgumentError("values", f"{self.path}: {len(self.values)} values for {len(self.times)} times")
        pairs = [(self._time(t), self.type.check(v, self.path)) for t, v in zip(self.times, self.values)]
        if any(b[0] < a[0] for a, b in zip(pairs, pairs[1:])):
            raise ArgumentError("times", f"{self.path}: times must not go backwards")
        self.times = [p[0] for p in pairs]
        self.values = [p[1] for p in pairs]

    def _time(self, t: float) -> float:
        t = float(t)
        if not np.isfinite(t):
            raise ArgumentError("time", f"{self.path}: must be finite, got {t!r}")
        return t

    def add(self, t: float, value: object) -> None:
        """Add ``value`` at time ``t`` (after any others at the same time)."""
        t = self._time(t)
        i = int(np.searchsorted(self.times, t, side="right"))
        self.times.insert(i, t)
        self.values.insert(i, self.type.check(value, self.path))

    def value_at(self, t: float) -> object:
        """The value holding at ``t``, or None before the first."""
        i = int(np.searchsorted(self.times, t, side="right"))
        return self.values[i - 1] if i else None

    def between(self, t0: float, t1: float) -> list[tuple[float, object]]:
        """The (time, value) pairs with ``t0 < time <= t1``: what fires when playback
        moves from ``t0`` to ``t1``."""
        a = int(np.searchsorted(self.times, t0, side="right"))
        b = int(np.searchsorted(self.times, t1, side="right"))
        return list(zip(self.times[a:b], self.values[a:b]))


#: Either kind of track.
Track = ContinuousTrack | DiscreteTrack
