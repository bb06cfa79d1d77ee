"""The studio's websocket protocol through FastAPI's TestClient: good and bad messages,
a foreign origin, the size and rate limits, the JSON API."""

from __future__ import annotations

import json

import numpy as np
import pytest
from fastapi.testclient import TestClient
from starlette.websockets import WebSocketDisconnect

from sketchanim.project.store import Project
from sketchanim.studio import app as studio_app
from sketchanim.studio.app import create_app
from sketchanim.studio.protocol import MAX_MESSAGE_BYTES


def receive_until(ws, kind: str, limit: int = 50, id: object = None) -> tuple[dict, list[dict]]:
    """Messages up to the first of type ``kind`` (with ``id``, if given): that one and
    all before it."""
    seen = []
    for _ in range(limit):
        m = ws.receive_json()
        seen.append(m)
        if m["type"] == kind and (id is None or m.get("id") == id):
            return m, seen
    raise AssertionError(f"no {kind} in {[m['type'] for m in seen]}")


def test_state_on_connect_has_default_scene_and_tracks(client):
    with client.websocket_connect("/ws") as ws:
        state = ws.receive_json()
    assert state["type"] == "state" and state["ready"] is True
    names = {o["name"]: o for o in state["objects"]}
    assert {"box", "lamp", "cam"} <= set(names)
    box = {a["name"]: a for a in names["box"]["attributes"]}
    assert box["position"]["value"] == [0.0, 0.5, 0.0] and box["shape"]["type"]["choices"][0] == "box"
    lamp = {a["name"]: a for a in names["lamp"]["attributes"]}
    assert lamp["color"]["type"]["continuous"] and lamp["intensity"]["type"]["dim"] == 1
    assert {a["name"] for a in names["cam"]["attributes"]} >= {"fov", "position", "orientation"}
    assert state["tracks"] == [] and state["history"]["can_undo"] is False
    assert client.get("/api/state").json()["objects"] == state["objects"]


def test_ping_set_undo_redo_acks_and_broadcast(client):
    with client.websocket_connect("/ws") as a, client.websocket_connect("/ws") as b:
        a.receive_json(), b.receive_json()
        a.send_json({"type": "ping", "id": 7})
        assert a.receive_json()["type"] == "pong"
        assert a.receive_json() == {"type": "ack", "id": 7, "ref": "ping"}
        a.send_json({"type": "set", "id": "s1", "path": "lamp.intensity", "value": [2.5]})
        values, _ = receive_until(b, "values")          # the other page hears of it
        assert values["values"] == {"lamp.intensity": [2.5]}
        history, _ = receive_until(a, "history")
        assert history["undo"] == ["set lamp.intensity"] and history["can_undo"]
        receive_until(a, "ack")
        a.send_json({"type": "undo", "id": 2})
        values, _ = receive_until(a, "values")
        assert values["values"] == {"lamp.intensity": [1.0]}
        a.send_json({"type": "redo", "id": 3})
        values, _ = receive_until(a, "values")
        assert values["values"] == {"lamp.intensity": [2.5]}


@pytest.mark.parametrize("text, code, field", [
    ("not json", "bad_message", "not JSON"),
    ("[1, 2]", "bad_message", "JSON object"),
    ('{"type": "warp", "id": 1}', "bad_message", "type"),
    ('{"type": "set", "id": 2, "path": "box.position", "value": [1, 2]}', "refused", "3 numbers"),
    ('{"type": "set", "id": 3, "path": "nobox.position", "value": [1, 2, 3]}', "refused", "nobox"),
    ('{"type": "set", "id": 4, "path": "box.position", "value": [1, 2, NaN]}', "bad_message", "value"),
    ('{"type": "take.begin", "id": 5, "take": "t", "paths": ["box.visible"]}', "refused", "bool"),
    ('{"type": "take.samples", "id": 6, "take": "nope", "t": [0], "values": [[0, 0, 0]]}', "refused", "nope"),
    ('{"type": "take.begin", "id": 7, "take": "t", "paths": ["box.position"], "speed": 0}', "bad_message", "speed"),
    ('{"type": "export", "id": 8, "file": "../escape.json"}', "refused", "not a path"),
    ('{"type": "export", "id": 9, "file": "x.txt"}', "refused", ".glb or .json"),
    ('{"type": "object.rename", "id": 10, "name": "box", "to": "lamp"}', "refused", "exists"),
])
def test_bad_messages_get_an_error_and_change_nothing(client, tmp_path, text, code, field):
    before = client.get("/api/project").content
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        ws.send_text(text)
        error = ws.receive_json()
        ws.send_json({"type": "ping", "id": "after"})         # the socket goes on
        receive_until(ws, "pong")
    assert error["type"] == "error" and error["code"] == code and field in error["message"], error
    sent = json.loads(text) if text.startswith("{") else {}
    assert error["id"] == sent.get("id")
    assert client.get("/api/project").content == before
    assert not (tmp_path.parent / "escape.json").exists()


