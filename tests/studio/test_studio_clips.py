"""Clips into the scene (``POST /api/clips``): a real BVH's joints become objects whose world
position and orientation tracks are in ``GET /api/project``, within their tolerances of the
clip's frames (forward kinematics), added and undone as one step; a truncated or mistyped or
too large upload refused with a message naming it, the project unchanged."""

from __future__ import annotations

import numpy as np
import pytest
from fastapi.testclient import TestClient
from scipy.spatial.transform import Rotation

from sketchanim.formats.bvh import read_bvh
from sketchanim.formats.c3d import read_c3d
from sketchanim.mocap.scene_clip import object_names
from sketchanim.motion.kinematics import world_pose
from sketchanim.project.store import Project
from sketchanim.studio import clips
from sketchanim.studio.app import create_app
from studio_browser import curve, held

CLIP = "bvh/bandai1_dash_normal_001.bvh"


@pytest.fixture
def client(tmp_path):  # noqa: ANN001, ANN201
    app = create_app(tmp_path / "p.sketchanim", warm=False)
    with TestClient(app) as c:
        yield c, app.state.hub.session
    app.state.hub.session.close()


@pytest.mark.realdata
def test_a_bvh_becomes_objects_whose_tracks_play_its_joints(client, data_dir) -> None:  # noqa: ANN001
    c, session = client
    source = data_dir / CLIP
    r = c.post("/api/clips?name=dash.bvh", content=source.read_bytes())
    assert r.status_code == 200, r.text
    clip = read_bvh(source)
    answer = r.json()
    names = clip.skeleton.names
    assert answer["objects"] == [f"dash_{n}" for n in names] and answer["frames"] == len(clip.times)
    assert answer["tracks"] == 2 * len(names)
    doc = c.get("/api/project").json()
    turns, positions = world_pose(clip.skeleton, clip.rotations, clip.translations)
    unit = clip.guess_unit_m()
    for j, name in enumerate(names):
        spline, entry = curve(doc, f"dash_{name}.position")
        assert np.abs(held(spline, clip.times) - positions[:, j] * unit).max() <= entry["tol"] * (1 + 1e-9)
        spline, entry = curve(doc, f"dash_{name}.orientation")
        q = held(spline, clip.times)
        played = Rotation.from_quat(q / np.linalg.norm(q, axis=1, keepdims=True))
        assert np.degrees((played.inv() * turns[j]).magnitude()).max() <= entry["tol"] * (1 + 1e-9)
    state = c.get("/api/state").json()
    assert state["history"]["undo"][-1] == "import dash.bvh"
    session.undo()
    assert not [o for o in c.get("/api/state").json()["objects"] if o["name"].startswith("dash_")]
    # again: the names are free again, and a second import beside the first is numbered
    assert c.post("/api/clips?name=dash.bvh", content=source.read_bytes()).status_code == 200
    again = c.post("/api/clips?name=dash.bvh", content=source.read_bytes()).json()
    assert again["objects"][0] == f"dash_{names[0]}_2"


@pytest.mark.realdata
@pytest.mark.parametrize("cut", [0.5, 0.95])
def test_a_truncated_bvh_is_refused_naming_it_and_changes_nothing(client, data_dir, cut: float) -> None:  # noqa: ANN001
    c, _ = client
    data = (data_dir / CLIP).read_bytes()
    before = c.get("/api/project").content
    r = c.post("/api/clips?name=dash.bvh", content=data[: int(len(data) * cut)])
    assert r.status_code == 400 and r.json()["detail"].startswith("dash.bvh"), r.text
    assert "upload.bvh" not in r.json()["detail"]
    assert c.get("/api/project").content == before


