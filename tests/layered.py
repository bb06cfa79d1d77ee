"""The layered-take example's scene (examples/layered_take.py) as clients play it:
every position and orientation track's error against the samples each take asked for
(the example's own measure), from values a client played."""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from blender_client import blender_play, object_pose
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.export.scene_gltf import scene_glb
from threejs_client import three_play

ROOT = Path(__file__).resolve().parents[1]


def example():  # type: ignore[no-untyped-def]
    """examples/layered_take.py as a module."""
    spec = importlib.util.spec_from_file_location("layered_take", ROOT / "examples" / "layered_take.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@dataclass
class Played:
    """A track as a client played it at ``times`` (what the example's max_error reads)."""

    takes: tuple
    type: object
    times: np.ndarray
    values: np.ndarray

    def evaluate(self, t: np.ndarray) -> np.ndarray:
        return self.values[np.searchsorted(self.times, t)]


@dataclass
class Exported:
    """The example performed and exported: its module, the position and orientation
    tracks (what glTF animates and the example measures), the tracks as pass 1 left
    them, every take's sample times, and the scene as .glb (exact, and frames)."""

    module: object
    tracks: dict[str, ContinuousTrack]
    first: dict
    times: np.ndarray
    curves: Path
    frames: Path


def exported(folder: Path) -> Exported:
    """Perform the example and export its scene into ``folder``."""
    module = example()
    scene, player, _, first = module.perform()
    tracks = {p: t for p, t in player.tracks.items() if p.split(".")[1] in ("position", "orientation")}
    times = np.unique(np.concatenate([take.times for t in tracks.values() for take in t.takes]))
    curves, frames = folder / "scene.glb", folder / "scene.frames.glb"
    curves.write_bytes(scene_glb(scene, player.tracks)[0])
    frames.write_bytes(scene_glb(scene, player.tracks, keys="frames")[0])
    return Exported(module, tracks, first, times, curves, frames)


def client(kind: str, path: Path, tracks: dict[str, ContinuousTrack], times: np.ndarray
           ) -> dict[str, np.ndarray]:
    """Each track's values as ``kind`` (three, addon, gltf) played ``path`` at ``times``."""
    if kind == "three":
        played = three_play(path, times)
        return {p: played[p.split(".")[0]]["quaternion" if p.endswith("orientation") else "position"] for p in tracks}
    poses = blender_play(kind, path, times)
    return {p: object_pose(poses, p.split(".")[0], kind)[1 if p.endswith("position") else 0] for p in tracks}


def errors(ex: Exported, values: dict[str, np.ndarray]) -> dict[str, float]:
    """Each track's error (its unit; degrees for orientations) against what its takes
    asked for, as the example measures it, from the played ``values``."""
    error: Callable = ex.module.max_error  # type: ignore[attr-defined]
    return {p: error(Played(t.takes, t.type, ex.times, values[p]), ex.first.get(p)) for p, t in ex.tracks.items()}
