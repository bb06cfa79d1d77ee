"""A sample table reduced while it is read: chunks of rows from
:func:`~sketchanim.formats.tables.stream_table`, their quirks resolved
(:class:`~sketchanim.formats.quirks.Resolver`), each channel group and the rotation fed
to its own :class:`~sketchanim.reducer.StreamReducer`, so memory stays that of a chunk
and of the curves, however many rows.

What comes out is what :func:`sketchanim.reduce` with ``method="incremental"`` makes of
the whole table: exact duplicates dropped, the take cut at its jumps (found with the
look-ahead of one sample that :func:`~sketchanim.reducer.gaps.find_jumps` needs), each
run between them streamed on its own and the runs bridged
(:func:`~sketchanim.reducer.gaps.reduce_across`). The stream keeps the tolerance at every
sample and the no-swing rule itself, so the whole-take checks that
:func:`sketchanim.reduce` runs afterwards find nothing to change; the largest error is
the streams' own, measured at every sample.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field, replace
from itertools import chain

import numpy as np
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from sketchanim.errors import ArgumentError, InputError, SampleError
from sketchanim.formats.csvio import CHUNK_ROWS, SampleTable
from sketchanim.formats.quirks import Resolver
from sketchanim.formats.tables import TableStream
from sketchanim.motion import continuous_quaternions, euler_angles
from sketchanim.pipeline.table_options import TableOptions
from sketchanim.reducer import Reduction, StreamReducer
from sketchanim.reducer.features import Feature
from sketchanim.reducer.gaps import find_jumps, reduce_across
from sketchanim.reducer.swing import local_ranges


@dataclass
class _Run:
    """The samples between two cuts: their stream while they come, then its curve."""

    first: tuple[float, np.ndarray]
    stream: StreamReducer | None
    n: int = 0
    end: float = 0.0
    reduced: Reduction | None = None


@dataclass
class _Cut:
    """An interval cut at a jump: its ends and the range its bridge stays in."""

    start: float
    end: float
    lo: np.ndarray
    hi: np.ndarray


@dataclass
class ChannelStream:
    """:func:`sketchanim.reduce` (``method="incremental"``) of samples given a chunk at a
    time; a sample the reducer refuses is an :class:`~sketchanim.errors.InputError`
    naming ``source`` and the sample's line.

    Examples
    --------
    >>> t = np.linspace(0, 4, 2000); x = np.c_[np.sin(t), (t > 2) * 1.0]
    >>> s = ChannelStream(2, np.array([1e-3, 1e-3]), TableOptions(tol=1e-3, method="incremental"))
    >>> for a in range(0, 2000, 300):
    ...     s.extend(t[a : a + 300], x[a : a + 300], 1 + a)
    >>> r = s.finish()
    >>> [f.kind for f in r.features], bool(np.all(r.max_error <= 1e-3))
    (['jump'], True)
    """

    dim: int
    tol: np.ndarray
    options: TableOptions
    angle: float = 0.0
    source: str = "samples"
    duplicates: int = 0
    n: int = 0
    _context: tuple[np.ndarray, np.ndarray] = field(init=False)   # the last 2 samples fed
    _pending: tuple[np.ndarray, np.ndarray, np.ndarray] = field(init=False)   # fed with the next chunk
    _runs: list[_Run] = field(default_factory=list)
    _cuts: list[_Cut] = field(default_factory=list)
    _clock: float = 0.0

    def __post_init__(self) -> None:
        self._context = (np.zeros(0), np.zeros((0, self.dim)))
        self._pending = (np.zeros(0), np.zeros((0, self.dim)), np.zeros(0, dtype=np.int64))
        self._widen = np.full(self.dim, 2 * np.sin(self.angle / 4)) if self.angle else self.tol

    def extend(self, times: np.ndarray, values: np.ndarray, lines: np.ndarray | int) -> None:
        """Add the next samples (in time order, shape (m,) and (m, dim)) and their lines."""
        clock = time.perf_counter()
        lines = np.arange(lines, lines + len(times)) if isinstance(lines, (int, np.integer)) else np.asarray(lines)
        t, x, where = self._pending
        t, x, where = np.r_[t, times], np.r_[x, values], np.r_[where, lines]
        keep = np.ones(len(t), dtype=bool)
        before_t, before_x = self._context
        prev_t = np.r_[before_t[-1:], t[:-1]]
        prev_x = np.r_[before_x[-1:], x[:-1]]
        keep[len(t) - len(prev_t):] = ~((t[len(t) - len(prev_t):] == prev_t)
                                        & np.all(x[len(t) - len(prev_t):] == prev_x, axis=1))
        self.duplicates += int(len(t) - np.count_nonzero(keep))
        self._feed(t[keep], x[keep], where[keep], final=False)
        self._clock += time.perf_counter() - clock

    def _feed(self, t: np.ndarray, x: np.ndarray, where: np.ndarray, final: bool) -> None:
        """Judge the intervals whose neighbours are known, feed the samples after them
        to the runs, and keep the last sample back (unless ``final``)."""
        ct, cx = self._context
        wt, wx = np.r_[ct, t], np.r_[cx, x]
        c = len(ct)
        stop = len(wt) if final else len(wt) - 1                  # samples fed now: wt[c:stop]
        if stop <= c:
            self._pending = (t, x, where)
            return
        starts = np.zeros(0, dtype=int)
        if self.options.features.jumps:
            judged = find_jumps(wx, self.tol, wt)
            starts = judged[(judged >= max(c - 1, 0)) & (judged < stop - 1)] + 1
        edges = np.r_[c, starts, stop]
        for k, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
            if k > 0 or not self._runs:                           # a run starts at ``a``
                if self._runs:
                    self._end_run(wt, wx, a - 1)
                o = self.options
                self._runs.append(_Run((float(wt[a]), wx[a].copy()), StreamReducer(
                    self.dim, self.tol, order=o.order, window=o.window, features=o.features, angle=self.angle or None,
                    grow=True)))
            run = self._runs[-1]
            stream = run.stream
            if a == b or stream is None:
                continue
            pushed = stream.pushed
            try:
                stream.extend(wt[a:b], wx[a:b])
            except SampleError as err:
                index = (err.index if err.index is not None else pushed) - pushed
                raise InputError(f"{self.source}, line {int(where[a - c + index])}: {err}") from None
            run.n += b - a
            run.end = float(wt[b - 1])
        self.n += stop - c
        self._context = (wt[max(stop - 2, 0) : stop], wx[max(stop - 2, 0) : stop])
        self._pending = (wt[stop:], wx[stop:], where[stop - c :])

    def _end_run(self, wt: np.ndarray, wx: np.ndarray, i: int) -> None:
        """End the last run at the jump over interval ``i`` of ``wt``: its curve, and the
        range the bridge over the interval stays in."""
        self._close(self._runs[-1])
        lo, hi = local_ranges(wx[max(i - 1, 0) : i + 3], self._widen)
        row = i - max(i - 1, 0)
        self._cuts.append(_Cut(float(wt[i]), float(wt[i + 1]), lo[row], hi[row]))

    @staticmethod
    def _close(run: _Run) -> None:
        """A run's curve (none for one sample); its stream is let go."""
        if run.n > 1 and run.stream is not None:
            run.reduced = run.stream.finish()
        run.stream = None

    def finish(self) -> Reduction:
        """The curve of every sample given (as :func:`sketchanim.reduce` returns it;
        :func:`sketchanim.reduce` would check ``max_error`` against ``tol`` and keep the
        interpolant where rounding broke it: the caller does)."""
        clock = time.perf_counter()
        t, x, where = self._pending
        self._pending = (np.zeros(0), np.zeros((0, self.dim)), np.zeros(0, dtype=np.int64))
        self._feed(t, x, where, final=True)
        if self.n < 2:
            raise SampleError(f"{self.n} distinct samples, at least 2 needed", field="times")
        self._close(self._runs[-1])
        parts: dict[tuple[float, float], tuple[BSpline, tuple[Feature, ...]]] = {}
        report: dict[str, object] = {"duplicates_dropped": self.duplicates}
        error = np.zeros(1 if self.angle else self.dim)
        for run in self._runs:
            if run.reduced is not None:
                report.update((k, v) for k, v in run.reduced.report.items() if k != "duplicates_dropped")
                parts[(run.first[0], run.end)] = (run.reduced.columns, run.reduced.features)
                error = np.maximum(error, run.reduced.max_error)
        if not self._cuts:
            spline, found = parts[(self._runs[0].first[0], self._runs[0].end)]
            features = list(found)
        else:
            spline, features = self._bridged(parts)
            report["jumps"] = len(self._cuts)
        bound = np.array([self.angle]) if self.angle else self.tol
        return Reduction(spline=spline, tol=bound, max_error=error, n_samples=self.n, method="incremental",
                         timings={"total": self._clock + time.perf_counter() - clock}, report=report,
                         metric="rotation" if self.angle else "channels", features=tuple(features))

    def _bridged(self, parts: dict[tuple[float, float], tuple[BSpline, tuple[Feature, ...]]]
                 ) -> tuple[BSpline, list[Feature]]:
        """The runs joined over the cuts by :func:`reduce_across`, given the runs' ends
        only (what it reads of the samples there): two samples a run, one for a run of one."""
        times, values, cuts = [], [], []
        lo = []
        hi = []
        inside = (np.full(self.dim, -np.inf), np.full(self.dim, np.inf))
        for k, run in enumerate(self._runs):
            times.append(run.first[0])
            values.append(run.first[1])
            if run.n > 1:
                times.append(run.end)
                values.append(run.first[1])                      # not read: the run's curve gives its ends
                lo.append(inside[0])
                hi.append(inside[1])
            if k < len(self._cuts):
                cuts.append(len(times) - 1)
                lo.append(self._cuts[k].lo)
                hi.append(self._cuts[k].hi)
        cut = np.asarray(cuts, dtype=int)
        return reduce_across(np.asarray(times), np.asarray(values), cut, self.options.order,
                             lambda t, x: parts[(float(t[0]), float(t[-1]))], cut, np.asarray(lo), np.asarray(hi),
                             normalised=bool(self.angle))


