"""Compact clip files (``keys="compact"``): the world bound through quantisation and
meshopt, measured on the file as written (decoded and played by the test's own reader),
constant tracks as their node's values, the Khronos validator, the command line."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from typer.testing import CliRunner

from clips import ROOT, clips, played_pose, samplers, validate, world_misses
from mocap.test_contacts import WALKS, walker_clip
from walk_paths import segments
from world_metric import file_world_error
from sketchanim.cli import app
from sketchanim.errors import ArgumentError
from sketchanim.export.compact_clip import PLANTED_M, compact_clip
from sketchanim.formats.bvh import write_bvh
from sketchanim.formats.clip_files import read_clip
from sketchanim.formats.gltf import Node
from sketchanim.formats.gltf_compact import MESHOPT, CompactChannel, compact_glb, held, roundings
from sketchanim.mocap.contacts import SLIDING_SLACK_M_S, planted, sliding
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.reducer.metric import rotation_angle

DATA = ROOT.parent / "shared" / "data"
REAL = sorted((DATA / "bvh").glob("*.bvh")) + sorted((DATA / "amc").glob("*.amc"))


def world_error(path: Path, clip: Clip, shell: float) -> np.ndarray:
    """Per frame and joint, the file's played joint distance from the source's in the
    world plus the largest move of a point ``shell`` from the joint (any direction)."""
    return world_misses(clip, *played_pose(path, clip.skeleton, clip.times), shell)


@settings(max_examples=40, deadline=None)
@given(clips(), st.floats(0.05, 2.0), st.sampled_from([0.0, 3.0]), st.sampled_from(["found", "none", "given"]),
       st.integers(0, 2**32 - 1))
def test_the_file_as_written_plays_within_the_world_distance(tmp_path_factory, clip, tol, shell, contacts, seed):
    """Whatever frames are held on the ground: those the clip plants, none, or any the
    caller gives (there within the bound the report gives them)."""
    shape = (len(clip.times), len(clip.skeleton))
    held = {"found": None, "none": np.zeros(shape, bool),
            "given": np.random.default_rng(seed).random(shape) < 0.3}[contacts]
    made = compact_clip(clip, tol, shell, contacts=held)
    path = tmp_path_factory.mktemp("c") / "c.glb"
    path.write_bytes(made.glb)
    errors = world_error(path, clip, shell)
    assert errors.max() <= tol * (1 + 1e-6) + 1e-9, (errors.max(), tol)
    assert made.report.max_world_error <= tol
    assert errors.max() <= made.report.max_world_error + made.report.float32_margin + 1e-12   # the report: what plays
    if held is not None:
        assert made.report.planted == held.sum()
        assert errors[held].max(initial=0.0) <= made.report.planted_bound * (1 + 1e-6) + 1e-9


@settings(max_examples=40, deadline=None)
@given(clips(), st.floats(0.01, 0.05), st.floats(0.0, 600.0), st.integers(0, 2**32 - 1))
def test_a_jump_into_the_first_pose_and_late_times_play_within_the_world_distance_or_are_refused(
        tmp_path_factory, clip, tol, start, seed):
    """A take that jumps into its first pose from another (a T-pose), late in a long
    recording: float32 key times move fast points most. The file plays within ``tol`` in
    float32, or the tolerance is refused, naming the frame and the joint it cannot be kept
    at (float32 times may take half of it there, or 16-bit rotations cannot hold it)."""
    clip.rotations[0, clip.rotating] = Rotation.random(int(clip.rotating.sum()), random_state=seed).as_quat()
    clip = replace(clip, times=clip.times + start)
    try:
        made = compact_clip(clip, tol, 3.0)
    except ArgumentError as refused:
        assert re.match(r"tol: .* at frame \d+ .* joint '|tol: .* of joint '.* at frame \d+", str(refused)), refused
        return
    path = tmp_path_factory.mktemp("late") / "c.glb"
    path.write_bytes(made.glb)
    assert world_error(path, clip, 3.0).max() <= tol * (1 + 1e-6), tol


def test_a_tolerance_float32_cannot_keep_is_refused_naming_the_frame_and_joint():
    clip = still_joints()
    late = replace(clip, times=clip.times + 600.0)            # ten minutes into a recording
    with pytest.raises(ArgumentError, match=r"tol: .* at frame \d+ \(60\d.* s\) of joint '(root|arm|hand)'.*float32.*nearer 0"):
        compact_clip(late, 0.001, 3.0)
    assert compact_clip(late, 0.5, 3.0).report.max_world_error <= 0.5          # a tolerance it keeps there


def still_joints() -> Clip:
    """Three joints: the root translating, the first joint turning, the second still in
    a pose that is not the rest (a constant track)."""
    s = Skeleton(("root", "arm", "hand"), (-1, 0, 1), np.array([[0.0, 90, 0], [30.0, 0, 0], [25.0, 0, 0]]))
    t = np.arange(120) / 60
    clip = Clip.still(s, t)
    clip.translations[:, 0] = np.c_[10 * np.sin(t), 90 + 0 * t, 0 * t]
    clip.rotations[:, 1] = Rotation.from_euler("Z", np.sin(3 * t)[:, None]).as_quat()
    clip.rotations[:, 2] = Rotation.from_euler("X", [[40.0]] * len(t), degrees=True).as_quat()
    return replace(clip, translating=np.array([True, False, False]))


def test_a_constant_track_is_its_nodes_value(tmp_path):
    clip = still_joints()
    made = compact_clip(clip, 0.5, 3.0)
    path = tmp_path / "c.glb"
    path.write_bytes(made.glb)
    doc = gl.GLTF2().load_binary(str(path))
    hand = next(n for n in doc.nodes if n.name == "hand")
    animated = set(samplers(path))
    assert animated == {("root", "translation"), ("arm", "rotation")}      # the root does not turn either
    assert made.report.constant_tracks == 2
    angle = Rotation.from_quat(hand.rotation).inv() * Rotation.from_quat(clip.rotations[0, 2])
    assert np.degrees(angle.magnitude()) < 1e-6
    assert world_error(path, clip, 3.0).max() <= 0.5


def test_files_require_meshopt_and_pass_the_validator(tmp_path):
    clip = still_joints()
    path = tmp_path / "c.glb"
    path.write_bytes(compact_clip(clip, 0.5, 3.0).glb)
    report = validate(path)[0]
    assert report["numErrors"] == 0 and report["numWarnings"] == 0, report["messages"]
    doc = gl.GLTF2().load_binary(str(path))
    assert doc.extensionsRequired == [MESHOPT]
    filters = {v.extensions[MESHOPT].get("filter") for v in doc.bufferViews if v.extensions}
    assert filters == {None, "QUATERNION", "EXPONENTIAL"}


@settings(max_examples=30, deadline=None)
@given(st.integers(2, 40), st.integers(0, 2**32 - 1))
def test_keys_of_one_channel_may_each_have_their_own_bits(tmp_path_factory, count, seed):
    rng = np.random.default_rng(seed)
    t = np.arange(count) / 30.0
    q = Rotation.random(count, random_state=seed).as_quat()
    move = rng.normal(0, 10, (count, 3))
    bits = {"rotation": rng.integers(4, 17, count), "translation": rng.integers(2, 25, count)}
    channels = [CompactChannel(0, "rotation", t, q, bits["rotation"]),
                CompactChannel(0, "translation", t, move, bits["translation"])]
    path = tmp_path_factory.mktemp("bits") / "b.glb"
    path.write_bytes(compact_glb([Node("a")], channels))
    read = samplers(path)
    for ch in channels:
        _, times, values = read[("a", ch.path)]
        assert np.allclose(times, t, rtol=0, atol=1e-6)
        one = np.stack([held(v[None], ch.path, int(k))[0] for v, k in zip(ch.values, ch.bits)])
        assert np.array_equal(held(ch.values, ch.path, ch.bits), one)          # each key decoded at its own bits
        assert np.allclose(values, one, rtol=1e-6, atol=1e-6)                  # as the file gives them


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 30), st.integers(0, 2**32 - 1))
def test_a_rounding_picked_is_written_as_itself(tmp_path_factory, count, seed):
    """Every rounding ``roundings`` offers, given as a channel's values, is what the
    file holds once decoded (not rounded again), within a few of the filter's steps of
    the value."""
    rng = np.random.default_rng(seed)
    t = np.arange(count) / 30.0
    values = {"rotation": Rotation.random(count, random_state=seed).as_quat(),
              "translation": rng.normal(0, 10, (count, 3))}
    bits = {"rotation": rng.integers(5, 16, count), "translation": rng.integers(6, 24, count)}
    for path, v in values.items():
        near = roundings(v, path, bits[path])
        valid = ~np.isnan(near[..., 0])
        assert valid.mean() > 0.5
        k = np.argmax(valid & (rng.random(valid.shape) < 0.5), axis=0)
        use = valid[k, np.arange(count)]
        picked = np.where(use[:, None], near[k, np.arange(count)], v)
        file = tmp_path_factory.mktemp("r") / "r.glb"
        file.write_bytes(compact_glb([Node("a")], [CompactChannel(0, path, t, picked, bits[path])]))
        _, _, read = samplers(file)[("a", path)]
        assert np.allclose(read[use], picked[use], rtol=0, atol=1e-7)      # as picked, not rounded again
        if path == "rotation":
            off = rotation_angle(near[valid], np.broadcast_to(v, near.shape)[valid])
            step = np.broadcast_to(1 / np.sqrt(2) / (2.0 ** (bits[path] - 1) - 1), valid.shape)[valid]   # the filter's
        else:
            off = np.abs(near - v).max(axis=-1)[valid]
            step = np.broadcast_to(np.abs(v).max(axis=1) * 2.0 ** (2 - bits[path]), valid.shape)[valid]
        assert (off <= 16 * step).all(), (off / step).max()   # three components a step off, the fourth from them


def test_bad_arguments_are_named():
    clip = still_joints()
    with pytest.raises(Exception, match="tol"):
        compact_clip(clip, 0.0, 3.0)
    with pytest.raises(Exception, match="sharing"):
        compact_clip(clip, 0.5, 3.0, sharing="joint")
    with pytest.raises(ArgumentError, match=r"contacts: must be \(frames, joints\)"):
        compact_clip(clip, 0.5, 3.0, contacts=np.zeros((2, 1), bool))


@pytest.mark.skipif(not REAL, reason="../shared/data is not here")
@pytest.mark.parametrize("source", REAL, ids=lambda p: p.name)
def test_real_clips_play_within_half_a_centimetre_in_the_world_here_and_in_three_js(tmp_path, source):
    clip = read_clip(source)
    clip = replace(clip, unit_m=clip.guess_unit_m())
    tol, shell = 0.005 / clip.unit_m, 0.03 / clip.unit_m
    made = compact_clip(clip, tol, shell)
    path = tmp_path / "c.glb"
    path.write_bytes(made.glb)
    assert world_error(path, clip, shell).max() <= tol * (1 + 1e-6)
    played = file_world_error(clip, path)                 # three.js with its meshopt decoder, in cm
    assert max(played.joint_cm, played.point_cm) <= 0.5 * (1 + 1e-6), played
    report = validate(path)[0]
    assert report["numErrors"] == 0 and report["numWarnings"] == 0, report["messages"]
    raw = 4 * len(clip.times) * sum(len(c) for c in clip.channels)
    assert len(made.glb) < raw or len(clip.times) < 50          # smaller than the frames, but for a few frames


def test_the_command_line_writes_compact_files_and_refuses_other_formats(tmp_path):
    source = tmp_path / "walk.bvh"
    write_bvh(source, still_joints())
    run = CliRunner().invoke(app, ["reduce", str(source), "-o", str(tmp_path / "w.glb"), "--keys", "compact",
                                   "--units", "cm"])
    assert run.exit_code == 0, run.output
    assert "largest world error as played" in run.output and (tmp_path / "w.glb").exists()
    run = CliRunner().invoke(app, ["reduce", str(source), "-o", str(tmp_path / "w.bvh"), "--keys", "compact",
                                   "--units", "cm"])
    assert run.exit_code == 2 and "--keys: compact files are .glb" in run.output, run.output
    assert not (tmp_path / "w.bvh").exists()


def test_the_command_line_holds_planted_feet_unless_told_not_to(tmp_path):
    clip, _ = walker_clip(segments([(1.0, 0.0, 0.0), (2.0, 1.2, 0.0)]))
    source = tmp_path / "walk.bvh"
    write_bvh(source, clip)
    held = {}
    for flags in ([], ["--no-contacts"]):
        out = tmp_path / f"walk{len(flags)}.glb"
        run = CliRunner().invoke(app, ["reduce", str(source), "-o", str(out), "--keys", "compact", "--units", "m",
                                       *flags], env={"COLUMNS": "200"})
        assert run.exit_code == 0, run.output
        held[bool(flags)] = int(re.search(r"held on the ground / their bound / their largest world error +│ +"
                                          r"([\d,]+) /", run.output).group(1).replace(",", ""))
    assert held[False] == planted(replace(read_clip(source), unit_m=1.0)).sum() > 0 and held[True] == 0


@pytest.mark.parametrize(("finest", "refusal"), [(1e-5, "finer than 16 bits hold it"),
                                               (1e-12, "less than twice what float32 may move it")])
def test_a_planted_bound_too_fine_to_keep_ends_the_descent_with_the_last_file(tmp_path, monkeypatch, finest, refusal):
    """A planted bound that 16-bit keys or float32 cannot keep is refused when it is the
    only one; tried after others, none keeping the sliding (a slack below zero), it ends
    the descent: the file is the last one made, within its planted bound."""
    clip, _ = walker_clip(segments([(1.0, 0.0, 0.0), (2.0, 1.2, 0.0)]))
    clip = replace(clip, unit_m=1.0)
    monkeypatch.setattr("sketchanim.export.compact_clip.SLIDING_SLACK_M_S", -np.inf)
    monkeypatch.setattr("sketchanim.export.compact_clip.PLANTED_M", (finest,))
    with pytest.raises(ArgumentError, match=rf"tol: .*{refusal}"):
        compact_clip(clip, 0.01, 0.03)
    monkeypatch.setattr("sketchanim.export.compact_clip.PLANTED_M", (0.005, 0.002, finest))
    made = compact_clip(clip, 0.01, 0.03)
    assert made.report.planted_bound == 0.002
    path = tmp_path / "walk.glb"
    path.write_bytes(made.glb)
    assert world_error(path, clip, 0.03)[planted(clip)].max() <= 0.002 * (1 + 1e-6)


def assert_compact_contacts_kept(tmp_path: Path, clip: Clip, tol: float, shell: float, unit: float) -> None:
    """A compact file's planted joints: within the planted bound it reports (one of
    PLANTED_M, at most ``tol``) on their frames, and sliding (played from the file, at
    60 Hz) no more than the source's plus SLIDING_SLACK_M_S, as its report says."""
    path = tmp_path / "walk.glb"
    made = compact_clip(clip, tol, shell)
    path.write_bytes(made.glb)
    held = planted(clip)
    assert held.any() and made.report.planted == held.sum()
    assert made.report.planted_bound in [min(m / unit, tol) for m in PLANTED_M]
    assert world_error(path, clip, shell)[held].max() <= made.report.planted_bound * (1 + 1e-3)

    def sample(t: np.ndarray) -> Clip:
        return replace(clip, times=t, rotations=(pose := played_pose(path, clip.skeleton, t))[0], translations=pose[1])

    source, export = sliding(clip, contacts=held) * unit, sliding(clip, sample, contacts=held) * unit
    assert export <= source + SLIDING_SLACK_M_S, (source, export)
    # the report's measure is the same
    assert np.allclose(np.array(made.report.sliding) * unit, [source, export], atol=1e-3), (made.report, source,
                                                                                            export)


