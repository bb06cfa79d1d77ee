"""The studio's session against the model: takes from sample batches (within tolerance
of every sample, timing kept), layers during playback, stalls, loop recording, capture
speed, undo / redo, reload."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from sketchanim.anim.layers import compose
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.formats.recordings import read_tum
from sketchanim.studio import protocol as p
from sketchanim.studio.outbound import layout
from sketchanim.studio.session import Session
from sketchanim.studio.takes import ORDER
import tolerance

OWNER = 1


def take(session, name, paths, t, rows, *, batch=6, mode="replace", loop=None, speed=1.0, gap=0.25, label=None):
    """Perform a take through the session as the page does: begin, batches, end. An
    attribute without a track is grabbed where it is (the scene holds the first sample),
    as a drag on the page starts."""
    for path, lo, hi in layout(session.scene, paths):
        if path not in session.player.tracks and mode == "replace":
            session.scene.set(path, rows[0][lo:hi])
    session.begin_take(OWNER, name, paths, mode, 0.1, float(t[0]), speed, {}, loop, gap)
    for i in range(0, len(t), batch):
        session.samples(OWNER, name, t[i:i + batch], rows[i:i + batch].tolist())
    return session.end_take(OWNER, name, label)


def track_within(track: ContinuousTrack, t, x) -> bool:
    """``track`` within its tolerance at the samples (:func:`tolerance.within`)."""
    return tolerance.within(track.evaluate(t), x, track.tol, rotation=track.type.is_rotation)


def motion(seed: int, n: int, rate: float):
    rng = np.random.default_rng(seed)
    t = 0.37 + np.arange(n) / rate + rng.uniform(0, 0.2 / rate, n)       # a page's jittery frames
    w = rng.uniform(0.3, 3.0, 3)
    pos = np.c_[np.sin(w[0] * t), 0.5 + 0.3 * np.cos(w[1] * t), 0.2 * t * np.sin(w[2] * t)]
    rot = Rotation.from_rotvec(np.c_[np.sin(w[1] * t), 0.5 * t, np.cos(w[2] * t) - 1]).as_quat()
    return t, pos, rot


@settings(max_examples=8)
@given(seed=st.integers(0, 2**31), n=st.integers(3, 400), batch=st.integers(1, 40), rate=st.sampled_from([30.0, 60.0, 144.0]))
def test_take_from_batches_keeps_every_sample_and_its_time(tmp_path_factory, seed, n, batch, rate):
    t, pos, rot = motion(seed, n, rate)
    s = Session(tmp_path_factory.mktemp("p") / "s.sketchanim")
    try:
        out = take(s, "a", ["box.position", "box.orientation"], t, np.c_[pos, rot], batch=batch)
        for path, x in (("box.position", pos), ("box.orientation", rot)):
            track = s.player.tracks[path]
            assert track_within(track, t, x)
            assert track.start == t[0] and track.end == t[-1]          # timing kept: the span is the take's
        ended = [m for _, m in out if m["type"] == "take.ended"][0]
        assert ended["gaps"] == [] and ended["label"] == "take box.position, box.orientation"
    finally:
        s.close()


def test_the_track_between_samples_stays_near_them(session):
    """Between two frames the curve does not leave the samples' neighbourhood (no
    wiggle the page would show between frames)."""
    t, pos, _ = motion(3, 300, 60.0)
    take(session, "a", ["box.position"], t, pos)
    fine = np.linspace(t[0], t[-1], 20 * len(t))
    lin = np.c_[[np.interp(fine, t, pos[:, j]) for j in range(3)]].T
    step = np.abs(np.diff(pos, axis=0)).max()
    assert np.abs(session.player.tracks["box.position"].evaluate(fine) - lin).max() <= 0.005 + step


def test_layer_during_playback_changes_only_the_layered_track_on_the_take_span(session):
    t = np.arange(0, 4, 1 / 60)
    take(session, "a", ["box.position"], t, np.c_[np.sin(t), 0.5 + 0 * t, np.cos(t)])
    take(session, "b", ["lamp.intensity"], t, (1 + 0.5 * np.sin(3 * t))[:, None])
    before = dict(session.player.tracks)
    lamp = before["lamp.intensity"]
    inside = (t >= 1.5) & (t <= 2.5)
    layer = np.c_[np.sin(t) + 0.4, 0.9 + 0 * t, np.cos(t)][inside]
    take(session, "c", ["box.position"], t[inside], layer)          # a punch-in while everything plays
    after = session.player.tracks
    assert after["lamp.intensity"] is lamp                           # every other track unchanged
    box = after["box.position"]
    outside = np.r_[np.linspace(0, 1.5, 200, endpoint=False), np.linspace(2.5, 4, 200)[1:]]
    assert np.abs(box.evaluate(outside) - before["box.position"].evaluate(outside)).max() <= 1e-12
    core = (t[inside] >= 1.6) & (t[inside] <= 2.4)                   # past the 0.1 s fades
    assert np.abs(box.evaluate(t[inside][core]) - layer[core]).max() <= box.tol
    assert len(box.takes) == 2


def test_additive_layer_adds_on_the_span_only(session):
    t = np.arange(0, 3, 1 / 60)
    take(session, "a", ["ball.position"], t, np.c_[t, 0.5 + 0 * t, 0 * t])
    old = session.player.tracks["ball.position"]
    inside = (t >= 1) & (t <= 2)
    take(session, "b", ["ball.position"], t[inside], np.c_[0 * t, 0.3 + 0 * t, 0 * t][inside], mode="additive")
    new = session.player.tracks["ball.position"]
    assert abs(new.evaluate([1.5])[0, 1] - 0.8) <= new.tol
    assert np.abs(new.evaluate([0.5, 2.5]) - old.evaluate([0.5, 2.5])).max() <= 1e-12


def test_every_take_is_one_undo_step_and_redo_restores_it(session):
    t = np.arange(0, 2, 1 / 60)
    take(session, "a", ["box.position"], t, np.c_[t, 0 * t, 0 * t])
    first = session.player.tracks["box.position"]
    take(session, "b", ["box.position", "cam.fov"], t, np.c_[t, t, 0 * t, 50 + 5 * t])
    second = dict(session.player.tracks)
    assert session.history.labels[0] == ["take box.position", "take box.position, cam.fov"]
    session.undo()
    assert session.player.tracks == {"box.position": first}
    session.redo()
    assert session.player.tracks == second
    session.undo(); session.undo()
    assert session.player.tracks == {} and session.history.labels == ([], ["take box.position, cam.fov",
                                                                           "take box.position"])


def test_undoing_a_take_shows_the_scene_value_of_the_path_it_leaves_without_a_track(session):
    t = np.arange(0, 2, 1 / 60)
    before = session.scene.get("lamp.intensity").tolist()
    take(session, "a", ["lamp.intensity"], t, np.c_[1 + t])
    out = session.undo()
    values = [m["values"] for who, m in out if m["type"] == "values" and who == "all"]
    assert values and values[-1]["lamp.intensity"] == before        # every page shows it again
    out = session.redo()
    assert not any("lamp.intensity" in m.get("values", {}) for _, m in out)   # the track plays it


def test_scene_edits_are_undoable_steps(session):
    t = np.arange(0, 1, 1 / 60)
    take(session, "a", ["ball.position"], t, np.c_[t, t, t])
    session.set("lamp.intensity", [3.0], None, None)
    session.rename_object("ball", "orb")
    assert "orb.position" in session.player.tracks and "ball" not in session.scene.objects
    session.remove_object("orb")
    assert "orb.position" not in session.player.tracks and "orb" not in session.scene.objects
    session.undo()
    assert session.player.tracks["orb.position"].path == "orb.position"
    session.undo()
    assert "ball.position" in session.player.tracks and "orb" not in session.scene.objects
    session.undo()
    assert session.scene.get("lamp.intensity").tolist() == [1.0]
    out = session.add_object("crate", "object")
    assert out[0][1]["type"] == "state" and session.scene.get("crate.shape") == "box"


def test_reload_gives_the_same_state(tmp_path):
    path = tmp_path / "s.sketchanim"
    s = Session(path)
    t = np.arange(0, 2, 1 / 60)
    take(s, "a", ["box.orientation"], t, Rotation.from_rotvec(np.c_[t, 0 * t, 0 * t]).as_quat())
    s.set("lamp.color", [0.2, 0.4, 0.6], None, None)
    state = s.state()
    s.close()
    again = Session(path)
    reloaded = again.state()
    again.close()
    for key in ("objects", "tracks", "span"):
        assert reloaded[key] == state[key], key


def test_a_stall_is_a_gap_not_a_swing(session):
    t = np.r_[np.arange(0, 1, 1 / 60), np.arange(3, 4, 1 / 60)]           # a 2 s stall (tab in the background)
    x = np.c_[np.cos(4 * t), 0.5 + 0 * t, np.sin(4 * t)]
    out = take(session, "a", ["box.position"], t, x)
    ended = [m for _, m in out if m["type"] == "take.ended"][0]
    last, first = t[59], t[60]
    assert ended["gaps"] == [[last, first]]
    track = session.player.tracks["box.position"]
    stalled = np.linspace(last, first - 0.1, 400)              # held, then faded into the next part
    assert np.abs(track.evaluate(stalled) - x[59]).max() <= track.tol
    lo, hi = np.minimum(x[59], x[60]), np.maximum(x[59], x[60])
    fade = track.evaluate(np.linspace(first - 0.1, first, 100))
    assert np.all(fade >= lo - track.tol) and np.all(fade <= hi + track.tol)    # no overshoot
    keep = (t <= last) | (t >= first + 0.1)
    assert track_within(track, t[keep], x[keep])


def test_capture_speed_scales_the_stall_threshold(session):
    real = np.arange(0, 2, 1 / 60)
    t = 0.25 * real                                       # performed at a quarter of real time
    x = np.c_[np.sin(8 * t), 0 * t, 0 * t]
    out = take(session, "a", ["box.position"], t, x, speed=0.25)
    assert [m for _, m in out if m["type"] == "take.ended"][0]["gaps"] == []
    track = session.player.tracks["box.position"]
    assert track.end == pytest.approx(0.5 - 0.25 / 60) and track_within(track, t, x)


def test_loop_recording_keeps_the_last_pass_as_one_step(session):
    t = np.arange(0, 2, 1 / 60)
    take(session, "a", ["lamp.intensity"], t, (1 + 0 * t)[:, None])
    base = session.player.tracks["lamp.intensity"]
    for k in (1, 2, 3):
        take(session, f"p{k}", ["lamp.intensity", "box.position"] if k == 1 else ["lamp.intensity"],
             t[30:90], (1 + k * 0.1 + 0 * t[30:90])[:, None] if k > 1 else np.c_[1.1 + 0 * t[30:90], t[30:90], 0 * t[30:90], 0 * t[30:90]],
             loop="L")
    assert session.history.labels[0] == ["take lamp.intensity", "take lamp.intensity"]
    track = session.player.tracks["lamp.intensity"]
    assert abs(track.evaluate([1.0])[0, 0] - 1.3) <= track.tol
    # recorded over the base, not the earlier passes, which are kept muted after it
    assert [(tk.muted, tk.loop, tk.loop_pass) for tk in track.takes] == [
        (False, None, 0), (True, "L", 0), (True, "L", 1), (False, "L", 2)]
    assert track.takes[0] is base.takes[0]
    assert "box.position" not in session.player.tracks     # pass 1 only armed it; the last pass is what stays
    session.edit_take("lamp.intensity", 1, "keep", None, None)          # keep the first pass instead
    kept = session.player.tracks["lamp.intensity"]
    assert abs(kept.evaluate([1.0])[0, 0] - 1.1) <= kept.tol
    assert [tk.muted for tk in kept.takes] == [False, False, True, True]
    np.testing.assert_array_equal(kept.spline.c, compose(kept.type, [kept.takes[0], kept.takes[1]], kept.tol, ORDER).c)
    session.undo()
    assert session.player.tracks["lamp.intensity"] is track
    session.undo()
    assert session.player.tracks["lamp.intensity"] is base


def test_a_bad_sample_is_refused_and_what_came_before_is_kept(session):
    t = np.arange(0, 1, 1 / 60)
    session.begin_take(OWNER, "a", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    session.samples(OWNER, "a", t[:30], np.c_[t, t, t][:30].tolist())
    with pytest.raises(Exception, match="sample 2 of the batch"):
        session.samples(OWNER, "a", t[30:40], np.c_[t, t, t][30:32].tolist() + [[0.0, 0.0]] * 8)
    with pytest.raises(Exception, match="another page"):
        session.samples(OWNER + 1, "a", t[40:], np.c_[t, t, t][40:].tolist())
    session.end_take(OWNER, "a", None)
    assert len(session.player.tracks["box.position"].takes[0].times) == 32


@pytest.mark.realdata
def test_real_camera_take_through_the_session(session, data_dir):
    t, pos, quat = read_tum(data_dir / "camera" / "freiburg1_xyz-groundtruth.txt")
    n = min(len(t), 2000)
    t, pos, quat = t[:n] - t[0], pos[:n], quat[:n]
    take(session, "cam", ["cam.position", "cam.orientation"], t, np.c_[pos, quat], batch=10, gap=5.0)
    for path, x in (("cam.position", pos), ("cam.orientation", quat)):
        track = session.player.tracks[path]
        assert track_within(track, t, x) and track.n_coefficients < n / 2


def test_pieces_of_the_curve_come_while_the_take_goes_on(session):
    """The reduced curve grows while the take goes on: pieces come back with the batches,
    each within tolerance of the samples it spans."""
    import time

    t = np.arange(0, 6, 1 / 60)
    x = np.c_[np.sin(3 * t), 0.5 + 0.2 * np.cos(5 * t), t]
    session.begin_take(OWNER, "a", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    pieces = []
    for i in range(0, len(t), 6):
        pieces += [m for _, m in session.samples(OWNER, "a", t[i:i + 6], x[i:i + 6].tolist())]
        time.sleep(0.002)
    time.sleep(0.2)
    session.end_take(OWNER, "a", None)
    assert len(pieces) >= 2 and all(p["type"] == "take.piece" and p["path"] == "box.position" for p in pieces)
    from scipy.interpolate import BSpline
    for p in pieces:
        s = BSpline(np.array(p["knots"]), np.array(p["coef"]), p["order"] - 1)
        k = p["order"] - 1
        inside = (t >= p["knots"][k]) & (t <= p["knots"][-k - 1])
        assert np.abs(s(t[inside]) - x[inside]).max() <= 0.005 + 1e-9


def test_an_additive_take_cut_by_a_crash_comes_back_additive(tmp_path):
    """The take's mode and tolerances are kept beside the journal, so a recovered
    additive take is an offset again, not a replacement."""
    import time

    path = tmp_path / "crash.sketchanim"
    s = Session(path)
    t = np.arange(0, 3, 1 / 60)
    take(s, "base", ["ball.position"], t, np.c_[t, 0.5 + 0 * t, 0 * t])
    s.save()
    inside = t[60:120]
    s.begin_take(OWNER, "add", ["ball.position"], "additive", 0.1, 1.0, 1.0, {"ball.position": 0.002}, None, 0.25)
    s.samples(OWNER, "add", inside, np.c_[0 * inside, 0.25 + 0 * inside, 0 * inside].tolist())
    time.sleep(0.3)                                     # committed by the journal thread; then the process "dies"
    s.lock.handle.close()                                   # as the system lets go of a dead process's lock
    again = Session(path)                               # the next start, without s ever ending the take
    try:
        assert again.recovered == "ball.position" and again.history.labels[0][-1] == "recovered take"
        track = again.player.tracks["ball.position"]
        assert track.tol == 0.002 and track.takes[-1].mode == "additive"
        assert abs(track.evaluate([1.5])[0, 1] - 0.75) <= 0.002 and abs(track.evaluate([2.5])[0, 1] - 0.5) <= 1e-9
    finally:
        again.close()
        s.take.recorder.stop()
        s.takes.take = None
        s.project.close()


def test_one_studio_per_project(tmp_path):
    first = Session(tmp_path / "one.sketchanim")
    with pytest.raises(ValueError, match="open in another studio"):
        Session(tmp_path / "one.sketchanim")
    first.close()
    Session(tmp_path / "one.sketchanim").close()            # free again once closed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["one.sketchanim"]


def test_a_reducer_process_that_died_is_a_notice_for_every_page(session, monkeypatch, caplog):
    """The recorder warns that a reducer process died (its attributes reduced from the
    raw take): the session says so to every page and logs it, and keeps the take."""
    import logging

    from sketchanim.anim.workers import Pool

    real = Pool.results

    def one_lost(self, take, n):
        return real(self, take, n)[1:]                 # the first process's answer never comes

    monkeypatch.setattr(Pool, "results", one_lost)
    t = np.arange(0, 1, 1 / 60)
    with caplog.at_level(logging.WARNING, logger="sketchanim.studio"):
        out = take(session, "a", ["box.position"], t, np.c_[t, 0.5 + 0 * t, 0 * t])
    notices = [(who, m) for who, m in out if m["type"] == "notice"]
    assert notices == [("all", {"type": "notice", "level": "warning", "source": "recorder",
                                "text": "a reducer process died; reducing its attributes from the raw take"})]
    assert any("a reducer process died" in r.getMessage() for r in caplog.records)
    track = session.player.tracks["box.position"]
    assert track_within(track, t, np.c_[t, 0.5 + 0 * t, 0 * t])


def test_undo_after_previews_restores_the_value_before_the_gesture(session):
    """A drag previews (the scene shows each value live) and its release sets the last
    one: undo gives back exactly the value before the first preview."""
    before = session.scene.get("box.position").tolist()
    for i in range(1, 20):
        session.preview(p.Preview(type="preview", key="move box", path="box.position", value=[0.1 * i, 0.5, 0.0]),
                        OWNER)
    assert session.scene.get("box.position").tolist() == [1.9000000000000001, 0.5, 0.0]    # live
    session.set("box.position", [1.9, 0.5, 0.0], "move box", "move box 1")
    session.undo()
    assert session.scene.get("box.position").tolist() == before
    session.redo()
    assert session.scene.get("box.position").tolist() == [1.9, 0.5, 0.0]


def test_previews_of_a_page_that_went_away_are_put_back(session):
    before = session.scene.get("lamp.intensity").tolist()
    session.preview(p.Preview(type="preview", key="slide", path="lamp.intensity", value=[4.0]), OWNER)
    out = session.leave(OWNER)
    assert session.scene.get("lamp.intensity").tolist() == before
    assert ("all", {"type": "values", "values": {"lamp.intensity": before}}) in out
    assert session.history.labels == ([], [])


@settings(max_examples=6, deadline=None)
@given(start=st.floats(0.2, 8.0), value=st.lists(st.floats(0.0, 1.0), min_size=3, max_size=3),
       n=st.integers(3, 60), mode=st.sampled_from(["replace", "additive"]))
def test_a_take_over_an_attribute_with_a_value_keeps_it_before_the_take(tmp_path_factory, start, value, n, mode):
    """A take at ``start`` > 0 of an attribute with no track: before the take the track
    holds the scene's value (replacing: until the blend before the take, then eases onto
    its first sample, and every sample of the take is kept; additive: the offsets fade in
    over the blend, onto the value); the raw takes recompose the curve."""
    from sketchanim.anim.layers import compose

    s = Session(tmp_path_factory.mktemp("p") / "s.sketchanim")
    try:
        colour = np.array(value)
        s.scene.set("lamp.color", colour)
        t = start + np.arange(n) / 60
        picked = np.tile([0.9, 0.1, 0.3], (n, 1)) if mode == "replace" else np.tile([0.05, -0.05, 0.02], (n, 1))
        s.begin_take(OWNER, "a", ["lamp.color"], mode, 0.1, float(t[0]), 1.0, {}, None, 0.25)
        s.samples(OWNER, "a", t, picked.tolist())
        s.end_take(OWNER, "a", None)
        track = s.player.tracks["lamp.color"]
        ease = min(0.1, start / 2) if mode == "replace" else 0.0
        earlier = np.linspace(min(0.0, start - 1), t[0] - ease, 50)
        assert np.abs(track.evaluate(earlier) - colour).max() <= track.tol, "the value before the take changed"
        target = picked if mode == "replace" else np.clip(colour + picked, *track.type.bounds)   # kept in [0, 1]
        settled = t >= t[0] + (0.1 if mode == "additive" else 0.0) - 1e-12
        assert not settled.any() or np.abs(track.evaluate(t[settled]) - target[settled]).max() <= track.tol
        again = compose(track.type, track.takes, track.tol, track.spline.k + 1)       # from the raw takes
        assert np.abs(again(earlier) - colour).max() <= track.tol
        assert not settled.any() or np.abs(again(t[settled]) - target[settled]).max() <= track.tol
    finally:
        s.close()


def test_a_take_that_starts_where_the_value_is_is_the_take_alone(session):
    """A drag starts where the object is: its take is the track (no hold added)."""
    t = 2.0 + np.arange(40) / 60
    x = np.c_[np.sin(t - 2), 0.5 + 0 * t, 0 * t]
    session.scene.set("box.position", x[0])
    take(session, "a", ["box.position"], t, x)
    track = session.player.tracks["box.position"]
    assert len(track.takes) == 1 and track.start == t[0] and track_within(track, t, x)


def test_a_loop_pass_over_a_path_the_earlier_passes_left_keeps_its_takes_once(session):
    """Pass 2 records a path pass 1 did not: its takes from before the loop stay as they
    were (not taken for an earlier pass), and the pass is numbered as the loop's second."""
    t = np.arange(0, 2, 1 / 60)
    take(session, "base", ["box.position"], t, np.c_[t, 0 * t, 0 * t])
    take(session, "p1", ["lamp.intensity"], t[30:90], (1.1 + 0 * t[30:90])[:, None], loop="L")
    take(session, "p2", ["lamp.intensity", "box.position"], t[30:90],
         np.c_[1.2 + 0 * t[30:90], t[30:90], 0 * t[30:90] + 1, 0 * t[30:90]], loop="L")
    box = session.player.tracks["box.position"]
    assert [(tk.muted, tk.loop, tk.loop_pass) for tk in box.takes] == [(False, None, 0), (False, "L", 1)]
    lamp = session.player.tracks["lamp.intensity"]
    passes = {(tk.loop_pass, tk.muted) for tk in lamp.takes if tk.loop == "L"}        # a pass may be several takes
    assert passes == {(0, True), (1, False)}
