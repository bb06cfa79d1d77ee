"""The animation model: scene and attribute paths, tracks, the player."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import BOOL, EVENT, ORIENTATION, POSITION, AttributeType
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack
from sketchanim.errors import ArgumentError


def random_spline(rng: np.random.Generator, order: int, dim: int, n: int, start: float = 0.0) -> BSpline:
    """A clamped spline with ``n`` coefficients, interior knots possibly repeated."""
    inner = np.sort(rng.uniform(start, start + 5, n - order))
    if n > order and rng.random() < 0.5:
        inner[rng.integers(len(inner))] = inner[0]        # a repeated knot
        inner.sort()
    t = np.r_[[start] * order, inner, [start + 5] * order]
    return BSpline(t, rng.normal(0, 1, (n, dim)), order - 1)


def test_scene_paths_types_and_errors_name_the_part() -> None:
    scene = Scene()
    scene.add("box")
    scene.add("lamp", "light")
    scene.add("cam", "camera")
    scene.objects["box"].add("mood", AttributeType.enum(["calm", "angry"]))
    assert "lamp.color" in scene.paths() and "cam.fov" in scene.paths() and "box.mood" in scene.paths()
    scene.set("box.orientation", [0, 0, 3, 4])
    assert np.allclose(scene.get("box.orientation"), [0, 0, 0.6, 0.8])
    scene.set("box.mood", "angry")
    with pytest.raises(ArgumentError, match="no object 'ghost'"):
        scene.get("ghost.position")
    with pytest.raises(ArgumentError, match="has no attribute 'fov'"):
        scene.get("lamp.fov")
    with pytest.raises(ArgumentError, match="lamp.color: must be 3 numbers"):
        scene.set("lamp.color", [1, 2])
    with pytest.raises(ArgumentError, match="must be finite"):
        scene.set("box.position", [0, np.nan, 0])
    with pytest.raises(ArgumentError, match="zero quaternion"):
        scene.set("box.orientation", [0, 0, 0, 0])
    with pytest.raises(ArgumentError, match="one of"):
        scene.set("box.mood", "sad")
    with pytest.raises(ArgumentError, match="not a valid name"):
        scene.add("a.b")
    with pytest.raises(ArgumentError, match="exists already"):
        scene.add("box")
    with pytest.raises(ArgumentError, match="kind"):
        scene.add("x", "dragon")


@given(st.integers(0, 2**32 - 1), st.lists(st.tuples(st.integers(1, 6), st.integers(1, 4)), min_size=1, max_size=8),
       st.floats(-2, 8))
@settings(max_examples=60)
def test_player_evaluates_every_track_as_scipy_does(seed: int, shapes: list[tuple[int, int]], t: float) -> None:
    rng = np.random.default_rng(seed)
    scene = Scene()
    tracks = []
    for i, (order, dim) in enumerate(shapes):
        obj = scene.add(f"o{i}")
        if dim == 4 and order > 1:
            kind = ORIENTATION
        else:
            kind = AttributeType.vector(dim)
            obj.add("v", kind)
        spline = random_spline(rng, order, dim, order + int(rng.integers(0, 12)), start=rng.uniform(-1, 1))
        if kind.is_rotation:
            spline = BSpline(spline.t, spline.c + np.array([0, 0, 0, 5.0]), spline.k)    # away from zero
        tracks.append(ContinuousTrack(f"o{i}.{'orientation' if kind.is_rotation else 'v'}", kind, spline, 1e-3))
    player = Player(scene, tracks)
    got = player.evaluate(t)
    for track in tracks:
        lo, hi = track.spline.t[track.spline.k], track.spline.t[-track.spline.k - 1]
        want = track.spline(np.clip(t, lo, hi))
        if track.type.is_rotation:
            want = want / np.linalg.norm(want)
        np.testing.assert_allclose(got[track.path], want, rtol=1e-12, atol=1e-12 * (1 + np.abs(track.spline.c).max()))
        np.testing.assert_allclose(track.evaluate([t])[0], got[track.path], rtol=1e-12, atol=1e-12)


def test_apply_skips_manipulated_paths_and_steps_discrete_tracks() -> None:
    scene = Scene()
    scene.add("box")
    scene.add("lamp", "light")
    line = BSpline(np.r_[[0.0] * 2, [4.0] * 2], np.array([[0.0, 0, 0], [4.0, 0, 0]]), 1)
    player = Player(scene, [ContinuousTrack("box.position", POSITION, line, 0.005),
                            ContinuousTrack("lamp.position", POSITION, line, 0.005),
                            DiscreteTrack("lamp.on", BOOL, [1.0, 3.0], [False, True])])
    scene.set("box.position", [9.0, 9.0, 9.0])
    player.seek(2.0)
    player.apply(skip=["box.position"])                    # the user holds the box
    assert scene.get("box.position").tolist() == [9.0, 9.0, 9.0]
    assert scene.get("lamp.position").tolist() == [2.0, 0.0, 0.0]
    assert scene.get("lamp.on") is False
    player.seek(3.5)
    player.apply()
    assert scene.get("box.position").tolist() == [3.5, 0.0, 0.0] and scene.get("lamp.on") is True
    with pytest.raises(ArgumentError, match="is position, the track is bool"):
        player.add(DiscreteTrack("box.position", BOOL))


def test_events_fire_once_per_pass_forwards_backwards_and_across_the_loop() -> None:
    scene = Scene()
    obj = scene.add("box")
    obj.add("hit", EVENT)
    line = BSpline(np.r_[[0.0] * 2, [4.0] * 2], np.zeros((2, 3)), 1)
    player = Player(scene, [ContinuousTrack("box.position", POSITION, line, 0.005),
                            DiscreteTrack("box.hit", EVENT, [1.0, 3.0], ["a", "b"])])
    fired = []
    for _ in range(8):                                     # 0 -> 4 in steps of 0.5
        player.advance(0.5)
        fired += [label for _, _, label in player.apply()]
    assert fired == ["a", "b"] and player.time == 4.0      # stops at the end
    player.loop = True
    player.seek(3.5)
    player.advance(1.0)                                    # 3.5 -> 0.5 across the wrap: nothing there
    assert player.time == 0.5 and player.apply() == []
    player.seek(2.5)
    player.advance(2.0)                                    # 2.5 -> 0.5: passes b, wraps
    assert [e[2] for e in player.apply()] == ["b"]
    player.speed = -1.0
    player.seek(3.5)
    player.advance(3.0)                                    # backwards 3.5 -> 0.5: b then a
    assert [e[2] for e in player.apply()] == ["b", "a"]
    player.seek(1.0)
    assert player.apply() == []                            # scrubbing fires nothing
    with pytest.raises(ArgumentError, match="finite"):
        player.seek(float("nan"))


def test_discrete_tracks_check_their_values_and_times() -> None:
    with pytest.raises(ArgumentError, match="lamp.on: a bool attribute takes"):
        DiscreteTrack("lamp.on", BOOL, [0.0], ["yes"])
    with pytest.raises(ArgumentError, match="backwards"):
        DiscreteTrack("lamp.on", BOOL, [1.0, 0.0], [True, False])
    with pytest.raises(ArgumentError, match="discrete type"):
        DiscreteTrack("box.position", POSITION)
    track = DiscreteTrack("lamp.on", BOOL)
    track.add(2.0, True)
    track.add(1.0, False)
    track.add(2.0, False)                                  # after the one already at 2.0
    assert track.times == [1.0, 2.0, 2.0] and track.value_at(2.0) is False
    assert track.between(0.0, 2.0) == [(1.0, False), (2.0, True), (2.0, False)]
