"""A read-only project in the studio: it loads and plays, its state says so, every edit
is refused with ``read_only`` (the file's bytes unchanged), and it exports into a
writable exports folder; through the app the refusal is an error on a socket that
stays open."""

from __future__ import annotations

import json
import os

import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from sketchanim.cli import app as cli

from sketchanim.errors import FileFormatError, InputError
from sketchanim.studio import protocol as p
from sketchanim.studio.app import create_app
from sketchanim.studio.handlers import EDITS, HANDLERS, error_code, handle
from sketchanim.studio.session import Session

#: One valid message of every type that edits.
EDIT_MESSAGES = [
    {"type": "set", "path": "lamp.intensity", "value": [2]},
    {"type": "preview", "key": "k", "path": "box.position", "value": [1, 2, 3]},
    {"type": "object.add", "name": "crate"},
    {"type": "object.remove", "name": "box"},
    {"type": "object.rename", "name": "box", "to": "crate"},
    {"type": "take.begin", "take": "t1", "paths": ["box.position"]},
    {"type": "take.samples", "take": "t1", "t": [0, 0.1], "values": [[0, 0, 0], [1, 1, 1]]},
    {"type": "take.end", "take": "t1"},
    {"type": "take.cancel", "take": "t1"},
    {"type": "undo"},
    {"type": "redo"},
    {"type": "tolerance.set", "path": "box.position", "amount": 2},
    {"type": "object.duplicate", "name": "box", "to": "box2"},
    {"type": "curve.points", "edits": [{"path": "box.position", "index": 0, "value": [0, 0, 0]}]},
    {"type": "curve.key", "path": "box.position", "time": 0.5, "value": [0, 0, 0]},
    {"type": "curve.knots", "path": "box.position", "insert": [0.5]},
    {"type": "track.key", "path": "lamp.on", "time": 0.5, "value": False},
    {"type": "track.reduce", "paths": ["box.position"], "tol": 0.01},
    {"type": "take.edit", "path": "box.position", "take": 0, "op": "mute"},
    {"type": "settings", "fps": 30},
    {"type": "track.retime", "paths": ["box.position"], "shift": 1},
    {"type": "track.cut", "paths": ["box.position"], "t0": 0, "t1": 1},
    {"type": "track.paste", "path": "box.position", "at": 0, "length": 1,
     "piece": {"path": "box.visible", "kind": "steps", "times": [0.5], "values": [False]}},
    {"type": "sound.set", "name": "a.wav", "offset": 1},
    {"type": "sound.remove", "name": "a.wav"},
    {"type": "sound.beats", "name": "a.wav"},
]


@pytest.fixture
def project(tmp_path):
    """A saved project with one edit in it, and its exports folder."""
    path = tmp_path / "show" / "p.sketchanim"
    path.parent.mkdir()
    session = Session(path)
    handle(session, p.parse('{"type": "set", "path": "lamp.intensity", "value": [3]}'), 0)
    session.close()
    (tmp_path / "out").mkdir()
    return path


def test_every_edit_is_listed_and_what_remains_only_reads():
    assert {m["type"] for m in EDIT_MESSAGES} == EDITS
    assert set(HANDLERS) - EDITS == {"ping", "state", "transport", "export", "track.samples",
                                     "track.copy"}


