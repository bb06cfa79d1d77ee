"""Editing what was performed, through the session and the websocket: tracks re-reduced
from their raw takes at a new tolerance (within it at every kept sample, as the model's
``compose`` makes them), takes managed as layers, curve edits, objects duplicated, the
frame rate; each one History step, undone bit for bit."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import ORIENTATION, POSITION
from sketchanim.anim.layers import composition, largest_error, recorded_over, rereduced
from sketchanim.anim.tracks import Take
from sketchanim.formats.recordings import read_tum
from sketchanim.project.store import Project
from sketchanim.studio import protocol as p
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.handlers import handle
from sketchanim.studio.session import Session
from sketchanim.studio.takes import ORDER
from test_studio_protocol import receive_until

OWNER = 1


def layered_track(seed: int, modes: list[str], tol: float = 0.002):
    """A position track of one take per mode (the first over the whole span, the others
    over parts of it), as recording them in turn makes it."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, 4, 1 / 60)
    x = np.c_[np.sin(t), np.cos(1.3 * t), 0.2 * t] + np.cumsum(rng.normal(0, 0.0005, (len(t), 3)), axis=0)
    track = recorded_over("box.position", POSITION, None, Take(t, x), tol, ORDER)
    for mode in modes:
        a = int(rng.integers(0, len(t) - 60))
        b = a + int(rng.integers(30, len(t) - a))
        s = t[a:b]
        wave = np.sin(np.pi * (s - s[0]) / (s[-1] - s[0]))[:, None] * rng.normal(0, 0.3, 3)
        values = wave if mode == "additive" else x[a:b] + wave
        track = recorded_over(track.path, POSITION, track, Take(s, values, mode), tol, ORDER)
    return track


def put(session, track):
    session.player.add(track)
    session.editor.changes()


def send(session, message: dict):
    return handle(session, p.parse(json.dumps(message)), OWNER)


@given(st.integers(0, 2**32 - 1), st.lists(st.sampled_from(["replace", "additive"]), max_size=2),
       st.floats(0.0005, 0.05))
@settings(max_examples=25, deadline=None)
def test_a_re_reduction_is_the_models_composition_within_the_new_tolerance_of_every_kept_sample(seed, modes, tol):
    track = layered_track(seed, modes)
    made = rereduced(track, tol, ORDER)
    kept = composition(track.type, track.takes, tol, ORDER)
    np.testing.assert_array_equal(made.track.spline.c, kept.curve.c)     # the model's compose, from the raw takes
    assert made.track.takes is track.takes and made.track.tol == tol and not made.track.edited
    worst = np.abs(made.track.evaluate(kept.times) - kept.targets).max()
    assert worst <= tol * (1 + 1e-9) and made.error == pytest.approx(worst, rel=1e-12)
    assert len(kept.times) >= len(track.takes[0].times) - sum(len(t.times) for t in track.takes[1:])


def test_a_re_reduced_orientation_keeps_every_sample_within_its_angle():
    t = np.arange(0, 3, 1 / 120)
    q = Rotation.from_rotvec(np.c_[np.sin(t), 0.5 * np.cos(2 * t), 0.3 * t]).as_quat()
    track = recorded_over("cam.orientation", ORIENTATION, None, Take(t, q), 0.2, ORDER)
    for tol in (0.1, 1.0, 3.0):
        made = rereduced(track, tol, ORDER)
        angles = np.degrees((Rotation.from_quat(made.track.evaluate(t)).inv() * Rotation.from_quat(q)).magnitude())
        assert angles.max() <= tol * (1 + 1e-9) and made.error == pytest.approx(angles.max(), abs=1e-9)


