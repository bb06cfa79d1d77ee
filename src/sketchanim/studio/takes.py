"""The take recorder: a take's lifecycle in the studio.

The page sends a take's samples in batches, stamped in the page with the transport
time; each row goes to the :class:`~sketchanim.anim.recorder.Recorder` as a frame, so the
curves are reduced while the take goes on and the samples stream into the project's
journal. A stall (no frame for ``gap`` seconds of real time: a tab in the background)
cuts the take: the part before is stopped and kept, the part after is recorded over the
result, so the curve never swings across the stall (it holds, or keeps the motion below,
and fades into the next part over ``blend``). The take ends as one History step
(:class:`~sketchanim.anim.commands.RecordTake`); the passes of a loop recording (the
same ``loop`` key) are recorded over what was there before the last pass and replace it,
as one step.

An attribute without a track still has a value (the scene's). A take of it that starts
later than the project (after ``min(0, the tracks' first time)``) would hold its first
sample before it; where that sample is further than the tolerance from the value (a
colour picked at 5.8 s), or the take is additive (its offsets go onto the value), the
take is recorded over the value as over a track (:func:`value_track`). Replacing, the
value holds until ``blend`` seconds before the take and eases (smoothstep) onto the
take's first sample, and the take joins it without a fade (its samples are kept as
performed); additive, the value holds and the offsets fade in over ``blend``. That
track is itself made of takes (the hold's two samples, the ease's samples), so the raw
takes still recompose the curve (:func:`~sketchanim.anim.layers.compose`).

A take's life, one state at a time (the studio's :class:`~.session.Session` drives it):

- *begun* (``take.begin``): armed, no sample yet; what it is recorded over is known at its
  first sample (the values it holds, above);
- *recording*: samples go to the current part; a refused sample changes nothing; a sample
  after a stall ends the part (kept in ``result``) and starts the next;
- *ended*, kept as one History step: by its page (``take.end``), its page gone (socket
  closed), silent (no message for :data:`SILENCE` seconds) or the server stopping;
- *cancelled* (``take.cancel``): nothing changes; the session removes the take's notes
  first (a journal without them is not recovered) and then its journal rows, so nothing of
  it comes back after a crash.

What the recorder warns of when a part stops (a reducer process died, the journal
failed) is logged and becomes a ``notice`` for every page.
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.commands import RecordTake
from sketchanim.anim.layers import recorded_over
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.tracks import ContinuousTrack, Take, Track
from sketchanim.errors import ArgumentError, InputError, SampleError
from sketchanim.project.journal import Journal
from sketchanim.reducer.metric import max_errors
from sketchanim.studio import protocol as p
from sketchanim.studio.editor import Editor
from sketchanim.studio.outbound import layout, piece_info
from sketchanim.studio.saving import write_fault

#: Spline order of recorded curves.
ORDER = 4
#: Seconds without a message from a take's page after which the take ends (kept): the
#: page is gone without closing its socket, or frozen. A page recording pings every second.
SILENCE = 5.0

log = logging.getLogger("sketchanim.studio")


@dataclass
class RunningTake:
    """The take in progress: its settings, what it is recorded over, and the parts
    recorded so far."""

    id: str
    owner: int
    paths: list[str]
    mode: str
    blend: float
    speed: float
    gap: float
    tol: dict[str, float]
    loop: str | None
    time: float                                # the transport's time at the press
    over: dict[str, Track]                     # what the take is recorded over
    smoothing: float = 0.0                     # seconds its samples are smoothed over
    recorder: Recorder | None = None
    result: dict[str, Track] = field(default_factory=dict)   # parts before the last stall
    last: float = -np.inf
    samples: int = 0
    gaps: list[tuple[float, float]] = field(default_factory=list)
    eased: set[str] = field(default_factory=set)              # paths recorded over their value's ease
    journal_fault: str | None = None                          # why its journal fails (the pages were told)

    def info(self, editor: Editor) -> p.TakeInfo:
        """The take as a ``state`` shows it."""
        return p.TakeInfo(take=self.id, paths=self.paths, mode=self.mode, time=self.time,
                          layout=layout(editor.scene, self.paths))


def _flat(row: object) -> bool:
    return isinstance(row, (list, tuple)) and all(isinstance(x, (int, float)) for x in row)


#: Samples of the ease from an attribute's value onto a take's first sample.
EASE_SAMPLES = 16


def value_track(path: str, type: AttributeType, value: np.ndarray, onto: np.ndarray, start: float, end: float,
                ease: float, tol: float) -> ContinuousTrack:
    """The track of an attribute that holds ``value`` from ``start`` and eases onto
    ``onto`` (smoothstep; a quaternion's normalized, in ``value``'s hemisphere) over the
    ``ease`` seconds before ``end``: a take of two samples (the hold), then one of samples
    of the ease, as :func:`~sketchanim.anim.layers.recorded_over` lays them.

    >>> from sketchanim.anim.attributes import COLOR
    >>> track = value_track("lamp.color", COLOR, np.array([1.0, 0.5, 0.2]), np.array([0.0, 0.0, 1.0]),
    ...                     0.0, 5.8, 0.1, 0.005)
    >>> track.evaluate([0.0, 5.7]).round(3).tolist(), track.evaluate([5.8]).round(3).tolist(), len(track.takes)
    ([[1.0, 0.5, 0.2], [1.0, 0.5, 0.2]], [[0.0, 0.0, 1.0]], 2)
    """
    value, onto = np.asarray(value, dtype=float), np.asarray(onto, dtype=float)
    ease = min(ease, (end - start) / 2)
    held = recorded_over(path, type, None, Take(np.array([start, end - ease]), np.vstack([value, value])), tol, ORDER)
    if ease <= 0:
        return held
    if type.is_rotation and float(np.dot(value, onto)) < 0:
        onto = -onto
    u = np.linspace(0.0, 1.0, EASE_SAMPLES + 1)
    w = u * u * (3 - 2 * u)
    ramp = value + w[:, None] * (onto - value)
    if type.is_rotation:
        ramp /= np.linalg.norm(ramp, axis=1, keepdims=True)
    return recorded_over(path, type, held, Take(end - ease + ease * u, ramp, blend=0.0), tol, ORDER)


def stopped(recorder: Recorder) -> tuple[dict[str, Track], list[p.Notice]]:
    """Stop ``recorder``: its tracks, and a notice for each warning it gave (each also
    logged), instead of the warnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tracks = recorder.stop()
    notices = []
    for w in caught:
        log.warning("recorder: %s", w.message)
        notices.append(p.Notice(level="warning", text=str(w.message), source="recorder"))
    return tracks, notices


