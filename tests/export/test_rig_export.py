"""Chains and walkers baked on export: the .glb passes the Khronos validator and plays,
in three.js and through the Blender add-on, the pose the model derives (every joint within
the goal's tolerance in the world at every tick, float32 included), its goal as the node
``<object>.goal``; the BVH and USD files hold the same pose; a walker's planted feet stay
planted in the file; baking is a pure function of the tracks (an edited goal moves the
figure)."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clips import played as played32
from clips import validate
from sketchanim.anim.attributes import POSITION
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.rigs import LEAD, rig_clip, ticks
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.export.rig_bake import WALKER_SHARE, SHELL, bake
from sketchanim.export.scene_bvh import skeleton_clip
from sketchanim.export.scene_gltf import left_out, scene_glb
from sketchanim.formats.bvh import read_bvh, write_bvh
from sketchanim.motion import walk
from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Clip
from threejs_client import three_play

RATE = 120.0
#: What float32 keys and times may add to a baked joint's world position, metres (values of
#: a few metres: about 1e-7 each, summed down a chain and over a key's time rounding).
FLOAT32 = 1e-4


def goal_track(path: str, t: np.ndarray, points: np.ndarray) -> ContinuousTrack:
    return ContinuousTrack(path, POSITION, reduce_samples(POSITION, t, points, POSITION.tol, 4, "global"), POSITION.tol)


def reaching(t: np.ndarray, reach: float, swell: float = 1.4) -> np.ndarray:
    """A goal looping around a chain's base, leaving its reach in the middle."""
    out = reach * (0.55 + (swell - 0.55) * np.exp(-(((t - t.mean()) / (0.15 * t[-1])) ** 4)))
    angle, height = 0.9 * t, 0.5 + 0.4 * np.sin(1.7 * t)
    return out[:, None] * np.c_[np.cos(angle) * np.sqrt(1 - height ** 2), height, np.sin(angle) * np.sqrt(1 - height ** 2)]


def walking(t: np.ndarray) -> np.ndarray:
    """A floor path: an arc at about 1.2 m/s, a pause, on at a brisk walk."""
    s = np.where(t < 2.5, 1.2 * t, np.where(t < 3.5, 3.0, 3.0 + 1.6 * (t - 3.5)))
    return np.c_[3 * np.sin(s / 3), 0 * s, 3 * (1 - np.cos(s / 3))]


def scene_of(t: np.ndarray) -> tuple[Scene, dict[str, Track]]:
    scene = Scene()
    scene.add("arm", "chain")
    scene.set("arm.position", [1.0, 0.0, -1.0])
    scene.add("walker", "walker")
    reach = float(np.sum(scene.get("arm.lengths")))
    tracks: dict[str, Track] = {"arm.goal": goal_track("arm.goal", t, [1.0, 0.0, -1.0] + reaching(t, reach)),
                                "walker.goal": goal_track("walker.goal", t, walking(t))}
    return scene, tracks


def played_world(played: dict, clip: Clip, name: str) -> np.ndarray:
    """Joint world positions (n, J, 3) of the rig ``name`` as a client played its nodes."""
    names = [f"{name}.{j}" for j in clip.skeleton.names]
    rotations = np.stack([played[n]["quaternion"] for n in names], axis=1)
    translations = np.stack([played[n]["position"] for n in names], axis=1)
    return world_pose(clip.skeleton, rotations, translations)[1]


