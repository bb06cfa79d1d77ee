"""Clips reduced within a distance in the world: every joint, and every point at the
shell distance from a joint, within tolerance at every frame, checked by placing such
points independently of the reducer's own error measure."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from clips import clips
from sketchanim.mocap.clip_reduction import ReducedClip
from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Clip
from sketchanim.mocap.world_reduction import reduce_clip_world
from sketchanim.cli import app
from sketchanim.formats.bvh import read_bvh, write_bvh
from sketchanim.formats.clip_files import read_clip


def shell_points(clip: Clip, shell: float, directions: np.ndarray) -> np.ndarray:
    """World positions (n, J, k, 3) of points ``shell`` from each joint along
    ``directions`` (k, 3) of its own frame."""
    turns, positions = world_pose(clip.skeleton, clip.rotations, clip.translations)
    return np.stack([positions[:, j, None] + shell * np.stack([turn.apply(d) for d in directions], axis=1)
                     for j, turn in enumerate(turns)], axis=1)


def assert_world_within(reduced: ReducedClip, source: Clip, tol: float, shell: float, slack: float = 1e-9) -> None:
    """Every joint and 26 points on its shell within ``tol`` of the source at every frame."""
    directions = np.array([[x, y, z] for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if x or y or z],
                          dtype=float)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    ours = reduced.sample(source.times)
    joints = np.linalg.norm(ours.world_positions() - source.world_positions(), axis=-1)
    assert joints.max() <= tol * (1 + slack), joints.max()
    points = np.linalg.norm(shell_points(ours, shell, directions) - shell_points(source, shell, directions), axis=-1)
    assert points.max() <= tol * (1 + slack) + 1e-12, points.max()


@settings(max_examples=15, deadline=None)
@given(clips(), st.sampled_from([0.2, 1.0, 3.0]), st.sampled_from([0.0, 3.0, 10.0]))
def test_every_joint_and_shell_point_within_tolerance(clip: Clip, tol: float, shell: float) -> None:
    reduced = reduce_clip_world(clip, tol, shell)
    assert_world_within(reduced, clip, tol, shell)


def test_a_joint_translated_beyond_its_offset_counts_at_its_translation() -> None:
    """A child whose translation channels carry it 30 units from a parent whose offset
    says 0.1: the parent's turn moves it as a 30-unit bone (found by the property test
    above: the reach from offsets alone broke the provable angles)."""
    from sketchanim.motion.skeleton import Skeleton

    s = Skeleton(("root", "hand"), (-1, 0), np.array([[0.0, 0, 0], [0.1, 0, 0]]))
    t = np.arange(300) / 60
    rng = np.random.default_rng(3)
    clip = Clip.still(s, t)
    clip.translating[:] = True
    clip.translations[:, 1] = np.stack([30 * np.cos(t), 5 * np.sin(3 * t), 0 * t], axis=1)
    angles = 40 * np.sin(2 * t)[:, None] + rng.normal(0, 0.3, (len(t), 1))
    clip.rotations[:, 0] = Rotation.from_euler("Y", angles, degrees=True).as_quat()
    for shell in (0.0, 3.0):
        assert_world_within(reduce_clip_world(clip, 0.2, shell), clip, 0.2, shell)


def test_a_far_reaching_joint_gets_a_finer_angle_than_a_leaf() -> None:
    from sketchanim.motion.skeleton import Skeleton

    s = Skeleton(("hips", "knee", "ankle", "toe"), (-1, 0, 1, 2),
                 np.array([[0.0, 90, 0], [0, -45, 0], [0, -45, 0], [0, 0, 5.0]]))
    t = np.arange(600) / 120
    rng = np.random.default_rng(1)
    clip = Clip.still(s, t)
    for j in range(4):                               # the same noisy swing on every joint
        angles = 20 * np.sin(2 * t + j)[:, None] + rng.normal(0, 0.05, (len(t), 1))
        clip.rotations[:, j] = Rotation.from_euler("X", angles, degrees=True).as_quat()
    reduced = reduce_clip_world(clip, 0.5, 3.0)
    rotations = [reduced.joint_track(j, "orientation") for j in range(4)]
    angles = [r.reduction.tol[0] for r in rotations]                  # the angle each joint was given
    assert angles[0] < angles[1] < angles[2] < angles[3]
    assert all(r.reduction.max_error[0] <= a for r, a in zip(rotations, angles))
    assert rotations[0].track.n_coefficients > rotations[3].track.n_coefficients
    assert_world_within(reduced, clip, 0.5, 3.0)


def test_command_line_world_round_trip_through_bvh(tmp_path: Path) -> None:
    from hypothesis import find

    clip = find(clips(), lambda c: len(c.times) > 60 and len(c.skeleton) > 3 and c.guess_unit_m() is None)
    source = write_bvh(tmp_path / "in.bvh", clip)
    runner = CliRunner()
    result = runner.invoke(app, ["reduce", str(source), "-o", str(tmp_path / "out.bvh"), "--world", "--tol", "0.5"])
    assert result.exit_code == 2 and "--world: cannot tell the clip's units" in result.output
    result = runner.invoke(app, ["reduce", str(source), "-o", str(tmp_path / "out.bvh"), "--world", "--units", "cm",
                                 "--tol", "0.5", "--shell", "3"])
    assert result.exit_code == 0, result.output
    assert "3 cm shell within 0.5 units" in result.output
    back, original = read_bvh(tmp_path / "out.bvh"), read_bvh(source)
    directions = np.eye(3)
    points = np.linalg.norm(shell_points(back, 3.0, directions) - shell_points(original, 3.0, directions), axis=-1)
    assert points.max() <= 0.5 + 1e-5                                    # + the text's 10 significant digits


@pytest.mark.realdata
@pytest.mark.parametrize("name", ["bvh/bandai1_walk_happy_001.bvh", "bvh/xia_angry_13_000.bvh", "amc/cmu_11_01.amc"])
def test_real_clips_within_half_a_centimetre_in_the_world(data_dir: Path, name: str) -> None:
    clip = read_clip(data_dir / name)
    unit = clip.guess_unit_m()
    assert unit is not None
    tol, shell = 0.005 / unit, 0.03 / unit
    assert_world_within(reduce_clip_world(clip, tol, shell), clip, tol, shell)