@pytest.mark.parametrize("tol_cm", [0.5, 1.0])
@pytest.mark.parametrize("name", WALKS)
def test_real_walks_planted_feet_slide_no_more_in_compact_files(tmp_path, name, tol_cm):
    source = DATA / name
    if not source.exists():
        pytest.skip("../shared/data is not here")
    clip = read_clip(source)
    clip = replace(clip, unit_m=clip.guess_unit_m())
    tol, shell = tol_cm / 100 / clip.unit_m, 0.03 / clip.unit_m
    assert_compact_contacts_kept(tmp_path, clip, tol, shell, clip.unit_m)
    free = compact_clip(clip, tol, shell, contacts=np.zeros((len(clip.times), len(clip.skeleton)), bool))
    assert free.report.planted == 0 and free.report.sliding == ()
    assert free.report.max_world_error <= tol


@settings(max_examples=4, deadline=None)
@given(st.floats(0.8, 1.8), st.floats(-0.4, 0.4), st.floats(0.001, 0.015))
def test_generated_walks_planted_feet_slide_no_more_in_compact_files(tmp_path_factory, speed, turn, tol):
    clip, _ = walker_clip(segments([(1.0, 0.0, 0.0), (2.0, speed, 0.0), (2.0, speed, turn)]))
    assert_compact_contacts_kept(tmp_path_factory.mktemp("w"), clip, tol, 0.03, 1.0)
