"""The editor: a project's scene, its player and its history, every change to them an
undoable command (:mod:`sketchanim.anim.commands`), as three.js's ``Editor.js`` is over
its scene. It notes what changed, so that the session can tell the pages.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from sketchanim.anim.commands import AddObject, Command, RemoveObject, RenameObject, SetValue
from sketchanim.anim.history import History
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import Track
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

    def add_object(self, name: str, kind: str) -> None:
        """Add an object (with a ``shape`` if it is a plain object)."""
        self.run(AddObject(self.player, new_object(name, kind)))

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
