"""One project opened for the studio: the editor, the take recorder and the project
file, and the messages that tell the pages what changed.

:class:`Session` binds the :class:`~.editor.Editor` (scene, player, history, commands),
the :class:`~.takes.TakeRecorder` and the project's persistence (the
:class:`~sketchanim.project.store.Project`, its lock, and the recovery of a take a
killed server left in the journal) to the pages: each method returns the messages for
the clients. The model is not thread-safe: every call runs in one thread, in order (the
app sees to it). The project is saved after every step (the app calls :meth:`save`
soon after), never while a take streams into the journal.
"""

from __future__ import annotations

import contextlib
import errno
import logging
import os
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from urllib.parse import quote

import numpy as np

from sketchanim.anim.commands import Change, RecordTake
from sketchanim.anim.layers import Rereduction, composition, rereduced
from sketchanim.anim.history import History
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene
from sketchanim.anim.workers import shared_pool
from sketchanim.errors import ArgumentError, FileFormatError, StorageError
from sketchanim.project.document import SoundDoc, ToleranceDoc
from sketchanim.project.lock import ProjectLock
from sketchanim.project.recovery import forget_take, note_take, recovered_tracks
from sketchanim.project.store import Project, export_text
from sketchanim.studio import exports as exporting
from sketchanim.studio import protocol as p
from sketchanim.studio.beats import DEFAULT_PATH, beat_change, onsets
from sketchanim.studio.clipboard import piece_from, piece_message
from sketchanim.studio.sounds import SoundShelf
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.editor import Editor
from sketchanim.studio.outbound import history_info, objects_info, track_info, tracks_info
from sketchanim.studio.saving import SaveStatus, rescue, write_fault
from sketchanim.studio.takes import ORDER, SILENCE, RunningTake, TakeRecorder

log = logging.getLogger("sketchanim.studio")

#: Tracks re-reduced from their takes, by path (what :meth:`Session.reduction`'s work makes).
Reductions = dict[str, Rereduction]


