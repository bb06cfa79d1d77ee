"""The recorder's reducer processes: streaming reduction beside the performance.

The caller's process only checks and queues samples. One streaming reducer per armed
attribute runs in a pool of worker processes (one per core, shared by every recorder of
the program, started on first use), so the reduction never holds the caller's
interpreter lock and the attributes of a take are reduced in parallel. The workers are
forked, so that a script without a ``__main__`` guard is not run again in them; they
load the reducer's compiled kernels before the first take.

Each worker owns some attributes of a take (a :class:`Spec` each) and reads messages from
its own queue, in order:

* ``("take", take, order, window, specs)``: new streams for a take;
* ``("frames", take, stamp, times, values)``: frames of the worker's columns, ``(n,)``
  and ``(n, width)``; ``stamp`` is when the caller queued the first
  (:func:`time.perf_counter`, the same clock in every process);
* ``("sample", take, stamp, path, times, values)``: samples of one attribute;
* ``("stop", take)``: finish the take's streams and send back a :class:`Result`;
* ``None``: exit.

While a take goes on, each piece of curve a stream finishes is sent back as
``("piece", take, path, knots, coef)`` (:meth:`Pool.pieces` hands them out), so a
client can draw the curve growing.

A worker takes everything queued at once and feeds each stream one batch, in time
order: the further behind it is, the bigger the batch and the cheaper each sample, so it
catches up instead of falling further behind.
"""

from __future__ import annotations

import itertools
import multiprocessing
import os
import queue
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.layers import Overlay
from sketchanim.anim.smoothed import SampleSmoother
from sketchanim.motion.rotations import RotationStream
from sketchanim.reducer import StreamReducer
from sketchanim.reducer.stream import Piece

#: Seconds a worker lets samples gather before it feeds them (about 4 frames at 120 Hz).
GATHER = 0.03
#: How much lower the workers' scheduling priority is than the caller's.
NICE = 5


@dataclass(frozen=True)
class Spec:
    """One attribute a worker reduces during a take.

    Attributes
    ----------
    path : str
    type : AttributeType
    tol : float
        In the attribute's unit (degrees for an orientation).
    columns : (int, int) or None
        Where its values are in the worker's part of a frame, if it is framed.
    over : (BSpline or None, str, float) or None
        For a take recorded over a track or added onto one: the track's curve, the
        take's mode and blend; the worker then reduces the take's targets
        (:class:`~sketchanim.anim.layers.Overlay`).
    smoothing : float
        Seconds its samples are smoothed over before all that
        (:class:`~sketchanim.anim.smoothed.SampleSmoother`; 0: not smoothed).
    """

    path: str
    type: AttributeType
    tol: float
    columns: tuple[int, int] | None = None
    over: tuple[BSpline | None, str, float] | None = None
    smoothing: float = 0.0


@dataclass
class Result:
    """What a worker sends back for a take.

    Attributes
    ----------
    take, worker : int
    curves : dict
        path -> (spline, seams): the finished curve (coefficients (m, dim)), and for a
        take over a track the :attr:`~sketchanim.anim.layers.Overlay.seams` it assumed
        (else None).
    lags : list of (float, int)
        For each batch it took: seconds since the caller queued its first sample, and
        how many samples it held.
    busy : float
        Seconds the worker spent on the take.
    error : str or None
        The traceback, if the worker failed on this take (``curves`` is then empty).
    """

    take: int
    worker: int
    curves: dict[str, tuple[BSpline, tuple[bool, bool] | None]] = field(default_factory=dict)
    lags: list[tuple[float, int]] = field(default_factory=list)
    busy: float = 0.0
    error: str | None = None


