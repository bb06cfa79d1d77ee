"""The recorder: samples in from any source while the performer acts, tracks out.

Armed attributes take time-stamped samples from the caller (the studio, a device, a file
being replayed). The caller only checks and queues them; a worker thread drains the
queue in batches, feeds one streaming reducer per continuous attribute (orientations: a
quaternion stream with an angular tolerance) and keeps the raw samples of the take. The
bigger the backlog, the bigger the batch, so the worker catches up instead of falling
further behind. When the take stops, each streamed curve needs only its last windows
finished; a take recorded over an existing track is punched in (:mod:`.layers`).
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from sketchanim.anim.layers import punch_in
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import BLEND, MODES, ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.errors import ArgumentError, SampleError
from sketchanim.motion.rotations import MIN_NORM, RotationStream
from sketchanim.reducer import StreamReducer

#: Called from the worker with each batch taken: path, times (n,), values (n, dim) or
#: a list of discrete values.
Journal = Callable[[str, np.ndarray, object], None]


@dataclass
class _Armed:
    """One armed attribute's state during a take."""

    path: str
    tol: float
    mode: str
    blend: float
    stream: StreamReducer | RotationStream | None = None
    times: list[np.ndarray] = field(default_factory=list)
    values: list = field(default_factory=list)
    last: float = -np.inf                           # the last time queued by push (caller side)
    queued: int = 0
    framed: bool = False                            # also fed by push_frame


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
        Called from the worker thread with every batch it takes (see :data:`Journal`),
        e.g. to commit them to a project file while the take goes on.

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

    def __init__(self, scene: Scene, *, order: int = 4, window: int = 20, journal: Journal | None = None) -> None:
        self.scene = scene
        self.order = order
        self.window = window
        self.journal = journal
        self.armed: dict[str, _Armed] = {}
        self._queue: deque[tuple[float, str | None, np.ndarray, object]] = deque()
        self._worker: threading.Thread | None = None
        self._stopping = threading.Event()
        self._error: BaseException | None = None
        self._frame: list[tuple[str, int, int]] = []
        self._width = 0
        self._rotations = np.zeros((0, 4), dtype=np.int64)   # frame columns of each orientation
        self._is_rotation = np.zeros(0, dtype=bool)
        self._frames = 0
        self._frame_last = -np.inf
        self._single_last = -np.inf                 # latest push() time on a framed attribute
        #: (seconds behind, samples) of each batch the worker took: how far it lagged
        self.lags: deque[tuple[float, int]] = deque(maxlen=100_000)

    # -- arming ----------------------------------------------------------------------------

    def arm(self, path: str, *, tol: float | None = None, mode: str = "replace", blend: float = BLEND) -> None:
        """Record ``path`` in the next take: a continuous one within ``tol`` (its type's
        default if None, in its unit), replacing or added onto its track (``mode``)."""
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
        self.armed[path] = _Armed(path, tol, mode, blend)

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
        for path in self.armed:
            kind = self.scene.type(path)
            if kind.continuous:
                layout.append((path, at, at + kind.dim))
                at += kind.dim
        return layout

    # -- a take ----------------------------------------------------------------------------

    @property
    def recording(self) -> bool:
        return self._worker is not None

    def start(self) -> None:
        """Start a take: fresh streams for every armed attribute and the worker."""
        if self.recording:
            raise ArgumentError("start", "already recording")
        if not self.armed:
            raise ArgumentError("start", "no attribute is armed")
        for a in self.armed.values():
            kind = self.scene.type(a.path)
            a.times, a.values, a.last, a.queued, a.framed = [], [], -np.inf, 0, False
            if kind.is_rotation:
                a.stream = RotationStream(a.tol, order=self.order, window=self.window, keep=True)
            elif kind.continuous:
                a.stream = StreamReducer(kind.dim, a.tol, order=self.order, window=self.window, keep=True)
        self._frame = self.layout
        self._width = self._frame[-1][2] if self._frame else 0
        self._is_rotation = np.array([self.scene.type(p).is_rotation for p, _, _ in self._frame], dtype=bool)
        self._rotations = np.array([np.arange(a, b) for (p, a, b), r in zip(self._frame, self._is_rotation) if r],
                                   dtype=np.int64).reshape(-1, 4)
        self._frames, self._frame_last, self._single_last = 0, -np.inf, -np.inf
        for path, _, _ in self._frame:
            self.armed[path].framed = True
        self._queue.clear()
        self.lags.clear()
        self._error = None
        self._stopping.clear()
        self._worker = threading.Thread(target=self._work, name="sketchanim-recorder", daemon=True)
        self._worker.start()

    def push(self, path: str, t: float, value: object) -> None:
        """Queue one sample of an armed attribute (never waits for the reducer).

        Raises :class:`SampleError` naming the path and the sample's index in the take
        for a non-finite time, a time not after the last, or a bad value; nothing is
        queued then, and what was recorded stays.
        """
        a = self._armed(path)
        last = max(a.last, self._frame_last) if a.framed else a.last
        t = self._time(t, last, a.queued, path)
        try:
            value = self.scene.type(path).check(value, path)
        except ArgumentError as err:
            raise SampleError(str(err), index=a.queued, field=path) from None
        a.last = t
        a.queued += 1
        if a.framed:
            self._single_last = max(self._single_last, t)
        self._queue.append((time.perf_counter(), path, np.array([t]), value))

    def push_frame(self, t: float, values: ArrayLike) -> None:
        """Queue one frame of every armed continuous attribute at time ``t``: their
        values end to end, as :attr:`layout` says (a device's frame, one call)."""
        if not self.recording:
            raise ArgumentError("push", "not recording: call start() first")
        t = self._time(t, max(self._frame_last, self._single_last), self._frames, "frame")
        try:
            x = np.asarray(values, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise SampleError(f"not numbers: {values!r}", index=self._frames, field="frame") from None
        if x.shape != (self._width,) or not np.all(np.isfinite(x)):
            raise SampleError(f"needs {self._width} finite numbers, got {x.size}: {x.tolist()}", index=self._frames,
                              field="frame")
        if len(self._rotations):
            norms = np.linalg.norm(x[self._rotations], axis=1)
            if norms.min() < MIN_NORM:
                bad = self._frame[int(np.flatnonzero(self._is_rotation)[np.argmin(norms)])][0]
                raise SampleError(f"a zero quaternion is no orientation (norm {norms.min():.3g})",
                                  index=self._frames, field=bad)
        self._frame_last = t
        self._frames += 1
        self._queue.append((time.perf_counter(), None, np.array([t]), x))

    def _armed(self, path: str) -> _Armed:
        if not self.recording:
            raise ArgumentError("push", "not recording: call start() first")
        if path not in self.armed:
            raise ArgumentError("path", f"{path!r} is not armed")
        return self.armed[path]

    @staticmethod
    def _time(t: float, last: float, index: int, where: str) -> float:
        t = float(t)
        if not np.isfinite(t) or t <= last:
            raise SampleError(f"time {t!r} must be finite and after {last!r}", index=index, field=f"{where} time")
        return t

    def _work(self) -> None:
        """The worker: drain, feed, repeat until stopped and drained."""
        try:
            while True:
                stopping = self._stopping.is_set()
                if not self._drain() and stopping:
                    return
                if not stopping:
                    time.sleep(0.002)
        except BaseException as err:        # handed to the caller by stop()
            self._error = err

    def _drain(self) -> bool:
        """Take everything queued, in one batch per attribute, in time order; False
        if the queue was empty."""
        n = len(self._queue)
        if not n:
            return False
        items = [self._queue.popleft() for _ in range(n)]
        self.lags.append((time.perf_counter() - items[0][0], n))
        parts: dict[str, tuple[list, list]] = {}
        frames: list[tuple[np.ndarray, np.ndarray]] = []

        def flush() -> None:
            if frames:
                t = np.concatenate([f[0] for f in frames])
                x = np.vstack([f[1] for f in frames])
                for path, a, b in self._frame:
                    ts, xs = parts.setdefault(path, ([], []))
                    ts.append(t)
                    xs.append(x[:, a:b])
                frames.clear()

        for _, path, t, value in items:
            if path is None:
                frames.append((t, value))
                continue
            flush()
            ts, xs = parts.setdefault(path, ([], []))
            ts.append(t)
            xs.append(value[None, :] if isinstance(value, np.ndarray) else [value])
        flush()
        for path, (ts, xs) in parts.items():
            a = self.armed[path]
            self._take(a, np.concatenate(ts), np.vstack(xs) if a.stream is not None else sum(xs, []))
        return True

    def _take(self, a: _Armed, t: np.ndarray, x: object) -> None:
        if a.stream is not None:
            a.stream.extend(t, x)
        a.times.append(t)
        a.values.append(x)
        if self.journal is not None:
            self.journal(a.path, t, x)

    def stop(self, tracks: Mapping[str, Track] | None = None, *,
             at: tuple[float, float] | None = None) -> dict[str, Track]:
        """End the take: the new tracks of the armed attributes that got samples,
        recorded over ``tracks`` (path -> track, e.g. a player's), which is not changed.

        ``at`` is the span of the take for discrete attributes (events recorded over it
        replace those there); by default from their first to their last sample.
        """
        if not self.recording:
            raise ArgumentError("stop", "not recording")
        self._stopping.set()
        self._worker.join()
        self._worker = None
        if self._error is not None:
            raise self._error
        made: dict[str, Track] = {}
        for a in self.armed.values():
            if not a.times:
                continue
            made[a.path] = self._track(a, (tracks or {}).get(a.path), at)
        return made

    def _track(self, a: _Armed, old: Track | None, at: tuple[float, float] | None) -> Track:
        kind = self.scene.type(a.path)
        times = np.concatenate(a.times)
        if not kind.continuous:
            values = [v for batch in a.values for v in batch]
            lo, hi = at if at is not None else (times[0], times[-1])
            before = old if isinstance(old, DiscreteTrack) else DiscreteTrack(a.path, kind)
            keep = [(t, v) for t, v in zip(before.times, before.values) if not lo <= t <= hi]
            merged = sorted(keep + list(zip(times.tolist(), values)), key=lambda p: p[0])
            return DiscreteTrack(a.path, kind, [p[0] for p in merged], [p[1] for p in merged])
        take = Take(times, np.vstack(a.values), a.mode, a.blend)
        if isinstance(old, ContinuousTrack):
            spline = punch_in(kind, old.spline, take, a.tol, self.order)
            return ContinuousTrack(a.path, kind, spline, a.tol, old.takes + (take,))
        if a.mode == "additive":
            spline = punch_in(kind, None, take, a.tol, self.order)
        else:
            spline = a.stream.finish().columns
        return ContinuousTrack(a.path, kind, spline, a.tol, (take,))