def test_reduce_previews_change_nothing_and_the_step_is_one_undo(session):
    track = layered_track(1, ["additive"])
    put(session, track)
    labels = session.history.labels
    out = send(session, {"type": "track.reduce", "paths": ["box.position"], "tol": 0.02, "preview": True})
    assert [(a, m["type"]) for a, m in out] == [("self", "reduced")]
    reply = out[0][1]
    preview = rereduced(track, 0.02, ORDER).track
    assert reply["results"] == [{"path": "box.position", "tol": 0.02, "n": preview.n_coefficients,
                                 "error": pytest.approx(rereduced(track, 0.02, ORDER).error)}]
    assert reply["curves"][0]["coef"] == np.asarray(preview.spline.c).tolist()
    assert session.player.tracks["box.position"] is track and session.history.labels == labels
    out = send(session, {"type": "track.reduce", "paths": ["box.position"], "tol": 0.02})
    assert {m["type"] for _, m in out} == {"tracks", "history", "reduced"}
    assert session.player.tracks["box.position"].n_coefficients == preview.n_coefficients
    assert session.history.labels[0][-1] == "tolerance 0.02 on box.position"
    session.undo()
    assert session.player.tracks["box.position"] is track


def test_a_track_changed_while_it_was_reduced_is_refused(session):
    put(session, layered_track(2, []))
    work = session.reduction(["box.position"], 0.01)
    send(session, {"type": "curve.points", "edits": [{"path": "box.position", "index": 2, "value": [0, 1, 0]}]})
    with pytest.raises(Exception, match="changed while being re-reduced"):
        session.reduced(work(), False)
    assert session.player.tracks["box.position"].edited


def test_a_curve_without_takes_or_a_missing_one_cannot_be_re_reduced(session):
    from dataclasses import replace
    put(session, replace(layered_track(3, []), takes=()))
    for path, why in (("box.position", "no takes"), ("ball.position", "has no curve")):
        with pytest.raises(Exception, match=why):
            send(session, {"type": "track.reduce", "paths": [path], "tol": 0.01})


@pytest.mark.parametrize("op, args, keeps", [
    ("mute", {}, lambda takes, i: [t for j, t in enumerate(takes) if j != i]),
    ("delete", {}, lambda takes, i: [t for j, t in enumerate(takes) if j != i]),
    ("solo", {}, lambda takes, i: [takes[i]]),
    ("move", {"to": 0}, lambda takes, i: [takes[i]] + [t for j, t in enumerate(takes) if j != i]),
])
def test_take_edits_recompose_the_track_as_the_model_does_and_undo_bit_for_bit(session, op, args, keeps):
    track = layered_track(4, ["additive", "replace"])
    put(session, track)
    send(session, {"type": "take.edit", "path": "box.position", "take": 1, "op": op, **args})
    after = session.player.tracks["box.position"]
    expected = composition(track.type, keeps(track.takes, 1), track.tol, ORDER).curve
    np.testing.assert_array_equal(after.spline.c, expected.c)
    np.testing.assert_array_equal(after.spline.t, expected.t)
    assert len(after.takes) == len(track.takes) - (op == "delete")
    assert session.history.labels[0][-1] == f"{op} take 2 of box.position"
    session.undo()
    assert session.player.tracks["box.position"] is track


def test_a_track_plays_a_take_deleting_its_last_removes_it_and_names_persist(session, tmp_path):
    track = layered_track(5, [])
    put(session, track)
    with pytest.raises(Exception, match="at least one take"):
        send(session, {"type": "take.edit", "path": "box.position", "take": 0, "op": "mute"})
    send(session, {"type": "take.edit", "path": "box.position", "take": 0, "op": "rename", "name": "  good one "})
    named = session.player.tracks["box.position"]
    assert named.takes[0].name == "good one" and named.spline is track.spline
    session.save()
    assert Project(session.path, read_only=True).load()[1]["box.position"].takes[0].name == "good one"
    send(session, {"type": "take.edit", "path": "box.position", "take": 0, "op": "delete"})
    assert "box.position" not in session.player.tracks
    session.undo()
    assert session.player.tracks["box.position"] is named


