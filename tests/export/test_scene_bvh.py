"""A scene's skeletons as BVH (:mod:`sketchanim.export.scene_bvh`): the joint objects'
world motion written as a hierarchy of local rotations plays back, through the BVH reader
and forward kinematics, as the scene plays it at every frame."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import ORIENTATION, POSITION, AttributeType
from sketchanim.anim.scene import BONE_PARENT, Scene
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.errors import ArgumentError
from sketchanim.export.scene_bvh import skeleton_clip, skeletons
from sketchanim.formats.bvh import read_bvh, write_bvh
from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Skeleton

FPS = 30.0


def _exact(path: str, kind, times: np.ndarray, values: np.ndarray) -> ContinuousTrack:  # noqa: ANN001
    """A linear curve through ``values`` at ``times``: exact at every frame."""
    knots = np.r_[times[0], times, times[-1]]
    return ContinuousTrack(path, kind, BSpline(knots, values, 1), 1e-6)


@st.composite
def rigs(draw: st.DrawFn) -> tuple[Skeleton, np.ndarray, np.ndarray, np.ndarray]:
    """A random tree of 2 to 7 joints, its offsets, and smooth local rotations over frames."""
    j = draw(st.integers(2, 7))
    parents = (-1,) + tuple(draw(st.integers(0, i - 1)) for i in range(1, j))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    offsets = np.r_[[[0.0, 0, 0]], rng.uniform(-0.5, 0.5, (j - 1, 3))]
    n = draw(st.integers(2, 40))
    times = np.arange(n) / FPS
    phase = rng.uniform(0, 2 * np.pi, (j, 3))
    rotvec = 1.2 * np.sin(2 * times[:, None, None] + phase[None])
    rotations = Rotation.from_rotvec(rotvec.reshape(-1, 3)).as_quat().reshape(n, j, 4)
    translations = np.broadcast_to(offsets, (n, j, 3)).copy()
    translations[:, 0] = np.c_[np.sin(times), 1 + 0 * times, times]
    return Skeleton(tuple(f"j{i}" for i in range(j)), parents, offsets), times, rotations, translations


@settings(max_examples=60, deadline=None)
@given(rig=rigs())
def test_a_skeleton_written_as_bvh_plays_its_joints_world_motion_at_every_frame(rig, tmp_path_factory) -> None:
    skeleton, times, rotations, translations = rig
    turns, positions = world_pose(skeleton, rotations, translations)
    scene, tracks = Scene(), {}
    for i, name in enumerate(skeleton.names):
        obj = scene.add(name)
        if skeleton.parents[i] >= 0:
            up = skeleton.names[skeleton.parents[i]]
            obj.add(BONE_PARENT, AttributeType.enum([up]), up)
        tracks[f"{name}.position"] = _exact(f"{name}.position", POSITION, times, positions[:, i])
        tracks[f"{name}.orientation"] = _exact(f"{name}.orientation", ORIENTATION, times, turns[i].as_quat())
    assert skeletons(scene) == [list(skeleton.names)]
    path = write_bvh(tmp_path_factory.mktemp("bvh") / "rig.bvh", skeleton_clip(scene, tracks, FPS))
    back = read_bvh(path)                       # its joints depth first, as the file lists them
    order = [skeleton.names.index(name) for name in back.skeleton.names]
    assert sorted(order) == list(range(len(order)))
    assert [skeleton.parents[i] for i in order] == [-1 if p < 0 else order[p] for p in back.skeleton.parents]
    assert len(back.times) == len(times)
    turns_back, positions_back = world_pose(back.skeleton, back.rotations, back.translations)
    assert np.abs(positions_back - positions[:, order]).max() <= 1e-6           # BVH's text: 10 digits
    for i, b in zip(order, turns_back):
        assert np.degrees((turns[i].inv() * b).magnitude()).max() <= 1e-5


def test_a_scene_without_a_skeleton_has_no_bvh() -> None:
    scene = Scene()
    scene.add("box")
    assert skeletons(scene) == []
    with pytest.raises(ArgumentError, match="no skeleton"):
        skeleton_clip(scene, {}, FPS)