def test_not_a_bvh_or_too_large_is_refused(client, monkeypatch: pytest.MonkeyPatch) -> None:  # noqa: ANN001
    c, _ = client
    before = c.get("/api/project").content
    r = c.post("/api/clips?name=song.mp3", content=b"ID3....")
    assert r.status_code == 400 and "'song.mp3': a clip upload is a .bvh or a .c3d file" in r.json()["detail"]
    r = c.post("/api/clips?name=noise.bvh", content=bytes(range(256)) * 4)
    assert r.status_code == 400 and r.json()["detail"].startswith("noise.bvh")
    monkeypatch.setattr(clips, "MAX_CLIP_BYTES", 1000)
    r = c.post("/api/clips?name=big.bvh", content=b"HIERARCHY\n" * 500)
    assert r.status_code == 413 and "at most" in r.json()["detail"]
    assert c.get("/api/project").content == before


@pytest.mark.realdata
def test_a_take_over_a_joint_is_layered_over_its_clip_track(client, data_dir) -> None:  # noqa: ANN001
    c, _ = client
    source = data_dir / "bvh" / "bandai1_walk_happy_001.bvh"
    assert c.post("/api/clips?name=walk.bvh", content=source.read_bytes()).status_code == 200
    path = "walk_Hips.position"
    spline, _ = curve(c.get("/api/project").json(), path)
    t = np.linspace(2.0, 3.0, 61)                      # a punch-in over 2..3 s of the 7 s clip
    lifted = held(spline, t) + [0.0, 0.3, 0.0]
    with c.websocket_connect("/ws") as page:
        page.send_json({"type": "take.begin", "id": 1, "take": "lift", "paths": [path], "time": 2.0})
        page.send_json({"type": "take.samples", "take": "lift", "t": t.tolist(), "values": lifted.tolist()})
        page.send_json({"type": "take.end", "id": 2, "take": "lift"})
        while not (m := page.receive_json())["type"] == "ack" or m["id"] != 2:
            assert m["type"] != "error", m
    layered, entry = curve(c.get("/api/project").json(), path)
    assert len(entry["takes"]) == 2
    inside = (t > 2.2) & (t < 2.8)                     # clear of the blends at the seams
    assert np.abs(held(layered, t[inside]) - lifted[inside]).max() <= entry["tol"] * (1 + 1e-6)
    early = np.linspace(0.2, 1.5, 40)                  # before it: the clip as it was
    assert np.abs(held(layered, early) - held(spline, early)).max() <= entry["tol"]


@pytest.mark.realdata
def test_a_read_only_project_takes_no_clip(tmp_path, data_dir) -> None:  # noqa: ANN001
    create_app(tmp_path / "ro.sketchanim", warm=False).state.hub.session.close()     # the project, made
    app = create_app(tmp_path / "ro.sketchanim", warm=False, read_only=True)
    with TestClient(app) as c:
        before = c.get("/api/project").content
        r = c.post("/api/clips?name=dash.bvh", content=(data_dir / CLIP).read_bytes())
        assert r.status_code == 400 and "read-only" in r.json()["detail"]
        assert c.get("/api/project").content == before
    app.state.hub.session.close()


@pytest.mark.realdata
def test_each_joint_names_its_parent_joint_in_the_project(client, data_dir) -> None:  # noqa: ANN001
    c, session = client
    clip = read_bvh(data_dir / CLIP)
    assert c.post("/api/clips?name=dash.bvh", content=(data_dir / CLIP).read_bytes()).status_code == 200
    doc = c.get("/api/project").json()
    objects = {o["name"]: {a["name"]: a for a in o["attributes"]} for o in doc["objects"]}
    skeleton = clip.skeleton
    for name, up in zip(skeleton.names, skeleton.parents):
        attrs = objects[f"dash_{name}"]
        if up < 0:
            assert clips.BONE_PARENT not in attrs
        else:
            assert attrs[clips.BONE_PARENT]["type"]["choices"] == [f"dash_{skeleton.names[up]}"]
            assert attrs[clips.BONE_PARENT]["value"] == f"dash_{skeleton.names[up]}"
    c.app.state.hub.thread.submit(session.save).result()    # in the model's thread (the app saves there too)
    scene, _ = Project(session.path).load()
    hips = skeleton.names[skeleton.parents[1]]
    assert scene.get(f"dash_{skeleton.names[1]}.{clips.BONE_PARENT}") == f"dash_{hips}"


