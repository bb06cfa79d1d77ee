"""Blender plays our files as we do (the bpy wheel from PyPI, in .venv-blender, which
scripts/setup installs): .glb clips and scenes imported by our add-on
(blender/sketchanim_import.py) are our curves at every frame (within float32), and
``--keys frames`` files imported by Blender's own glTF importer or by the add-on are
within the asked tolerance of the source; the add-on refuses, with a message, what it
cannot play exactly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from blender_client import Refused, blender_play, joint_locals, object_pose
from clips import float32_shares, local_errors
from sketchanim.anim.attributes import ORIENTATION, POSITION
from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Take, held_values
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import read_clip
from sketchanim.export.scene_gltf import scene_glb, written_curve
from sketchanim.reducer.metric import rotation_angle


@pytest.mark.realdata
def test_real_clips_in_blender(real_clips: list[Path], tmp_path: Path) -> None:
    for source in real_clips:
        clip = read_clip(source)
        tol = 0.005 / clip.guess_unit_m()
        reduced = reduce_clip(clip, tol, 0.5)
        ours = reduced.sample(clip.times, spherical=False)                   # as F-curves play straight pieces
        curves = write_reduced(tmp_path / f"{source.stem}.glb", reduced)
        frames = write_reduced(tmp_path / f"{source.stem}.frames.glb", reduced, keys="frames")
        rot, trans = joint_locals(blender_play("addon", curves, clip.times), clip.skeleton, clip.unit_m)
        angle, dist = local_errors(rot, trans, ours)                        # our curves, within float32's share
        share = float32_shares(clip, tol, 0.5)
        assert angle <= share[0] and dist <= share[1], (source.name, angle, dist, share)
        angle, dist = local_errors(rot, trans, clip)                        # the source, within the tolerance
        assert angle <= 0.5 and dist <= tol, (source.name, angle, dist)
        rot, trans = joint_locals(blender_play("gltf", frames, clip.times), clip.skeleton, clip.unit_m)
        angle, dist = local_errors(rot, trans, clip)
        assert angle <= 0.5 and dist <= tol, (source.name, "glTF importer", angle, dist)
        rot, trans = joint_locals(blender_play("addon", frames, clip.times), clip.skeleton, clip.unit_m)
        angle, dist = local_errors(rot, trans, clip)
        assert angle <= 0.5 and dist <= tol, (source.name, "add-on, frames", angle, dist)


def test_scene_in_blender_through_the_addon(tmp_path: Path) -> None:
    t = np.arange(240) / 60
    pos = np.c_[np.sin(t), 0.5 + 0.5 * np.abs(np.sin(2 * t)), np.cos(3 * t)]
    q = Rotation.from_rotvec(np.c_[0.3 * np.sin(2 * t), 1.5 * t, 0.2 * t]).as_quat()
    scene = Scene()
    scene.add("cam", "camera")
    scene.add("box")
    tracks = {"cam.orientation": ContinuousTrack("cam.orientation", ORIENTATION,
                                                 reduce_samples(ORIENTATION, t, q, 0.5, 4), 0.5, (Take(t, q),)),
              "box.position": ContinuousTrack("box.position", POSITION, reduce_samples(POSITION, t, pos, 0.005, 4),
                                              0.005, (Take(t, pos),))}
    path = tmp_path / "scene.glb"
    path.write_bytes(scene_glb(scene, tracks)[0])
    poses = blender_play("addon", path, t)
    cam_q, _ = object_pose(poses, "cam", "addon")
    _, box_p = object_pose(poses, "box", "addon")
    ours_q = held_values(written_curve(tracks["cam.orientation"]), t, True)     # the curve the file holds
    assert np.degrees(rotation_angle(cam_q, ours_q)).max() < 1e-3
    assert np.degrees(rotation_angle(cam_q, q)).max() <= 0.5
    assert np.abs(box_p - written_curve(tracks["box.position"])(t)).max() < 1e-5
    assert np.abs(box_p - pos).max() <= 0.005
    with pytest.raises(Refused, match="not a binary glTF"):
        (tmp_path / "bad.glb").write_bytes(b"not glTF at all")
        blender_play("addon", tmp_path / "bad.glb", t[:2])


def test_addon_command_line(tmp_path: Path) -> None:
    import subprocess

    from hypothesis import find

    from blender_client import PYTHON, ROOT
    from clips import clips

    reduced = reduce_clip(find(clips(), lambda c: len(c.times) > 30), 0.5, 0.5)
    curves = write_reduced(tmp_path / "c.glb", reduced)
    frames = write_reduced(tmp_path / "f.glb", reduced, keys="frames")
    addon = str(ROOT / "blender" / "sketchanim_import.py")
    run = subprocess.run([str(PYTHON), addon, str(curves), "--save", str(tmp_path / "c.blend")],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    assert (tmp_path / "c.blend").stat().st_size > 0
    bad = tmp_path / "bad.glb"
    bad.write_bytes(b"not glTF at all")
    run = subprocess.run([str(PYTHON), addon, str(frames), str(bad)], capture_output=True, text=True)
    assert run.returncode == 2 and "not a binary glTF" in run.stderr
    # Installed as an add-on: its operator (File > Import) imports, or reports why not.
    script = ("import importlib.util, sys, bpy\n"
              f"spec = importlib.util.spec_from_file_location('sketchanim_import', {addon!r})\n"
              "m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m); m.register()\n"
              f"assert bpy.ops.import_scene.sketchanim_glb(filepath={str(curves)!r}) == {{'FINISHED'}}\n"
              "assert any(o.type == 'ARMATURE' for o in bpy.data.objects)\n"
              f"try:\n    bpy.ops.import_scene.sketchanim_glb(filepath={str(bad)!r})\n"
              "except RuntimeError as err:\n    print('refused:', err)\n")
    run = subprocess.run([str(PYTHON), "-c", script], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "refused: Error:" in run.stdout and "not a binary glTF" in run.stdout


def test_layered_take_scene_in_every_client(tmp_path: Path) -> None:
    """examples/layered_take.py's scene: our add-on plays our curves (positions within
    float32, the orientation within the share its unit keys may take), and the add-on,
    three.js and Blender's importer (frames) are within each track's tolerance of what
    its takes asked for."""
    import layered
    from sketchanim.export.scene_gltf import KEY_SHARE

    ex = layered.exported(tmp_path)
    addon = layered.client("addon", ex.curves, ex.tracks, ex.times)
    for p, track in ex.tracks.items():
        ours = track.evaluate(ex.times)
        if track.type.is_rotation:
            assert np.degrees(rotation_angle(addon[p], ours)).max() <= KEY_SHARE * track.tol + 1e-4, p
        else:
            assert np.abs(addon[p] - ours).max() <= 1e-5, p
    for kind, path in (("addon", ex.curves), ("three", ex.curves), ("three", ex.frames), ("gltf", ex.frames)):
        played = addon if kind == "addon" else layered.client(kind, path, ex.tracks, ex.times)
        for p, error in layered.errors(ex, played).items():
            assert error <= ex.tracks[p].tol, (kind, path.name, p, error)