def euler_quaternions(degrees: np.ndarray, seq: str) -> np.ndarray:
    """Scalar-last quaternions of Euler angles given in degrees, in ``seq`` order.

    >>> euler_quaternions(np.array([[90.0, 0.0, 0.0]]), "ZXY").round(4).tolist()
    [[0.0, 0.0, 0.7071, 0.7071]]
    """
    if not np.all(np.isfinite(degrees)):
        row = int(np.flatnonzero(~np.isfinite(degrees).all(axis=1))[0])
        raise SampleError("Euler angle is not finite", index=row, field="rot_cols")
    try:
        return Rotation.from_euler(seq, degrees, degrees=True).as_quat()
    except ValueError as err:
        raise ArgumentError("seq", f"{seq!r} is not an Euler sequence ({err})") from None


@dataclass
class _RotationStream:
    """The rotation columns of a table read in chunks, made a curve as
    :func:`~sketchanim.motion.reduce_rotations` makes it of the whole column."""

    columns: list[int]
    options: TableOptions
    source: str
    _last: np.ndarray | None = None

    def __post_init__(self) -> None:
        o = self.options
        angle = float(np.radians(o.rot_tol_deg))
        self.quaternion = len(self.columns) == 4
        self.scalar_first = o.scalar_first and self.quaternion and o.rot_cols is not None
        self.euler = o.rot_mode == "euler"
        self.stream = ChannelStream(3, np.full(3, angle), o, source=self.source) if self.euler else \
            ChannelStream(4, np.full(4, np.sin(angle / 2)), o, angle=angle, source=self.source)

    def extend(self, table: SampleTable) -> None:
        values = table.values[:, self.columns]
        try:
            q = values if self.quaternion else euler_quaternions(values, self.options.seq)
            values = euler_angles(q, self.options.seq, scalar_first=self.scalar_first, previous=self._last) \
                if self.euler else continuous_quaternions(q, previous=self._last)
        except SampleError as err:
            raise InputError(f"{self.source}, {table.where(err.index or 0)}: {err}") from None
        if len(values):
            self._last = values[-1].copy()
        self.stream.extend(table.times, values, table.lines)

    def finish(self) -> Reduction:
        r = self.stream.finish()
        o = self.options
        r.report.update(mode=o.rot_mode, **({"seq": o.seq} if self.euler else {"scalar_first": self.scalar_first}))
        return r


