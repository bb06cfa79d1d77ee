"""History with scene edits (set, add, remove, rename) and tracks, merged steps, the
change callback: any sequence undone gives the start back, redone gives the end."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings, strategies as st
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.history import History
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene, SceneObject
from sketchanim.anim.tracks import ContinuousTrack


def snapshot(player: Player) -> tuple:
    scene = player.scene
    return (tuple((o.name, o.kind, tuple((n, str(np.asarray(a.value).tolist())) for n, a in o.attributes.items()))
                  for o in scene.objects.values()),
            tuple(sorted((p, id(t)) for p, t in player.tracks.items())))


def line(path: str, v: float) -> ContinuousTrack:
    return ContinuousTrack(path, POSITION, BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0, 0, 0], [v, v, v]]), 1),
                           0.005)


ops = st.lists(st.tuples(st.sampled_from(["set", "add", "remove", "rename", "track", "nudge"]),
                         st.integers(0, 5), st.floats(-10, 10)), max_size=25)


@settings(max_examples=60)
@given(ops)
def test_undo_all_gives_the_start_and_redo_all_the_end(steps):
    scene = Scene()
    for name in ("a", "b"):
        scene.add(name)
    player = Player(scene)
    calls = []
    history = History(player, on_change=lambda h: calls.append(h.labels))
    start = snapshot(player)
    applied = 0
    for op, i, v in steps:
        names = list(scene.objects)
        name = names[i % len(names)] if names else None
        if op == "set" and name:
            history.set(f"{name}.position", [v, 0, 0])
        elif op == "nudge" and name:
            history.set(f"{name}.position", [0, v, 0], "nudge", merge=f"nudge {name}")
        elif op == "add" and f"n{i}" not in scene.objects:
            obj = SceneObject(f"n{i}", "object")
            history.apply(f"add n{i}", {}, ((lambda o=obj: scene.insert(o), lambda n=obj.name: scene.remove(n)),))
        elif op == "remove" and name:
            obj = scene.objects[name]
            tracks = {p: None for p in player.tracks if p.startswith(name + ".")}
            at = scene.index(name)
            history.apply(f"remove {name}", tracks,
                          ((lambda n=name: scene.remove(n), lambda o=obj, k=at: scene.insert(o, k)),))
        elif op == "rename" and name and f"r{i}" not in scene.objects:
            to = f"r{i}"
            tracks = {}
            for p, t in list(player.tracks.items()):
                if p.startswith(name + "."):
                    tracks[p] = None
                    tracks[to + p[len(name):]] = line(to + p[len(name):], 1.0)
            history.apply("rename", tracks, ((lambda n=name, t=to: scene.rename(n, t), lambda n=name, t=to: scene.rename(t, n)),))
        elif op == "track" and name:
            history.apply("take", {f"{name}.position": line(f"{name}.position", v)})
        else:
            continue
        applied += 1
    end = snapshot(player)
    assert len(calls) == applied                       # told of every step
    while history.undo() is not None:
        pass
    assert snapshot(player) == start
    while history.redo() is not None:
        pass
    assert snapshot(player) == end
    for path in player.tracks:                          # tracks always follow an existing attribute
        assert scene.type(path) == POSITION


def test_rename_keeps_the_place_and_refuses_clashes():
    scene = Scene()
    for name in ("a", "b", "c"):
        scene.add(name)
    scene.rename("b", "z")
    assert list(scene.objects) == ["a", "z", "c"] and scene.objects["z"].name == "z"
    for bad in (("a", "c"), ("q", "r"), ("a", "no.dots")):
        try:
            scene.rename(*bad)
        except ValueError as err:
            assert bad[0] in str(err) or bad[1] in str(err)
        else:
            raise AssertionError(f"rename {bad} was allowed")
    assert list(scene.objects) == ["a", "z", "c"]
