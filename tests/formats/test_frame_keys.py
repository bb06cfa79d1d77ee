"""``keys="frames"``: the same curves as LINEAR keys at frames, for importers that drop
CUBICSPLINE tangents (Blender's own). Played as any glTF client plays LINEAR keys
(spherically, or component-wise and normalised as Blender's F-curves do), in float32,
every source frame is within the asked tolerance; keys the neighbours reproduce are
dropped."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from clips import clips, linear_play32, samplers, validate
from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.cli import app
from sketchanim.formats.bvh import write_bvh
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import read_clip
from sketchanim.reducer.linear_keys import linear_keys, played_at
from sketchanim.reducer.metric import rotation_angle

TOL, ROT_TOL = 0.5, 0.5
runner = CliRunner()


def assert_frames_within(path: Path, clip: Clip, tol: float, rot_tol: float) -> None:
    """Every LINEAR channel played at every source frame, both ways for rotations,
    within the asked tolerance of the source."""
    channels = samplers(path)
    for j, name in enumerate(clip.skeleton.names):
        if clip.rotating[j]:
            kind, times, keys = channels[(name, "rotation")]
            assert kind == "LINEAR"
            for spherical in (True, False):
                played = linear_play32(times, keys, clip.times, True, spherical).astype(float)
                angle = np.degrees(rotation_angle(played, clip.rotations[:, j]))
                assert angle.max() <= rot_tol, (name, spherical, angle.max())
        if clip.translating[j]:
            kind, times, keys = channels[(name, "translation")]
            assert kind == "LINEAR"
            played = linear_play32(times, keys, clip.times, False)
            assert np.linalg.norm(played - clip.translations[:, j], axis=1).max() <= tol, name


@settings(max_examples=8)
@given(clips())
def test_frame_keys_play_within_tolerance_in_any_client(tmp_path_factory: pytest.TempPathFactory, clip: Clip) -> None:
    path = write_reduced(tmp_path_factory.mktemp("frames") / "clip.glb", reduce_clip(clip, TOL, ROT_TOL),
                         keys="frames")
    assert_frames_within(path, clip, TOL, ROT_TOL)
    assert max(float(t[-1]) for _, t, _ in samplers(path).values()) > clip.times[-1]
    (report,) = validate(path)
    assert report["numErrors"] == 0, report["messages"]


@settings(max_examples=60)
@given(st.integers(2, 80), st.integers(0, 2**32 - 1), st.sampled_from([0.0, 1e-3, 0.05, 0.5]), st.booleans())
def test_thinned_keys_reproduce_every_frame(n: int, seed: int, allowance: float, rotation: bool) -> None:
    rng = np.random.default_rng(seed)
    times = np.cumsum(rng.uniform(0.01, 0.1, n))
    values = np.cumsum(rng.normal(0, 0.05, (n, 4 if rotation else 3)) * rng.integers(0, 2, (n, 1)), axis=0)
    if rotation:
        values[:, 3] += 1
        values /= np.linalg.norm(values, axis=1, keepdims=True)
    keep = np.flatnonzero(linear_keys(times, values[None], allowance, rotation=rotation)[0])
    assert keep[0] == 0 and keep[-1] == n - 1 and np.all(np.diff(keep) > 0)
    for spherical in (True, False):
        played = linear_play32(times[keep], values[keep], times, rotation, spherical).astype(float)
        err = rotation_angle(played, values) if rotation else np.linalg.norm(played - values, axis=1)
        assert err.max() <= allowance + 1e-5


@settings(max_examples=60)
@given(st.integers(2, 60), st.integers(0, 2**32 - 1), st.booleans())
def test_keys_played_at_any_time_as_a_client_plays_them(n: int, seed: int, rotation: bool) -> None:
    """``played_at`` (what the compact writer measures sliding with, between frames)
    against the test's own client, at times between, on, before and after the keys."""
    rng = np.random.default_rng(seed)
    times = np.cumsum(rng.uniform(0.01, 0.1, n))
    values = np.cumsum(rng.normal(0, 0.2, (n, 4 if rotation else 3)), axis=0)
    if rotation:                                         # keys on one hemisphere, as every writer puts them
        values[:, 3] += 3
        values /= np.linalg.norm(values, axis=1, keepdims=True)
    keep = rng.random(n) < 0.5
    keep[[0, -1]] = True
    at = np.r_[rng.uniform(times[0] - 0.1, times[-1] + 0.1, 40), times]
    mine = played_at(times, values[None], keep[None], at, rotation)[0]
    for way, spherical in enumerate((True, False)):
        client = linear_play32(times[keep], values[keep], at, rotation, spherical).astype(float)
        if rotation:
            ours = mine[:, way] / np.linalg.norm(mine[:, way], axis=1, keepdims=True)
            assert rotation_angle(ours, client).max() < 1e-5
        else:
            assert np.allclose(mine, client, rtol=1e-5, atol=1e-5)


def test_a_still_joint_gets_two_keys_and_cli_writes_frames(tmp_path: Path) -> None:
    s = Skeleton(("hips", "knee"), (-1, 0), np.array([[0.0, 90, 0], [0, -45, 0]]))
    clip = Clip.still(s, np.arange(90) / 30)
    source = write_bvh(tmp_path / "still.bvh", clip)
    out = tmp_path / "still.glb"
    result = runner.invoke(app, ["reduce", str(source), "-o", str(out), "--tol", "0.5", "--keys", "frames"])
    assert result.exit_code == 0, result.output
    for kind, times, _ in samplers(out).values():
        assert kind == "LINEAR" and len(times) == 2
    result = runner.invoke(app, ["reduce", str(source), "-o", str(out), "--tol", "0.5", "--keys", "bezier"])
    assert result.exit_code == 2 and "--keys: one of curves, frames" in result.output
    result = runner.invoke(app, ["reduce", str(source), "-o", str(out), "--tol", "0.5", "--keys", "frames",
                                 "--rate", "-3"])
    assert result.exit_code == 2 and "--rate" in result.output
    scene = tmp_path / "absent.sketchanim"                 # the rate is refused before the project is opened
    result = runner.invoke(app, ["export", str(scene), "-o", str(tmp_path / "s.glb"), "--keys", "frames",
                                 "--rate", "1e9"])
    assert result.exit_code == 2 and "--rate" in result.output and "1000000" in result.output
    assert not (tmp_path / "s.glb").exists() and not scene.exists()


@pytest.mark.realdata
def test_real_clips_as_frames_within_tolerance(real_clips: list[Path], tmp_path: Path) -> None:
    for source in real_clips:
        clip = read_clip(source)
        tol = 0.005 / clip.guess_unit_m()
        path = write_reduced(tmp_path / f"{source.stem}.glb", reduce_clip(clip, tol, 0.5), keys="frames")
        assert_frames_within(path, clip, tol, 0.5)
