"""three.js plays every .glb we export (clips, exactly or as frames; markers; scenes) at
every source frame as our curves (within float32) and within the asked tolerance of the
source, the last frame included (a looping mixer wraps at the clip's end)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pygltflib as gl
from hypothesis import find

from clips import clips, float32_shares, local_errors
from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.motion.skeleton import Clip
from sketchanim.formats.c3d import read_c3d
from sketchanim.mocap.markers import reduce_markers
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import read_clip
from sketchanim.motion.kinematics import world_pose
from sketchanim.reducer.metric import rotation_angle
from threejs_client import three_play, three_play_world
from web_peers import gltfpack


def clip_errors(played: dict, clip: Clip) -> tuple[float, float]:
    """:func:`local_errors` of a clip as three.js played it."""
    names = clip.skeleton.names
    return local_errors(np.stack([played[n]["quaternion"] for n in names], axis=1),
                        np.stack([played[n]["position"] for n in names], axis=1), clip)


def _check_clip(clip: Clip, tol: float, folder: Path) -> None:
    reduced = reduce_clip(clip, tol, 0.5)
    ours = reduced.sample(clip.times)
    share = float32_shares(clip, tol, 0.5)
    for keys in ("curves", "frames"):
        path = write_reduced(folder / f"clip.{keys}.glb", reduced, keys=keys)
        played = three_play(path, clip.times)
        angle, dist = clip_errors(played, clip)
        assert angle <= 0.5 and dist <= tol, (keys, angle, dist)
        if keys == "curves":
            angle, dist = clip_errors(played, ours)
            assert angle <= share[0] and dist <= share[1], (angle, dist, share)      # float32's share


def test_threejs_plays_a_clip(tmp_path: Path) -> None:
    _check_clip(find(clips(), lambda c: len(c.times) > 100), 0.5, tmp_path)


@pytest.mark.realdata
def test_threejs_plays_the_real_clips(real_clips: list[Path], tmp_path: Path) -> None:
    for source in real_clips:
        clip = read_clip(source)
        _check_clip(clip, 0.005 / clip.guess_unit_m(), tmp_path)


@pytest.mark.realdata
def test_threejs_plays_the_real_markers(real_c3d: list[Path], tmp_path: Path) -> None:
    for source in real_c3d:
        markers = read_c3d(source)
        tol = 0.005 / (markers.unit_m or 0.001)
        reduced = reduce_markers(markers, tol)
        for keys in ("curves", "frames"):
            played = three_play(write_reduced(tmp_path / f"m.{keys}.glb", reduced, keys=keys), markers.times)
            for m, name in enumerate(markers.names):
                seen = np.all(np.isfinite(markers.positions[:, m]), axis=1)
                if not seen.any():
                    continue
                dist = np.linalg.norm(played[name]["position"][seen] - markers.positions[seen, m], axis=1)
                assert dist.max() <= tol, (keys, name, dist.max())
                shown = played[name]["scale"][:, 0] > 0
                assert np.array_equal(shown, seen), (keys, name)


def _check_meshopt(clip: Clip, tol: float, folder: Path) -> None:
    """gltfpack -cc (keys kept: -af 0) of our frames file plays in three.js with its meshopt
    decoder: the local pose is the uncompressed file's within gltfpack's quantisation, and
    the world pose (matrixWorld) is that local pose's forward kinematics."""
    ours = write_reduced(folder / "clip.glb", reduce_clip(clip, tol, 0.5), keys="frames")
    packed = folder / "clip.cc.glb"
    gltfpack(ours, packed, "-cc", "-af", "0")
    doc = gl.GLTF2().load_binary(str(packed))
    filters = {v.extensions.get("EXT_meshopt_compression", {}).get("filter") for v in doc.bufferViews}
    assert "EXT_meshopt_compression" in doc.extensionsRequired and {"QUATERNION", "EXPONENTIAL"} <= filters
    names = clip.skeleton.names
    plain, local, world = (play(path, clip.times) for play, path in ((three_play, ours), (three_play, packed),
                                                                        (three_play_world, packed)))

    def stack(played: dict, key: str) -> np.ndarray:
        return np.stack([played[n][key] for n in names], axis=1)

    # 12-bit quaternion filter: each of the three stored components within half a step,
    # 1 / (2 sqrt 2 (2^11 - 1)); the rebuilt one within sqrt 3 times that; the angle is twice
    # the quaternion's distance
    step = 1 / (2 * np.sqrt(2) * (2**11 - 1))
    angle = np.degrees(rotation_angle(stack(local, "quaternion").reshape(-1, 4), stack(plain, "quaternion").reshape(-1, 4)))
    assert angle.max() <= np.degrees(2 * 2 * np.sqrt(3) * step), angle.max()
    # 16-bit exponential filter: each component within 2^-15 of the largest it shares an exponent with
    moved = np.linalg.norm(stack(local, "position") - stack(plain, "position"), axis=-1)
    assert moved.max() <= np.sqrt(3) * np.abs(stack(plain, "position")).max() * 2.0**-15, moved.max()
    unit = clip.unit_m or 1.0                  # our file is in metres where the clip's unit is known
    turns, fk = world_pose(clip.skeleton, stack(local, "quaternion"), stack(local, "position"))
    # three's quaternions, decoded from normalised shorts, are unit to about 1e-5 (scipy's are exactly)
    assert np.abs(fk * unit - stack(world, "position")).max() <= 1e-4 * np.abs(fk * unit).max()
    fk_turns = np.stack([r.as_quat() for r in turns], axis=1).reshape(-1, 4)
    assert np.degrees(rotation_angle(fk_turns, stack(world, "quaternion").reshape(-1, 4))).max() <= 0.01


