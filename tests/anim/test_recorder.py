"""The recorder: samples queued by the caller, reduced by worker processes, tracks out."""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import sketchanim.anim.layers
from sketchanim.anim.attributes import EVENT, ORIENTATION, POSITION
from sketchanim.anim.layers import Overlay
from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.anim.workers import shared_pool
from sketchanim.errors import ArgumentError, SampleError
from sketchanim.reducer.metric import rotation_angle
from sketchanim.reducer.splice import split
from tests.signals import performances


def scene() -> Scene:
    s = Scene()
    s.add("box")
    s.add("lamp", "light")
    s.objects["box"].add("hit", EVENT)
    return s


@given(performances(dims=(3, 3)), st.integers(1, 50))
@settings(max_examples=20)
def test_recorded_tracks_keep_every_sample_within_tolerance(p, batch) -> None:
    sc = scene()
    rec = Recorder(sc)
    rec.arm("box.position", tol=float(p.tol[0]))
    rec.arm("box.orientation", tol=0.5)
    rec.start()
    quats = Rotation.from_rotvec(p.values).as_quat()
    for i in range(0, len(p.times), batch):           # frames and single pushes mixed in time
        for j in range(i, min(i + batch, len(p.times))):
            if j % 2:
                rec.push_frame(p.times[j], np.r_[p.values[j], quats[j]])
            else:
                rec.push("box.position", p.times[j], p.values[j])
                rec.push("box.orientation", p.times[j], quats[j])
    tracks = rec.stop()
    pos, rot = tracks["box.position"], tracks["box.orientation"]
    assert np.abs(pos.evaluate(p.times) - p.values).max() <= p.tol[0] * (1 + 1e-9)
    assert np.degrees(rotation_angle(rot.evaluate(p.times), quats)).max() <= 0.5 * (1 + 1e-9)
    assert len(pos.takes) == 1 and np.array_equal(pos.takes[0].times, p.times)     # raw kept


def test_bad_samples_are_named_and_lose_nothing() -> None:
    sc = scene()
    batches = []
    rec = Recorder(sc, journal=lambda got: batches.extend((path, len(t)) for path, t, _ in got))
    rec.arm("box.position")
    rec.arm("box.hit")
    with pytest.raises(ArgumentError, match="not recording"):
        rec.push("box.position", 0.0, [0, 0, 0])
    rec.start()
    with pytest.raises(ArgumentError, match="cannot arm while recording"):
        rec.arm("lamp.color")
    for i in range(100):
        rec.push("box.position", i / 100, [i / 100, 0, 0])
    with pytest.raises(SampleError, match=r"sample 100, box.position: box.position: must be finite"):
        rec.push("box.position", 1.0, [np.nan, 0, 0])
    with pytest.raises(SampleError, match=r"sample 100, box.position time: time 0.5 must be finite and after 0.99"):
        rec.push("box.position", 0.5, [0, 0, 0])
    with pytest.raises(SampleError, match="frame: needs 3 finite numbers"):
        rec.push_frame(1.0, [1, 2])
    with pytest.raises(SampleError, match="an event carries a label"):
        rec.push("box.hit", 0.3, 7)
    with pytest.raises(ArgumentError, match="'lamp.color' is not armed"):
        rec.push("lamp.color", 0.3, [1, 1, 1])
    rec.push("box.hit", 0.3, "bang")
    rec.push_frame(1.0, [1.0, 0, 0])
    tracks = rec.stop()
    t = np.r_[np.arange(100) / 100, 1.0]
    assert np.abs(tracks["box.position"].evaluate(t)[:, 0] - t).max() <= 0.005
    assert tracks["box.hit"].times == [0.3] and tracks["box.hit"].values == ["bang"]
    assert sum(n for path, n in batches if path == "box.position") == 101