C3D = "c3d/pyomeca_markers_analogs.c3d"


@pytest.mark.realdata
def test_a_c3d_becomes_one_object_per_marker_hidden_in_its_gaps(client, data_dir) -> None:  # noqa: ANN001
    c, session = client
    markers = read_c3d(data_dir / C3D)
    r = c.post("/api/clips?name=lab.c3d", content=(data_dir / C3D).read_bytes())
    assert r.status_code == 200, r.text
    answer = r.json()
    names = object_names("lab", markers.names, set())
    assert answer["objects"] == names and answer["frames"] == len(markers.times)
    doc = c.get("/api/project").json()
    visible = {s["path"]: s for s in doc["steps"]}
    gapped = 0
    for m, name in enumerate(names):
        spline, entry = curve(doc, f"{name}.position")
        seen = np.all(np.isfinite(markers.positions[:, m]), axis=1)
        values = held(spline, markers.times[seen])
        assert np.abs(values - markers.positions[seen, m] * markers.unit_m).max() <= entry["tol"] * (1 + 1e-9)
        steps = visible.get(f"{name}.visible")
        if seen.all():
            assert steps is None
            continue
        gapped += 1                                    # hidden exactly on the frames it was not seen
        shown = [value for _, value in sorted(zip(steps["times"], steps["values"]))]
        at = np.searchsorted(steps["times"], markers.times, side="right") - 1
        assert [bool(shown[i]) for i in at] == seen.tolist()
    assert gapped >= 10
    assert c.get("/api/state").json()["history"]["undo"][-1] == "import lab.c3d"
    session.undo()
    assert not [o for o in c.get("/api/state").json()["objects"] if o["name"].startswith("lab_")]