def test_foreign_origin_is_refused_and_own_origin_accepted(client):
    with pytest.raises(WebSocketDisconnect):
        with client.websocket_connect("/ws", headers={"origin": "http://evil.example"}) as ws:
            ws.receive_json()
    with client.websocket_connect("/ws", headers={"origin": "http://testserver"}) as ws:
        assert ws.receive_json()["type"] == "state"


def test_oversized_message_is_refused(client):
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        ws.send_text(json.dumps({"type": "ping", "pad": "x" * MAX_MESSAGE_BYTES}))
        error = ws.receive_json()
        assert error["code"] == "too_large"


def test_rate_limit_drops_messages_past_the_burst(client, monkeypatch):
    monkeypatch.setattr(studio_app, "BURST", 20.0)
    monkeypatch.setattr(studio_app, "RATE", 1.0)
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        for i in range(40):
            ws.send_json({"type": "ping", "id": i})
        got = [ws.receive_json() for _ in range(2 * 20 + 20)]
    codes = [m.get("code") for m in got if m["type"] == "error"]
    assert codes.count("rate") == 20 and sum(m["type"] == "pong" for m in got) == 20


def test_take_over_the_socket_and_the_project_document(client, tmp_path):
    t = np.arange(90) / 60
    x = np.c_[np.sin(t), 0.5 + 0 * t, np.cos(2 * t)]
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        ws.send_json({"type": "take.begin", "id": 1, "take": "a", "paths": ["box.position"], "time": 0.0})
        started, _ = receive_until(ws, "take.started")
        assert started["layout"] == [["box.position", 0, 3]] and started["width"] == 3
        for i in range(0, 90, 9):
            ws.send_json({"type": "take.samples", "take": "a", "t": t[i:i + 9].tolist(), "values": x[i:i + 9].tolist()})
        ws.send_json({"type": "take.end", "id": 2, "take": "a"})
        tracks, _ = receive_until(ws, "tracks")
        ended, _ = receive_until(ws, "take.ended")
    assert ended["paths"] == ["box.position"] and ended["label"] == "take box.position"
    track = tracks["changed"][0]
    assert track["order"] == 4 and not track["rotation"] and track["takes"][0]["n"] == 90
    doc = client.get("/api/project").json()
    assert doc["curves"][0]["path"] == "box.position" and len(doc["takes"][0]["times"]) == 90
    exported = tmp_path / "x.json"
    with Project(tmp_path / "p.sketchanim", create=False) as project:
        project.export_json(exported)
    assert client.get("/api/project").content == exported.read_bytes()


def test_closing_the_socket_mid_take_keeps_the_take(client):
    t = np.arange(30) / 60
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        ws.send_json({"type": "take.begin", "id": 1, "take": "a", "paths": ["lamp.intensity"]})
        receive_until(ws, "take.started")
        ws.send_json({"type": "take.samples", "id": 2, "take": "a", "t": t.tolist(), "values": (1 + t)[:, None].tolist()})
        receive_until(ws, "ack", id=2)                            # the samples' (the test client drops what is unread at close)
    with client.websocket_connect("/ws") as ws:                  # a reload
        state = ws.receive_json()
        tracks = state["tracks"] or receive_until(ws, "tracks")[0]["changed"]    # if it came before the take ended
    assert [tr["path"] for tr in tracks] == ["lamp.intensity"] and tracks[0]["takes"][0]["n"] == 30