def test_an_attribute_with_one_sample_is_left_as_it_was_without_a_warning() -> None:
    """One sample is no curve: the reducer process skips it (no failure, no warning), the
    recorder leaves that attribute as it was and makes the others' tracks."""
    import warnings

    rec = Recorder(scene())
    rec.arm("box.position")
    rec.arm("box.orientation")
    rec.arm("lamp.color")
    rec.start()
    for i in range(30):
        rec.push("box.position", i / 30, [i / 30, 0, 0])
    rec.push("lamp.color", 0.5, [1.0, 0.5, 0.5])
    rec.push("box.orientation", 0.5, [0.0, 0.0, 0.0, 1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tracks = rec.stop()
    assert set(tracks) == {"box.position"}


def test_recording_over_playback_punches_in_and_leaves_other_tracks_alone() -> None:
    sc = scene()
    rec = Recorder(sc)
    rec.arm("box.position")
    rec.arm("lamp.color")
    rec.arm("box.hit")
    t = np.arange(0, 4, 1 / 120)
    rec.start()
    for ti in t:
        rec.push_frame(ti, np.r_[np.sin(ti), np.cos(ti), 0.0, 0.5 + 0.4 * np.sin(ti), 0.5, 0.5])
    rec.push("box.hit", 1.0, "a")
    rec.push("box.hit", 2.5, "b")
    player = Player(sc, rec.stop().values())
    before = {p: tr for p, tr in player.tracks.items()}
    # second pass: only the box position, over [1.5, 2.5], while the rest plays
    rec.disarm("lamp.color")
    rec.start(player.tracks)
    s = t[(t >= 1.5) & (t <= 2.5)]
    for ti in s:
        player.seek(ti)
        player.apply(skip=["box.position"])
        rec.push("box.position", ti, [np.sin(ti) + 0.3 * np.sin(np.pi * (ti - 1.5)), np.cos(ti), 0.0])
    rec.push("box.hit", 2.0, "c")
    new = rec.stop(at=(1.5, 2.5))
    for track in new.values():
        player.add(track)
    assert player.tracks["lamp.color"] is before["lamp.color"]          # bit-identical: the same object
    assert player.tracks["box.hit"].times == [1.0, 2.0]                   # b at 2.5 replaced by c at 2.0
    pos = player.tracks["box.position"]
    out = t[(t < 1.5) | (t > 2.5)]
    assert np.allclose(pos.evaluate(out), before["box.position"].evaluate(out), atol=1e-12)
    assert len(pos.takes) == 2 and pos.takes[1].mode == "replace"
    assert abs(pos.evaluate([2.0])[0, 0] - (np.sin(2.0) + 0.3)) <= 0.005


@given(st.floats(0.3, 2.2), st.floats(0.4, 3.0), st.sampled_from([0.0, 0.05, 0.2]),
       st.sampled_from(["replace", "additive"]), st.booleans(), st.integers(0, 2**32 - 1))
@settings(max_examples=25, deadline=None)
def test_a_take_over_a_track_is_streamed_and_joined_c1_within_tolerance(start, length, blend, mode, framed,
                                                                         seed) -> None:
    """Punch-in and additive takes through the recorder, reduced while recorded: the
    curve outside the take is the old one, every target is kept, the seams are C1,
    and stop() reduces nothing again (its cost does not grow with the take)."""
    rng = np.random.default_rng(seed)
    sc = Scene()
    sc.add("box")
    rec = Recorder(sc)
    rec.arm("box.position", tol=0.002, mode=mode, blend=blend)
    rec.arm("box.orientation", tol=0.3, mode=mode, blend=blend)
    t = np.arange(0, 3, 1 / 120)
    f = rng.uniform(0.5, 2.0, 3)
    rec.start()
    for ti in t:
        rec.push_frame(ti, np.r_[np.sin(f * ti), Rotation.from_rotvec(0.5 * np.sin(f * ti)).as_quat()])
    old = rec.stop()
    s = t[(t >= start) & (t <= start + length)]
    if mode == "replace":
        move, turn = np.sin(f * s[:, None] + 0.3), 0.5 * np.sin(f * s[:, None] + 0.3)
        joins = np.sin(f * s[:, None]), 0.5 * np.sin(f * s[:, None])         # the old samples
    else:
        move, turn = 0.1 * np.sin(3 * f * s[:, None]), 0.1 * np.sin(3 * f * s[:, None])
        joins = np.zeros_like(move), np.zeros_like(turn)                     # no offset
    if blend == 0.0:                        # a join without a fade: start (and end) on the old curve
        u = ((s - s[0]) / (s[-1] - s[0]))[:, None] if s[-1] < t[-1] else np.zeros((len(s), 1))
        for x, join in zip((move, turn), joins):
            x += (1 - u) * (join[0] - x[0]) + u * (join[-1] - x[-1])
    take, spin = move, Rotation.from_rotvec(turn).as_quat()
    rec.start(old)
    for i, ti in enumerate(s):
        if framed:
            rec.push_frame(ti, np.r_[take[i], spin[i]])
        else:
            rec.push("box.position", ti, take[i])
            rec.push("box.orientation", ti, spin[i])
    with mock.patch.object(sketchanim.anim.layers, "reduce_samples", None):      # the streamed curve is used
        new = rec.stop()
    for path, kind, values in (("box.position", POSITION, take), ("box.orientation", ORIENTATION, spin)):
        before, after = old[path], new[path]
        over = Overlay(kind, before.spline, mode, blend)
        got = [over.push(s, values), over.close()]
        targets = np.vstack([g[1] for g in got])
        out = t[(t < s[0]) | (t > s[-1])]
        assert np.allclose(after.evaluate(out), before.evaluate(out), rtol=0, atol=1e-12), path
        x = after.evaluate(s)
        err = np.abs(x - targets).max() if kind is POSITION else np.degrees(rotation_angle(x, targets).max())
        assert err <= after.tol * (1 + 1e-9), (path, err)
        for side, seam in ((0, s[0]), (1, s[-1])):
            if t[0] < seam < t[-1]:
                assert np.allclose(after.spline(seam), before.spline(seam), atol=1e-9), (path, seam)
                # the old curve's slope on the side it is kept (it may have a corner there)
                kept = split(before.spline, seam)[side].derivative()(seam)
                for piece in split(after.spline, seam):           # the new curve: the same on both sides
                    slope = piece.derivative()(seam)
                    assert np.allclose(slope, kept, atol=1e-6 * (1 + np.abs(kept).max())), (path, seam)
        assert len(after.takes) == 2 and after.takes[1].mode == mode


def test_a_failed_reducer_process_loses_nothing() -> None:
    """A reducer process killed mid-take: stop() says so and reduces its attributes from
    the raw take, within tolerance; the next take gets a fresh pool."""
    sc = scene()
    rec = Recorder(sc)
    rec.arm("box.position")
    rec.arm("lamp.color")
    t = np.arange(0, 2, 1 / 120)
    rec.start()
    for i, ti in enumerate(t):
        if i == 120:
            shared_pool().processes[0].kill()
            shared_pool().processes[0].join()
        rec.push_frame(ti, np.r_[np.sin(ti), ti, 0.0, 0.5, 0.5 + 0.3 * np.sin(ti), 0.5])
    with pytest.warns(RuntimeWarning, match="reducer process"):
        tracks = rec.stop()
    assert np.abs(tracks["box.position"].evaluate(t)[:, 0] - np.sin(t)).max() <= 0.005
    assert np.abs(tracks["lamp.color"].evaluate(t)[:, 1] - (0.5 + 0.3 * np.sin(t))).max() <= 0.01
    assert shared_pool().alive
    rec.start()
    rec.push_frame(0.0, np.zeros(6))
    rec.push_frame(0.1, np.ones(6))
    assert set(rec.stop()) == {"box.position", "lamp.color"}


def test_layered_take_example_reports_a_c1_punch_in_within_tolerance(tmp_path) -> None:
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    repo = Path(__file__).resolve().parents[2]
    env = dict(os.environ, PYTHONPATH=str(repo / "src"))
    out = subprocess.run([sys.executable, str(repo / "examples" / "layered_take.py"), "--project",
                          str(tmp_path / "p.sketchanim")], capture_output=True, text=True, env=env, check=True)
    summary = json.loads(out.stdout)
    assert sorted(summary["untouched_by_pass_2"]) == ["cube.orientation", "lamp.color"]
    for path, track in summary["tracks"].items():
        assert track["max_error_vs_raw"] <= track["tolerance"] * (1 + 1e-9), path
        assert track["control_points"] < track["raw_samples"] / 10, path
    for path, seams in summary["seams"].items():
        for s in seams:
            assert s["value_jump"] <= 1e-9 and s["velocity_jump"] <= 1e-6, (path, s)
    assert summary["undo"] == summary["redo"] == "record pass 2"
    assert (tmp_path / "p.sketchanim").exists()