class Session:
    """A project opened for the studio.

    Parameters
    ----------
    path : path-like
        The project file; created with :func:`~.defaults.default_scene` if it does not
        exist (or holds no objects).
    read_only : bool, optional
        Open the project read-only (True), or as the project detects (None: read-only
        if its file or folder cannot be written).
    exports : path-like, optional
        The folder exports go to (an existing one); the project's if None.

    Examples
    --------
    >>> import tempfile
    >>> session = Session(Path(tempfile.mkdtemp()) / "show.sketchanim")
    >>> _ = session.begin_take(1, "t1", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    >>> t = np.arange(120) / 60
    >>> _ = session.samples(1, "t1", t, np.c_[np.sin(t), 0 * t + 0.5, t])
    >>> out = session.end_take(1, "t1", None)
    >>> track = session.player.tracks["box.position"]
    >>> bool(np.abs(track.evaluate(t) - np.c_[np.sin(t), 0 * t + 0.5, t]).max() <= track.tol), session.history.labels
    (True, (['take box.position'], []))
    >>> session.close()
    """

    def __init__(self, path: str | os.PathLike[str], read_only: bool | None = None,
                 exports: str | os.PathLike[str] | None = None) -> None:
        shared_pool()                   # the reducer processes forked now, before the app's threads exist
        self.path = Path(path).resolve()
        self.folder = self.path.parent
        #: The folder exports are written to (the project's, unless given).
        self.exports = self.folder if exports is None else Path(exports).resolve()
        if exports is not None and not self.exports.is_dir():
            raise ArgumentError("exports", f"{self.exports} is not a folder")
        self.lock = ProjectLock(self.path)
        try:
            self.project = Project(self.path, read_only=read_only)
        except BaseException:
            self.lock.release()
            raise
        try:
            scene, tracks = self.project.load()
        except BaseException:           # damaged: the file closed, the lock let go
            self.project.close()
            self.lock.release()
            raise
        #: The animator's take tolerances by path (the project keeps them; not History).
        self.tolerances: dict[str, ToleranceDoc] = self.project.tolerances(scene)
        #: The project's frame rate (a project setting, not History).
        self.fps = self.project.fps()
        #: The project's sounds, their files checked now (a project setting, not History).
        self.sounds = SoundShelf(self.path, self.project.sounds())
        fresh = not scene.objects
        self.editor = Editor(default_scene() if fresh else scene, tracks.values())
        self.takes = TakeRecorder(self.editor, lambda: self.project.journal())
        #: Whether the compiled kernels are warm (the app says so; pages see it in ``state``).
        self.ready = True
        self.transport = p.TransportInfo()
        self._previewed: dict[int, set[str]] = {}     # client -> paths it previewed since their last set
        self._heard: dict[int, float] = {}            # client -> monotonic time of its last message
        #: Whether the project's saves go through (the pages see it in ``state`` and ``saved``).
        self.saving = SaveStatus(self.path.name)
        self._journal_stale = True                    # journal rows to clear (a cancelled take's; at start, any)
        # a read-only project shows what its file holds: a take left in its journal waits for a writable start
        made = {} if self.read_only else recovered_tracks(self.project, self.scene, self.player.tracks, ORDER)
        if made:
            self.editor.run(RecordTake(self.player, made, "recovered take"))
        #: What was recovered from the journal (its paths), or None.
        self.recovered = ", ".join(made) or None
        self.editor.dirty |= fresh and not self.read_only
        self.editor.changes()           # the pages get all of it in their first state
        self._try_save()                # a failure is news for the first tick; the first state says it too

    @property
    def read_only(self) -> bool:
        """Whether the project is open read-only (asked for, or its file or folder cannot
        be written): it plays and exports, edits are refused (:mod:`.handlers`)."""
        return self.project.read_only

    @property
    def scene(self) -> Scene:
        return self.editor.scene

    @property
    def player(self) -> Player:
        return self.editor.player

    @property
    def history(self) -> History:
        return self.editor.history

    @property
    def dirty(self) -> bool:
        """Whether the model changed since the project was last saved."""
        return self.editor.dirty

    @property
    def take(self) -> RunningTake | None:
        """The take in progress, or None."""
        return self.takes.take

    # -- what the clients see --------------------------------------------------------------

    def state(self) -> dict:
        """Everything a page needs to show the project (see the protocol)."""
        take = self.takes.take
        return p.wire(p.State(ready=self.ready, project=self.path.name, objects=objects_info(self.scene),
                              tracks=[track_info(t) for t in self.player.tracks.values()], span=self.player.span,
                              history=history_info(self.history), transport=self.transport,
                              take=None if take is None else take.info(self.editor),
                              tolerances=self._tolerance_info(), saved=self.saving.info(),
                              read_only=self.read_only, settings=p.SettingsInfo(fps=self.fps),
                              sounds=self.sound_infos()))

    def _tolerance_info(self) -> dict[str, p.ToleranceInfo]:
        return {path: p.ToleranceInfo(amount=t.amount, unit=t.unit) for path, t in self.tolerances.items()}

    def _told(self) -> list[p.Out]:
        """The messages for what changed since the last call: the whole state if objects
        came or went, else the values set, the tracks changed, the history."""
        changes = self.editor.changes()
        if changes.restructured:
            return [("all", self.state())]
        out: list[p.Out] = []
        if changes.values:
            out.append(("all", p.wire(p.Values(values=changes.values))))
        if changes.tracks:
            out.append(("all", p.wire(tracks_info(changes.tracks, self.player.span))))
        if changes.history:
            out.append(("all", p.wire(history_info(self.history))))
        return out

    # -- scene edits -----------------------------------------------------------------------

    def set(self, path: str, value: object, label: str | None, merge: str | None) -> list[p.Out]:
        """Set ``path`` to ``value`` as one History step (undone to the value before
        the previews of the gesture it ends)."""
        self.editor.set(path, value, label, merge)
        for paths in self._previewed.values():
            paths.discard(path)
        return self._told()

    def preview(self, message: p.Preview, client: int) -> list[p.Out]:
        """A live value from ``client`` (not a History step), relayed to the other pages."""
        self.editor.preview(message.path, message.value)
        self._previewed.setdefault(client, set()).add(message.path)
        return [("others", p.relay(message))]

    def leave(self, client: int) -> list[p.Out]:
        """``client`` went away: a take it was recording ends as if released (kept), and
        what it previewed without a set goes back to the value before."""
        take = self.take
        out = [] if take is None or take.owner != client else self.end_take(client, take.id, None, "gone")
        self.editor.cancel_previews(self._previewed.pop(client, ()))
        self._heard.pop(client, None)
        return out + self._told()

    def heard(self, client: int, now: float) -> None:
        """``client`` sent a message at monotonic time ``now`` (the app calls this for
        every message, before it is parsed: a page that sends is alive)."""
        self._heard[client] = now

    def tick(self, now: float) -> list[p.Out]:
        """What time does, at monotonic time ``now`` (the app calls this a few times a
        second): a take whose page sent nothing for :data:`~.takes.SILENCE` seconds
        ends (kept); what changed is saved (a failed save is tried again every
        :data:`~.saving.RETRY` seconds).

        >>> import tempfile
        >>> session = Session(Path(tempfile.mkdtemp()) / "tick.sketchanim")
        >>> session.heard(1, 100.0)
        >>> _ = session.begin_take(1, "t", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
        >>> session.tick(101.0), [m.get("reason") for _, m in session.tick(100.0 + SILENCE + 0.1)][-1]
        ([], 'silent')
        >>> session.close()
        """
        out: list[p.Out] = []
        take = self.take
        if take is not None and now - self._heard.get(take.owner, now) > SILENCE:
            log.warning("take %r ended: its page sent nothing for %g s", take.id, SILENCE)
            out += self.end_take(take.owner, take.id, None, "silent")
        if self.saving.ok or self.saving.due(now):
            self._try_save()
        return out + self.saving.news()

    def add_object(self, name: str, kind: str, position: list[float] | None = None) -> list[p.Out]:
        """Add an object (with a ``shape`` if it is a plain object), at ``position`` if
        given, as one step."""
        self.editor.add_object(name, kind, position)
        return self._told()

    def duplicate_object(self, name: str, to: str) -> list[p.Out]:
        """Copy an object, its values and tracks, as ``to`` (one step; its take
        tolerances, a recording setting outside History, are not copied: an undo could
        not take them back)."""
        self.takes.refuse_while_recording("object.duplicate")
        self.editor.duplicate_object(name, to)
        return self._told()

    # -- curve edits -----------------------------------------------------------------------

    def move_points(self, edits: list[p.PointMove], label: str | None) -> list[p.Out]:
        """Move control points of one or more curves, as one step."""
        self._refuse_recorded(e.path for e in edits)
        moves: dict[str, dict[int, list[float]]] = {}
        for e in edits:
            moves.setdefault(e.path, {})[e.index] = e.value
        self.editor.move_points(moves, label)
        return self._told()

    def move_key(self, path: str, time: float, value: list[float] | None, slope: list[float] | None,
                 label: str | None) -> list[p.Out]:
        """Set a curve's value and / or slope at ``time`` (a key dragged), as one step."""
        self._refuse_recorded([path])
        self.editor.move_key(path, time, value, slope, label)
        return self._told()

    def edit_knots(self, path: str, insert: list[float], remove: list[int]) -> list[p.Out]:
        """Remove and insert knots of a curve, as one step."""
        self._refuse_recorded([path])
        self.editor.edit_knots(path, insert, remove)
        return self._told()

    def key(self, path: str, time: float, value: object) -> list[p.Out]:
        """Key a discrete attribute at ``time`` (a toggle while playing, a cue), as one step."""
        self.editor.key(path, time, value)
        return self._told()

    def edit_take(self, path: str, take: int, op: str, name: str | None, to: int | None, by: float | None = None,
                  factor: float | None = None, pivot: float | None = None) -> list[p.Out]:
        """Change a take of a track (``shift`` it by ``by`` s, ``scale`` it by ``factor``
        about ``pivot``, ...) and compose it again from its takes, as one step."""
        self._refuse_recorded([path])
        self.editor.edit_take(path, take, op, name, to, ORDER, by, factor, pivot)
        return self._told()

    # -- the timeline: retiming and the clipboard -------------------------------------------

    def retime(self, paths: list[str], factor: float, pivot: float, shift: float) -> list[p.Out]:
        """Retime tracks as a whole (``t -> pivot + factor * (t - pivot) + shift``), as one step."""
        self._refuse_recorded(paths)
        self.editor.retime(paths, factor, pivot, shift)
        return self._told()

    def cut(self, paths: list[str], t0: float, t1: float) -> list[p.Out]:
        """Delete the motion of tracks over ``(t0, t1)``, as one step ("delete range")."""
        self._refuse_recorded(paths)
        self.editor.cut(paths, t0, t1)
        return self._told()

    def copy(self, path: str, t0: float, t1: float) -> list[p.Out]:
        """The motion of ``path`` over ``(t0, t1)`` for the page's clipboard (``track.piece``)."""
        return [("self", p.wire(piece_message(path, self.editor.copy(path, t0, t1))))]

    def paste(self, path: str, at: float, info: p.CurveInfo | p.StepsInfo, length: float) -> list[p.Out]:
        """Put a piece the page copied on the track of ``path`` at ``at``, as one step;
        the piece's attribute (its path's) must still exist and be of the track's type."""
        self._refuse_recorded([path])
        self.editor.paste(path, piece_from(info, length, self.scene.type(info.path)), at, ORDER)
        return self._told()

    def reduction(self, paths: list[str], tol: float) -> Callable[[], Reductions]:
        """What re-reducing ``paths`` from their raw takes within ``tol`` takes: checked
        now, in the model's thread; the work (the call returned) runs anywhere (it reads
        only the tracks as they are now, which are never changed in place), and
        :meth:`reduced` puts its result.

        >>> import tempfile
        >>> session = Session(Path(tempfile.mkdtemp()) / "r.sketchanim")
        >>> session.reduction(["box.position"], 0.01)
        Traceback (most recent call last):
        ...
        sketchanim.errors.ArgumentError: path: box.position: has no curve
        >>> session.close()
        """
        tracks = {path: self.editor.curve(path) for path in dict.fromkeys(paths)}
        for path, track in tracks.items():
            if not track.takes:
                raise ArgumentError("path", f"{path}: its curve was not recorded (no takes to re-reduce it from)")
        return lambda: {path: rereduced(track, tol, ORDER) for path, track in tracks.items()}

    def reduced(self, made: Reductions, preview: bool) -> list[p.Out]:
        """Put the tracks a :meth:`reduction` made (one step), or with ``preview`` only
        tell the page what they would be; refused if a track changed meanwhile."""
        results = [p.Reduction(path=path, tol=r.track.tol, n=r.track.n_coefficients, error=r.error)
                   for path, r in made.items()]
        if preview:
            return [("self", p.wire(p.Reduced(preview=True, results=results,
                                              curves=[track_info(r.track) for r in made.values()])))]
        self._refuse_recorded(made)
        changed = [path for path, r in made.items() if self.player.tracks.get(path) is not r.source]
        if changed:
            raise ArgumentError("path", f"{', '.join(changed)} changed while being re-reduced: try again")
        tol = next(iter(made.values())).track.tol
        self.editor.run(Change(self.player, f"tolerance {tol:.4g} on {', '.join(made)}",
                               {path: r.track for path, r in made.items()}))
        return [*self._told(), ("self", p.wire(p.Reduced(preview=False, results=results)))]

    def reduce(self, paths: list[str], tol: float, preview: bool) -> list[p.Out]:
        """:meth:`reduction` and :meth:`reduced` in one call (in the model's thread)."""
        return self.reduced(self.reduction(paths, tol)(), preview)

    def kept_samples(self, path: str) -> Callable[[], list[p.Out]]:
        """What answering ``track.samples`` for ``path`` takes (checked now; the work, the
        call returned, runs anywhere, as :meth:`reduction`'s): the samples its curve keeps
        within its tolerance, for the page (none for a curve without takes)."""
        track = self.editor.curve(path)

        def work() -> list[p.Out]:
            times: list[float] = []
            values: list[list[float]] = []
            if any(not t.muted for t in track.takes):
                made = composition(track.type, track.takes, track.tol, ORDER)
                times, values = made.times.tolist(), made.targets.tolist()
            return [("self", p.wire(p.Samples(path=path, tol=track.tol, times=times, values=values)))]

        return work

    def _refuse_recorded(self, paths: Iterable[str]) -> None:
        """Refuse an edit of a track the running take records (its end would undo it)."""
        take = self.take
        hit = take is not None and [path for path in paths if path in take.paths]
        if hit:
            raise ArgumentError("path", f"{', '.join(hit)}: being recorded; edit it once the take ends")

    def set_settings(self, fps: float) -> list[p.Out]:
        """The project's frame rate (> 0, at most 1000: the protocol checks it; a project
        setting, not a History step); every page gets it."""
        self.fps = float(fps)
        self.editor.dirty = True
        return [("all", p.wire(p.SettingsInfo(fps=self.fps)))]

    def remove_object(self, name: str) -> list[p.Out]:
        """Remove an object and its tracks as one step."""
        self.takes.refuse_while_recording("object.remove")
        self.editor.remove_object(name)
        return self._told()

    def rename_object(self, name: str, to: str) -> list[p.Out]:
        """Rename an object, its tracks with it, as one step."""
        self.takes.refuse_while_recording("object.rename")
        self.editor.rename_object(name, to)
        self.tolerances = {(f"{to}.{path.split('.', 1)[1]}" if path.split(".", 1)[0] == name else path): t
                           for path, t in self.tolerances.items()}
        return self._told()

    def undo(self) -> list[p.Out]:
        self.takes.refuse_while_recording("undo")
        return self._told() if self.editor.undo() else [("self", p.wire(history_info(self.history)))]

    def redo(self) -> list[p.Out]:
        self.takes.refuse_while_recording("undo")
        return self._told() if self.editor.redo() else [("self", p.wire(history_info(self.history)))]

    def set_transport(self, message: p.Transport) -> list[p.Out]:
        """The page's transport and record settings, kept for a reload and relayed to
        the other pages."""
        self.transport = p.TransportInfo(**message.model_dump(exclude={"id", "type"}))
        return [("others", p.relay(message))]

    def set_tolerance(self, path: str, amount: float | None, unit: str) -> list[p.Out]:
        """The tolerance takes of ``path`` are recorded within: ``amount`` (> 0, finite)
        input steps (``px``) or units of the attribute (``units``); None: what the input
        resolves. Kept by the project, not a History step (a recording setting, like the
        layer mode: undo stays with what the animator made). Every page gets them all.

        >>> import tempfile
        >>> session = Session(Path(tempfile.mkdtemp()) / "tol.sketchanim")
        >>> session.set_tolerance("box.position", 3, "px")[0][1]["tolerances"]
        {'box.position': {'amount': 3.0, 'unit': 'px'}}
        >>> session.set_tolerance("box.shape", 3, "px")
        Traceback (most recent call last):
        ...
        sketchanim.errors.ArgumentError: path: box.shape: a enum attribute is set, not performed
        >>> session.close()
        """
        kind = self.scene.type(path)
        if not kind.continuous:
            raise ArgumentError("path", f"{path}: a {kind.name} attribute is set, not performed")
        if amount is None:
            self.tolerances.pop(path, None)
        else:
            if not (np.isfinite(amount) and amount > 0):
                raise ArgumentError("amount", f"{path}: a tolerance must be > 0 and finite, got {amount!r}")
            self.tolerances[path] = ToleranceDoc(amount=amount, unit=unit)
        self.editor.dirty = True
        return [("all", p.wire(p.Tolerances(tolerances=self._tolerance_info())))]

    # -- takes -----------------------------------------------------------------------------

    def begin_take(self, owner: int, take: str, paths: list[str], mode: str, blend: float, time: float,
                   speed: float, tol: dict[str, float], loop: str | None, gap: float,
                   smoothing: float = 0.0) -> list[p.Out]:
        """Start a take of ``paths`` (continuous attributes) for client ``owner`` (see
        :mod:`.takes`). Refused with :class:`StorageError` while the project cannot be
        saved (what is unsaved first leaves the journal the take would stream into: a
        crash then would lose it) or its settings cannot be noted; nothing changes."""
        self._try_save()                # the last take leaves the journal before this one streams into it
        if not self.saving.ok:          # the pages hear of it at the next tick; this page from the error
            raise StorageError(f"cannot record while the project cannot be saved ({self.saving.error}); "
                               "nothing is lost: free the disk or the folder and press record again")
        started = self.takes.begin(owner, take, paths, mode, blend, time, speed, tol, loop, gap, smoothing)
        try:
            note_take(self.path, self.takes.settings())
        except OSError as err:
            self.takes.take = None
            raise StorageError(f"cannot record: the take's settings cannot be written beside the project "
                               f"({write_fault(err)})") from None
        running = p.TakeRunning(**self.takes.take.info(self.editor).model_dump())
        return [*self.saving.news(), ("self", p.wire(started)), ("others", p.wire(running))]

    def samples(self, owner: int, take: str, times: np.ndarray, values: list) -> list[p.Out]:
        """Push a batch of frames (transport times (n,), rows (n, width))."""
        return [("all", p.wire(m)) for m in self.takes.samples(owner, take, times, values)]

    def end_take(self, owner: int, take: str, label: str | None, reason: p.EndReason = "end") -> list[p.Out]:
        """End the take (kept, for ``reason``): its tracks as one History step; the
        project is saved by the next :meth:`save`."""
        *notices, ended = self.takes.end(owner, take, label, reason)
        return [*(("all", p.wire(n)) for n in notices), *self._told(), ("all", p.wire(ended))]

    def cancel_take(self, owner: int, take: str) -> list[p.Out]:
        """Drop the take: nothing changes, and its samples leave the journal (at once, or
        at the next save that goes through), so nothing of it is recovered."""
        out = [("all", p.wire(m)) for m in self.takes.cancel(owner, take)]
        self._journal_stale = True
        with contextlib.suppress(OSError):     # without its notes a journal is not recovered
            forget_take(self.path)
        return out + self.save()

    # -- sounds (studio/sounds.py: a project setting; studio/beats.py: a History step) ----------

    def sound_infos(self) -> list[p.SoundInfo]:
        """The project's sounds as the pages see them."""
        return [self.sound_info(s.name) for s in self.sounds.docs()]

    def sound_info(self, name: str) -> p.SoundInfo:
        """The sound ``name`` as the pages see it (with the URL that serves it)."""
        return p.SoundInfo(**self.sounds.get(name).model_dump(), url=f"/api/sounds/{quote(name)}")

    def _sounds_told(self) -> list[p.Out]:
        self.editor.dirty = True
        return [("all", p.wire(p.Sounds(sounds=self.sound_infos())))]

    def add_sound(self, sound: SoundDoc) -> list[p.Out]:
        """List ``sound``, stored by :meth:`.sounds.SoundShelf.stored`, among the project's;
        every page gets the sounds."""
        self.sounds.put(sound)
        return self._sounds_told()

    def set_sound(self, name: str, offset: float) -> list[p.Out]:
        """Start sound ``name`` at ``offset`` seconds on the timeline."""
        self.sounds.set_offset(name, offset)
        return self._sounds_told()

    def remove_sound(self, name: str) -> list[p.Out]:
        """Drop sound ``name`` from the project (its file stays)."""
        self.sounds.remove(name)
        return self._sounds_told()

    def beat_finding(self, name: str, path: str | None) -> Callable[[], tuple[str, str, np.ndarray]]:
        """What baking the beats of sound ``name`` takes: checked now (the sound, its
        file, the target attribute), in the model's thread; the work (the call returned:
        the onsets, at the sound's offset) runs anywhere, and :meth:`beats_found` puts it.

        >>> import tempfile
        >>> session = Session(Path(tempfile.mkdtemp()) / "b.sketchanim")
        >>> session.beat_finding("none.wav", None)
        Traceback (most recent call last):
        ...
        sketchanim.studio.sounds.NoSuchSound: name: no sound 'none.wav' in the project
        >>> session.close()
        """
        sound = self.sounds.get(name)
        file = self.sounds.path(name)
        target = path or DEFAULT_PATH
        beat_change(self.player, target, np.zeros(0), name)       # refused now if the target cannot take beats
        return lambda: (name, target, sound.offset + onsets(file))

    def beats_found(self, found: tuple[str, str, np.ndarray]) -> list[p.Out]:
        """Put the beats a :meth:`beat_finding` found as one History step."""
        name, target, times = found
        self.takes.refuse_while_recording("sound.beats")
        self.editor.run(beat_change(self.player, target, times, name))
        return [*self._told(), ("self", p.wire(p.BeatsBaked(name=name, path=target, count=len(times))))]

    # -- files -----------------------------------------------------------------------------

    def save(self) -> list[p.Out]:
        """Save the project if anything changed (not while a take runs: saving clears
        the journal the take is streaming into); the messages for the pages if the save
        status changed (:class:`~.saving.SaveStatus`). A save that fails keeps the
        model as it is, to be saved by a later call."""
        self._try_save()
        return self.saving.news()

    def _try_save(self) -> None:
        """:meth:`save`, its outcome noted in :attr:`saving` (its news left there)."""
        if self.takes.take is not None or self.project.read_only or not (self.editor.dirty or self._journal_stale):
            return
        try:
            self._reopen_if_gone()
            if self.editor.dirty:
                self.project.save(self.scene, dict(self.player.tracks), self.tolerances, self.fps, self.sounds.docs())
            else:
                self.project.clear_journal()
            self.editor.dirty = self._journal_stale = False
        except (OSError, FileFormatError) as err:
            self.saving.failed(err)
            return
        with contextlib.suppress(OSError):     # notes left beside an empty journal recover nothing
            forget_take(self.path)
        self.saving.succeeded()

    def _reopen_if_gone(self) -> None:
        """If the project file was deleted or moved away (a save would go to a file no
        one can open again), make it anew at its path with the whole model; if its
        folder is gone too, :class:`FileNotFoundError` (tried again at the next save)."""
        if self.path.exists():
            return
        if not self.path.parent.is_dir():
            raise FileNotFoundError(errno.ENOENT, "the project's folder is gone", str(self.path.parent))
        log.warning("%s was deleted or moved; writing it anew", self.path)
        fresh = Project(self.path)
        self.project.close()
        self.project = fresh
        self.editor.dirty = True

    def export_document(self) -> bytes:
        """The project as ``sketchanim export PROJECT -o X.json`` writes it: the model
        as the pages see it, saved or not."""
        return export_text(self.scene, dict(self.player.tracks), self.tolerances, self.fps,
                           self.sounds.docs()).encode("utf-8")

    def export(self, name: str, overwrite: bool = False) -> Path:
        """Write the scene (``.glb``) or the project (``.json``) to ``name`` in the
        exports folder (see :mod:`.exports`: a bare name, never the project's own
        files, an existing file replaced only with ``overwrite``)."""
        from sketchanim.export.scene_gltf import scene_glb

        path = exporting.target(self.exports, name, self.path, overwrite)
        if path.suffix.lower() == ".json":
            data = self.export_document()
        else:
            data, _ = scene_glb(self.scene, dict(self.player.tracks), name=path.stem)
        return exporting.write(path, data, overwrite)

    # -- clips (clips.py) ---------------------------------------------------------------------

    def import_clip(self, prefix: str, joints: dict, parents: tuple[int, ...], label: str
                    ) -> tuple[list[str], list[p.Out]]:
        """Add a clip's joints (:func:`~sketchanim.mocap.scene_clip.joint_tracks`) as
        objects ``<prefix>_<joint>`` with their tracks and parents (index, -1: none), as one step; refused in a
        read-only project or while a take is recorded. The objects' names, and the
        messages."""
        from sketchanim.studio.clips import clip_change

        if self.read_only:
            raise ArgumentError("clip", f"{self.path.name} is open read-only: a clip cannot be added")
        self.takes.refuse_while_recording("clip import")
        change, names = clip_change(self.player, prefix, joints, parents, label)
        self.editor.run(change)
        return names, self._told()

    def flush(self) -> list[p.Out]:
        """End a take still running (kept) and save; the messages of the take's end."""
        out = [] if self.take is None else self.end_take(self.take.owner, self.take.id, None, "shutdown")
        return out + self.save()

    def close(self) -> None:
        """Flush, then close the file (and let another studio open it). If the project
        still cannot be saved, the model is written as a new project where it can be
        (:func:`~.saving.rescue`; the log says where)."""
        self.flush()
        if self.editor.dirty:
            try:
                where = rescue(self.path, self.scene, self.player.tracks, self.tolerances, self.sounds.docs())
                log.error("%s could not be saved; everything is in %s (open it with sketchanim studio)",
                          self.path, where)
            except OSError as err:
                log.critical("%s could not be saved, nor a copy anywhere (%s): the changes since %s are lost",
                             self.path, write_fault(err), time.ctime(self.saving.since or time.time()))
        self.project.close()
        self.lock.release()