def test_autosave_and_relays(client, tmp_path):
    import time

    with client.websocket_connect("/ws") as a, client.websocket_connect("/ws") as b:
        a.receive_json(), b.receive_json()
        for i in range(50):
            a.send_json({"type": "preview", "key": "drag box", "path": "box.position", "value": [i, 0.5, 0]})
        a.send_json({"type": "transport", "time": 1.5, "playing": True, "speed": 0.5, "loop": [1, 3]})
        a.send_json({"type": "set", "id": 1, "path": "cam.fov", "value": [35]})
        receive_until(a, "ack")
        transport, before = receive_until(b, "transport", limit=200)
        previews = [m["value"][0] for m in before if m["type"] == "preview"]
        assert previews and previews[-1] == 49 and previews == sorted(previews)     # newest kept, never older after newer
        assert transport == {"type": "transport", "time": 1.5, "playing": True, "speed": 0.5, "loop": [1.0, 3.0],
                             "count_in": 0.0, "capture_speed": 1.0, "mode": "replace", "loop_record": False,
                             "smoothing": 0.0}
        time.sleep(1.0)                                                  # saved within a tick (0.25 s) of a change
        with Project(tmp_path / "p.sketchanim", create=False) as project:
            scene, _ = project.load()
        assert scene.get("cam.fov").tolist() == [35.0]
        with client.websocket_connect("/ws") as c:                       # a page opened mid-drag sees it live
            assert _box(c.receive_json()) == [49.0, 0.5, 0.0]
    with client.websocket_connect("/ws") as c:      # the dragging page went without its set: the value is back
        state = c.receive_json()
    assert state["transport"]["time"] == 1.5
    assert _box(state) == [0.0, 0.5, 0.0]


def _box(state: dict) -> list:
    return {a["name"]: a["value"] for o in state["objects"] if o["name"] == "box" for a in o["attributes"]}["position"]


def test_objects_stay_while_a_take_runs(client):
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        ws.send_json({"type": "take.begin", "take": "a", "paths": ["box.position"]})
        receive_until(ws, "take.started")
        for m in ({"type": "object.remove", "id": 1, "name": "box"}, {"type": "object.rename", "id": 2, "name": "box", "to": "b"},
                  {"type": "undo", "id": 3}, {"type": "take.begin", "id": 4, "take": "b", "paths": ["ball.position"]}):
            ws.send_json(m)
            error, _ = receive_until(ws, "error")
            assert error["id"] == m["id"] and error["code"] == ("busy" if m["type"] == "take.begin" else "refused")
        ws.send_json({"type": "take.cancel", "id": 5, "take": "a"})
        ended, _ = receive_until(ws, "take.ended")
    assert ended["label"] is None and client.get("/api/state").json()["tracks"] == []


def test_only_local_host_names_are_answered_on_a_local_server(tmp_path):
    app = create_app(tmp_path / "h.sketchanim", warm=False, hosts=["127.0.0.1", "localhost"])
    with TestClient(app, base_url="http://127.0.0.1:8000") as local:
        assert local.get("/api/ready").status_code == 200
    with TestClient(app, base_url="http://attacker.example") as rebound:
        assert rebound.get("/api/project").status_code == 400
    app.state.hub.session.close()


def test_a_recorder_warning_reaches_every_page_as_a_notice_and_the_log(client, monkeypatch, caplog):
    """The journal fails during a take: the recorder warns when the take stops, and the
    warning goes to every page as a ``notice`` and into the server's log."""
    import logging

    from sketchanim.project.journal import Journal

    def broken(self, batches):
        raise OSError("disk full")

    monkeypatch.setattr(Journal, "__call__", broken)
    t = np.arange(60) / 60
    with caplog.at_level(logging.WARNING, logger="sketchanim.studio"), \
            client.websocket_connect("/ws") as a, client.websocket_connect("/ws") as b:
        a.receive_json(), b.receive_json()
        a.send_json({"type": "take.begin", "take": "k", "paths": ["lamp.intensity"]})
        receive_until(a, "take.started")
        a.send_json({"type": "take.samples", "take": "k", "t": t.tolist(), "values": (1 + t)[:, None].tolist()})
        import time
        time.sleep(0.2)                                         # the journal thread tries, and fails
        a.send_json({"type": "take.end", "take": "k"})
        for ws in (a, b):
            notice, _ = receive_until(ws, "notice")
            assert set(notice) == {"type", "level", "text", "source"}
            assert notice["level"] == "warning" and notice["source"] == "recorder"
            assert "the journal failed" in notice["text"] and "not safe from a crash" in notice["text"]
            receive_until(ws, "take.ended")                     # the take is kept all the same
    assert any("the journal failed" in r.getMessage() for r in caplog.records)
    assert [tr["path"] for tr in client.get("/api/state").json()["tracks"]] == ["lamp.intensity"]