def test_threejs_plays_gltfpack_meshopt_files(tmp_path: Path) -> None:
    _check_meshopt(find(clips(), lambda c: len(c.times) > 100), 0.5, tmp_path)


@pytest.mark.realdata
def test_threejs_plays_gltfpack_meshopt_files_of_real_clips(real_clips: list[Path], tmp_path: Path) -> None:
    for source in real_clips:
        clip = read_clip(source)
        _check_meshopt(clip, 0.005 / clip.guess_unit_m(), tmp_path)


def test_threejs_and_blender_play_a_scene(tmp_path: Path) -> None:
    from scipy.spatial.transform import Rotation
    from typer.testing import CliRunner

    from blender_client import blender_play, object_pose
    from sketchanim.anim.attributes import ORIENTATION, POSITION, SCALE
    from sketchanim.anim.layers import reduce_samples
    from sketchanim.anim.scene import Scene
    from sketchanim.anim.tracks import ContinuousTrack, Take
    from sketchanim.cli import app
    from sketchanim.project.store import Project

    t = np.arange(300) / 60 + 0.25
    pos = np.c_[np.sin(t), 0.5 + 0.5 * np.abs(np.sin(2 * t)), np.cos(3 * t)]
    q = Rotation.from_rotvec(np.c_[0.3 * np.sin(2 * t), 1.5 * t, 0.2 * t]).as_quat()
    size = 1.0 + 0.3 * np.c_[np.sin(t), np.cos(t), np.sin(2 * t)]
    scene = Scene()
    scene.add("cam", "camera")
    scene.add("box")
    tracks = {}
    for path, kind, values, tol in (("cam.orientation", ORIENTATION, q, 0.5), ("box.position", POSITION, pos, 0.005),
                                    ("box.scale", SCALE, size, 0.005)):
        tracks[path] = ContinuousTrack(path, kind, reduce_samples(kind, t, values, tol, 4), tol, (Take(t, values),))
    with Project(tmp_path / "s.sketchanim") as project:
        project.save(scene, tracks)
    runner = CliRunner()
    for keys in ("curves", "frames"):
        out = tmp_path / f"s.{keys}.glb"
        result = runner.invoke(app, ["export", str(tmp_path / "s.sketchanim"), "-o", str(out), "--keys", keys])
        assert result.exit_code == 0, result.output
        played = three_play(out, t)
        assert np.abs(played["box"]["position"] - pos).max() <= 0.005, keys      # float32's share is in the budget
        assert np.abs(played["box"]["scale"] - size).max() <= 0.005, keys
        angle = np.degrees(rotation_angle(played["cam"]["quaternion"], q)).max()
        assert angle <= 0.5, (keys, angle)
        assert float(played["box"]["position"][-1, 0]) == pytest.approx(pos[-1, 0], abs=0.006)   # no wrap at the end
    _, box = object_pose(blender_play("gltf", tmp_path / "s.frames.glb", t), "box", "gltf")
    assert np.abs(box - pos).max() <= 0.005                          # Blender's own importer, frames
    result = runner.invoke(app, ["export", str(tmp_path / "s.sketchanim"), "-o", str(out), "--keys", "spline"])
    assert result.exit_code == 2 and "--keys" in result.output
