"""Undo and redo: the commands run on a player's tracks and scene, in order.

:class:`History` keeps the commands done and undone, joins a command to the last one
when their merge keys match (three.js's updatable commands), and calls ``on_change``
after every step. Recording a take is a command too (:class:`.commands.RecordTake`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from sketchanim.anim.commands import Change, Command, SceneChange, SetValue
from sketchanim.anim.player import Player
from sketchanim.anim.tracks import Track
from sketchanim.errors import ArgumentError


class History:
    """Run commands on a player's tracks and scene, with undo and redo.

    ``on_change`` is called with the history after every step run, undone or redone
    (e.g. to tell clients the labels and whether undo and redo are possible).

    >>> import numpy as np
    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import FLOAT
    >>> from sketchanim.anim.edits import moved_points
    >>> from sketchanim.anim.scene import Scene
    >>> from sketchanim.anim.tracks import ContinuousTrack
    >>> scene = Scene(); obj = scene.add("a"); _ = obj.add("x", FLOAT)
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 1.0]], 1)
    >>> player = Player(scene, [ContinuousTrack("a.x", FLOAT, s, 0.01)])
    >>> history = History(player)
    >>> history.edit("a.x", "move point", moved_points, {1: [5.0]})
    >>> float(player.tracks["a.x"].evaluate([1.0])[0, 0]), history.undo(), float(player.tracks["a.x"].evaluate([1.0])[0, 0])
    (5.0, 'move point', 1.0)
    >>> history.set("a.x", [2.0], "nudge", merge="nudge"); history.set("a.x", [3.0], "nudge", merge="nudge")
    >>> history.labels, history.undo(), scene.get("a.x").tolist()
    ((['nudge'], []), 'nudge', [0.0])
    """

    def __init__(self, player: Player, limit: int = 1000,
                 on_change: Callable[[History], object] | None = None) -> None:
        self.player = player
        self.limit = limit
        self.on_change = on_change
        self.done: list[Command] = []
        self.undone: list[Command] = []

    @property
    def labels(self) -> tuple[list[str], list[str]]:
        """The labels of the steps to undo (oldest first) and of those to redo (the next
        redo last)."""
        return [c.label for c in self.done], [c.label for c in self.undone]

    def run(self, command: Command) -> None:
        """Do ``command`` as one step (joined to the last if their merge keys match)."""
        command.do()
        if command.merge is not None and self.done and self.done[-1].merge == command.merge:
            command = self.done.pop().merged(command)
        self.done.append(command)
        del self.done[: -self.limit]
        self.undone.clear()
        self._changed()

    def replaced_by_last(self, merge: str) -> Mapping[str, Track | None] | None:
        """What the last step replaced (path -> track before it, None: no track) if it was
        run with merge key ``merge``, else None: the next pass of a loop recording is
        recorded over what was there before the last pass, and replaces it.

        >>> from sketchanim.anim.scene import Scene
        >>> history = History(Player(Scene()))
        >>> history.apply("pass", {}, merge="loop"); history.replaced_by_last("loop"), history.replaced_by_last("other")
        ({}, None)
        """
        if self.done and self.done[-1].merge == merge:
            return self.done[-1].replaced
        return None

    def apply(self, label: str, tracks: Mapping[str, Track | None], scene: tuple[SceneChange, ...] = (),
              merge: str | None = None) -> None:
        """Put ``tracks`` and make the scene changes ``scene`` as one step (a
        :class:`~sketchanim.anim.commands.Change`)."""
        self.run(Change(self.player, label, tracks, scene, merge))

    def edit(self, path: str, label: str, change: Callable[..., Track], *args: object) -> None:
        """Replace the track at ``path`` by ``change(track, *args)`` as one step."""
        if path not in self.player.tracks:
            raise ArgumentError("path", f"no track for {path!r}")
        self.apply(label, {path: change(self.player.tracks[path], *args)})

    def set(self, path: str, value: object, label: str | None = None, merge: str | None = None) -> None:
        """Set the scene's value at ``path`` as one step (checked first: a bad value
        raises and changes nothing)."""
        self.run(SetValue(self.player, path, value, label, merge))

    def undo(self) -> str | None:
        """Undo the last step; its label, or None if there is none."""
        if not self.done:
            return None
        command = self.done.pop()
        command.undo()
        self.undone.append(command)
        self._changed()
        return command.label

    def redo(self) -> str | None:
        """Redo the last undone step; its label, or None if there is none."""
        if not self.undone:
            return None
        command = self.undone.pop()
        command.do()
        self.done.append(command)
        self._changed()
        return command.label

    def _changed(self) -> None:
        if self.on_change is not None:
            self.on_change(self)