def test_a_read_only_session_plays_refuses_edits_and_exports(project):
    before, listed = project.read_bytes(), sorted(os.listdir(project.parent))
    session = Session(project, read_only=True, exports=project.parent.parent / "out")
    try:
        assert session.read_only
        state = session.state()
        assert state["read_only"] is True
        assert {v["name"]: v["value"] for o in state["objects"] for v in o["attributes"]
                if o["name"] == "lamp"}["intensity"] == [3.0]
        for raw in EDIT_MESSAGES:
            message = p.parse(json.dumps(raw))
            with pytest.raises(InputError) as refused:
                handle(session, message, 0)
            assert error_code(message, refused.value, session) == "read_only"
            assert "read-only" in str(refused.value) and "export" in str(refused.value)
            assert str(refused.value).startswith(raw["type"])
        assert session.take is None and not session.dirty
        for raw in ({"type": "ping"}, {"type": "state"}, {"type": "transport", "time": 1.5, "playing": True}):
            assert handle(session, p.parse(json.dumps(raw)), 0)
        for name in ("a.glb", "a.json"):
            [(_, reply)] = handle(session, p.parse(json.dumps({"type": "export", "file": name})), 0)
            assert reply == {"type": "exported", "file": name}
        exported = json.loads((session.exports / "a.json").read_text())
        assert exported["objects"]
    finally:
        session.close()
    assert project.read_bytes() == before and sorted(os.listdir(project.parent)) == listed
    assert sorted(os.listdir(project.parent.parent / "out")) == ["a.glb", "a.json"]


def test_a_writable_session_says_it_is_not_read_only(project):
    session = Session(project)
    try:
        assert session.read_only is False and session.state()["read_only"] is False
    finally:
        session.close()


def test_a_missing_project_cannot_be_opened_read_only(tmp_path):
    with pytest.raises(FileFormatError, match="cannot be created read-only"):
        Session(tmp_path / "none.sketchanim", read_only=True)
    assert os.listdir(tmp_path) == []                       # nor is its lock left behind


def test_through_the_app_an_edit_is_refused_and_the_socket_stays_open(project):
    before = project.read_bytes()
    app = create_app(project, warm=False, read_only=True, exports=project.parent.parent / "out")
    with TestClient(app) as client, client.websocket_connect("/ws") as ws:
        assert ws.receive_json()["read_only"] is True
        ws.send_json({"type": "set", "id": "s", "path": "lamp.intensity", "value": [9]})
        error = ws.receive_json()
        assert (error["type"], error["code"], error["id"], error["ref"]) == ("error", "read_only", "s", "set")
        assert "read-only" in error["message"]
        ws.send_json({"type": "export", "id": "e", "file": "scene.glb"})
        assert ws.receive_json() == {"type": "exported", "file": "scene.glb"}
        assert ws.receive_json() == {"type": "ack", "id": "e", "ref": "export"}
        ws.send_json({"type": "export", "id": "again", "file": "scene.glb"})
        error = ws.receive_json()
        assert (error["code"], error["id"]) == ("exists", "again") and "'scene.glb' exists" in error["message"]
        ws.send_json({"type": "ping", "id": "after"})
        assert ws.receive_json()["type"] == "pong"
    app.state.hub.session.close()
    assert project.read_bytes() == before


def test_the_studio_command_passes_read_only_and_exports(tmp_path, monkeypatch):
    from sketchanim.studio import serve

    calls = []
    monkeypatch.setattr(serve, "serve", lambda *args, **kwargs: calls.append(kwargs))
    for flags, read_only in (([], None), (["--read-only"], True)):
        result = CliRunner().invoke(cli, ["studio", str(tmp_path / "p.sketchanim"), "--no-browser", *flags,
                                          "--exports", str(tmp_path)])
        assert result.exit_code == 0, result.output
        assert calls.pop() == {"read_only": read_only, "exports": tmp_path, "files": None}
    result = CliRunner().invoke(cli, ["studio", str(tmp_path / "p.sketchanim"), "--no-browser", "--files", str(tmp_path)])
    assert result.exit_code == 0 and calls.pop() == {"read_only": None, "exports": None, "files": tmp_path}


def test_an_exports_folder_that_is_not_one_is_refused_at_start(tmp_path):
    result = CliRunner().invoke(cli, ["studio", str(tmp_path / "p.sketchanim"), "--no-browser", "--port", "0",
                                      "--exports", str(tmp_path / "missing")])
    assert result.exit_code == 2 and "missing is not a folder" in result.output and "Traceback" not in result.output
    assert os.listdir(tmp_path) == []