def test_curve_edits_are_one_step_each_refused_while_recorded_and_kept_as_edited(session, tmp_path):
    track = layered_track(6, [])
    put(session, track)
    send(session, {"type": "curve.points", "edits": [{"path": "box.position", "index": 3, "value": [1, 2, 3]},
                                                      {"path": "box.position", "index": 4, "value": [1, 2, 4]}]})
    send(session, {"type": "curve.key", "path": "box.position", "time": 1.5, "value": [0, 0, 0], "slope": [1, 0, 0]})
    assert np.allclose(session.player.tracks["box.position"].evaluate([1.5])[0], [0, 0, 0])
    send(session, {"type": "curve.knots", "path": "box.position", "insert": [2.25, 2.5], "remove": [8]})
    edited = session.player.tracks["box.position"]
    assert session.history.labels[0][-3:] == ["move 2 points of box.position", "move key and tangent of box.position "
                                              "at 1.500 s", "insert 2 and remove 1 knots on box.position"]
    assert edited.edited and edited.n_coefficients == track.n_coefficients + 1
    session.save()
    assert Project(session.path, read_only=True).load()[1]["box.position"].edited
    session.begin_take(OWNER, "t", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    with pytest.raises(Exception, match="being recorded"):
        send(session, {"type": "curve.points", "edits": [{"path": "box.position", "index": 3, "value": [0, 0, 0]}]})
    session.cancel_take(OWNER, "t")
    for _ in range(3):
        session.undo()
    assert session.player.tracks["box.position"] is track


def test_objects_duplicated_renamed_removed_are_undone_exactly(session):
    put(session, layered_track(7, []))
    session.set_tolerance("box.position", 3, "px")
    before = session.export_document()
    send(session, {"type": "object.duplicate", "name": "box", "to": "box2"})
    assert list(session.scene.objects)[:2] == ["box", "box2"]
    copy = session.player.tracks["box2.position"]
    np.testing.assert_array_equal(copy.spline.c, session.player.tracks["box.position"].spline.c)
    assert "box2.position" not in session.tolerances          # a recording setting: not copied, nothing to undo
    send(session, {"type": "object.rename", "name": "box2", "to": "crate"})
    send(session, {"type": "object.remove", "name": "box"})
    send(session, {"type": "object.add", "name": "o1", "position": [1, 0.5, -2]})
    assert session.scene.get("o1.position").tolist() == [1.0, 0.5, -2.0]
    for _ in range(4):
        session.undo()
    assert json.loads(session.export_document()) == json.loads(before)


def test_the_frame_rate_is_a_project_setting_every_page_gets(session):
    assert session.state()["settings"] == {"type": "settings", "fps": 24.0}
    assert send(session, {"type": "settings", "fps": 30}) == [("all", {"type": "settings", "fps": 30.0})]
    session.save()
    assert Project(session.path, read_only=True).fps() == 30.0
    assert session.history.labels == ([], [])


def test_over_the_socket_a_reduction_answers_the_page_and_a_second_sees_the_track(client):
    with client.websocket_connect("/ws") as a, client.websocket_connect("/ws") as b:
        a.receive_json(), b.receive_json()
        t = np.arange(0, 2, 1 / 60)
        a.send_json({"type": "take.begin", "take": "k", "paths": ["box.position"]})
        a.send_json({"type": "take.samples", "take": "k", "t": t.tolist(), "values": np.c_[np.sin(t), t, 0 * t].tolist()})
        a.send_json({"type": "take.end", "take": "k", "id": 1})
        receive_until(a, "ack", limit=200, id=1)
        a.send_json({"type": "track.reduce", "paths": ["box.position"], "tol": 0.05, "preview": True, "id": 2})
        reply, _ = receive_until(a, "reduced", limit=200)
        assert reply["preview"] and reply["results"][0]["error"] <= 0.05
        a.send_json({"type": "track.reduce", "paths": ["box.position"], "tol": 0.05, "id": 3})
        done, _ = receive_until(a, "reduced", limit=200)
        assert not done["preview"] and done["results"][0]["n"] == reply["results"][0]["n"]
        seen = [receive_until(b, "history", limit=400)[0]["undo"][-1] for _ in range(2)]
        assert seen == ["take box.position", "tolerance 0.05 on box.position"]


def project_with_a_take(tmp_path, seed: int):
    """A saved project whose box.position was recorded (one take)."""
    path = tmp_path / "ro.sketchanim"
    with Project(path) as project:
        project.save(default_scene(), {"box.position": layered_track(seed, [])})
    return path


def test_a_read_only_project_previews_a_reduction_but_refuses_the_step(tmp_path):
    ro = Session(project_with_a_take(tmp_path, 8), read_only=True)
    try:
        assert send(ro, {"type": "track.reduce", "paths": ["box.position"], "tol": 0.01, "preview": True})
        with pytest.raises(Exception, match="read-only"):
            send(ro, {"type": "track.reduce", "paths": ["box.position"], "tol": 0.01})
    finally:
        ro.close()


def test_over_the_socket_a_read_only_project_previews_a_reduction_and_refuses_the_step(tmp_path):
    from fastapi.testclient import TestClient

    from sketchanim.studio.app import create_app

    app = create_app(project_with_a_take(tmp_path, 10), warm=False, read_only=True)
    with TestClient(app) as c, c.websocket_connect("/ws") as ws:
        ws.receive_json()
        ws.send_json({"type": "track.reduce", "paths": ["box.position"], "tol": 0.02, "preview": True})
        assert receive_until(ws, "reduced", limit=50)[0]["preview"]
        ws.send_json({"type": "track.reduce", "paths": ["box.position"], "tol": 0.02, "id": 7})
        refused, _ = receive_until(ws, "error", limit=50)
        assert (refused["code"], refused["ref"], refused["id"]) == ("read_only", "track.reduce", 7)
        ws.send_json({"type": "track.samples", "path": "box.position"})
        assert receive_until(ws, "samples", limit=50)[0]["path"] == "box.position"
    app.state.hub.session.close()


@pytest.mark.realdata
def test_a_real_camera_path_re_reduced_keeps_every_sample(data_dir):
    t, pos, quat = read_tum(data_dir / "camera" / "freiburg1_xyz-groundtruth.txt")
    t = t - t[0]
    for path, kind, x, tols in (("cam.position", POSITION, pos, (0.0005, 0.002, 0.01)),
                                ("cam.orientation", ORIENTATION, quat, (0.1, 0.5, 2.0))):
        track = recorded_over(path, kind, None, Take(t, x), tols[1], ORDER)
        counts = []
        for tol in tols:
            made = rereduced(track, tol, ORDER)
            assert largest_error(kind, made.track.spline, t, x) <= tol * (1 + 1e-9), (path, tol)
            counts.append(made.track.n_coefficients)
        assert counts[0] > counts[1] > counts[2], (path, counts)


def test_a_reduction_runs_beside_the_model_which_answers_meanwhile(client, monkeypatch):
    import threading

    release = threading.Event()
    real = Session.reduction

    def slow(self, paths, tol):
        work = real(self, paths, tol)
        return lambda: (release.wait(10), work())[1]

    monkeypatch.setattr(Session, "reduction", slow)
    with client.websocket_connect("/ws") as a:
        a.receive_json()
        t = np.arange(0, 1, 1 / 60)
        a.send_json({"type": "take.begin", "take": "k", "paths": ["box.position"]})
        a.send_json({"type": "take.samples", "take": "k", "t": t.tolist(), "values": np.c_[t, t, t].tolist()})
        a.send_json({"type": "take.end", "take": "k", "id": 1})
        receive_until(a, "ack", limit=200, id=1)
        a.send_json({"type": "track.reduce", "paths": ["box.position"], "tol": 0.05, "preview": True})
        a.send_json({"type": "set", "path": "lamp.intensity", "value": [2], "id": 2})
        a.send_json({"type": "ping", "id": 3})
        pong, before = receive_until(a, "pong", limit=200)
        assert not any(m["type"] == "reduced" for m in before)         # the model answered while it was reduced
        release.set()
        reply, _ = receive_until(a, "reduced", limit=200)
        assert reply["preview"] and reply["results"][0]["path"] == "box.position"


def test_the_samples_a_curve_keeps_are_its_takes_targets_all_within_its_tolerance(session):
    track = layered_track(9, ["additive", "replace"])
    put(session, track)
    (audience, reply), = send(session, {"type": "track.samples", "path": "box.position"})
    kept = composition(track.type, track.takes, track.tol, ORDER)
    assert audience == "self" and reply["tol"] == track.tol
    np.testing.assert_array_equal(reply["times"], kept.times)
    np.testing.assert_array_equal(reply["values"], kept.targets)
    assert np.all(np.diff(reply["times"]) >= 0)
    assert np.abs(track.evaluate(reply["times"]) - reply["values"]).max() <= track.tol * (1 + 1e-9)
