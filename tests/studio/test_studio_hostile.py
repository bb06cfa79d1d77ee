"""Hostile and unlucky clients through the app: every bad frame gets an error reply on a
socket that stays open, from a page that is recording (its take goes on), with no
traceback in the log; frame sizes through a real server (uvicorn's limit); a page that
never reads is dropped while the others are answered; a silent owner loses its take (kept); a disk that fails is told to every page, logged once, and
what was acked is saved once the disk is back."""

from __future__ import annotations

import errno
import json
import logging
import threading
import time

import numpy as np
import pytest
import uvicorn
from fastapi.testclient import TestClient
from test_studio_protocol import receive_until

from sketchanim.project.store import Project
from sketchanim.studio import app as studio_app
from sketchanim.studio import saving
from sketchanim.studio import session as studio_session
from sketchanim.studio.app import create_app
from sketchanim.studio.protocol import MAX_ERROR_TEXT, MAX_FRAME_BYTES, MAX_MESSAGE_BYTES
from sketchanim.studio.serve import server_config
from studio_browser import free_port, studio_server, unread_socket

HOSTILE = {
    "a 5000-digit integer": '{"type": "ping", "id": ' + "9" * 5000 + "}",
    "JSON 2000 deep": '{"type": "set", "path": "box.position", "value": ' + "[" * 2000 + "]" * 2000 + "}",
    "an export name with NUL": json.dumps({"type": "export", "id": "nul", "file": "a\x00b.glb"}),
    "an export name over 255 bytes": json.dumps({"type": "export", "id": "long", "file": "€" * 100 + ".glb"}),
    "an export name that is a folder": json.dumps({"type": "export", "id": "folder", "file": "sub.json"}),
    "1.5 MiB of 'é' in under 1 MiB characters": json.dumps({"type": "ping", "pad": "é" * (3 * 2**19 // 2)},
                                                           ensure_ascii=False),
    "a 5 MiB frame": json.dumps({"type": "ping", "pad": "x" * 5 * 2**20}),
    "a 600k-character id": json.dumps({"type": "ping", "id": "i" * 600_000}),
    "a binary frame that is not UTF-8": b'{"type": "ping", "id": 1, "pad": "\xff\xfe"}',
}
CODES = {"a 5000-digit integer": "bad_message", "JSON 2000 deep": "bad_message",
         "1.5 MiB of 'é' in under 1 MiB characters": "too_large", "a 5 MiB frame": "too_large",
         "a 600k-character id": "bad_message", "a binary frame that is not UTF-8": "bad_message"}


def begin(ws, take: str = "t", path: str = "box.position", samples: int = 30) -> None:
    """Begin a take of ``path`` and send it ``samples`` frames (acked)."""
    ws.send_json({"type": "take.begin", "id": "begin", "take": take, "paths": [path]})
    receive_until(ws, "take.started")
    t = np.arange(samples) / 60
    ws.send_json({"type": "take.samples", "id": "s", "take": take, "t": t.tolist(),
                  "values": np.c_[np.sin(t), 0.5 + 0 * t, t].tolist()})
    receive_until(ws, "ack", id="s")


def running(ws) -> str | None:
    """The take the server says is running (asked with ``state``), or None."""
    ws.send_json({"type": "state"})
    state, _ = receive_until(ws, "state")
    return None if state["take"] is None else state["take"]["take"]


def test_every_hostile_frame_is_answered_on_an_open_socket_and_the_take_goes_on(client, tmp_path, caplog):
    multibyte = HOSTILE["1.5 MiB of 'é' in under 1 MiB characters"]
    assert len(multibyte) < MAX_MESSAGE_BYTES < len(multibyte.encode())          # bytes, not characters, count
    (tmp_path / "sub.json").mkdir()
    caplog.set_level(logging.INFO)
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        begin(ws)
        for name, frame in HOSTILE.items():
            ws.send_bytes(frame) if isinstance(frame, bytes) else ws.send_text(frame)
            error, _ = receive_until(ws, "error")
            assert error["code"] == CODES.get(name, error["code"]) and error["code"] != "rate", (name, error)
            assert len(error["message"]) <= MAX_ERROR_TEXT and len(json.dumps(error)) < 1000, name
            assert error["id"] in (None, "nul", "long", "folder"), name
            ws.send_json({"type": "ping", "id": name})
            pong, _ = receive_until(ws, "pong")
            assert pong["id"] == name
            assert running(ws) == "t", name
        ws.send_json({"type": "take.end", "id": "end", "take": "t"})
        ended, _ = receive_until(ws, "take.ended")
    assert ended["reason"] == "end" and ended["paths"] == ["box.position"]
    assert [r.getMessage() for r in caplog.records if r.exc_info is not None] == []
    assert not any(f.name.startswith("a") and f.suffix == ".glb" for f in tmp_path.iterdir())


def test_frames_over_the_message_limit_are_answered_and_over_the_frame_limit_close_the_socket(tmp_path):
    from websockets.exceptions import ConnectionClosed
    from websockets.sync import client as websockets

    with studio_server(tmp_path / "big.sketchanim") as url:
        with websockets.connect(url.replace("http", "ws") + "ws", max_size=None) as ws:
            assert json.loads(ws.recv())["type"] == "state"
            ws.send(json.dumps({"type": "ping", "id": 1, "pad": "x" * (MAX_FRAME_BYTES - 2**20)}))
            error = _next(ws, "error")
            assert error["code"] == "too_large" and error["id"] is None
            ws.send(json.dumps({"type": "ping", "id": 2}))
            assert _next(ws, "pong")["id"] == 2
            ws.send("x" * (MAX_FRAME_BYTES + 1))
            with pytest.raises(ConnectionClosed) as closed:
                while True:
                    ws.recv()
        assert closed.value.rcvd.code == 1009


def _next(ws, kind: str) -> dict:
    while True:
        message = json.loads(ws.recv())
        if message["type"] == kind:
            return message


def test_a_page_that_never_reads_is_dropped_and_the_others_go_on(tmp_path, monkeypatch, caplog):
    from websockets.sync import client as websockets

    monkeypatch.setattr(studio_app, "SEND_TIMEOUT", 1.0)
    monkeypatch.setattr(studio_app, "MAX_QUEUED", 2**16)
    monkeypatch.setattr(studio_app, "RATE", 1e6)
    monkeypatch.setattr(studio_app, "BURST", 1e6)
    caplog.set_level(logging.INFO)
    app = create_app(tmp_path / "slow.sketchanim", warm=False)
    port = free_port()
    server = uvicorn.Server(server_config(app, host="127.0.0.1", port=port))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    hub = app.state.hub
    try:
        while not server.started:
            time.sleep(0.05)
        stuck = unread_socket(port)                             # the handshake, and nothing more is read from it
        with websockets.connect(f"ws://127.0.0.1:{port}/ws", max_size=None) as ws:
            json.loads(ws.recv())
            assert len(hub.clients) == 2
            pad = "k" * 100
            sent = 0
            while len(hub.clients) == 2:                        # previews of new keys: nothing coalesces
                for _ in range(500):
                    ws.send(json.dumps({"type": "preview", "key": f"{sent}{pad}"[:128], "path": "box.position",
                                        "value": [sent, 0, 0]}))
                    sent += 1
                ws.send(json.dumps({"type": "ping", "id": sent}))
                assert _next(ws, "pong")["id"] == sent          # the reading page is answered all along
                assert max(c.queued for c in list(hub.clients.values())) <= studio_app.MAX_QUEUED
                assert sent < 2_000_000, "the page that does not read was never dropped"
            ws.send(json.dumps({"type": "ping", "id": "after"}))
            assert _next(ws, "pong")["id"] == "after"
        stuck.close()
    finally:
        server.should_exit = True
        thread.join(30)
        hub.session.close()
    assert any("has read nothing for 1 s" in r.getMessage() for r in caplog.records)
    assert any("is not reading" in r.getMessage() for r in caplog.records)     # its backlog was dropped first


def test_a_silent_owner_loses_its_take_kept_and_a_page_that_pings_keeps_it(client, monkeypatch):
    monkeypatch.setattr(studio_session, "SILENCE", 0.5)
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        begin(ws, "quiet")
        tracks, _ = receive_until(ws, "tracks", limit=200)      # nothing sent: the take ends on its own
        ended, _ = receive_until(ws, "take.ended")
        assert ended["reason"] == "silent" and ended["take"] == "quiet" and ended["paths"] == ["box.position"]
        assert [t["path"] for t in tracks["changed"]] == ["box.position"]
        begin(ws, "alive", "ball.position")
        pings = 0
        started = time.monotonic()
        while time.monotonic() - started < 4 * 0.5:             # four silences' worth of pings
            ws.send_json({"type": "ping", "id": pings})
            receive_until(ws, "pong")
            pings += 1
            time.sleep(0.05)
        assert running(ws) == "alive"
        ws.send_json({"type": "take.end", "take": "alive"})
        ended, _ = receive_until(ws, "take.ended")
    assert ended["reason"] == "end"
    paths = {t["path"]: t for t in client.get("/api/state").json()["tracks"]}
    assert set(paths) == {"box.position", "ball.position"} and paths["box.position"]["takes"][0]["n"] == 30


def test_a_failing_disk_is_told_to_every_page_logged_once_and_the_edit_saved_when_it_is_back(tmp_path, monkeypatch,
                                                                                          caplog):
    caplog.set_level(logging.INFO)
    monkeypatch.setattr(saving, "RETRY", 0.2)
    project = tmp_path / "p.sketchanim"
    app = create_app(project, warm=False)
    real_save, tries = Project.save, []

    def full(*args, **kwargs):
        tries.append(time.monotonic())
        raise OSError(errno.ENOSPC, "No space left on device", str(project))

    with TestClient(app) as client:
        with client.websocket_connect("/ws") as a, client.websocket_connect("/ws") as b:
            a.receive_json(), b.receive_json()
            monkeypatch.setattr(Project, "save", full)
            a.send_json({"type": "set", "id": "fov", "path": "cam.fov", "value": [35]})
            receive_until(a, "ack")
            for page in (a, b):
                saved, seen = receive_until(page, "saved")
                notices = [m for m in seen + [page.receive_json()] if m["type"] == "notice"]
                assert saved["ok"] is False and "No space left on device" in saved["error"]
                assert [n["level"] for n in notices] == ["error"] and notices[0]["source"] == "disk"
            while len(tries) < 4:                               # the retries go on ...
                a.send_json({"type": "ping"})
                receive_until(a, "pong")
                time.sleep(0.05)
            errors = [r for r in caplog.records if r.levelno >= logging.ERROR]
            assert len(errors) == 1 and "No space left on device" in errors[0].getMessage()   # ... logged once
            monkeypatch.setattr(Project, "save", real_save)
            for page in (a, b):
                saved, _ = receive_until(page, "saved", limit=200)
                assert saved["ok"] is True and saved["error"] is None
            assert _value(client.get("/api/project").json(), "cam", "fov") == [35.0]
            with Project(project, create=False) as on_disk:
                scene, _ = on_disk.load()
            assert scene.get("cam.fov").tolist() == [35.0]
    app.state.hub.session.close()
    again = create_app(project, warm=False)
    with TestClient(again) as client:
        fov = _value(client.get("/api/state").json(), "cam", "fov")
    again.state.hub.session.close()
    assert fov == [35.0]
    assert not any(r.exc_info for r in caplog.records)


def _value(state: dict, name: str, attribute: str) -> object:
    return {a["name"]: a["value"] for o in state["objects"] if o["name"] == name for a in o["attributes"]}[attribute]


def test_a_server_bug_answers_failed_and_logs_its_traceback_once(client, monkeypatch, caplog):
    from sketchanim.studio import handlers

    def broken(session, message, number):  # noqa: ANN001, ANN202
        raise ZeroDivisionError("a bug")

    monkeypatch.setitem(handlers.HANDLERS, "undo", broken)
    caplog.set_level(logging.INFO)
    with client.websocket_connect("/ws") as ws:
        ws.receive_json()
        ws.send_json({"type": "undo", "id": 5})
        error, _ = receive_until(ws, "error")
        ws.send_json({"type": "ping", "id": 6})
        assert receive_until(ws, "pong")[0]["id"] == 6
    assert error["code"] == "failed" and error["id"] == 5 and error["ref"] == "undo"
    assert "ZeroDivisionError" in error["message"] and "a bug" not in error["message"]
    traced = [r for r in caplog.records if r.exc_info is not None]
    assert len(traced) == 1 and traced[0].levelno == logging.ERROR and traced[0].exc_info[0] is ZeroDivisionError
