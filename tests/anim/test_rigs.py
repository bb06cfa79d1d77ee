"""Rigs in the model: a chain's or walker's pose is its solver's on the goal as the player
plays it at the ticks (a chain's relative to its base), between ticks interpolated, over a
second past the last key; bad structure is refused naming the attribute."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.rigs import LEAD, SETTLE, chain, rig_clip, rigs, ticks
from sketchanim.anim.scene import Scene
from sketchanim.anim.layers import compose
from sketchanim.anim.tracks import ContinuousTrack, Take, Track
from sketchanim.errors import ArgumentError
from sketchanim.motion import ik, walk
from sketchanim.reducer.metric import rotation_angle


def line(path: str, start: list[float], end: list[float], t1: float) -> ContinuousTrack:
    return ContinuousTrack(path, POSITION, BSpline(np.r_[[0.0] * 2, [t1] * 2], np.array([start, end]), 1), 0.005)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-1.5, 1.5), min_size=6, max_size=6), st.floats(0.1, 3.0), st.booleans())
def test_a_chain_is_its_solver_on_the_goal_from_its_base(ends: list[float], t1: float, moving_base: bool) -> None:
    scene = Scene()
    scene.add("arm", "chain")
    scene.set("arm.position", [0.2, 0.0, -0.3])
    tracks: dict[str, Track] = {"arm.goal": line("arm.goal", ends[:3], ends[3:], t1)}
    if moving_base:
        tracks["arm.position"] = line("arm.position", [0.2, 0.0, -0.3], [0.5, 0.1, 0.0], t1 / 2)
    at = ticks(tracks)
    assert at[0] == 0 and at[-1] >= t1 + SETTLE - 1e-9 and np.allclose(np.diff(at), 1 / ik.RATE)
    clip = rig_clip(scene, tracks, "arm")
    held = np.r_[np.zeros(LEAD), at]                                      # LEAD ticks at the start, then on
    base = tracks["arm.position"].evaluate(held) if moving_base else np.tile([0.2, 0.0, -0.3], (len(held), 1))
    expected = ik.solve(chain(scene, "arm"), tracks["arm.goal"].evaluate(held) - base)[LEAD:]
    assert np.array_equal(clip.rotations[:, :-1], expected)
    assert np.allclose(clip.world_positions()[:, 0], base[LEAD:])
    mid = (at[:-1] + at[1:]) / 2                                           # between ticks: slerped
    between = rig_clip(scene, tracks, "arm", mid)
    for j in range(len(clip.skeleton) - 1):
        halves = rotation_angle(between.rotations[:, j], clip.rotations[:-1, j])
        whole = rotation_angle(clip.rotations[1:, j], clip.rotations[:-1, j])
        assert np.allclose(halves, whole / 2, atol=1e-9)


def test_a_walker_is_the_walk_of_its_goal() -> None:
    scene = Scene()
    scene.add("bob", "walker")
    scene.set("bob.height", [1.6])
    tracks: dict[str, Track] = {"bob.goal": line("bob.goal", [0.0, 0.0, 0.0], [3.0, 0.0, 1.0], 3.0)}
    clip = rig_clip(scene, tracks, "bob")
    done = walk.walk(walk.humanoid(1.6), tracks["bob.goal"].evaluate(np.r_[np.zeros(LEAD), ticks(tracks)]))
    assert clip.skeleton.names == walk.humanoid(1.6).names
    assert np.array_equal(clip.rotations, done.rotations[LEAD:])
    assert np.array_equal(clip.translations[:, 0], done.root[LEAD:])
    assert np.all(np.isfinite(clip.world_positions()))


def test_rigs_and_their_errors() -> None:
    scene = Scene()
    scene.add("box")
    scene.add("arm", "chain")
    scene.add("bob", "walker")
    assert rigs(scene) == ["arm", "bob"]
    with pytest.raises(ArgumentError, match="'box' is not a chain or a walker"):
        rig_clip(scene, {}, "box")
    scene.set("bob.height", [0.0])
    with pytest.raises(ArgumentError, match="bob.height"):
        rig_clip(scene, {}, "bob")
    scene.set("arm.lengths", [0.5] + [0.0] * 7)
    with pytest.raises(ArgumentError, match="arm.lengths"):
        rig_clip(scene, {}, "arm")


@settings(max_examples=10, deadline=None)
@given(st.floats(0.8, 2.5), st.floats(0.3, 1.5), st.floats(-1.0, 1.0))
def test_a_punch_in_on_a_walkers_path_moves_the_walk_from_there_on_only(start: float, length: float, swerve: float) -> None:
    """Re-recording part of a walker's path: the walk follows the new path and, the pose being
    stepped forward in time, nothing before the punch-in changes."""
    t = np.arange(int(4 * ik.RATE) + 1) / ik.RATE
    first = Take(t, np.c_[1.1 * t, 0 * t, 0.3 * np.sin(t)])
    part = t[(t >= start) & (t <= start + length)]
    again = Take(part, np.c_[1.1 * part, 0 * part, 0.3 * np.sin(part) + swerve * np.sin(np.pi * (part - start) / length)])
    scene = Scene()
    scene.add("bob", "walker")
    before = {"bob.goal": ContinuousTrack("bob.goal", POSITION, compose(POSITION, [first], 0.005, 4), 0.005, (first,))}
    after = {"bob.goal": ContinuousTrack("bob.goal", POSITION, compose(POSITION, [first, again], 0.005, 4), 0.005,
                                         (first, again))}
    old, new = rig_clip(scene, before, "bob"), rig_clip(scene, after, "bob")
    changed = np.flatnonzero(np.any(np.abs(new.world_positions() - old.world_positions()) > 0, axis=(1, 2)))
    curve_changed = np.flatnonzero(np.any(np.abs(after["bob.goal"].evaluate(new.times)
                                                 - before["bob.goal"].evaluate(new.times)) > 0, axis=1))
    if abs(swerve) > 0.05:
        assert changed.size and curve_changed.size
    if changed.size:
        assert changed[0] >= curve_changed[0]                              # nothing before the goal changed
    hips = np.linalg.norm(new.translations[:, 0, [0, 2]] - after["bob.goal"].evaluate(new.times)[:, [0, 2]], axis=1)
    assert hips[new.times <= t[-1]].max() < 0.6                           # the walk follows the new path