@pytest.mark.realdata
def test_a_truncated_c3d_is_refused_naming_it_and_changes_nothing(client, data_dir) -> None:  # noqa: ANN001
    c, _ = client
    data = (data_dir / C3D).read_bytes()
    before = c.get("/api/project").content
    r = c.post("/api/clips?name=lab.c3d", content=data[: len(data) // 2])
    assert r.status_code == 400 and r.json()["detail"].startswith("lab.c3d"), r.text
    assert "truncated" in r.json()["detail"] and "upload.c3d" not in r.json()["detail"]
    assert c.get("/api/project").content == before


ASF, AMC = "amc/cmu_11.asf", "amc/cmu_11_01.amc"


def _amc_body(data_dir, motion: str | None = None) -> dict:  # noqa: ANN001
    return {"skeleton": (data_dir / ASF).read_text(), "motion": motion if motion is not None else (data_dir / AMC).read_text()}


@pytest.mark.realdata
def test_an_asf_amc_pair_becomes_parented_joint_objects(client, data_dir) -> None:  # noqa: ANN001
    from sketchanim.formats.clip_files import read_clip

    c, session = client
    r = c.post("/api/clips/amc?name=walk.amc&skeleton=cmu_11.asf", json=_amc_body(data_dir))
    assert r.status_code == 200, r.text
    clip = read_clip(data_dir / AMC, skeleton=data_dir / ASF)
    names = clip.skeleton.names
    assert r.json()["objects"] == [f"walk_{n}" for n in names] and r.json()["frames"] == len(clip.times)
    doc = c.get("/api/project").json()
    turns, positions = world_pose(clip.skeleton, clip.rotations, clip.translations)
    unit = clip.unit_m or clip.guess_unit_m()
    spline, entry = curve(doc, f"walk_{names[0]}.position")
    assert np.abs(held(spline, clip.times) - positions[:, 0] * unit).max() <= entry["tol"] * (1 + 1e-9)
    objects = {o["name"]: {a["name"]: a["value"] for a in o["attributes"]} for o in doc["objects"]}
    for name, up in zip(names, clip.skeleton.parents):
        assert objects[f"walk_{name}"].get(clips.BONE_PARENT) == (f"walk_{names[up]}" if up >= 0 else None)
    assert c.get("/api/state").json()["history"]["undo"][-1] == "import walk.amc"


@pytest.mark.realdata
def test_a_truncated_amc_or_a_bad_pair_is_refused_naming_it_and_changes_nothing(client, data_dir) -> None:  # noqa: ANN001
    c, _ = client
    before = c.get("/api/project").content
    text = (data_dir / AMC).read_text()
    cut = text[: len(text) // 2].rsplit("\n", 3)[0]                     # ends inside a frame
    r = c.post("/api/clips/amc?name=walk.amc&skeleton=cmu_11.asf", json=_amc_body(data_dir, cut))
    assert r.status_code == 400 and r.json()["detail"].startswith("walk.amc"), r.text
    assert "upload" not in r.json()["detail"]
    body = _amc_body(data_dir)
    body["skeleton"] = body["skeleton"][:300]
    r = c.post("/api/clips/amc?name=walk.amc&skeleton=cmu_11.asf", json=body)
    assert r.status_code == 400 and r.json()["detail"].startswith("cmu_11.asf"), r.text
    r = c.post("/api/clips/amc?name=walk.amc&skeleton=cmu_11.asf", content=b"not json")
    assert r.status_code == 400 and "walk.amc" in r.json()["detail"]
    r = c.post("/api/clips/amc?name=walk.bvh&skeleton=cmu_11.asf", json=body)
    assert r.status_code in (400, 422)
    assert c.get("/api/project").content == before


@pytest.mark.realdata
def test_an_imported_skeleton_exports_as_bvh_that_plays_the_scenes_joints(client, data_dir) -> None:  # noqa: ANN001
    """The export dialog offers BVH once the scene has a skeleton; the download, read and
    played by forward kinematics, puts every joint where the scene plays it at every frame:
    orientations as the tracks', positions within what fixed bone lengths allow (at each
    level of the chain: twice the position tolerance, and the bone swung by twice the
    orientation tolerance)."""
    c, session = client
    assert "bvh" not in [x["format"] for x in c.get("/api/export/choices").json()["choices"]]
    assert c.get("/api/export?format=bvh").status_code == 409                   # no skeleton yet
    assert c.post("/api/clips?name=dash.bvh", content=(data_dir / CLIP).read_bytes()).status_code == 200
    assert "bvh" in [x["format"] for x in c.get("/api/export/choices").json()["choices"]]
    r = c.get("/api/export?format=bvh")
    assert r.status_code == 200 and 'filename="p.bvh"' in r.headers["content-disposition"]
    path = session.path.parent / "got.bvh"
    path.write_bytes(r.content)
    back = read_bvh(path)
    turns, positions = world_pose(back.skeleton, back.rotations, back.translations)
    doc = c.get("/api/project").json()
    fps = session.fps
    assert np.allclose(np.diff(back.times), 1 / fps)
    # from the truth (the clip's own frames): the root's translation is its track's (within its
    # tolerance); a joint is where its parent is put, plus its bone (a median over the frames of
    # tracks within their tolerances) turned by its parent's orientation (within its tolerance)
    sk, far = back.skeleton, np.zeros(len(back.skeleton))
    for j, name in enumerate(sk.names):
        spline, entry = curve(doc, f"{name}.position")
        rot, _ = curve(doc, f"{name}.orientation")
        up = sk.parents[j]
        if up < 0:
            far[j] = entry["tol"]
        else:
            parent_tol = curve(doc, f"{sk.names[up]}.position")[1]["tol"]
            parent_rot = np.radians(curve(doc, f"{sk.names[up]}.orientation")[1]["tol"])
            far[j] = far[up] + entry["tol"] + parent_tol + 2 * np.linalg.norm(sk.offsets[j]) * parent_rot
        assert np.abs(positions[:, j] - held(spline, back.times)).max() <= far[j] + entry["tol"] + 1e-6, name
        q = held(rot, back.times)
        angle = np.degrees((Rotation.from_quat(q / np.linalg.norm(q, axis=1, keepdims=True)).inv() * turns[j]).magnitude())
        assert angle.max() <= 1e-4, name
