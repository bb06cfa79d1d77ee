"""The editor: a project's scene, its player and its history, every change to them an
undoable command (:mod:`sketchanim.anim.commands`), as three.js's ``Editor.js`` is over
its scene. It notes what changed, so that the session can tell the pages.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

from sketchanim.anim.commands import AddObject, Change, Command, DuplicateObject, RemoveObject, RenameObject, SetValue
from sketchanim.anim.edits import moved_key, moved_points, with_key, with_knots, without_knots, without_range
from sketchanim.anim.history import History
from sketchanim.anim.layers import recomposed
from sketchanim.anim.retime import Piece, pasted, piece, retimed
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene
from sketchanim.anim.take_edits import edited_takes
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Track
from sketchanim.errors import ArgumentError
from sketchanim.studio.defaults import new_object
from sketchanim.studio.outbound import plain


@dataclass(frozen=True)
class Changes:
    """What changed in the model since it was last asked.

    Attributes
    ----------
    restructured : bool
        Objects came, went or were renamed (the pages need the whole state).
    values : dict
        Scene values set (path -> value, as JSON holds it).
    tracks : dict
        Tracks put (path -> track) or removed (path -> None).
    history : bool
        The history changed (a step run, undone or redone).
    """

    restructured: bool
    values: dict[str, object]
    tracks: dict[str, Track | None]
    history: bool


class Editor:
    """The scene, its player (with ``tracks``) and its history.

    Examples
    --------
    >>> from sketchanim.studio.defaults import default_scene
    >>> editor = Editor(default_scene(), [])
    >>> editor.set("lamp.intensity", [2.0], None, None)
    >>> changes = editor.changes()
    >>> changes.values, changes.history, editor.history.labels
    ({'lamp.intensity': [2.0]}, True, (['set lamp.intensity'], []))
    """

    def __init__(self, scene: Scene, tracks: Iterable[Track]) -> None:
        self.scene = scene
        self.player = Player(scene, tracks)
        self._history_changed = False
        self.history = History(self.player, on_change=lambda _: setattr(self, "_history_changed", True))
        #: Whether the model changed since the project was last saved.
        self.dirty = False
        self._scene_changes: list[tuple[str, str, str | None]] = []
        self._shown: dict[str, Track] = dict(self.player.tracks)
        self._before: dict[str, object] = {}     # path -> its value before the previews since its last set
        scene.watch(lambda *change: self._scene_changes.append(change))

    def run(self, command: Command) -> None:
        """Do ``command`` as one History step."""
        self.history.run(command)
        self.dirty = True

    def set(self, path: str, value: object, label: str | None, merge: str | None) -> None:
        """Set ``path`` to ``value`` (steps with the same ``merge`` key join); the step
        undoes to the value before any preview of ``path`` since its last set."""
        checked = self.scene.type(path).check(value, path)
        if path in self._before:
            self.scene.attribute(path).value = self._before.pop(path)
        self.run(SetValue(self.player, path, checked, label, merge))

    def preview(self, path: str, value: object) -> None:
        """A live value (not a History step): the scene's current value until the next
        preview, the :meth:`set` that ends the gesture, or :meth:`cancel_previews`.

        >>> from sketchanim.studio.defaults import default_scene
        >>> editor = Editor(default_scene(), [])
        >>> before = editor.scene.get("lamp.intensity").tolist()
        >>> editor.preview("lamp.intensity", [3.0]); editor.preview("lamp.intensity", [4.0])
        >>> editor.set("lamp.intensity", [4.0], None, None)
        >>> _ = editor.undo()
        >>> editor.scene.get("lamp.intensity").tolist() == before
        True
        """
        checked = self.scene.type(path).check(value, path)
        self._before.setdefault(path, self.scene.get(path))
        self.scene.attribute(path).value = checked

    def cancel_previews(self, paths: Iterable[str]) -> None:
        """Put back the values ``paths`` had before their previews (a gesture that ended
        without its set: the page went away)."""
        for path in paths:
            if path in self._before and self._exists(path):
                self.scene.set(path, self._before.pop(path))

    def add_object(self, name: str, kind: str, position: Sequence[float] | None = None) -> None:
        """Add an object (with a ``shape`` if it is a plain object), at ``position`` if given."""
        obj = new_object(name, kind, position)
        self.run(AddObject(self.player, obj))

    def duplicate_object(self, name: str, to: str) -> None:
        """Copy an object, its values and tracks, as ``to``."""
        self.run(DuplicateObject(self.player, name, to))

    def curve(self, path: str) -> ContinuousTrack:
        """The curve of ``path``; :class:`ArgumentError` if it has none."""
        track = self.player.tracks.get(path)
        if not isinstance(track, ContinuousTrack):
            raise ArgumentError("path", f"{path}: has no curve" + ("" if track is None else " (a discrete track)"))
        return track

    def move_points(self, moves: Mapping[str, Mapping[int, Sequence[float]]], label: str | None) -> None:
        """Move control points (path -> index -> value) of one or more curves, as one step."""
        made = {path: moved_points(self.curve(path), points) for path, points in moves.items()}
        count = sum(len(points) for points in moves.values())
        self.run(Change(self.player, label or f"move {count} point{'s' * (count != 1)} of {', '.join(made)}", made))

    def move_key(self, path: str, time: float, value: Sequence[float] | None, slope: Sequence[float] | None,
                 label: str | None) -> None:
        """Set the curve's value and / or slope at ``time`` (a key dragged), as one step."""
        what = "key" if slope is None else "tangent" if value is None else "key and tangent"
        made = moved_key(self.curve(path), time, value, slope)
        self.run(Change(self.player, label or f"move {what} of {path} at {time:.3f} s", {path: made}))

    def key(self, path: str, time: float, value: object) -> None:
        """Key the discrete attribute ``path`` to ``value`` at ``time`` (an event: add one),
        its track made if it has none, as one step (see :func:`~sketchanim.anim.edits.with_key`).
        A bool or an enum keyed first after time 0 keeps what it was before: its value is
        keyed at 0 too (a light switched off at 2 s is on until then).

        >>> from sketchanim.studio.defaults import default_scene
        >>> editor = Editor(default_scene(), [])
        >>> editor.key("lamp.on", 1.5, False); editor.key("box.cue", 2.0, "hit")
        >>> t = editor.player.tracks["lamp.on"]; (t.times, t.values), editor.history.labels[0]
        (([0.0, 1.5], [True, False]), ['key lamp.on at 1.500 s', 'cue box.cue at 2.000 s'])
        """
        kind = self.scene.type(path)
        if kind.continuous:
            raise ArgumentError("path", f"{path}: a {kind.name} attribute is performed or its curve edited, not keyed")
        track = self.player.tracks.get(path)
        track = track if isinstance(track, DiscreteTrack) else DiscreteTrack(path, kind)
        if kind.name != "event" and time > 0 and not any(t <= time for t in track.times):
            track = with_key(track, 0.0, self.scene.get(path))
        made = with_key(track, time, value)
        what = "cue" if kind.name == "event" else "key"
        self.run(Change(self.player, f"{what} {path} at {time:.3f} s", {path: made}))

    def edit_knots(self, path: str, insert: Sequence[float], remove: Sequence[int]) -> None:
        """Remove the interior knots ``remove`` (indices into the curve's knots), then
        insert knots at ``insert``, as one step."""
        if not insert and not remove:
            raise ArgumentError("knots", f"{path}: no knot to insert or remove")
        track = self.curve(path)
        track = without_knots(track, remove) if remove else track
        track = with_knots(track, insert) if insert else track
        what = " and ".join(x for x in (f"insert {len(insert)}" if insert else "",
                                        f"remove {len(remove)}" if remove else "") if x)
        self.run(Change(self.player, f"{what} knot{'s' * (len(insert) + len(remove) != 1)} on {path}", {path: track}))

    def edit_take(self, path: str, index: int, op: str, name: str | None, to: int | None, order: int,
                  by: float | None = None, factor: float | None = None, pivot: float | None = None) -> None:
        """Change a take of the curve of ``path`` (see :func:`~sketchanim.anim.take_edits.edited_takes`)
        and compose the curve again from its takes, as one step; deleting its last take
        removes the track."""
        track = self.curve(path)
        takes = edited_takes(track.takes, index, op, name, to, by, factor, pivot)
        made = (replace(track, takes=takes) if op == "rename" else recomposed(track, takes, order=order)) if takes else None
        self.run(Change(self.player, f"{op} take {index + 1} of {path}", {path: made}))

    # -- the timeline: retiming, cutting, pasting --------------------------------------------

    def track(self, path: str) -> Track:
        """The track of ``path``; :class:`ArgumentError` if it has none."""
        track = self.player.tracks.get(path)
        if track is None:
            raise ArgumentError("path", f"{path}: is not animated (no track)")
        return track

    def retime(self, paths: Sequence[str], factor: float, pivot: float, shift: float) -> None:
        """Retime the tracks ``paths`` as a whole (:func:`~sketchanim.anim.retime.retimed`), as one step."""
        made = {path: retimed(self.track(path), factor, pivot, shift) for path in dict.fromkeys(paths)}
        what = f"move {shift:+.3f} s" if factor == 1 else f"scale x{factor:.3g} about {pivot:.3f} s"
        self.run(Change(self.player, f"{what}: {', '.join(made)}", made))

    def cut(self, paths: Sequence[str], t0: float, t1: float) -> None:
        """Delete the motion of ``paths`` over ``(t0, t1)`` (:func:`~sketchanim.anim.edits.without_range`), as one step."""
        made = {path: without_range(self.track(path), t0, t1) for path in dict.fromkeys(paths)}
        self.run(Change(self.player, f"delete range {t0:.3f}-{t1:.3f} s: {', '.join(made)}", made))

    def copy(self, path: str, t0: float, t1: float) -> Piece:
        """The motion of ``path`` over ``(t0, t1)`` (:func:`~sketchanim.anim.retime.piece`); nothing changes."""
        return piece(self.track(path), t0, t1)

    def paste(self, path: str, clip: Piece, at: float, order: int) -> None:
        """Put ``clip`` on the track of ``path`` at ``at`` (:func:`~sketchanim.anim.retime.pasted`), as one step."""
        made = pasted(self.track(path), clip, at, order)
        self.run(Change(self.player, f"paste {clip.length:.3f} s at {at:.3f} s: {path}", {path: made}))

    def remove_object(self, name: str) -> None:
        """Remove an object and its tracks."""
        self.run(RemoveObject(self.player, name))

    def rename_object(self, name: str, to: str) -> None:
        """Rename an object, its tracks with it."""
        self.run(RenameObject(self.player, name, to))

    def undo(self) -> bool:
        """Undo the last step; whether there was one (previews in progress stay as the
        scene's values, their gestures' undo targets those values as undone)."""
        self._before.clear()
        self.dirty |= (done := self.history.undo() is not None)
        return done

    def redo(self) -> bool:
        """Redo the last undone step; whether there was one (as :meth:`undo` for previews)."""
        self._before.clear()
        self.dirty |= (done := self.history.redo() is not None)
        return done

    def changes(self) -> Changes:
        """What changed since the last call (values of attributes that still exist: those
        set, and those whose track went, which show their scene value again)."""
        scene_changes, self._scene_changes = self._scene_changes, []
        history, self._history_changed = self._history_changed, False
        now = self.player.tracks
        tracks = {p: now.get(p) for p in (*self._shown, *(p for p in now if p not in self._shown))
                  if now.get(p) is not self._shown.get(p)}
        self._shown = dict(now)
        restructured = any(what != "set" for what, _, _ in scene_changes)
        changed = (*(s for _, s, _ in scene_changes), *(p for p, t in tracks.items() if t is None))
        values = {} if restructured else {p: plain(self.scene.get(p)) for p in dict.fromkeys(changed)
                                          if self._exists(p)}
        return Changes(restructured, values, tracks, history)

    def _exists(self, path: str) -> bool:
        try:
            self.scene.attribute(path)
        except ArgumentError:
            return False
        return True
