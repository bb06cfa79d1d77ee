"""Exports as downloads (``GET /api/export``) and the export dialog's choices
(``GET /api/export/choices``): each format made by the existing writers, named after the
project, valid (Khronos validator, pxr), within the tracks' tolerances of their takes;
a bad format a 400 with a clear message, nothing written beside the project."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient
from scipy.spatial.transform import Rotation

from clips import validate
from sketchanim.anim.attributes import ORIENTATION, POSITION
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.project.store import Project
from sketchanim.reducer.metric import rotation_angle
from sketchanim.studio.app import create_app
from sketchanim.studio.defaults import default_scene
from threejs_client import three_play

T = np.linspace(0, 2, 121)
POS = np.c_[np.sin(2 * T), 0.5 + 0.2 * T, np.cos(3 * T)]
QUAT = Rotation.from_rotvec(np.c_[np.sin(T), 0.5 * T, 0 * T]).as_quat()
TOL, ROT_TOL = 0.004, 0.5


def _track(path: str, type, values: np.ndarray, tol: float) -> ContinuousTrack:  # noqa: ANN001
    return ContinuousTrack(path, type, reduce_samples(type, T, values, tol, 4), tol, (Take(T, values),))


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory):  # noqa: ANN201
    """A studio app on a project whose box has a position and an orientation take; the
    folder, and a client."""
    folder = tmp_path_factory.mktemp("downloads")
    tracks = {"box.position": _track("box.position", POSITION, POS, TOL),
              "box.orientation": _track("box.orientation", ORIENTATION, QUAT, ROT_TOL)}
    Project(folder / "show.sketchanim").save(default_scene(), tracks)
    app = create_app(folder / "show.sketchanim", warm=False)
    with TestClient(app) as client:
        yield folder, client
    app.state.hub.session.close()


def _download(client: TestClient, folder: Path, fmt: str) -> Path:
    before = set(os.listdir(folder))
    r = client.get(f"/api/export?format={fmt}")
    assert r.status_code == 200, r.text
    disposition = r.headers["content-disposition"]
    assert disposition.startswith("attachment; filename=")
    name = disposition.split('"')[1]
    assert name.startswith("show.")
    assert set(os.listdir(folder)) == before, "a download wrote beside the project"
    out = folder / "got" / name
    out.parent.mkdir(exist_ok=True)
    out.write_bytes(r.content)
    return out


def test_glb_downloads_validate_and_three_js_plays_them_within_the_tolerances(exported) -> None:  # noqa: ANN001
    folder, client = exported
    for fmt, name in (("glb", "show.glb"), ("glb-frames", "show.frames.glb"), ("glb-compact", "show.compact.glb")):
        path = _download(client, folder, fmt)
        assert path.name == name
        (report,) = validate(path)
        assert report["numErrors"] == 0, report["messages"][:3]
        box = three_play(path, T)["box"]
        assert np.abs(box["position"] - POS).max() <= TOL
        assert np.degrees(rotation_angle(box["quaternion"], QUAT)).max() <= ROT_TOL


def test_usd_download_opens_with_pxr_within_the_tolerances_at_every_sample(exported) -> None:  # noqa: ANN001
    from pxr import Usd

    folder, client = exported
    path = _download(client, folder, "usd")
    stage = Usd.Stage.Open(str(path))
    rate = stage.GetTimeCodesPerSecond()
    box = stage.GetPrimAtPath("/box")
    pos = np.array([box.GetAttribute("xformOp:translate").Get(float(t * rate)) for t in T])
    quats = [box.GetAttribute("xformOp:orient").Get(float(t * rate)) for t in T]
    xyzw = np.array([[*q.GetImaginary(), q.GetReal()] for q in quats])
    assert np.abs(pos - POS).max() <= TOL
    assert np.degrees(rotation_angle(xyzw, QUAT)).max() <= ROT_TOL
    assert {p.GetName() for p in stage.GetPseudoRoot().GetChildren()} == {"box", "ball", "cone", "lamp", "cam"}


def test_json_download_is_the_project_document(exported) -> None:  # noqa: ANN001
    folder, client = exported
    path = _download(client, folder, "json")
    assert path.read_bytes() == client.get("/api/project").content


def test_choices_say_what_each_client_plays_within(exported) -> None:  # noqa: ANN001
    _, client = exported
    choices = client.get("/api/export/choices").json()["choices"]
    assert [c["format"] for c in choices] == ["glb", "glb-frames", "glb-compact", "usd", "json"]
    three = choices[0]["clients"][0]
    assert three["client"].startswith("three.js") and three["plays"] == "within 4 mm, 0.5°"
    assert "not within" in choices[0]["clients"][2]["plays"]          # Blender's importer and exact keys
    assert choices[1]["clients"][0]["plays"] == "within 4 mm, 0.5°"
    assert choices[2]["clients"][0]["plays"] == "within 4 mm, 0.5°" and "not at all" in choices[2]["clients"][2]["plays"]
    assert choices[4]["file"] == "show.json" and choices[4]["clients"][0]["plays"].startswith("exact")


@pytest.mark.parametrize("query, words", [("format=fbx", ["'fbx'", "glb, glb-frames, glb-compact, usd, bvh, json"]),
                                          ("format=", ["''", "not an export format"]),
                                          ("format=../x", ["'../x'"])])
def test_a_bad_format_is_a_400_naming_it(exported, query: str, words: list[str]) -> None:  # noqa: ANN001
    folder, client = exported
    before = set(os.listdir(folder))
    r = client.get(f"/api/export?{query}")
    assert r.status_code == 400 and r.headers["content-type"] == "application/json"
    assert all(w in r.json()["detail"] for w in words), r.json()
    assert set(os.listdir(folder)) == before


def test_a_tolerance_float32_cannot_keep_is_a_400_the_page_shows_and_the_project_is_kept(tmp_path: Path) -> None:
    """A take ten minutes into the scene's time at 0.01 mm: float32 key times alone move
    it by more than half of that, so every glTF download is refused naming the track and
    the advice (the page's export dialog shows the 400's detail); nothing is written,
    the project and its tracks are as they were, and the formats that keep it still
    download."""
    late = T + 600.0
    track = ContinuousTrack("box.position", POSITION, reduce_samples(POSITION, late, POS, 1e-5, 4), 1e-5,
                            (Take(late, POS),))
    Project(tmp_path / "late.sketchanim").save(default_scene(), {"box.position": track})
    app = create_app(tmp_path / "late.sketchanim", warm=False)
    with TestClient(app) as client:
        before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
        for fmt in ("glb", "glb-frames", "glb-compact"):
            r = client.get(f"/api/export?format={fmt}")
            assert r.status_code == 400 and r.headers["content-type"] == "application/json", r.text
            detail = r.json()["detail"]
            assert detail.startswith("tolerance: 1e-05 for track 'box.position' is less than twice what float32 may move it")
            assert detail.endswith("ask for a larger tolerance, or start the times nearer 0"), detail
        assert client.get("/api/export?format=json").status_code == 200
        assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before
        assert "box.position" in app.state.hub.session.player.tracks
    app.state.hub.session.close()
