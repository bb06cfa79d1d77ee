"""Baking rigs for export: the time to derive and reduce a chain's or walker's pose, per
second of animation, and the baked curves' size against the raw frames.

    .venv/bin/python benchmarks/bench_bake.py [--seconds 10 60] [--repeats 3]

For an 8-joint chain reaching for a looping goal that leaves its reach, and a walker on a
stop-and-go path (the examples' generated paths, examples/reach.py and walk_path.py), over
each duration: seconds to solve the pose at the ticks (120 Hz, :func:`rig_clip`) and to
reduce it within the goal's 5 mm in the world with a 3 cm shell (:func:`bake`), medians of
``--repeats`` runs, both per second of animation; the raw pose as float32 frames (its BVH
channels: three angles a joint, the root's position too, at every tick), the baked curves' bytes
(:meth:`ReducedClip.reduced_bytes`) and their ratio; and the .glb's bytes.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.rigs import rig_clip
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.export.rig_bake import bake
from sketchanim.export.scene_gltf import scene_glb

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "examples"))
from reach import goal_path  # noqa: E402  (the examples' generated paths)
from walk_path import generated_path  # noqa: E402

RATE = 120.0


def rig_scene(kind: str, seconds: float) -> tuple[Scene, dict[str, ContinuousTrack]]:
    """A scene of one rig ``kind`` whose goal runs ``seconds`` (the example paths, repeated)."""
    scene = Scene()
    scene.add("rig", kind)
    if kind == "chain":
        scene.set("rig.lengths", [0.3, 0.28, 0.25, 0.22, 0.2, 0.18, 0.16, 0.14])
        scene.set("rig.hinges", [0, 1, 1, 0, 1, 1, 0, 1])
        t, points = goal_path(float(np.sum(scene.get("rig.lengths"))))
    else:
        t, points = generated_path()
    laps = int(np.ceil(seconds / t[-1]))
    span = t[-1] + 1.0 / RATE
    times = np.concatenate([t + k * span for k in range(laps)])
    if kind == "walker":                                          # each lap walks on from where the last ended
        points = np.concatenate([points + k * (points[-1] - points[0]) for k in range(laps)])
    else:
        points = np.tile(points, (laps, 1))
    keep = times <= seconds
    track = ContinuousTrack("rig.goal", POSITION, reduce_samples(POSITION, times[keep], points[keep], POSITION.tol, 4,
                                                                 "global"), POSITION.tol)
    return scene, {"rig.goal": track}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, nargs="+", default=[10.0, 60.0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    table = Table(title="rig bake: pose at 120 Hz ticks, reduced within 5 mm in the world (3 cm shell)")
    for column in ("rig", "joints", "seconds", "solve ms/s", "bake ms/s", "raw float32 bytes", "curve bytes",
                   "ratio", ".glb bytes"):
        table.add_column(column, justify="right")
    for kind in ("chain", "walker"):
        for seconds in args.seconds:
            scene, tracks = rig_scene(kind, seconds)
            solve, total = [], []
            for _ in range(args.repeats):
                start = time.perf_counter()
                clip = rig_clip(scene, tracks, "rig")
                solve.append(time.perf_counter() - start)
                start = time.perf_counter()
                baked = bake(scene, tracks, "rig")
                total.append(time.perf_counter() - start)
            span = float(clip.times[-1])
            raw, curves = baked.reduced.raw_bytes(), baked.reduced.reduced_bytes()
            table.add_row(kind, str(len(clip.skeleton)), f"{span:.1f}", f"{1e3 * statistics.median(solve) / span:.1f}",
                          f"{1e3 * statistics.median(total) / span:.1f}", f"{raw:,}", f"{curves:,}",
                          f"{raw / curves:.1f}:1", f"{len(scene_glb(scene, tracks)[0]):,}")
    Console(width=140).print(table)


if __name__ == "__main__":
    main()
