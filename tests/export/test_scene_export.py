"""Scenes of the animation model as glTF: objects, cameras and spot lights as nodes;
position, orientation and scale tracks as channels that play (by the spec's formulas,
from the float32 file, in float32 arithmetic) within tolerance of what was recorded; valid by the Khronos validator; the tracks glTF
cannot animate are listed, not silently dropped."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from clips import played, samplers, validate
from sketchanim.anim.attributes import BOOL, COLOR, ORIENTATION, POSITION, SCALE, AttributeType
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.cli import app
from sketchanim.export.scene_gltf import scene_glb
from sketchanim.project.store import Project
from sketchanim.formats.recordings import read_tum
from sketchanim.reducer.metric import rotation_angle


def recorded(path: str, type: AttributeType, times: np.ndarray, values: np.ndarray, tol: float,
             edge: bool = False) -> ContinuousTrack:
    """A track as a take records it: the samples reduced within ``tol``, the take kept.
    With ``edge``, the take's samples are moved away from the curve (each one's error
    scaled) until the worst is at the tolerance exactly, per axis (or in angle), as a
    streaming reducer may leave a curve: float32 must then not add to it."""
    spline = reduce_samples(type, times, values, tol, 4)
    if edge:
        curve = ContinuousTrack(path, type, spline, tol).evaluate(times)
        if type.is_rotation:
            off = (Rotation.from_quat(curve).inv() * Rotation.from_quat(values)).as_rotvec()
            angle = np.linalg.norm(off, axis=1).max()
            values = (Rotation.from_quat(curve) * Rotation.from_rotvec(off * np.radians(tol) / angle)).as_quat()
        else:
            off = values - curve
            values = curve + off * tol / np.maximum(np.abs(off).max(axis=0), 1e-300)
    return ContinuousTrack(path, type, spline, tol, (Take(times, values),))


@st.composite
def performances(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A take of 20 to 300 samples at 30 to 120 Hz, with a little jitter in time,
    starting up to 100 s in (float32 times coarser there), at up to 100 m: a position,
    an orientation (turning up to a few times) and a scale."""
    n = draw(st.integers(20, 300))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    start = draw(st.sampled_from([0.0, 7.3, 100.0]))
    t = start + np.arange(n) / draw(st.sampled_from([30.0, 60.0, 120.0])) + rng.uniform(0, 1e-3, n)
    t.sort()
    wave = lambda amp: sum(rng.uniform(0, amp, 3) * np.sin(rng.uniform(0.2, 3.0) * t[:, None] + rng.uniform(0, 6, 3))
                           for _ in range(3))
    turns = draw(st.floats(0.1, 4.0))
    q = Rotation.from_rotvec(wave(turns)).as_quat()
    return t, wave(2.0) + draw(st.sampled_from([0.0, 100.0])), q, 1.0 + np.abs(wave(0.5))