def test_rigs_bake_into_a_valid_glb_that_three_js_plays_within_tolerance(tmp_path: Path) -> None:
    t = np.arange(int(4 * RATE) + 1) / RATE
    scene, tracks = scene_of(t)
    glb, skipped = scene_glb(scene, tracks)
    assert skipped == [] and left_out(scene, tracks) == []
    frames, _ = scene_glb(scene, tracks, keys="frames")
    (tmp_path / "rigs.glb").write_bytes(glb)
    (tmp_path / "rigs.frames.glb").write_bytes(frames)
    for report in validate(tmp_path / "rigs.glb", tmp_path / "rigs.frames.glb"):
        assert report["numErrors"] == 0, report["messages"][:5]
    at = ticks(tracks)
    for file in ("rigs.glb", "rigs.frames.glb"):
        played = three_play(tmp_path / file, at)
        for name in ("arm", "walker"):
            clip = rig_clip(scene, tracks, name)
            miss = np.linalg.norm(played_world(played, clip, name) - clip.world_positions(), axis=-1)
            within = POSITION.tol * (WALKER_SHARE if name == "walker" else 1.0)
            assert miss.max() <= within + FLOAT32, (file, name, float(miss.max()))
            keyed = slice(None) if file == "rigs.glb" else np.isclose(at * 30, np.round(at * 30))   # frames: at 30 Hz
            goal = played[f"{name}.goal"]["position"][keyed] - tracks[f"{name}.goal"].evaluate(at[keyed])
            assert np.linalg.norm(goal, axis=-1).max() <= POSITION.tol, (file, name)


@settings(max_examples=12, deadline=None)
@given(st.integers(2, 8), st.floats(0.6, 1.6), st.floats(0.3, 2.0), st.integers(0, 2 ** 16))
def test_a_baked_chain_plays_in_float32_within_its_goals_tolerance(joints: int, swell: float, seconds: float,
                                                                    seed: int) -> None:
    """Any chain, any goal path (in and out of reach): the file's float32 curves, played by
    the spec's rules, keep every joint within the goal's tolerance of the derived pose."""
    rng = np.random.default_rng(seed)
    scene = Scene()
    scene.add("arm", "chain")
    lengths = np.zeros(8)
    lengths[:joints] = rng.uniform(0.1, 0.6, joints)
    scene.set("arm.lengths", lengths)
    scene.set("arm.hinges", (rng.random(8) < 0.5).astype(float))
    scene.set("arm.limits", rng.uniform(20, 180, 8))
    t = np.arange(int(seconds * RATE) + 2) / RATE
    tracks: dict[str, Track] = {"arm.goal": goal_track("arm.goal", t, reaching(t, float(lengths.sum()), swell))}
    baked = bake(scene, tracks, "arm")
    assert baked.reduced.world_errors(baked.clip, SHELL).max() <= POSITION.tol
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "arm.glb"
        out.write_bytes(scene_glb(scene, tracks)[0])
        at = baked.clip.times
        names = baked.clip.skeleton.names
        rotations = np.stack([played32(out, f"arm.{n}", "rotation", at) if baked.clip.rotating[j]
                              else baked.clip.rotations[:, j] for j, n in enumerate(names)], axis=1)
        translations = baked.clip.translations.copy()
        translations[:, 0] = played32(out, "arm.j1", "translation", at)
    got = world_pose(baked.clip.skeleton, rotations, translations)[1]
    miss = np.linalg.norm(got - baked.clip.world_positions(), axis=-1)
    assert miss.max() <= POSITION.tol + FLOAT32, float(miss.max())


def test_editing_the_goal_moves_the_figure_and_nothing_else() -> None:
    t = np.arange(int(3 * RATE) + 1) / RATE
    scene, tracks = scene_of(t)
    before = {name: rig_clip(scene, tracks, name).world_positions() for name in ("arm", "walker")}
    again = {name: rig_clip(scene, tracks, name).world_positions() for name in ("arm", "walker")}
    assert all(np.array_equal(before[n], again[n]) for n in before)           # a pure function of the tracks
    moved = dict(tracks, **{"arm.goal": goal_track("arm.goal", t, [1.0, 0.0, -1.0] + reaching(t, 1.65, 0.9))})
    after = rig_clip(scene, moved, "arm").world_positions()
    assert np.abs(after - before["arm"]).max() > 0.05
    assert np.array_equal(rig_clip(scene, moved, "walker").world_positions(), before["walker"])