@dataclass(frozen=True)
class Streamed:
    """What :func:`reduce_streamed` made of a table.

    Attributes
    ----------
    reductions : tuple of Reduction
        One per channel group.
    rotation : Reduction or None
    rows : int
        Samples reduced (after the quirks were resolved).
    span : (float, float)
        The first and the last sample's time.
    moved, merged_away : int
        As :class:`~sketchanim.formats.quirks.Resolver` counts them.
    """

    reductions: tuple[Reduction, ...]
    rotation: Reduction | None
    rows: int
    span: tuple[float, float]
    moved: int
    merged_away: int

    @property
    def within(self) -> bool:
        """Whether every curve keeps its tolerance at every sample."""
        return all(bool(np.all(r.max_error <= r.tol)) for r in self.reductions + ((self.rotation,) if self.rotation
                                                                                   else ()))


def sliced(blocks: Iterable[SampleTable], rows: int) -> Iterator[SampleTable]:
    """The rows of ``blocks``, in blocks of at most ``rows`` (views, not copies).

    >>> b = SampleTable(np.arange(5.0), np.zeros((5, 1)), ["x"], 2)
    >>> [(s.times.tolist(), s.lines) for s in sliced([b], 2)]
    [([0.0, 1.0], 2), ([2.0, 3.0], 4), ([4.0], 6)]
    """
    for block in blocks:
        n = len(block.times)
        if n <= rows:
            yield block
            continue
        step = isinstance(block.lines, (int, np.integer))
        for a in range(0, n, rows):
            yield replace(block, times=block.times[a : a + rows], values=block.values[a : a + rows],
                          lines=int(block.lines) + a if step else block.lines[a : a + rows])


