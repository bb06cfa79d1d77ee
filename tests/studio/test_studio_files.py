"""Project files from the page: save as (a copy in the files folder, atomically, never over a
file; the studio goes on with it and every page gets its state), open (a project of the files
folder or of the recent list), the recent list (``GET /api/recent``, ``sketchanim studio
--recent``); bad names refused with a message naming the file, nothing changed."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.cli import app as cli
from sketchanim.project.recent import recent, recent_file
from sketchanim.project.store import Project
from sketchanim.studio.app import create_app
from sketchanim.studio.defaults import default_scene

T = np.linspace(0, 1, 61)
POS = np.c_[T, np.sin(3 * T), 0 * T]


@pytest.fixture
def studio(tmp_path: Path):  # noqa: ANN201
    """An app on ``show.sketchanim`` (the box's position recorded), its folder and a client."""
    track = ContinuousTrack("box.position", POSITION, reduce_samples(POSITION, T, POS, 0.005, 4), 0.005,
                            (Take(T, POS),))
    Project(tmp_path / "show.sketchanim").save(default_scene(), {"box.position": track}, fps=24.0)
    app = create_app(tmp_path / "show.sketchanim", warm=False)
    with TestClient(app) as client:
        yield tmp_path, client, app
    app.state.hub.session.close()


def _curves(doc: dict) -> dict:
    return {c["path"]: (c["knots"], c["coef"]) for c in doc["curves"]}


def test_save_as_writes_the_copy_and_goes_on_with_it(studio) -> None:  # noqa: ANN001
    folder, client, app = studio
    before = client.get("/api/project").json()
    with client.websocket_connect("/ws") as page:
        assert page.receive_json()["project"] == "show.sketchanim"
        r = client.post("/api/project/save-as?name=take2.sketchanim")
        assert r.status_code == 200, r.text
        assert r.json()["name"] == "take2.sketchanim"
        state = page.receive_json()
        while state["type"] != "state":
            state = page.receive_json()
        assert state["project"] == "take2.sketchanim"
    assert client.get("/api/state").json()["project"] == "take2.sketchanim"
    after = client.get("/api/project").json()
    assert _curves(after) == _curves(before) and after["fps"] == 24.0
    assert app.state.hub.session.path == folder / "take2.sketchanim"
    # the project it was is closed, its lock let go: it opens elsewhere, as it was
    with Project(folder / "show.sketchanim", create=False) as old:
        scene, tracks = old.load()
        assert list(tracks) == ["box.position"]
    assert not [n for n in os.listdir(folder) if "tmp" in n], "a temporary file was left"
    assert [Path(r.path).name for r in recent()][:1] == ["take2.sketchanim"]
    listed = client.get("/api/recent").json()
    assert listed["current"] == str(folder / "take2.sketchanim") and listed["folder"] == str(folder)
    assert listed["recent"][0]["name"] == "take2.sketchanim" and listed["recent"][0]["exists"]


@pytest.mark.parametrize("name, status, words", [
    ("show.sketchanim", 409, ["'show.sketchanim' exists", "another name"]),
    ("../up.sketchanim", 400, ["'../up.sketchanim'", "not a path"]),
    ("copy.glb", 400, ["'copy.glb'", "ends in .sketchanim"]),
    (".hidden.sketchanim", 400, ["hidden"]),
    ("", 400, ["needs a file name"]),
])
def test_save_as_refuses_a_bad_name_and_changes_nothing(studio, name: str, status: int,  # noqa: ANN001
                                                        words: list[str]) -> None:
    folder, client, _ = studio
    listing = sorted(os.listdir(folder))
    r = client.post("/api/project/save-as", params={"name": name})
    assert r.status_code == status, r.text
    assert all(w in r.json()["detail"] for w in words), r.json()
    assert sorted(os.listdir(folder)) == listing
    assert client.get("/api/state").json()["project"] == "show.sketchanim"


def test_open_a_project_of_the_files_folder_or_the_recent_list(studio) -> None:  # noqa: ANN001
    folder, client, _ = studio
    Project(folder / "other.sketchanim").save(default_scene(), {})
    r = client.post("/api/project/open", params={"path": "other.sketchanim"})
    assert r.status_code == 200, r.text
    state = client.get("/api/state").json()
    assert state["project"] == "other.sketchanim" and not state["tracks"]
    # back to the first, by its path in the recent list (it was not put there: the CLI does)
    r = client.post("/api/project/open", params={"path": str(folder / "show.sketchanim")})
    assert r.status_code == 400 and "neither a project in the files folder nor a recent one" in r.json()["detail"]
    r = client.post("/api/project/open", params={"path": "show.sketchanim"})
    assert r.status_code == 200 and client.get("/api/state").json()["project"] == "show.sketchanim"
    r = client.post("/api/project/open", params={"path": str(folder / "other.sketchanim")})   # recent now
    assert r.status_code == 200 and client.get("/api/state").json()["project"] == "other.sketchanim"


@pytest.mark.parametrize("path, status, words", [("/etc/passwd", 400, ["neither"]),
                                                 ("gone.sketchanim", 404, ["no such project file"]),
                                                 ("notes.txt", 400, ["ends in .sketchanim"]),
                                                 ("show.sketchanim", 409, ["is the open project"])])
def test_open_refuses_and_changes_nothing(studio, path: str, status: int, words: list[str]) -> None:  # noqa: ANN001
    folder, client, _ = studio
    (folder / "notes.txt").write_text("x")
    r = client.post("/api/project/open", params={"path": path})
    assert r.status_code == status and all(w in r.json()["detail"] for w in words), r.json()
    assert client.get("/api/state").json()["project"] == "show.sketchanim"


def test_studio_recent_lists_the_projects_opened(studio) -> None:  # noqa: ANN001
    folder, client, _ = studio
    recent_file().unlink(missing_ok=True)
    result = CliRunner().invoke(cli, ["studio", "--recent"])
    assert result.exit_code == 0 and "no recent projects" in result.output
    assert client.post("/api/project/save-as?name=b.sketchanim").status_code == 200
    result = CliRunner().invoke(cli, ["studio", "--recent"])
    assert result.exit_code == 0 and str(folder / "b.sketchanim") in result.output
    (folder / "b.sketchanim").rename(folder / "moved.sketchanim")
    assert "(gone)" in CliRunner().invoke(cli, ["studio", "--recent"]).output


def test_open_a_project_another_studio_has_open_is_refused(studio) -> None:  # noqa: ANN001
    from sketchanim.project.lock import ProjectLock

    folder, client, _ = studio
    Project(folder / "busy.sketchanim").save(default_scene(), {})
    lock = ProjectLock(folder / "busy.sketchanim")
    try:
        r = client.post("/api/project/open", params={"path": "busy.sketchanim"})
        assert r.status_code == 400 and "open in another studio" in r.json()["detail"], r.text
        assert client.get("/api/state").json()["project"] == "show.sketchanim"
        assert client.get("/api/project").json()["curves"], "the open project lost its tracks"
    finally:
        lock.release()


def test_a_files_folder_that_is_not_one_is_refused_and_the_project_let_go(tmp_path: Path) -> None:
    from sketchanim.errors import ArgumentError

    with pytest.raises(ArgumentError, match="missing is not a folder"):
        create_app(tmp_path / "p.sketchanim", warm=False, files=tmp_path / "missing")
    create_app(tmp_path / "p.sketchanim", warm=False).state.hub.session.close()     # its lock was let go
