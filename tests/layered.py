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


def transform_tracks(tracks: dict) -> dict[str, ContinuousTrack]:
    """The position and orientation tracks (what glTF animates and the example measures)."""
    return {p: t for p, t in tracks.items() if p.split(".")[1] in ("position", "orientation")}


def take_times(tracks: dict[str, ContinuousTrack]) -> np.ndarray:
    """Every sample time of every take of ``tracks``."""
    return np.unique(np.concatenate([take.times for t in tracks.values() for take in t.takes]))


def client(kind: str, path: Path, tracks: dict[str, ContinuousTrack], times: np.ndarray
           ) -> dict[str, np.ndarray]:
    """Each track's values as ``kind`` (three, addon, gltf) played ``path`` at ``times``."""
    if kind == "three":
        played = three_play(path, times)
        return {p: played[p.split(".")[0]]["quaternion" if p.endswith("orientation") else "position"] for p in tracks}
    poses = blender_play(kind, path, times)
    return {p: object_pose(poses, p.split(".")[0], kind)[1 if p.endswith("position") else 0] for p in tracks}


def errors(module, tracks: dict[str, ContinuousTrack], first: dict, times: np.ndarray,  # type: ignore[no-untyped-def]
           values: dict[str, np.ndarray]) -> dict[str, float]:
    """Each track's error (its unit; degrees for orientations) against what its takes
    asked for, as the example measures it, from the played ``values``."""
    error: Callable = module.max_error
    return {p: error(Played(t.takes, t.type, times, values[p]), first.get(p)) for p, t in tracks.items()}