def test_every_page_message_type_has_a_handler():
    from sketchanim.studio.handlers import HANDLERS
    from sketchanim.studio.protocol import Message

    inbound = {m.model_fields["type"].annotation.__args__[0] for m in Message.__origin__.__args__}
    assert inbound == set(HANDLERS)


def test_what_the_server_sends_is_declared_in_the_protocol(client):
    """Every message a session of ordinary use sends validates against its model."""
    from pydantic import TypeAdapter

    from sketchanim.studio import protocol

    adapter = TypeAdapter(protocol.ServerMessage)
    t = np.arange(30) / 60
    with client.websocket_connect("/ws") as a, client.websocket_connect("/ws") as b:
        seen = [a.receive_json(), b.receive_json()]
        for m in ({"type": "ping", "id": 1}, {"type": "set", "id": 2, "path": "cam.fov", "value": [30]},
                  {"type": "preview", "key": "k", "path": "box.position", "value": [1, 2, 3]},
                  {"type": "transport", "time": 1.0, "loop": [0, 2]},
                  {"type": "take.begin", "take": "a", "paths": ["box.position"]},
                  {"type": "take.samples", "take": "a", "t": t.tolist(), "values": np.c_[t, t, t].tolist()},
                  {"type": "take.end", "id": 3, "take": "a"}, {"type": "undo"}, {"type": "object.add", "name": "c"},
                  {"type": "export", "file": "x.glb"}, {"type": "warp"}):
            a.send_json(m)
        seen += receive_until(a, "exported", limit=200)[1] + [a.receive_json()]
        seen += receive_until(b, "state", limit=200)[1]
    assert {m["type"] for m in seen} >= {"state", "pong", "ack", "values", "history", "take.started", "tracks",
                                         "take.ended", "exported", "error", "preview", "transport", "take.running"}
    for m in seen:
        model = adapter.validate_python(m)
        assert protocol.wire(model) == m or m["type"] in ("preview", "transport"), m


def test_one_performer_per_project_the_others_see_the_take(client):
    """While page a records, page b is told (``take.running``), is refused a take of its
    own (``busy``), gets a's pieces as they come and the take's end; then b may record."""
    import time

    t = np.arange(0, 6, 1 / 60)
    x = np.c_[np.sin(3 * t), 0.5 + 0.2 * np.cos(5 * t), t]
    with client.websocket_connect("/ws") as a, client.websocket_connect("/ws") as b:
        a.receive_json(), b.receive_json()
        a.send_json({"type": "take.begin", "take": "a1", "paths": ["box.position"], "time": 0.0})
        receive_until(a, "take.started")
        running, _ = receive_until(b, "take.running")
        assert running == {"type": "take.running", "take": "a1", "paths": ["box.position"], "mode": "replace",
                           "time": 0.0, "layout": [["box.position", 0, 3]]}
        b.send_json({"type": "take.begin", "id": 7, "take": "b1", "paths": ["ball.position"]})
        error, _ = receive_until(b, "error")
        assert error["id"] == 7 and error["code"] == "busy"
        for i in range(0, len(t), 6):
            a.send_json({"type": "take.samples", "take": "a1", "t": t[i:i + 6].tolist(), "values": x[i:i + 6].tolist()})
            time.sleep(0.002)
        time.sleep(0.2)
        a.send_json({"type": "take.end", "take": "a1"})
        ended, before = receive_until(b, "take.ended", limit=400)
        assert ended["label"] == "take box.position"
        assert any(m["type"] == "take.piece" and m["take"] == "a1" for m in before), "b saw none of the take"
        with client.websocket_connect("/ws") as c:                   # no take runs now: c is told none
            assert c.receive_json()["take"] is None
        b.send_json({"type": "take.begin", "take": "b2", "paths": ["ball.position"]})
        receive_until(b, "take.started")
        receive_until(a, "take.running")
        b.send_json({"type": "take.cancel", "take": "b2"})
        receive_until(b, "take.ended")
