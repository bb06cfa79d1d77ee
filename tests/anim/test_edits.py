"""Track edits and their undo/redo."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.anim.attributes import BOOL, ORIENTATION, POSITION
from sketchanim.anim.history import History
from sketchanim.anim.edits import moved_points, scaled, shifted, with_knots, without_knots, without_range
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack
from sketchanim.errors import ArgumentError
from tests.anim.test_anim_model import random_spline
from tests.anim.test_punch_in import one_sided


def setup(seed: int) -> tuple[Player, np.random.Generator]:
    rng = np.random.default_rng(seed)
    scene = Scene()
    scene.add("box")
    scene.add("lamp", "light")
    tracks = [ContinuousTrack("box.position", POSITION, random_spline(rng, 4, 3, 12), 0.005),
              ContinuousTrack("box.orientation", ORIENTATION, random_spline(rng, 4, 4, 9), 0.5),
              DiscreteTrack("lamp.on", BOOL, [0.5, 1.5, 3.0], [False, True, False])]
    return Player(scene, tracks), rng


EDITS = ["move", "insert", "remove", "shift", "scale", "delete", "drop"]


@given(st.integers(0, 2**32 - 1), st.lists(st.sampled_from(EDITS), min_size=1, max_size=12))
@settings(max_examples=40)
def test_undo_then_redo_round_trips_any_sequence_of_edits(seed, edits) -> None:
    player, rng = setup(seed)
    history = History(player)
    start = dict(player.tracks)
    states = [dict(player.tracks)]
    for name in edits:
        path = ["box.position", "box.orientation", "lamp.on"][rng.integers(3)]
        track = player.tracks.get(path)
        if track is None:
            continue
        if isinstance(track, DiscreteTrack) and name in ("move", "insert", "remove"):
            name = "shift"
        n = len(getattr(track.spline, "c", [])) if isinstance(track, ContinuousTrack) else 0
        if name == "move":
            history.edit(path, name, moved_points, {int(rng.integers(n)): rng.normal(0, 1, track.type.dim) + [0, 0, 0, 2][: track.type.dim]})
        elif name == "insert":
            history.edit(path, name, with_knots, [float(rng.uniform(track.start + 0.01, track.end - 0.01))])
        elif name == "remove":
            k = track.spline.k
            if len(track.spline.c) > k + 1:
                history.edit(path, name, without_knots, [int(rng.integers(k + 1, len(track.spline.t) - k - 1))])
        elif name == "shift":
            history.edit(path, name, shifted, float(rng.normal()))
        elif name == "scale":
            history.edit(path, name, scaled, float(rng.uniform(0.5, 2)), float(rng.normal()))
        elif name == "delete":
            a = float(rng.uniform(0, 4))
            history.edit(path, name, without_range, a, a + float(rng.uniform(0.1, 1)))
        else:
            history.apply(name, {path: None})
        states.append(dict(player.tracks))
    end = dict(player.tracks)
    while history.undo():
        pass
    assert player.tracks == start and all(player.tracks[p] is start[p] for p in start)
    while history.redo():
        pass
    assert player.tracks.keys() == end.keys() and all(player.tracks[p] is end[p] for p in end)
    assert len(history.done) == len(states) - 1
    player.seek(1.0)
    player.apply()                                   # the player re-packs what the edits left


def test_edits_do_what_they_say() -> None:
    player, rng = setup(3)
    track = player.tracks["box.position"]
    t = np.linspace(track.start, track.end, 200)
    more = with_knots(track, [2.2])
    assert more.n_coefficients == track.n_coefficients + 1 and np.allclose(more.evaluate(t), track.evaluate(t))
    less = without_knots(more, [int(np.searchsorted(more.spline.t, 2.2))])
    assert less.n_coefficients == track.n_coefficients
    assert np.allclose(less.evaluate(t), track.evaluate(t), atol=1e-8)        # removing what was inserted
    moved = shifted(track, 1.5)
    assert np.allclose(moved.evaluate(t + 1.5), track.evaluate(t))
    slow = scaled(track, 2.0, pivot=1.0)
    assert np.allclose(slow.evaluate(1.0 + 2.0 * (t - 1.0)), track.evaluate(t))
    cut = without_range(track, 1.0, 3.0)
    out = t[(t < 1.0) | (t > 3.0)]
    assert np.allclose(cut.evaluate(out), track.evaluate(out))
    for x in (1.0, 3.0):
        v0, d0, v1, d1 = one_sided(cut.spline, x)
        assert np.allclose(v0, v1) and np.allclose(d0, d1)
    with pytest.raises(ArgumentError, match="control point 99 of 12"):
        moved_points(track, {99: [0, 0, 0]})
    with pytest.raises(ArgumentError, match="not an interior knot"):
        without_knots(track, [0])
    with pytest.raises(ArgumentError, match="time scale must be > 0"):
        scaled(track, 0.0)
    with pytest.raises(ArgumentError, match="needs t0 < t1"):
        without_range(track, 2.0, 1.0)
    history = History(player)
    with pytest.raises(ArgumentError, match="no track for 'lamp.color'"):
        history.edit("lamp.color", "move", moved_points, {0: [0, 0, 0]})
    assert history.undo() is None and history.redo() is None
