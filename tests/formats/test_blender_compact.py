"""Compact clip files (``--keys compact``) through the Blender add-on
(blender/sketchanim_import.py in the bpy wheel, .venv-blender): decoded with meshopt,
LINEAR rotations put on one hemisphere and interpolated component-wise by F-curves,
constant tracks played as their nodes' values; every joint, and every point ``shell``
from one, within the file's world tolerance of the source at every source frame.
Without meshopt in Blender's Python the add-on refuses a compact file, saying how to
install it."""

from __future__ import annotations

import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from blender_client import PYTHON, ROOT, blender_play_all, joint_locals
from clips import clips, samplers, world_misses
from sketchanim.export.compact_clip import compact_clip
from sketchanim.formats.clip_files import read_clip
from sketchanim.motion.skeleton import Clip, Skeleton

ADDON = ROOT / "blender" / "sketchanim_import.py"


def blender_errors(files: list[tuple[Path, Clip, float]]) -> list[tuple[np.ndarray, float]]:
    """Each (file, source clip, shell) played by the add-on in one Blender run: per
    frame and joint, the joint's world distance from the source's plus the most a point
    ``shell`` from it moves by their world rotations' difference (clip units); and the
    slack Blender's float32 matrices take at the clip's size."""
    played = blender_play_all("addon", [(path, clip.times) for path, clip, _ in files])
    out = []
    for (_, clip, shell), poses in zip(files, played):
        errors = world_misses(clip, *joint_locals(poses, clip.skeleton, clip.unit_m), shell)
        size = float(np.abs(clip.world_positions()).max())
        out.append((errors, 64 * float(np.finfo(np.float32).eps) * (size + shell)))
    return out


def written(tmp: Path, name: str, clip: Clip, tol: float, shell: float) -> Path:
    path = tmp / f"{name}.glb"
    path.write_bytes(compact_clip(clip, tol, shell).glb)
    return path


def real_clip(source: Path) -> Clip:
    clip = read_clip(source)
    return replace(clip, unit_m=clip.guess_unit_m())


@pytest.mark.realdata
def test_real_compact_clips_play_in_blender_within_the_world_tolerance(real_clips: list[Path],
                                                                     tmp_path: Path) -> None:
    files, tols = [], []
    for source in real_clips:
        clip = real_clip(source)
        tol, shell = 0.005 / clip.unit_m, 0.03 / clip.unit_m      # half a centimetre, a point 3 cm out
        files.append((written(tmp_path, source.stem, clip, tol, shell), clip, shell))
        tols.append(tol)
    for source, tol, (errors, slack) in zip(real_clips, tols, blender_errors(files)):
        assert errors.max() <= tol + slack, (source.name, errors.max() / tol)


def constant_joint() -> Clip:
    """A root translating, an arm turning one and a half turns (the quaternion filter
    flips its keys' signs on the way), a hand held still 40 degrees off its rest."""
    s = Skeleton(("root", "arm", "hand"), (-1, 0, 1), np.array([[0.0, 90, 0], [30.0, 0, 0], [25.0, 0, 0]]))
    t = np.arange(120) / 60
    clip = Clip.still(s, t)
    clip.translations[:, 0] = np.c_[10 * np.sin(t), 90 + 0 * t, 0 * t]
    clip.rotations[:, 1] = Rotation.from_euler("Z", 5 * t[:, None] ** 1.5).as_quat()
    clip.rotations[:, 2] = Rotation.from_euler("X", [[40.0]] * len(t), degrees=True).as_quat()
    return replace(clip, translating=np.array([True, False, False]))


def test_a_constant_joint_plays_as_its_pose(tmp_path: Path) -> None:
    clip = constant_joint()
    path = written(tmp_path, "still", clip, 0.5, 3.0)
    doc = gl.GLTF2().load_binary(str(path))
    hand = next(n for n in doc.nodes if n.name == "hand")
    assert ("hand", "rotation") not in samplers(path) and hand.rotation != [0, 0, 0, 1]   # its pose is the node's
    _, arm = samplers(path)[("arm", "rotation")][1:]
    assert np.any(np.sum(arm[1:] * arm[:-1], axis=1) < 0)          # keys on both hemispheres, as decoded
    [(errors, slack)] = blender_errors([(path, clip, 3.0)])
    assert errors.max() <= 0.5 + slack, errors.max()


@settings(max_examples=6, deadline=None)
@given(st.lists(st.tuples(clips(), st.floats(0.05, 2.0), st.sampled_from([0.0, 3.0])), min_size=4, max_size=4))
def test_compact_files_play_in_blender_within_the_world_distance(tmp_path_factory, cases) -> None:
    tmp = tmp_path_factory.mktemp("c")
    files = [(written(tmp, f"c{k}", clip, tol, shell), clip, shell) for k, (clip, tol, shell) in enumerate(cases)]
    for (_, tol, _), (errors, slack) in zip(cases, blender_errors(files)):
        assert errors.max() <= tol + slack, (errors.max(), tol)


def test_without_meshopt_a_compact_file_is_refused_saying_how_to_install_it(tmp_path: Path) -> None:
    path = written(tmp_path, "still", constant_joint(), 0.5, 3.0)
    script = ("import importlib.util, sys\n"
              "sys.modules['meshopt'] = None\n"                    # import meshopt fails, as without it
              f"spec = importlib.util.spec_from_file_location('sketchanim_import', {str(ADDON)!r})\n"
              "m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)\n"
              f"sys.exit(m.main([{str(path)!r}]))\n")
    run = subprocess.run([str(PYTHON), "-c", script], capture_output=True, text=True)
    assert run.returncode == 2, run.stderr[-2000:]
    assert "EXT_meshopt_compression" in run.stderr and "meshopt package in Blender's Python" in run.stderr
    assert "-m', 'pip', 'install', 'meshopt==0.1.0'" in run.stderr and "Traceback" not in run.stderr


def test_a_damaged_compact_file_is_refused_naming_the_view(tmp_path: Path) -> None:
    path = written(tmp_path, "still", constant_joint(), 0.5, 3.0)
    doc = gl.GLTF2().load_binary(str(path))
    view = next(i for i, v in enumerate(doc.bufferViews) if (v.extensions or {}).get("EXT_meshopt_compression"))
    ext = doc.bufferViews[view].extensions["EXT_meshopt_compression"]
    data = bytearray(path.read_bytes())
    chunk = 20 + int.from_bytes(data[12:16], "little") + 8          # the binary chunk's first byte
    data[chunk + ext["byteOffset"] + 1:chunk + ext["byteOffset"] + ext["byteLength"]] = b"\xff" * (ext["byteLength"] - 1)
    path.write_bytes(bytes(data))
    run = subprocess.run([str(PYTHON), str(ADDON), str(path)], capture_output=True, text=True)
    assert run.returncode == 2 and f"buffer view {view} does not decode" in run.stderr, run.stderr[-2000:]
