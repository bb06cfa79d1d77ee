"""Undoable commands: a refused command changes nothing; merged commands undo as one;
the passes of a loop (one merge key) replace one another."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.commands import AddObject, Change, RecordTake, RemoveObject, RenameObject, SetValue
from sketchanim.anim.history import History
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene, SceneObject
from sketchanim.anim.tracks import ContinuousTrack


def line(path: str, v: float) -> ContinuousTrack:
    return ContinuousTrack(path, POSITION, BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0] * 3, [v] * 3]), 1),
                           0.01)


@pytest.fixture
def player():
    scene = Scene()
    for name in ("a", "b"):
        scene.add(name)
    return Player(scene)


def test_a_refused_command_changes_nothing(player):
    history = History(player)
    for make in (lambda: SetValue(player, "a.position", [1.0, 2.0]), lambda: AddObject(player, SceneObject("a", "object")),
                 lambda: RemoveObject(player, "zz"), lambda: RenameObject(player, "a", "b"),
                 lambda: RenameObject(player, "a", "no.dots")):
        with pytest.raises(ValueError):
            history.run(make())
    assert history.labels == ([], []) and list(player.scene.objects) == ["a", "b"]


def test_mixed_commands_with_one_merge_key_undo_as_one(player):
    history = History(player)
    history.run(SetValue(player, "a.position", [1.0, 0, 0], "drag", merge="m"))
    history.run(Change(player, "drag", {"a.position": line("a.position", 2.0)}, merge="m"))
    history.run(SetValue(player, "b.position", [3.0, 0, 0], "drag", merge="m"))
    assert history.labels == (["drag"], [])
    history.undo()
    assert player.tracks == {} and player.scene.get("a.position").tolist() == [0.0, 0.0, 0.0]
    assert player.scene.get("b.position").tolist() == [0.0, 0.0, 0.0]
    history.redo()
    assert list(player.tracks) == ["a.position"] and player.scene.get("b.position").tolist() == [3.0, 0.0, 0.0]


def test_loop_passes_replace_one_another(player):
    history = History(player)
    base = line("a.position", 1.0)
    history.run(RecordTake(player, {"a.position": base}))
    history.run(RecordTake(player, {"a.position": line("a.position", 2.0), "b.position": line("b.position", 2.0)},
                           merge="L"))
    replaced = history.replaced_by_last("L")
    assert replaced == {"a.position": base, "b.position": None} and history.replaced_by_last("M") is None
    second = {**{p: t for p, t in replaced.items() if p != "a.position"}, "a.position": line("a.position", 3.0)}
    history.run(RecordTake(player, second, "take a.position", merge="L"))
    assert history.labels[0] == ["take a.position", "take a.position"] and "b.position" not in player.tracks
    assert history.replaced_by_last("L") == {"a.position": base, "b.position": None}
    history.undo()
    assert player.tracks == {"a.position": base}
