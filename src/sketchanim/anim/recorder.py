"""The recorder: samples in from any source while the performer acts, tracks out.

Armed attributes take time-stamped samples from the caller (the studio, a device, a file
being replayed). The caller only checks and queues them, and keeps the raw take; the
reducer processes (:mod:`.workers`) feed one streaming reducer per continuous attribute
(orientations: a quaternion stream with an angular tolerance) while the take goes on, in
parallel and outside the caller's interpreter lock. A take recorded over an existing
track (a punch-in) or added onto it is streamed as its targets (:class:`.layers.Overlay`)
and joined to the track when it stops (:func:`.layers.punch_in`). So when the take
stops, each curve needs only its last windows finished, whatever the take's length. An
attribute whose reducer process failed is reduced from its raw samples, with a warning.
An attribute armed with ``smoothing`` is streamed smoothed (:class:`.smoothed.SampleSmoother`,
in its reducer process); its take keeps the raw samples.
"""

from __future__ import annotations

import threading
import time
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.layers import recorded_over
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import BLEND, MODES, ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.anim.workers import Pool, Spec, shared_pool
from sketchanim.errors import ArgumentError, SampleError
from sketchanim.reducer.stream import Piece
from sketchanim.motion.rotations import MIN_NORM
from sketchanim.reducer.conditioning import TIME_RANGE, VALUE_RANGE
from sketchanim.reducer.smoothing import check_sigma

#: Called from the recorder's journal thread about every :data:`JOURNAL_PERIOD` seconds
#: with the samples queued since the last call: (path, times (n,), values (n, dim) or a
#: list of discrete values) for each attribute that got some.
SampleSink = Callable[[list[tuple[str, np.ndarray, object]]], None]
JOURNAL_PERIOD = 0.05


def _in_range(x: np.ndarray, first: np.ndarray, tol: np.ndarray, index: int, field: str) -> None:
    """Refuse a sample with a value beyond :data:`VALUE_RANGE` tolerances of the take's
    first (no reducer could keep it; the check it would fail in a reducer process)."""
    far = np.flatnonzero(np.abs(np.asarray(x, dtype=float) - first) > VALUE_RANGE * tol)
    if far.size:
        j = int(far[0])
        raise SampleError(f"value {float(x[j])!r} (column {j}) is more than {VALUE_RANGE:g} tolerances from the "
                          f"take's first {float(first[j])!r}", index=index, field=field)


@dataclass
class _Armed:
    """One armed attribute's state during a take."""

    path: str
    type: AttributeType
    tol: float
    mode: str
    blend: float
    smoothing: float = 0.0
    times: list[float] = field(default_factory=list)      # pushed one at a time
    values: list = field(default_factory=list)
    columns: tuple[int, int] | None = None          # where it is in a frame
    worker: int | None = None                       # the reducer process streaming it


class _Frames:
    """The frames of a take, in a store that grows by doubling."""

    def __init__(self, width: int) -> None:
        self.n = 0
        self.t = np.empty(1024)
        self.x = np.empty((1024, width))

    def append(self, t: float, x: np.ndarray) -> None:
        if self.n == len(self.t):
            self.t = np.r_[self.t, np.empty(self.n)]
            self.x = np.vstack([self.x, np.empty_like(self.x)])
        self.t[self.n] = t
        self.x[self.n] = x
        self.n += 1

    @property
    def last(self) -> float:
        """The latest frame's time (-inf before the first)."""
        return float(self.t[self.n - 1]) if self.n else -np.inf


