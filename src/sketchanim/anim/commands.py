"""Undoable operations as command objects (as the three.js editor's ``commands/``).

A command is made from the model it will change (its checks run then, so a refused
command changes nothing), and :class:`~sketchanim.anim.history.History` runs it: ``do``,
then ``undo`` and ``do`` again as the animator undoes and redoes. Two commands with the
same merge key in a row become one (:meth:`Command.merged`): a run of nudges, the passes
of a loop recording.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from copy import deepcopy
from dataclasses import replace

from sketchanim.anim.player import Player
from sketchanim.anim.scene import SceneObject, check_name
from sketchanim.anim.tracks import Track
from sketchanim.errors import ArgumentError

#: A change to the scene in a command: (do, undo), two calls without arguments.
SceneChange = tuple[Callable[[], object], Callable[[], object]]


class Command:
    """One undoable step on a player's tracks and scene.

    Attributes
    ----------
    label : str
        What the animator sees in the history.
    merge : str or None
        The merge key: a command run with the same key as the last one joins it.
    """

    label: str
    merge: str | None = None

    def do(self) -> None:
        """Make the change (again, after an undo)."""
        raise NotImplementedError

    def undo(self) -> None:
        """Take the change back."""
        raise NotImplementedError

    @property
    def replaced(self) -> Mapping[str, Track | None]:
        """The tracks as they were before the command, for the paths it puts (None:
        there was none)."""
        return {}

    def merged(self, later: Command) -> Command:
        """One command for this one and then ``later`` (both already done), labelled
        as ``later``."""
        return Batch((self, later), later.label, later.merge)


class Batch(Command):
    """Commands done in order and undone in reverse, as one."""

    def __init__(self, commands: tuple[Command, ...], label: str, merge: str | None = None) -> None:
        self.commands, self.label, self.merge = commands, label, merge

    def do(self) -> None:
        for command in self.commands:
            command.do()

    def undo(self) -> None:
        for command in reversed(self.commands):
            command.undo()

    @property
    def replaced(self) -> Mapping[str, Track | None]:
        out: dict[str, Track | None] = {}
        for command in reversed(self.commands):
            out.update(command.replaced)
        return out

    def merged(self, later: Command) -> Command:
        return Batch((*self.commands, later), later.label, later.merge)


class Change(Command):
    """Put ``tracks`` (path -> new track, or None to remove it) and make the scene
    changes ``scene`` (each ``(do, undo)``): removals first, then the scene changes,
    then the tracks put (so a track can follow its object).

    >>> from scipy.interpolate import BSpline
    >>> import numpy as np
    >>> from sketchanim.anim.attributes import FLOAT
    >>> from sketchanim.anim.scene import Scene
    >>> from sketchanim.anim.tracks import ContinuousTrack
    >>> scene = Scene(); _ = scene.add("a").add("x", FLOAT)
    >>> player = Player(scene)
    >>> line = ContinuousTrack("a.x", FLOAT, BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 1.0]], 1), 0.01)
    >>> change = Change(player, "take", {"a.x": line})
    >>> change.do(); list(player.tracks), change.replaced
    (['a.x'], {'a.x': None})
    >>> change.undo(); list(player.tracks)
    []
    """

    def __init__(self, player: Player, label: str, tracks: Mapping[str, Track | None],
                 scene: tuple[SceneChange, ...] = (), merge: str | None = None) -> None:
        self.player, self.label, self.merge = player, label, merge
        self.before: dict[str, Track | None] = {path: player.tracks.get(path) for path in tracks}
        self.after: dict[str, Track | None] = dict(tracks)
        self.scene = tuple(scene)

    def do(self) -> None:
        self._put(self.after, [do for do, _ in self.scene])

    def undo(self) -> None:
        self._put(self.before, [undo for _, undo in reversed(self.scene)])

    @property
    def replaced(self) -> Mapping[str, Track | None]:
        return self.before

    def merged(self, later: Command) -> Command:
        if not isinstance(later, Change) or later.player is not self.player:
            return super().merged(later)
        joined = Change(self.player, later.label, {}, self.scene + later.scene, later.merge)
        joined.before = {**later.before, **self.before}
        joined.after = {**self.after, **later.after}
        return joined

    def _put(self, tracks: Mapping[str, Track | None], calls: list[Callable[[], object]]) -> None:
        for path, track in tracks.items():
            if track is None and path in self.player.tracks:
                self.player.remove(path)
        for call in calls:
            call()
        for track in tracks.values():
            if track is not None:
                self.player.add(track)


class SetValue(Change):
    """Set the scene's value at ``path`` (checked now: a bad value raises and nothing
    changes)."""

    def __init__(self, player: Player, path: str, value: object, label: str | None = None,
                 merge: str | None = None) -> None:
        scene = player.scene
        old, new = scene.get(path), scene.type(path).check(value, path)
        super().__init__(player, label or f"set {path}", {},
                         ((lambda: scene.set(path, new), lambda: scene.set(path, old)),), merge)


class AddObject(Change):
    """Add ``obj`` to the scene."""

    def __init__(self, player: Player, obj: SceneObject) -> None:
        scene = player.scene
        if obj.name in scene.objects:
            raise ArgumentError("object", f"{obj.name!r} exists already")
        super().__init__(player, f"add {obj.name}", {}, ((lambda: scene.insert(obj), lambda: scene.remove(obj.name)),))


def _owner(path: str) -> str:
    return path.split(".")[0]


class RemoveObject(Change):
    """Remove the object ``name`` and its tracks."""

    def __init__(self, player: Player, name: str) -> None:
        scene = player.scene
        obj = scene.objects.get(name)
        if obj is None:
            raise ArgumentError("object", f"no object {name!r}")
        at = scene.index(name)
        super().__init__(player, f"remove {name}", {p: None for p in player.tracks if _owner(p) == name},
                         ((lambda: scene.remove(name), lambda: scene.insert(obj, at)),))


class RenameObject(Change):
    """Rename the object ``name`` to ``to``, its tracks with it."""

    def __init__(self, player: Player, name: str, to: str) -> None:
        scene = player.scene
        if name not in scene.objects:
            raise ArgumentError("object", f"no object {name!r}")
        if to in scene.objects:
            raise ArgumentError("object", f"{to!r} exists already")
        check_name(to, "object")
        tracks: dict[str, Track | None] = {}
        for p, t in player.tracks.items():
            if _owner(p) == name:
                moved = f"{to}.{p.split('.')[1]}"
                tracks[p], tracks[moved] = None, replace(t, path=moved)
        super().__init__(player, f"rename {name} to {to}", tracks,
                         ((lambda: scene.rename(name, to), lambda: scene.rename(to, name)),))


class DuplicateObject(Change):
    """Copy the object ``name`` as ``to``: its attributes with their values, and its
    tracks (placed after it in the scene's order).

    >>> from sketchanim.anim.scene import Scene
    >>> scene = Scene(); _ = scene.add("box")
    >>> player = Player(scene)
    >>> DuplicateObject(player, "box", "box2").do(); list(scene.objects)
    ['box', 'box2']
    """

    def __init__(self, player: Player, name: str, to: str) -> None:
        scene = player.scene
        obj = scene.objects.get(name)
        if obj is None:
            raise ArgumentError("object", f"no object {name!r}")
        if to in scene.objects:
            raise ArgumentError("object", f"{to!r} exists already")
        check_name(to, "object")
        copy = SceneObject(to, obj.kind, {n: replace(a, value=deepcopy(a.value)) for n, a in obj.attributes.items()})
        at = scene.index(name) + 1
        tracks: dict[str, Track | None] = {f"{to}.{p.split('.')[1]}": replace(t, path=f"{to}.{p.split('.')[1]}")
                                           for p, t in player.tracks.items() if _owner(p) == name}
        super().__init__(player, f"duplicate {name} as {to}", tracks,
                         ((lambda: scene.insert(copy, at), lambda: scene.remove(to)),))


class RecordTake(Change):
    """Put the tracks a take made (labelled ``take <paths>`` unless ``label``); with a
    loop's ``merge`` key, a pass of a loop recording (the next pass joins it)."""

    def __init__(self, player: Player, tracks: Mapping[str, Track | None], label: str | None = None,
                 merge: str | None = None) -> None:
        super().__init__(player, label or f"take {', '.join(tracks)}", tracks, merge=merge)