class _Shard:
    """A worker's part of one take: its streams and the messages not yet fed. A failure
    is kept in the result (the caller then reduces those attributes from the raw take)."""

    def __init__(self, outbox: multiprocessing.Queue, take: int, worker: int, order: int, window: int,
                 specs: list[Spec]) -> None:
        self.result = Result(take, worker)
        self.framed = [s for s in specs if s.columns is not None]
        self.streams: dict[str, StreamReducer | RotationStream] = {}
        self.overlays = {s.path: Overlay(s.type, *s.over) for s in specs if s.over is not None}
        self.smoothers = {s.path: SampleSmoother(s.type, s.smoothing) for s in specs if s.smoothing > 0}
        self.pending: list[tuple] = []
        self.fed: set[str] = set()                      # streams that got samples
        def sender(path: str) -> Callable[[Piece], None]:
            return lambda piece: outbox.put(("piece", take, path, piece.knots, piece.coef))

        self._guarded(lambda: self.streams.update({
            s.path: RotationStream(s.tol, order=order, window=window, on_piece=sender(s.path)) if s.type.is_rotation
            else StreamReducer(s.type.dim, s.tol, order=order, window=window, on_piece=sender(s.path),
                               bounds=s.type.bounds)
            for s in specs
        }))

    def _guarded(self, work: Callable[[], object]) -> None:
        if self.result.error is None:
            clock = time.perf_counter()
            try:
                work()
            except Exception:
                self.result.error = traceback.format_exc()
                self.result.curves.clear()
            self.result.busy += time.perf_counter() - clock

    def feed(self) -> None:
        """Feed the pending messages, one batch per stream, in time order."""
        if self.pending:
            self._guarded(self._feed)
            self.pending.clear()

    def _feed(self) -> None:
        parts: dict[str, tuple[list, list]] = {}
        frames: list[tuple] = []

        def flush() -> None:
            if frames:
                t = np.concatenate([f[0] for f in frames])
                x = np.vstack([f[1] for f in frames])
                for s in self.framed:
                    ts, xs = parts.setdefault(s.path, ([], []))
                    ts.append(t)
                    xs.append(x[:, s.columns[0] : s.columns[1]])
                frames.clear()

        samples = 0
        for message in self.pending:
            if message[0] == "frames":
                frames.append(message[3:])
                samples += len(message[3]) * len(self.framed)
            else:
                flush()
                ts, xs = parts.setdefault(message[3], ([], []))
                ts.append(message[4])
                xs.append(message[5])
                samples += len(message[4])
        flush()
        self.result.lags.append((time.perf_counter() - self.pending[0][2], samples))
        for path, (ts, xs) in parts.items():
            t, x = (ts[0], xs[0]) if len(ts) == 1 else (np.concatenate(ts), np.vstack(xs))
            if path in self.smoothers:
                t, x = self.smoothers[path].push(t, x)
            self._extend(path, t, x)
            self.fed.add(path)

    def _extend(self, path: str, t: np.ndarray, x: np.ndarray) -> None:
        """Feed samples (smoothed, if so) to the path's stream, as targets if overlaid."""
        if len(t) and path in self.overlays:
            t, x = self.overlays[path].push(t, x)
        if len(t):
            self.streams[path].extend(t, x)

    def finish(self) -> Result:
        """Feed what is pending and finish every stream that got two samples or more (one
        sample is no curve: the recorder leaves that attribute as it was)."""
        self.feed()

        def finish_all() -> None:
            for path in self.fed:
                if path in self.smoothers:
                    self._extend(path, *self.smoothers[path].close())
                over = self.overlays.get(path)
                if over is not None:
                    t, x = over.close()
                    if len(t):
                        self.streams[path].extend(t, x)
                if self.streams[path].taken < 2:
                    continue
                self.result.curves[path] = (self.streams[path].finish().columns,
                                             None if over is None else over.seams)

        self._guarded(finish_all)
        return self.result


def _warm() -> None:
    """Load the reducer's compiled kernels before the first take needs them."""
    t = np.linspace(0.0, 1.0, 121)
    for stream, x in ((StreamReducer(1, 1e-3), np.c_[np.sin(5 * t)]),
                      (RotationStream(0.5), np.c_[np.sin(t / 2), 0 * t, 0 * t, np.cos(t / 2)])):
        stream.extend(t, x)
        stream.finish()


def _gather(inbox: multiprocessing.Queue, first: object) -> list:
    """``first`` and what follows it: samples wait until the oldest is :data:`GATHER`
    seconds old (fewer, bigger batches cost less per sample), anything else is taken at
    once, with whatever is queued."""
    batch = [first]
    deadline = first[2] + GATHER if first is not None and first[0] in ("frames", "sample") else 0.0
    while True:
        remaining = deadline - time.perf_counter()
        try:
            message = inbox.get(timeout=remaining) if remaining > 0 else inbox.get_nowait()
        except queue.Empty:
            return batch
        batch.append(message)
        if message is None or message[0] not in ("frames", "sample"):
            deadline = 0.0