class Recorder:
    """Record armed attributes of a scene into tracks.

    Parameters
    ----------
    scene : Scene
    order : int
        Spline order of recorded curves.
    window : int
        The streaming reducer's window (see :class:`sketchanim.StreamReducer`).
    journal : callable or None
        Given every sample queued, in batches, while the take goes on (see
        :data:`SampleSink`), e.g. to commit them to a project file.

    Examples
    --------
    >>> scene = Scene(); _ = scene.add("box")
    >>> rec = Recorder(scene)
    >>> rec.arm("box.position")
    >>> rec.start()
    >>> t = np.arange(240) / 120
    >>> for ti in t:
    ...     rec.push("box.position", ti, [np.sin(ti), 0.0, ti])
    >>> tracks = rec.stop()
    >>> track = tracks["box.position"]
    >>> bool(np.abs(track.evaluate(t) - np.c_[np.sin(t), 0 * t, t]).max() <= track.tol), track.n_coefficients < 20
    (True, True)
    """

    def __init__(self, scene: Scene, *, order: int = 4, window: int = 20, journal: SampleSink | None = None) -> None:
        self.scene = scene
        self.order = order
        self.window = window
        self.journal = journal
        self.armed: dict[str, _Armed] = {}
        self._pool: Pool | None = None
        self._take = -1
        self._over: dict[str, Track] = {}
        self._workers: dict[int, tuple[int, int] | None] = {}     # worker -> its columns of a frame
        self._frame: list[tuple[str, int, int]] = []
        self._frames = _Frames(0)
        self._rotations = np.zeros((0, 4), dtype=np.int64)   # frame columns of each orientation
        self._is_rotation = np.zeros(0, dtype=bool)
        self._single_last = -np.inf                 # latest push() time on a framed attribute
        self._journaling: threading.Thread | None = None
        self._stopping = threading.Event()
        self._journal_error: BaseException | None = None
        #: (seconds behind, samples) of each batch a reducer process took in the last
        #: take: how far the reduction lagged behind the capture
        self.lags: list[tuple[float, int]] = []
        #: Seconds each reducer process spent on the last take
        self.busy: list[float] = []

    # -- arming ----------------------------------------------------------------------------

    def arm(self, path: str, *, tol: float | None = None, mode: str = "replace", blend: float = BLEND,
            smoothing: float = 0.0) -> None:
        """Record ``path`` in the next take: a continuous one within ``tol`` (its type's
        default if None, in its unit) of its samples smoothed over ``smoothing`` seconds
        (0: not smoothed; :attr:`.tracks.Take.smoothing`), replacing or added onto its
        track (``mode``)."""
        if self.recording:
            raise ArgumentError("arm", "cannot arm while recording")
        kind = self.scene.type(path)
        if mode not in MODES:
            raise ArgumentError("mode", f"must be one of {', '.join(MODES)}, got {mode!r}")
        if mode == "additive" and not kind.continuous:
            raise ArgumentError("mode", f"{path}: a {kind.name} attribute cannot be recorded additively")
        tol = kind.tol if tol is None else float(tol)
        if kind.continuous and not (np.isfinite(tol) and tol > 0):
            raise ArgumentError("tol", f"{path}: must be > 0, got {tol!r}")
        if not (np.isfinite(blend) and blend >= 0):
            raise ArgumentError("blend", f"{path}: must be >= 0 seconds, got {blend!r}")
        smoothing = check_sigma(smoothing, "smoothing")
        if smoothing and not kind.continuous:
            raise ArgumentError("smoothing", f"{path}: a {kind.name} attribute cannot be smoothed")
        self.armed[path] = _Armed(path, kind, tol, mode, float(blend), smoothing)

    def disarm(self, path: str) -> None:
        """Stop recording ``path`` in the next take."""
        if self.recording:
            raise ArgumentError("disarm", "cannot disarm while recording")
        self.armed.pop(path, None)

    @property
    def layout(self) -> list[tuple[str, int, int]]:
        """How :meth:`push_frame` reads a frame: (path, first, end) of each armed
        continuous attribute's values, in arming order."""
        layout, at = [], 0
        for a in self.armed.values():
            if a.type.continuous:
                layout.append((a.path, at, at + a.type.dim))
                at += a.type.dim
        return layout

    # -- a take ----------------------------------------------------------------------------

    @property
    def recording(self) -> bool:
        return self._pool is not None

    def start(self, over: Mapping[str, Track] | None = None) -> None:
        """Start a take recorded over ``over`` (path -> track, e.g. a player's; not
        changed): a reducer stream for every armed continuous attribute (of its targets,
        for one recorded over a continuous track there or added onto it), and the
        journal thread."""
        if self.recording:
            raise ArgumentError("start", "already recording")
        if not self.armed:
            raise ArgumentError("start", "no attribute is armed")
        self._over = dict(over or {})
        self._frame = self.layout
        width = self._frame[-1][2] if self._frame else 0
        self._frames = _Frames(width)
        self._is_rotation = np.array([self.armed[p].type.is_rotation for p, _, _ in self._frame], dtype=bool)
        self._rotations = np.array([np.arange(a, b) for (_, a, b), r in zip(self._frame, self._is_rotation) if r],
                                   dtype=np.int64).reshape(-1, 4)
        # per column: the tolerance that bounds its range (a quaternion's: none)
        self._range_tol = np.concatenate([np.full(b - a, np.inf if r else self.armed[p].tol)
                                          for (p, a, b), r in zip(self._frame, self._is_rotation)] or [np.zeros(0)])
        # per column: the bounds of its values (an additive take's offsets have none)
        limits = [(self.armed[p].type.bounds if self.armed[p].mode != "additive" else None) or (-np.inf, np.inf)
                  for p, _, _ in self._frame]
        self._low, self._high = (np.concatenate([np.full(b - a, lim[i]) for (_, a, b), lim in zip(self._frame, limits)]
                                                or [np.zeros(0)]) for i in (0, 1))
        self._single_last = -np.inf
        for a in self.armed.values():
            a.times, a.values, a.columns, a.worker = [], [], None, None
        for path, lo, hi in self._frame:
            self.armed[path].columns = (lo, hi)
        self._assign(shared_pool())
        self.lags, self.busy = [], []
        self._journal_error = None
        self._stopping.clear()
        if self.journal is not None:
            self._journaling = threading.Thread(target=self._journal_loop, name="sketchanim-journal", daemon=True)
            self._journaling.start()

    def _assign(self, pool: Pool) -> None:
        """Share the continuous attributes among the reducer processes: the framed ones in
        contiguous runs of a frame (each process gets its columns of every frame), the
        others in turn; and tell each process its part."""
        continuous = [a for a in self.armed.values() if a.type.continuous]
        framed = [a for a in continuous if a.columns is not None]
        specs: dict[int, list[Spec]] = {}
        self._workers = {}

        def spec(a: _Armed, w: int, columns: tuple[int, int] | None = None) -> None:
            old = self._over.get(a.path)
            below = old.spline if isinstance(old, ContinuousTrack) else None
            over = (below, a.mode, a.blend) if below is not None or a.mode == "additive" else None
            a.worker = w
            self._workers.setdefault(w, None)
            specs.setdefault(w, []).append(Spec(a.path, a.type, a.tol, columns, over, a.smoothing))

        for w, run in enumerate(np.array_split(np.arange(len(framed)), pool.size)):
            if len(run):
                lo, hi = framed[run[0]].columns[0], framed[run[-1]].columns[1]
                for i in run:
                    spec(framed[i], w, (framed[i].columns[0] - lo, framed[i].columns[1] - lo))
                self._workers[w] = (lo, hi)
        for i, a in enumerate(a for a in continuous if a.columns is None):
            spec(a, i % pool.size)
        self._take = pool.new_take()
        for w, part in specs.items():
            pool.send(w, ("take", self._take, self.order, self.window, part))
        self._pool = pool

    def push(self, path: str, t: float, value: object) -> None:
        """Queue one sample of an armed attribute (never waits for the reducer).

        Raises :class:`SampleError` naming the path and the sample's index in the take
        for a non-finite time, a time not after the last, or a bad value; nothing is
        queued then, and what was recorded stays.
        """
        if not self.recording:
            raise ArgumentError("push", "not recording: call start() first")
        if path not in self.armed:
            raise ArgumentError("path", f"{path!r} is not armed")
        a = self.armed[path]
        framed = a.columns is not None
        last = a.times[-1] if a.times else -np.inf
        last = max(last, self._frames.last) if framed else last
        index = len(a.times) + (self._frames.n if framed else 0)
        t = self._time(t, last, index, path)
        try:
            value = a.type.check(value, path, bounded=a.mode != "additive")    # offsets are not values
        except ArgumentError as err:
            raise SampleError(str(err), index=index, field=path) from None
        if a.type.continuous and not a.type.is_rotation and a.values:
            _in_range(value, a.values[0], np.full(len(value), a.tol), index, path)
        if framed:
            self._single_last = max(self._single_last, t)
        a.times.append(t)
        a.values.append(value)
        if a.worker is not None:
            self._pool.send(a.worker, ("sample", self._take, time.perf_counter(), path, np.array([t]),
                                       value[None, :]))

    def check_frame(self, t: float, values: ArrayLike) -> tuple[float, np.ndarray]:
        """The frame :meth:`push_frame` would queue at ``t`` (the time as a float, the
        values as a row), checked as it checks them, without queueing it: a
        :class:`~sketchanim.errors.SampleError` naming the field otherwise.

        >>> from sketchanim.anim.scene import Scene
        >>> scene = Scene(); _ = scene.add("box")
        >>> rec = Recorder(scene); rec.arm("box.position"); rec.start()
        >>> rec.check_frame(0.0, [1, 2, float("nan")])
        Traceback (most recent call last):
        ...
        sketchanim.errors.SampleError: sample 0, frame: needs 3 finite numbers, got 3: [1.0, 2.0, nan]
        >>> _ = rec.stop()
        """
        if not self.recording:
            raise ArgumentError("push", "not recording: call start() first")
        frames = self._frames
        t = self._time(t, max(frames.last, self._single_last), frames.n, "frame")
        try:
            x = np.asarray(values, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise SampleError(f"not numbers: {values!r}", index=frames.n, field="frame") from None
        if x.shape != (frames.x.shape[1],) or not np.all(np.isfinite(x)):
            raise SampleError(f"needs {frames.x.shape[1]} finite numbers, got {x.size}: {x.tolist()}",
                              index=frames.n, field="frame")
        if frames.n:
            _in_range(x, frames.x[0], self._range_tol, frames.n, "frame")
        out = np.flatnonzero((x < self._low) | (x > self._high))
        if len(out):
            bad = next(p for p, a, b in self._frame if a <= out[0] < b)
            raise SampleError(f"value {float(x[out[0]])!r} is outside the bounds [{self._low[out[0]]}, "
                              f"{self._high[out[0]]}] of {bad}", index=frames.n, field=bad)
        if len(self._rotations):
            norms = np.linalg.norm(x[self._rotations], axis=1)
            if norms.min() < MIN_NORM:
                bad = self._frame[int(np.flatnonzero(self._is_rotation)[np.argmin(norms)])][0]
                raise SampleError(f"a zero quaternion is no orientation (norm {norms.min():.3g})",
                                  index=frames.n, field=bad)
        return t, x

    def push_frame(self, t: float, values: ArrayLike) -> None:
        """Queue one frame of every armed continuous attribute at time ``t``: their
        values end to end, as :attr:`layout` says (a device's frame, one call), checked
        first (:meth:`check_frame`)."""
        t, x = self.check_frame(t, values)
        self._frames.append(t, x)
        stamp, times = time.perf_counter(), np.array([t])
        for w, (lo, hi) in ((w, c) for w, c in self._workers.items() if c is not None):
            self._pool.send(w, ("frames", self._take, stamp, times, x[None, lo:hi]))

    def pieces(self) -> list[tuple[str, Piece]]:
        """The pieces of curve the reducer processes finished since the last call, as
        (path, piece), during a take (never waits): a take over a track gives pieces of
        its targets (the take faded onto the track, :class:`.layers.Overlay`)."""
        return self._pool.pieces(self._take) if self.recording else []

    @staticmethod
    def _time(t: float, last: float, index: int, where: str) -> float:
        try:
            t = float(t)
        except (TypeError, ValueError):
            raise SampleError(f"time {t!r} is not a number", index=index, field=f"{where} time") from None
        if not np.isfinite(t) or t <= last or abs(t) > TIME_RANGE:
            raise SampleError(f"time {t!r} must be finite and after {last!r}", index=index, field=f"{where} time")
        return t

    def _samples(self, a: _Armed, first: tuple[int, int] = (0, 0)) -> tuple[np.ndarray, object, tuple[int, int]]:
        """The samples of ``a`` queued so far, in time order, from frame ``first[0]`` and
        single push ``first[1]`` on: times, values (n, dim) or a list (discrete), and
        where the next call should start (safe while the caller pushes)."""
        n, m = self._frames.n if a.columns is not None else 0, len(a.values)     # values go in last
        ft, fx = self._frames.t, self._frames.x          # read after n: they hold the first n
        times, values = a.times[first[1] : m], a.values[first[1] : m]
        if not a.type.continuous:
            return np.array(times, dtype=float), values, (n, m)
        t = np.array(times, dtype=float)
        x = np.array(values, dtype=float).reshape(-1, a.type.dim)
        if n > first[0]:
            lo, hi = a.columns
            framed = ft[first[0] : n], fx[first[0] : n, lo:hi]        # views: one copy for all
            if not len(times):
                return *framed, (n, m)
            t, x = np.r_[framed[0], t], np.vstack([framed[1], x])
            order = np.argsort(t, kind="stable")
            t, x = t[order], x[order]
        return t, x, (n, m)

    def _journal_loop(self) -> None:
        """Hand the journal what was queued since the last call, until stopped; a batch
        the journal refuses is tried again at the next call (with what came since), and
        :attr:`journal_error` says why until one goes through."""
        sent = {path: (0, 0) for path in self.armed}
        while True:
            stopping = self._stopping.wait(JOURNAL_PERIOD)
            batches, upto = [], dict(sent)
            for a in self.armed.values():
                t, x, upto[a.path] = self._samples(a, sent[a.path])
                if len(t):
                    batches.append((a.path, t, x))
            if batches:
                try:
                    self.journal(batches)
                except Exception as err:            # the take goes on; stop() warns if it never recovered
                    self._journal_error = err
                else:
                    sent, self._journal_error = upto, None
            if stopping:
                return

    @property
    def journal_error(self) -> BaseException | None:
        """Why the journal refused the last batch (None: what was pushed is journalled, or
        is about to be): samples since then are safe from a crash only when it recovers."""
        return self._journal_error

    def stop(self, *, at: tuple[float, float] | None = None) -> dict[str, Track]:
        """End the take: the new tracks of the armed attributes that got samples (two
        or more for a continuous one).

        ``at`` is the span of the take for discrete attributes (events recorded over it
        replace those there); by default from their first to their last sample.
        """
        if not self.recording:
            raise ArgumentError("stop", "not recording")
        pool, self._pool = self._pool, None
        for w in self._workers:
            pool.send(w, ("stop", self._take))
        self._stopping.set()
        raw = {}                                    # made while the reducer processes finish
        for a in self.armed.values():
            times, values, _ = self._samples(a)
            if len(times) >= (2 if a.type.continuous else 1):     # one sample is no curve: left as it was
                raw[a.path] = (Take(times, values, a.mode, a.blend, a.smoothing) if a.type.continuous
                               else (times, values))
        if self._journaling is not None:
            self._journaling.join()
            self._journaling = None
        results = pool.results(self._take, len(self._workers))
        curves = {}
        for r in results:
            self.lags += r.lags
            self.busy.append(r.busy)
            if r.error is not None:
                warnings.warn(f"reducer process {r.worker} failed; reducing its attributes from the raw take:\n"
                              f"{r.error}", RuntimeWarning, stacklevel=2)
            curves.update(r.curves)
        if len(results) < len(self._workers):
            warnings.warn("a reducer process died; reducing its attributes from the raw take", RuntimeWarning,
                          stacklevel=2)
        if self._journal_error is not None:
            warnings.warn(f"the journal failed during the take ({self._journal_error!r}); the take is not "
                          "safe from a crash until saved", RuntimeWarning, stacklevel=2)
        return {path: self._track(self.armed[path], take, curves.get(path), at) for path, take in raw.items()}

    def _track(self, a: _Armed, take: Take | tuple[np.ndarray, list], curve: tuple | None,
               at: tuple[float, float] | None) -> Track:
        old = self._over.get(a.path)
        if not isinstance(take, Take):
            times, values = take
            lo, hi = at if at is not None else (times[0], times[-1])
            before = old if isinstance(old, DiscreteTrack) else DiscreteTrack(a.path, a.type)
            keep = [(t, v) for t, v in zip(before.times, before.values) if not lo <= t <= hi]
            merged = sorted(keep + list(zip(times.tolist(), values)), key=lambda p: p[0])
            return DiscreteTrack(a.path, a.type, [p[0] for p in merged], [p[1] for p in merged])
        below = old if isinstance(old, ContinuousTrack) else None
        return recorded_over(a.path, a.type, below, take, a.tol, self.order, curve)
