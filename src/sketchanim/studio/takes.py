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

What the recorder warns of when a part stops (a reducer process died, the journal
failed) is logged and becomes a ``notice`` for every page.
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from sketchanim.anim.commands import RecordTake
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.tracks import Track
from sketchanim.errors import ArgumentError, InputError
from sketchanim.project.journal import Journal
from sketchanim.studio import protocol as p
from sketchanim.studio.editor import Editor
from sketchanim.studio.outbound import layout, piece_info

#: Spline order of recorded curves.
ORDER = 4

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

    def info(self, editor: Editor) -> p.TakeInfo:
        """The take as a ``state`` shows it."""
        return p.TakeInfo(take=self.id, paths=self.paths, mode=self.mode, time=self.time,
                          layout=layout(editor.scene, self.paths))


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
        self._start_part()
        rows = layout(scene, paths)
        return p.TakeStarted(take=take, layout=rows, width=rows[-1][2])

    def settings(self) -> dict:
        """The running take's settings, as a recovery needs them."""
        tk = self.take
        return {"paths": tk.paths, "mode": tk.mode, "blend": tk.blend, "tol": tk.tol, "speed": tk.speed,
                "gap": tk.gap, "loop": tk.loop, "smoothing": tk.smoothing}

    def _start_part(self) -> None:
        take = self.take
        rec = Recorder(self.editor.scene, order=ORDER, journal=self.journal())
        for path in take.paths:
            rec.arm(path, tol=take.tol.get(path), mode=take.mode, blend=take.blend, smoothing=take.smoothing)
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
        of a part cut."""
        tk = self._own(owner, take)
        times = np.asarray(times, dtype=float)
        if len(values) != len(times):
            raise ArgumentError("values", f"{len(values)} rows for {len(times)} times")
        stall = tk.gap * tk.speed
        notices: list[p.Notice] = []
        for i, (t, row) in enumerate(zip(times, values)):
            if tk.samples and t - tk.last > stall:
                notices += self._cut(tk)
                tk.gaps.append((tk.last, float(t)))
                self._start_part()
            try:
                tk.recorder.push_frame(t, row)
            except InputError as err:
                raise ArgumentError(f"values[{i}]", f"sample {i} of the batch (take sample {tk.samples}): {err}") \
                    from None
            tk.last = float(t)
            tk.samples += 1
        scene = self.editor.scene
        return [*notices, *(piece_info(take, path, piece, scene.type(path).is_rotation)
                            for path, piece in tk.recorder.pieces())]

    def _cut(self, tk: RunningTake) -> list[p.Notice]:
        """End the part recorded so far, keeping what it made."""
        rec, tk.recorder = tk.recorder, None
        made, notices = stopped(rec)
        tk.result.update(made)
        rec.journal.close()
        return notices

    def end(self, owner: int, take: str, label: str | None) -> list[p.TakeEnded | p.Notice]:
        """End the take: its tracks as one History step (replacing the last pass of a
        loop recording). The notices of its last part, then ``take.ended``."""
        clock = time.perf_counter()
        tk = self._own(owner, take)
        notices = self._cut(tk)
        self.take = None
        made: dict[str, Track | None] = dict(tk.result)
        if made:
            last_pass = None if tk.loop is None else self.editor.history.replaced_by_last(tk.loop)
            if last_pass is not None:               # what the last pass put and this one did not goes back
                made = {**{path: t for path, t in last_pass.items() if path not in made}, **made}
            self.editor.run(RecordTake(self.editor.player, made, label or f"take {', '.join(tk.result)}", tk.loop))
        self.editor.dirty = True                    # saved soon after (the journal holds the take until then)
        ms = 1000 * (time.perf_counter() - clock)
        return [*notices, p.TakeEnded(take=take, label=self.editor.history.labels[0][-1] if made else None,
                                      paths=list(made), ms=ms, gaps=tk.gaps, smoothing=tk.smoothing)]

    def cancel(self, owner: int, take: str) -> list[p.TakeEnded | p.Notice]:
        """Drop the take: nothing changes."""
        tk = self._own(owner, take)
        self.take = None
        notices: list[p.Notice] = []
        if tk.recorder is not None:
            _, notices = stopped(tk.recorder)
            tk.recorder.journal.close()
        return [*notices, p.TakeEnded(take=take, label=None, paths=[], ms=0.0, gaps=[])]