def _serve(worker: int, inbox: multiprocessing.Queue, outbox: multiprocessing.Queue) -> None:
    """A worker's loop (see the module's description); exits on None, or when the
    process that started it is gone. It runs at a lower priority than the caller: the
    performer's side comes first, the reduction takes the time left over."""
    os.nice(NICE)
    _warm()
    shards: dict[int, _Shard] = {}
    parent = multiprocessing.parent_process()
    while True:
        try:
            batch = _gather(inbox, inbox.get(timeout=1.0))
        except queue.Empty:
            if parent is not None and not parent.is_alive():
                return
            continue
        for message in batch:
            if message is None:
                return
            kind, take = message[0], message[1]
            if kind == "take":
                shards[take] = _Shard(outbox, take, worker, *message[2:])
            elif kind == "stop":
                outbox.put(shards.pop(take).finish())
            else:
                shards[take].pending.append(message)
        for shard in shards.values():
            shard.feed()


class Pool:
    """Worker processes and their queues.

    Examples
    --------
    >>> pool = shared_pool()
    >>> pool.size >= 1
    True
    """

    def __init__(self, size: int) -> None:
        # Forked, so that a script without a ``__main__`` guard is not run again in them.
        ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
        self.size = size
        self.inboxes = [ctx.Queue() for _ in range(size)]
        self.outbox = ctx.Queue()
        self.processes = [ctx.Process(target=_serve, args=(i, q, self.outbox), name=f"sketchanim-reducer-{i}",
                                      daemon=True) for i, q in enumerate(self.inboxes)]
        for p in self.processes:
            p.start()
        self.pid = os.getpid()
        self._takes = itertools.count()
        self._lock = threading.Lock()
        self._arrived: dict[int, list[Result]] = {}
        self._pieces: dict[int, list[tuple[str, Piece]]] = {}

    def new_take(self) -> int:
        """A number for a take, unique in this pool."""
        return next(self._takes)

    def send(self, worker: int, message: tuple) -> None:
        """Queue a message for ``worker`` (never waits for it)."""
        self.inboxes[worker].put(message)

    @property
    def alive(self) -> bool:
        return all(p.is_alive() for p in self.processes)

    def _sort(self, item: Result | tuple) -> None:
        """Keep a result or a piece that came back for the take it belongs to."""
        if isinstance(item, Result):
            self._arrived.setdefault(item.take, []).append(item)
        else:
            self._pieces.setdefault(item[1], []).append((item[2], Piece(item[3], item[4])))

    def pieces(self, take: int) -> list[tuple[str, Piece]]:
        """The (path, piece) of ``take`` finished since the last call (never waits)."""
        with self._lock:
            while True:
                try:
                    self._sort(self.outbox.get_nowait())
                except queue.Empty:
                    return self._pieces.pop(take, [])

    def results(self, take: int, count: int) -> list[Result]:
        """Wait for the ``count`` results of ``take``; fewer if a worker died. Its pieces
        not yet handed out are dropped."""
        with self._lock:
            while len(self._arrived.get(take, [])) < count:
                try:
                    self._sort(self.outbox.get(timeout=0.1))
                except queue.Empty:
                    if not self.alive:
                        break
            self._pieces.pop(take, None)
            return self._arrived.pop(take, [])

    def close(self) -> None:
        """Stop the workers."""
        for q in self.inboxes:
            q.put(None)
        for p in self.processes:
            p.join(timeout=5)
            if p.is_alive():
                p.terminate()


_pool: Pool | None = None
_pool_lock = threading.Lock()


def shared_pool() -> Pool:
    """The program's pool, one worker per core this process may use, started on first
    use (again if a worker died, or in a process forked from the one that started it)."""
    global _pool
    with _pool_lock:
        if _pool is None or _pool.pid != os.getpid() or not _pool.alive:
            if _pool is not None and _pool.pid == os.getpid():
                _pool.close()
            _pool = Pool(max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else
                             os.cpu_count() or 1))
        return _pool