def reduce_streamed(stream: TableStream, options: TableOptions, source: str, parts: list[list[int]],
                    tols: list[np.ndarray], rot: list[int], *, chunk_rows: int | None = None) -> Streamed:
    """Reduce a table read in chunks: each channel group ``parts`` (column indices) at
    its tolerances ``tols``, and the rotation columns ``rot``, as
    :func:`~sketchanim.pipeline.reduce_table` reduces the whole table with
    ``method="incremental"``.

    Blocks longer than ``chunk_rows`` (default :data:`CHUNK_ROWS`, the reader's chunk)
    are taken ``chunk_rows`` rows at a time: what the reduction allocates is in proportion
    to the rows it takes at once (the quirks' and the jumps' passes, the feature
    detector's look-ahead store, which keeps the size of the largest batch), so memory is
    bounded by ``chunk_rows`` and the curves whatever blocks the source yields; the curves
    do not depend on the blocks' sizes.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from sketchanim.formats.tables import stream_table
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> t = np.linspace(0, 2, 500)
    >>> np.savetxt(p, np.c_[t, np.sin(t), np.cos(t)], delimiter=",", header="t,x,y", comments="")
    >>> o = TableOptions(tol=0.001, method="incremental")
    >>> r = reduce_streamed(stream_table(p, "csv", chunk_rows=64), o, str(p), [[0, 1]], [np.full(2, 1e-3)], [])
    >>> r.rows, r.span, r.within
    (500, (0.0, 2.0), True)
    """
    resolver = Resolver(options.unordered, options.duplicates, source)
    streams = [ChannelStream(len(part), tol, options, source=source) for part, tol in zip(parts, tols)]
    rotation = _RotationStream(rot, options, source) if rot else None
    rows = 0
    span = [np.nan, np.nan]
    for block in chain(sliced(stream.blocks, CHUNK_ROWS if chunk_rows is None else chunk_rows), [None]):
        table = resolver.push(block) if block is not None else resolver.flush()
        if table is None or not len(table.times):
            continue
        for part, channel in zip(parts, streams):
            channel.extend(table.times, table.values[:, part], table.lines)
        if rotation is not None:
            rotation.extend(table)
        rows += len(table.times)
        span = [table.times[0] if rows == len(table.times) else span[0], table.times[-1]]
    return Streamed(tuple(s.finish() for s in streams), rotation.finish() if rotation else None, rows,
                    (float(span[0]), float(span[1])), resolver.moved, resolver.merged_away)