def test_bvh_and_usd_hold_the_derived_pose(tmp_path: Path) -> None:
    t = np.arange(int(4 * RATE) + 1) / RATE
    scene, tracks = scene_of(t)
    clip = skeleton_clip(scene, tracks, 60.0)
    write_bvh(tmp_path / "rigs.bvh", clip)
    back = read_bvh(tmp_path / "rigs.bvh")
    assert back.skeleton.names == clip.skeleton.names
    for name in ("arm", "walker"):
        ours = rig_clip(scene, tracks, name, clip.times).world_positions()
        mine = [i for i, n in enumerate(back.skeleton.names) if n.startswith(f"{name}.")]
        got = back.world_positions()[:, mine]
        assert np.abs(got - ours).max() <= 1e-4, name                       # BVH's printed digits
    pytest.importorskip("pxr", reason="usd-core is an optional dependency (scripts/setup installs it)")
    from pxr import Usd, UsdGeom

    from sketchanim.export.scene_usd import scene_usd

    assert scene_usd(tmp_path / "rigs.usda", scene, tracks, 30.0) == []
    stage = Usd.Stage.Open(str(tmp_path / "rigs.usda"))
    arm = rig_clip(scene, tracks, "arm")
    tip = UsdGeom.Xformable(stage.GetPrimAtPath("/arm/j1/j2/j3/j4/j5/tip"))
    for k in (0, 100, 333, len(arm.times) - 1):
        world = np.array(tip.ComputeLocalToWorldTransform(float(arm.times[k] * 30.0)))
        assert np.abs(world[3, :3] - arm.world_positions()[k, -1]).max() <= 1e-9
    goal = stage.GetPrimAtPath("/arm/goal").GetAttribute("xformOp:translate")
    assert np.abs(np.array(goal.Get(30.0)) - tracks["arm.goal"].evaluate([1.0])[0]).max() <= 1e-9


def test_a_walkers_planted_feet_stay_planted_in_the_file(tmp_path: Path) -> None:
    """The lowest node of each foot, sampled at 60 Hz from the .glb as three.js plays it,
    slides at most 2 cm/s (median) while the walk has that foot planted."""
    t = np.arange(int(8 * RATE) + 1) / RATE
    scene, tracks = scene_of(t)
    (tmp_path / "walk.glb").write_bytes(scene_glb(scene, tracks)[0])
    at = ticks(tracks)[::2]
    clip = rig_clip(scene, tracks, "walker")
    world = played_world(three_play(tmp_path / "walk.glb", at), clip, "walker")
    held = np.r_[np.zeros(LEAD), ticks(tracks)]
    stance = walk.walk(clip.skeleton, tracks["walker.goal"].evaluate(held)).stance[LEAD::2]
    for side, toe in enumerate(("l_toe", "r_toe")):
        j = clip.skeleton.index(toe)
        speed = np.linalg.norm(np.diff(world[:, j], axis=0), axis=1) * 60.0
        planted = stance[1:, side] & stance[:-1, side]
        assert planted.sum() > 60, toe
        assert float(np.median(speed[planted])) <= 0.02, (toe, float(np.median(speed[planted])))


def test_blender_plays_the_baked_rigs(tmp_path: Path) -> None:
    from blender_client import joint_locals, blender_play

    t = np.arange(int(3 * RATE) + 1) / RATE
    scene, tracks = scene_of(t)
    (tmp_path / "rigs.glb").write_bytes(scene_glb(scene, tracks)[0])
    at = ticks(tracks)[::4]
    poses = blender_play("addon", tmp_path / "rigs.glb", at)
    for name in ("arm", "walker"):
        clip = rig_clip(scene, tracks, name, at)
        named = Clip(type(clip.skeleton)(tuple(f"{name}.{j}" for j in clip.skeleton.names), clip.skeleton.parents,
                                         clip.skeleton.offsets), at, clip.rotations, clip.translations,
                     clip.rotating, clip.translating, clip.channels, 1.0)
        rotations, translations = joint_locals(poses, named.skeleton, 1.0)
        got = world_pose(clip.skeleton, rotations, translations)[1]
        miss = np.linalg.norm(got - clip.world_positions(), axis=-1)
        assert miss.max() <= POSITION.tol * (WALKER_SHARE if name == "walker" else 1.0) + FLOAT32, name