class TakeRecorder:
    """The studio's takes on ``editor``'s model, their samples journalled by the
    journals ``journal()`` makes (one per part of a take)."""

    def __init__(self, editor: Editor, journal: Callable[[], Journal]) -> None:
        self.editor = editor
        self.journal = journal
        #: The take in progress, or None.
        self.take: RunningTake | None = None

    def refuse_while_recording(self, what: str) -> None:
        """:class:`ArgumentError` naming ``what`` if a take is being recorded."""
        if self.take is not None:
            raise ArgumentError(what, f"not while take {self.take.id!r} is being recorded")

    def begin(self, owner: int, take: str, paths: list[str], mode: str, blend: float, time: float, speed: float,
              tol: dict[str, float], loop: str | None, gap: float, smoothing: float = 0.0) -> p.TakeStarted:
        """Start a take of ``paths`` (continuous attributes) for client ``owner``, its
        samples smoothed over ``smoothing`` seconds before they are reduced (0: not)."""
        if self.take is not None:
            raise ArgumentError("take", f"take {self.take.id!r} is being recorded")
        scene = self.editor.scene
        if len(set(paths)) != len(paths):
            raise ArgumentError("paths", "a path is armed twice")
        for path in paths:
            if not scene.type(path).continuous:
                raise ArgumentError("paths", f"{path}: a {scene.type(path).name} attribute is set, not performed")
        for path in tol:
            if path not in paths:
                raise ArgumentError("tol", f"{path} is not armed")
        over = dict(self.editor.player.tracks)
        if loop is not None and (last_pass := self.editor.history.replaced_by_last(loop)) is not None:
            over.update(last_pass)                      # the next pass of a loop: over what was there before
            over = {path: t for path, t in over.items() if t is not None}
        self.take = RunningTake(take, owner, list(paths), mode, blend, speed, gap, dict(tol), loop, time, over,
                                smoothing)
        rows = layout(scene, paths)
        return p.TakeStarted(take=take, layout=rows, width=rows[-1][2])

    def settings(self) -> dict:
        """The running take's settings, as a recovery needs them."""
        tk = self.take
        return {"paths": tk.paths, "mode": tk.mode, "blend": tk.blend, "tol": tk.tol, "speed": tk.speed,
                "gap": tk.gap, "loop": tk.loop, "smoothing": tk.smoothing}

    def _hold_values(self, tk: RunningTake, time: float, row: np.ndarray) -> None:
        """Put into ``tk.over`` the scene's value of each armed attribute without a track
        that the take would not keep before it (see the module's description), given the
        take's first sample ``row`` at ``time``."""
        scene = self.editor.scene
        start = min(0.0, self.editor.player.span[0])
        rows = layout(scene, tk.paths)
        if row.shape != (rows[-1][2],) or not np.all(np.isfinite(row)):
            return                                      # the recorder refuses the row, naming it
        for path, lo, hi in rows:
            type = scene.type(path)
            if path in tk.over or time <= start:
                continue
            value = np.asarray(scene.get(path), dtype=float)
            tol = tk.tol.get(path, type.tol)
            angle = 1.0 if type.is_rotation else 0.0
            gap = max_errors(row[None, lo:hi], value[None], angle)
            off = float(np.degrees(gap.max()) if type.is_rotation else gap.max())
            if tk.mode == "additive":
                tk.over[path] = value_track(path, type, value, value, start, time, 0.0, tol)
            elif off > tol:
                tk.over[path] = value_track(path, type, value, row[lo:hi], start, time, tk.blend, tol)
                tk.eased.add(path)

    def _start_part(self) -> None:
        take = self.take
        rec = Recorder(self.editor.scene, order=ORDER, journal=self.journal())
        for path in take.paths:
            eased = path in take.eased and not take.gaps            # the first part joins the ease unfaded
            rec.arm(path, tol=take.tol.get(path), mode=take.mode, blend=0.0 if eased else take.blend,
                    smoothing=take.smoothing)
        rec.start({**take.over, **take.result})
        take.recorder = rec

    def _own(self, owner: int, take: str) -> RunningTake:
        if self.take is None or self.take.id != take:
            raise ArgumentError("take", f"no take {take!r} is being recorded")
        if self.take.owner != owner:
            raise ArgumentError("take", f"take {take!r} belongs to another page")
        return self.take

    def samples(self, owner: int, take: str, times: np.ndarray, values: list) -> list[p.TakePiece | p.Notice]:
        """Push a batch of frames (transport times (n,), rows (n, width)); a stall cuts
        the take. The pieces of curve finished since the last batch, and the notices
        of a part cut. A refused sample (its time not after the last, a row that does
        not fit) is refused before it changes anything: the samples before it in the
        batch are kept, it cuts nothing."""
        tk = self._own(owner, take)
        times = np.asarray(times, dtype=float)
        if len(values) != len(times):
            raise ArgumentError("values", f"{len(values)} rows for {len(times)} times")
        stall = tk.gap * tk.speed
        notices: list[p.Notice] = []
        for i, (t, row) in enumerate(zip(times, values)):
            try:
                if not t > tk.last:
                    raise SampleError(f"time {float(t)!r} must be after the take's last {tk.last!r}",
                                      index=tk.samples, field="time")
                if tk.recorder is None and not tk.samples:     # the first sample: what the take is over is known
                    self._first_part(tk, float(t), row)
                elif t - tk.last > stall:
                    tk.recorder.check_frame(t, row)             # refused here, it cuts nothing
                    notices += self._cut(tk)
                    tk.gaps.append((tk.last, float(t)))
                    self._start_part()
                tk.recorder.push_frame(t, row)
            except InputError as err:
                raise ArgumentError(f"values[{i}]", f"sample {i} of the batch (take sample {tk.samples}): {err}") \
                    from None
            tk.last = float(t)
            tk.samples += 1
        notices += self._journal_news(tk)
        scene = self.editor.scene
        return [*notices, *(piece_info(take, path, piece, scene.type(path).is_rotation)
                            for path, piece in tk.recorder.pieces())]

    @staticmethod
    def _journal_news(tk: RunningTake) -> list[p.Notice]:
        """A notice when the take's journal starts failing (its samples are then kept in
        memory only, until the take is saved) or writes again."""
        err = tk.recorder.journal_error if tk.recorder is not None else None
        fault = None if err is None else write_fault(err)
        if fault == tk.journal_fault:
            return []
        tk.journal_fault = fault
        if fault is None:
            log.warning("take %r: its journal is written again", tk.id)
            return [p.Notice(level="info", source="disk", text=f"take {tk.id}: safe from a crash again "
                                                               "(its journal is written)")]
        log.error("take %r: its journal cannot be written: %s", tk.id, fault)
        return [p.Notice(level="error", source="disk",
                         text=f"take {tk.id}: its journal cannot be written ({fault}). The take goes on and is "
                              "kept when it ends, but a crash now would lose it.")]

    def _first_part(self, tk: RunningTake, time: float, row: object) -> None:
        """Start the take's first part at its first sample (``row`` at ``time``), over
        the values it holds (:meth:`_hold_values`); undone if the sample is refused."""
        over = dict(tk.over)
        self._hold_values(tk, time, np.asarray(row, dtype=float) if _flat(row) else np.empty(0))
        self._start_part()
        try:
            tk.recorder.check_frame(time, row)
        except InputError:
            stopped(tk.recorder)
            tk.recorder.journal.close()
            tk.recorder, tk.over = None, over
            tk.eased.clear()
            raise

    def _cut(self, tk: RunningTake) -> list[p.Notice]:
        """End the part recorded so far, keeping what it made (nothing before the first sample)."""
        rec, tk.recorder = tk.recorder, None
        if rec is None:
            return []
        made, notices = stopped(rec)
        tk.result.update(made)
        rec.journal.close()
        return notices

    def end(self, owner: int, take: str, label: str | None, reason: p.EndReason = "end") -> list[p.TakeEnded | p.Notice]:
        """End the take (kept, for ``reason``: see :data:`~.protocol.EndReason`): its
        tracks as one History step (replacing the last pass of a loop recording). The
        notices of its last part, then ``take.ended``."""
        clock = time.perf_counter()
        tk = self._own(owner, take)
        notices = self._cut(tk)
        self.take = None
        made: dict[str, Track | None] = dict(tk.result)
        if made:
            last_pass = None if tk.loop is None else self.editor.history.replaced_by_last(tk.loop)
            if tk.loop is not None:
                made = {path: self._as_pass(path, track, tk.loop, last_pass) for path, track in made.items()}
            if last_pass is not None:               # what the last pass put and this one did not goes back
                made = {**{path: t for path, t in last_pass.items() if path not in made}, **made}
            self.editor.run(RecordTake(self.editor.player, made, label or f"take {', '.join(tk.result)}", tk.loop))
        self.editor.dirty = True                    # saved soon after (the journal holds the take until then)
        ms = 1000 * (time.perf_counter() - clock)
        return [*notices, p.TakeEnded(take=take, label=self.editor.history.labels[0][-1] if made else None,
                                      paths=list(made), ms=ms, gaps=tk.gaps, smoothing=tk.smoothing, reason=reason)]

    def _as_pass(self, path: str, track: Track | None, loop: str, last_pass: Mapping[str, Track | None] | None
                 ) -> Track | None:
        """``track``, recorded by a pass of the loop recording ``loop`` over what was there
        before the loop, with the earlier passes' takes kept (muted) before this pass's."""
        if not isinstance(track, ContinuousTrack):
            return track
        tracks = self.editor.player.tracks
        now = tracks.get(path)
        if last_pass is None or path not in last_pass:      # the loop's earlier passes did not record it
            below = len(now.takes) if isinstance(now, ContinuousTrack) else 0
            earlier: tuple[Take, ...] = ()
        else:
            before = last_pass[path]
            below = len(before.takes) if isinstance(before, ContinuousTrack) else 0
            earlier = now.takes[below:] if isinstance(now, ContinuousTrack) else ()
        number = 1 + max((t.loop_pass for other in tracks.values() if isinstance(other, ContinuousTrack)
                          for t in other.takes if t.loop == loop), default=-1)
        mine = tuple(replace(t, loop=loop, loop_pass=number) for t in track.takes[below:])
        return replace(track, takes=track.takes[:below] + tuple(replace(t, muted=True) for t in earlier) + mine)

    def cancel(self, owner: int, take: str) -> list[p.TakeEnded | p.Notice]:
        """Drop the take: nothing changes."""
        tk = self._own(owner, take)
        self.take = None
        notices: list[p.Notice] = []
        if tk.recorder is not None:
            _, notices = stopped(tk.recorder)
            tk.recorder.journal.close()
        return [*notices, p.TakeEnded(take=take, label=None, paths=[], ms=0.0, gaps=[], reason="cancel")]
