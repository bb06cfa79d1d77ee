"""The recorder: samples queued by the caller, reduced by a worker, tracks out."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import EVENT
from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.errors import ArgumentError, SampleError
from sketchanim.reducer.metric import rotation_angle
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
    rec = Recorder(sc, journal=lambda path, t, x: batches.append((path, len(t))))
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
    rec.start()
    s = t[(t >= 1.5) & (t <= 2.5)]
    for ti in s:
        player.seek(ti)
        player.apply(skip=["box.position"])
        rec.push("box.position", ti, [np.sin(ti) + 0.3 * np.sin(np.pi * (ti - 1.5)), np.cos(ti), 0.0])
    rec.push("box.hit", 2.0, "c")
    new = rec.stop(player.tracks, at=(1.5, 2.5))
    for track in new.values():
        player.add(track)
    assert player.tracks["lamp.color"] is before["lamp.color"]          # bit-identical: the same object
    assert player.tracks["box.hit"].times == [1.0, 2.0]                   # b at 2.5 replaced by c at 2.0
    pos = player.tracks["box.position"]
    out = t[(t < 1.5) | (t > 2.5)]
    assert np.allclose(pos.evaluate(out), before["box.position"].evaluate(out), atol=1e-12)
    assert len(pos.takes) == 2 and pos.takes[1].mode == "replace"
    assert abs(pos.evaluate([2.0])[0, 0] - (np.sin(2.0) + 0.3)) <= 0.005


def test_layered_take_example_reports_a_c1_punch_in_within_tolerance(tmp_path) -> None:
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    repo = Path(__file__).resolve().parents[1]
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