@settings(max_examples=10, deadline=None)
@given(performances(), st.sampled_from([(0.005, 0.5), (0.001, 0.1)]), st.booleans())
def test_scene_tracks_play_within_tolerance_and_validate(tmp_path_factory: pytest.TempPathFactory,
                                                         take: tuple[np.ndarray, ...], tols: tuple[float, float],
                                                         edge: bool) -> None:
    t, pos, q, scale = take
    tol, rot_tol = tols
    scene = Scene()
    for name, kind in (("box", "object"), ("cam", "camera"), ("lamp", "light")):
        scene.add(name, kind)
    tracks: dict[str, Track] = {
        "box.position": recorded("box.position", POSITION, t, pos, tol, edge),
        "box.scale": recorded("box.scale", SCALE, t, scale, tol, edge),
        "cam.orientation": recorded("cam.orientation", ORIENTATION, t, q, rot_tol, edge),
        "lamp.position": recorded("lamp.position", POSITION, t, pos[::-1].copy(), tol, edge),
        "lamp.color": recorded("lamp.color", COLOR, t, np.clip(np.abs(pos) / 4, 0, 1), 0.01),
    }
    on = DiscreteTrack("lamp.on", BOOL)
    on.add(float(t[len(t) // 2]), False)
    tracks["lamp.on"] = on
    pos, scale, q, lamp = (tracks[p].takes[0].values for p in ("box.position", "box.scale", "cam.orientation",
                                                               "lamp.position"))
    glb, left_out = scene_glb(scene, tracks)
    assert left_out == ["lamp.color", "lamp.on"]
    path = tmp_path_factory.mktemp("scene") / "scene.glb"
    path.write_bytes(glb)
    (report,) = validate(path)
    assert report["numErrors"] == 0, report["messages"][:3]
    # Played from the float32 file in float32: every sample within the tolerance itself.
    assert np.abs(played(path, "box", "translation", t) - pos).max() <= tol
    assert np.abs(played(path, "box", "scale", t) - scale).max() <= tol
    assert np.abs(played(path, "lamp", "translation", t) - lamp).max() <= tol
    # Orientation keys are unit quaternions, and the curve they make is within the
    # tolerance of every recorded sample too (the unit keys' share is in the budget).
    _, _, keys = samplers(path)[("cam", "rotation")]
    assert np.allclose(np.linalg.norm(keys[:, 1], axis=1), 1.0, atol=1e-6)
    angle = np.degrees(rotation_angle(played(path, "cam", "rotation", t), q))
    assert angle.max() <= rot_tol
    doc = gl.GLTF2().load_binary(str(path))
    assert doc.extensions["KHR_lights_punctual"]["lights"][0]["type"] == "spot"
    assert [n.name for n in doc.nodes] == ["box", "cam", "lamp"] and doc.nodes[1].camera == 0


def test_rest_values_and_cameras(tmp_path: Path) -> None:
    scene = Scene()
    scene.add("cam", "camera")
    scene.set("cam.fov", [35.0])
    scene.set("cam.position", [1.0, 2.0, 3.0])
    scene.add("lamp", "light")
    scene.set("lamp.on", False)
    glb, left_out = scene_glb(scene, {})
    doc = gl.GLTF2.load_from_bytes(glb)
    assert doc.nodes[0].translation == [1.0, 2.0, 3.0] and doc.nodes[0].rotation == [0.0, 0.0, 0.0, 1.0]
    assert doc.cameras[0].perspective.yfov == pytest.approx(np.radians(35.0))
    assert doc.extensions["KHR_lights_punctual"]["lights"][0]["intensity"] == 0.0      # switched off
    assert not doc.animations and left_out == []
    (tmp_path / "still.glb").write_bytes(glb)
    assert validate(tmp_path / "still.glb")[0]["numErrors"] == 0


def test_export_command(tmp_path: Path) -> None:
    scene = Scene()
    scene.add("ball")
    t = np.linspace(0, 2, 121)
    tracks: dict[str, Track] = {"ball.position": recorded("ball.position", POSITION, t, np.c_[t, np.sin(t), 0 * t],
                                                          0.005),
                                "ball.visible": DiscreteTrack("ball.visible", BOOL, [1.0], [False])}
    with Project(tmp_path / "p.sketchanim") as project:
        project.save(scene, tracks)
    runner = CliRunner()
    result = runner.invoke(app, ["export", str(tmp_path / "p.sketchanim"), "-o", str(tmp_path / "p.glb")])
    assert result.exit_code == 0, result.output
    assert "not in the glTF" in result.output and "ball.visible" in result.output
    assert validate(tmp_path / "p.glb")[0]["numErrors"] == 0
    assert np.abs(played(tmp_path / "p.glb", "ball", "translation", t) - np.c_[t, np.sin(t), 0 * t]).max() <= 0.005
    result = runner.invoke(app, ["export", str(tmp_path / "p.sketchanim"), "-o", str(tmp_path / "p.json")])
    assert result.exit_code == 0 and (tmp_path / "p.json").read_text().startswith("{")
    result = runner.invoke(app, ["export", str(tmp_path / "none.sketchanim"), "-o", str(tmp_path / "n.glb")])
    assert result.exit_code == 2 and "no such project file" in result.output
    result = runner.invoke(app, ["export", str(tmp_path / "p.sketchanim"), "-o", str(tmp_path / "p.fbx")])
    assert result.exit_code == 2 and ".glb, .json, .bvh or .usd, .usda, .usdc" in result.output
    result = runner.invoke(app, ["export", str(tmp_path / "p.sketchanim"), "-o", str(tmp_path / "p.bvh")])
    assert result.exit_code == 2 and "no skeleton" in result.output and not (tmp_path / "p.bvh").exists()


def test_export_command_writes_a_skeleton_as_bvh(tmp_path: Path) -> None:
    from sketchanim.anim.scene import BONE_PARENT
    from sketchanim.formats.bvh import read_bvh

    scene = Scene()
    scene.add("hips")
    scene.add("head").add(BONE_PARENT, AttributeType.enum(["hips"]), "hips")
    t = np.linspace(0, 1, 61)
    walk = np.c_[t, 1 + 0 * t, 0 * t]
    tracks: dict[str, Track] = {"hips.position": recorded("hips.position", POSITION, t, walk, 0.005),
                                "head.position": recorded("head.position", POSITION, t, walk + [0, 0.6, 0], 0.005)}
    with Project(tmp_path / "p.sketchanim") as project:
        project.save(scene, tracks)
    result = CliRunner().invoke(app, ["export", str(tmp_path / "p.sketchanim"), "-o", str(tmp_path / "p.bvh")])
    assert result.exit_code == 0, result.output
    back = read_bvh(tmp_path / "p.bvh")
    assert back.skeleton.names == ("hips", "head") and back.skeleton.parents == (-1, 0)
    assert np.abs(back.world_positions()[:, 1] - (tracks["hips.position"].evaluate(back.times) + [0, 0.6, 0])).max() <= 0.011


def test_export_command_writes_usd_within_tolerance_at_every_sample(tmp_path: Path) -> None:
    from pxr import Usd

    scene = Scene()
    scene.add("ball")
    scene.add("cam", "camera")
    t = np.linspace(0, 2, 121)
    xyz, q = np.c_[t, np.sin(t), 0 * t], Rotation.from_rotvec(np.c_[np.sin(2 * t), t, 0 * t]).as_quat()
    tracks: dict[str, Track] = {"ball.position": recorded("ball.position", POSITION, t, xyz, 0.005),
                                "cam.orientation": recorded("cam.orientation", ORIENTATION, t, q, 0.5),
                                "ball.visible": DiscreteTrack("ball.visible", BOOL, [1.0], [False])}
    with Project(tmp_path / "p.sketchanim") as project:
        project.save(scene, tracks)
    result = CliRunner().invoke(app, ["export", str(tmp_path / "p.sketchanim"), "-o", str(tmp_path / "p.usda")])
    assert result.exit_code == 0, result.output
    assert "not in the USD" in result.output and "ball.visible" in result.output
    stage = Usd.Stage.Open(str(tmp_path / "p.usda"))
    rate = stage.GetTimeCodesPerSecond()
    ball = stage.GetPrimAtPath("/ball").GetAttribute("xformOp:translate")
    assert np.abs(np.array([ball.Get(float(c)) for c in t * rate]) - xyz).max() <= 0.005
    orient = [stage.GetPrimAtPath("/cam").GetAttribute("xformOp:orient").Get(float(c)) for c in t * rate]
    played = np.array([[*o.GetImaginary(), o.GetReal()] for o in orient])
    assert np.degrees(rotation_angle(played, q)).max() <= 0.5


@pytest.mark.realdata
def test_real_camera_path_exports_within_tolerance(data_dir: Path, tmp_path: Path) -> None:
    """The TUM hand-held camera's 30 s path as a camera's tracks, exported and played."""
    t, xyz, q = read_tum(data_dir / "camera" / "freiburg1_xyz-groundtruth.txt")
    t = t - t[0]
    scene = Scene()
    scene.add("cam", "camera")
    tracks: dict[str, Track] = {"cam.position": recorded("cam.position", POSITION, t, xyz, 0.002),
                                "cam.orientation": recorded("cam.orientation", ORIENTATION, t, q, 0.5)}
    glb, _ = scene_glb(scene, tracks)
    path = tmp_path / "camera.glb"
    path.write_bytes(glb)
    assert validate(path)[0]["numErrors"] == 0
    assert np.abs(played(path, "cam", "translation", t) - xyz).max() <= 0.002
    assert np.degrees(rotation_angle(played(path, "cam", "rotation", t), q)).max() <= 0.5
