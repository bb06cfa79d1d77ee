"""Blender as a client of our .glb files (scripts/blender_probe.py in the bpy wheel's
Python, .venv-blender): poses played by our add-on or by Blender's glTF importer, turned
back into glTF's terms (+Y up, node-local rotations and translations)."""

from __future__ import annotations

import subprocess
import tempfile
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.motion.skeleton import Skeleton

ROOT = Path(__file__).resolve().parents[1]
PYTHON = ROOT / ".venv-blender" / "bin" / "python"

#: Blender's +Z up from glTF's +Y up: a quarter turn about X.
Y_UP = Rotation.from_euler("X", 90, degrees=True).as_matrix()


class Refused(Exception):
    """The add-on refused the file; the message is its own."""


def blender_play(mode: str, glb: Path, times: np.ndarray) -> dict[str, np.ndarray]:
    """World matrices (n, 4, 4) of every pose bone (``bone:NAME``, with ``rest:bone:NAME``)
    and object (``object:NAME``) at ``times``, imported by ``mode`` (addon or gltf) into
    a scene running at the rate of ``times``."""
    return blender_play_all(mode, [(glb, times)])[0]


def blender_play_all(mode: str, files: Sequence[tuple[Path, np.ndarray]]) -> list[dict[str, np.ndarray]]:
    """:func:`blender_play` of each (file, times), in one Blender run (each file in a new
    scene)."""
    with tempfile.TemporaryDirectory() as tmp:
        args = []
        for k, (glb, times) in enumerate(files):
            rate = 1.0 / float(np.median(np.diff(times))) if len(times) > 1 else 24.0
            np.save(Path(tmp) / f"t{k}.npy", np.asarray(times, dtype=float))
            args += [str(glb), str(Path(tmp) / f"t{k}.npy"), repr(rate), str(Path(tmp) / f"out{k}.npz")]
        run = subprocess.run([str(PYTHON), str(ROOT / "scripts" / "blender_probe.py"), mode, *args],
                             capture_output=True, text=True)
        if run.returncode == 3:
            raise Refused(run.stdout.strip().splitlines()[-1])
        if run.returncode:
            raise RuntimeError(f"blender probe failed:\n{run.stdout[-2000:]}\n{run.stderr[-3000:]}")
        out = []
        for k in range(len(files)):
            with np.load(Path(tmp) / f"out{k}.npz") as z:
                out.append(dict(z))
        return out


def _rotations(m: np.ndarray) -> np.ndarray:
    """The rotation part of world matrices (..., 4, 4) with a uniform scale."""
    r = m[..., :3, :3]
    return r / np.linalg.norm(r[..., :, :1], axis=-2, keepdims=True)


def joint_locals(poses: dict[str, np.ndarray], skeleton: Skeleton, unit_m: float | None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Each joint's node-local rotation (n, J, 4, scalar-last) and translation (n, J, 3,
    clip units) as Blender played them: world rotations with the bone's rest
    orientation taken out (the importers choose their own), in glTF's axes."""
    unit = unit_m or 1.0
    world_r, world_p = [], []
    for name in skeleton.names:
        pose, rest = poses[f"bone:{name}"], poses[f"rest:bone:{name}"]
        r = np.einsum("ij,njk,lk,lm->nim", Y_UP.T, _rotations(pose), _rotations(rest), Y_UP)
        world_r.append(r)
        world_p.append(np.einsum("ij,nj->ni", Y_UP.T, pose[:, :3, 3]) / unit)
    n = len(world_r[0])
    rot, trans = np.empty((n, len(skeleton), 4)), np.empty((n, len(skeleton), 3))
    for j, p in enumerate(skeleton.parents):
        if p < 0:
            local_r, local_p = world_r[j], world_p[j]
        else:
            local_r = np.einsum("nji,njk->nik", world_r[p], world_r[j])
            local_p = np.einsum("nji,nj->ni", world_r[p], world_p[j] - world_p[p])
        rot[:, j] = Rotation.from_matrix(local_r).as_quat()
        trans[:, j] = local_p
    return rot, trans


def object_pose(poses: dict[str, np.ndarray], name: str, mode: str) -> tuple[np.ndarray, np.ndarray]:
    """An object's world rotation (n, 4) and position (n, 3) in glTF's axes (for objects
    without a parent other than the import's root), as imported by ``mode``: our add-on
    keeps glTF's local axes under a root turned to +Z up; Blender's glTF importer turns
    each object's axes too (its meshes with them)."""
    m = poses[f"object:{name}"]
    r = np.einsum("ij,njk->nik", Y_UP.T, _rotations(m))
    r = r if mode == "addon" else np.einsum("nik,kl->nil", r, Y_UP)
    return Rotation.from_matrix(r).as_quat(), np.einsum("ij,nj->ni", Y_UP.T, m[:, :3, 3])
