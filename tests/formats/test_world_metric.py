"""The world error the compact-export benchmark and tests measure every file by
(tests/world_metric.py): exact on known misses, and nil (to float32) on the source's own
frames as three.js plays them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from clips import clips
from sketchanim.formats.clip_files import read_clip
from sketchanim.motion.skeleton import Clip, Skeleton
from web_peers import source_glb
from world_metric import SHELL_M, clip_unit_m, file_world_error, source_world, world_error


def _played(clip: Clip) -> tuple[dict, np.ndarray, np.ndarray]:
    q, p = source_world(clip)
    return {n: {"quaternion": q[:, j].copy(), "position": p[:, j].copy()} for j, n in enumerate(clip.skeleton.names)}, q, p


@settings(max_examples=40, deadline=None)
@given(clips(), st.data(), st.floats(1e-4, 1.0), st.floats(-0.05, 0.05))
def test_a_turned_joint_misses_its_points_by_the_chord_and_a_moved_one_by_the_move(clip: Clip, data: st.DataObject,
                                                                                 angle: float, move: float) -> None:
    played, q, _ = _played(clip)
    j = data.draw(st.integers(0, len(clip.skeleton) - 1))
    f = data.draw(st.integers(0, len(clip.times) - 1))
    axis = Rotation.random(random_state=data.draw(st.integers(0, 2**16))).apply([1.0, 0, 0])
    name = clip.skeleton.names[j]
    played[name]["quaternion"][f] = (Rotation.from_rotvec(angle * axis) * Rotation.from_quat(q[f, j])).as_quat()
    error = world_error(clip, played)
    # each local axis v moves by the chord 2 sin(a / 2) |v across the turn's axis|
    local = Rotation.from_quat(q[f, j]).as_matrix().T                        # rows: the joint's axes in the world
    across = np.linalg.norm(local - np.outer(local @ axis, axis), axis=1)
    assert error.joint_cm <= 1e-9
    assert error.point_cm == pytest.approx(100 * SHELL_M * 2 * np.sin(angle / 2) * across.max(), rel=1e-6, abs=1e-9)
    played[name]["position"][f] += [0.0, move, 0.0]
    both = world_error(clip, played)
    assert both.joint_cm == pytest.approx(100 * abs(move), abs=1e-9)
    assert both.point_cm <= error.point_cm + both.joint_cm + 1e-9
    played[name]["quaternion"][f] = q[f, j]
    moved = world_error(clip, played)                                              # the points move with the joint
    assert moved.joint_cm == pytest.approx(100 * abs(move), abs=1e-9)
    assert moved.point_cm == pytest.approx(moved.joint_cm, abs=1e-9)


def test_a_file_in_other_units_is_scaled_and_a_missing_joint_is_named() -> None:
    skeleton = Skeleton(("hips", "knee", "foot"), (-1, 0, 1), np.array([[0.0, 90, 0], [0, -45, 0], [0, -45, 0]]))
    clip = Clip.still(skeleton, np.arange(3) / 30)
    played, _, _ = _played(clip)
    half = {n: {"quaternion": v["quaternion"], "position": v["position"] / 2} for n, v in played.items()}
    assert world_error(clip, half, file_unit_m=2.0).joint_cm <= 1e-9
    name = clip.skeleton.names[-1]
    del played[name]
    with pytest.raises(ValueError, match=f"no node named '{name}'"):
        world_error(clip, played)


@pytest.mark.realdata
def test_the_real_clips_own_frames_play_without_error(real_clips: list[Path], tmp_path: Path) -> None:
    for source in real_clips:
        clip = read_clip(source)
        glb = tmp_path / f"{source.stem}.glb"
        glb.write_bytes(source_glb(clip, clip_unit_m(clip)))
        error = file_world_error(clip, glb)
        assert error.point_cm <= 1e-3 and error.joint_cm <= 1e-3, (source.name, error)      # float32 only
