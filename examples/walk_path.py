"""A walker following a path, written as a .glb.

    .venv/bin/python examples/walk_path.py OUT.glb [PATH_FILE]

Without ``PATH_FILE`` the path is generated: a curving walk, a pause, a turn back on the
spot, then a jog. With a TUM trajectory (``timestamp tx ty tz qx qy qz qw`` lines, as
../shared/data/camera/freiburg1_xyz-groundtruth.txt) the path is that trajectory laid on
the floor: its two widest directions (principal axes) become the floor's x and z, in
metres, from the trajectory's own start. The path becomes the walker's goal track (reduced
as a take is), the walk is derived from it and baked into the file
(:mod:`sketchanim.export.rig_bake`). Prints a summary: the path's length, duration and top
speed, and the file's bytes.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.atomic import write_atomic
from sketchanim.export.scene_gltf import scene_glb
from sketchanim.formats.recordings import read_tum

RATE = 120.0


def generated_path() -> tuple[np.ndarray, np.ndarray]:
    """Times (n,) and floor points (n, 3): 4 s along an arc at about 1.3 m/s, 1.5 s
    still, 1 s turning back where it stands, 3 s back at a jog (about 2.8 m/s)."""
    t = np.arange(int(9.5 * RATE) + 1) / RATE
    out = np.zeros((len(t), 3))
    arc = t <= 4.0
    angle = 0.25 * t[arc]
    out[arc] = np.c_[5.2 * np.sin(angle), 0 * angle, 5.2 * (1 - np.cos(angle))]
    stop = out[arc][-1]
    rest = (t > 4.0) & (t <= 6.5)
    out[rest] = stop
    jog = t > 6.5
    back = np.clip(t[jog] - 6.5, 0.0, None)
    heading = np.array([-np.cos(1.0), 0.0, -np.sin(1.0)])
    ease = np.minimum(back, 0.5)                      # half a second to get up to speed
    distance = 2.8 * (back - ease + ease ** 2)
    out[jog] = stop + distance[:, None] * heading
    return t, out


def tum_path(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """A TUM trajectory laid on the floor: its two principal axes as x and z."""
    t, positions, _ = read_tum(path)
    centred = positions - positions[0]
    _, _, axes = np.linalg.svd(centred - centred.mean(axis=0), full_matrices=False)
    floor = centred @ axes[:2].T
    return t, np.c_[floor[:, 0], np.zeros(len(t)), floor[:, 1]]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="the .glb to write")
    parser.add_argument("path_file", type=Path, nargs="?", help="a TUM trajectory to walk (default: a generated path)")
    args = parser.parse_args()
    t, points = tum_path(args.path_file) if args.path_file else generated_path()
    scene = Scene()
    scene.add("walker", "walker")
    scene.set("walker.goal", points[0])
    goal = ContinuousTrack("walker.goal", POSITION, reduce_samples(POSITION, t, points, POSITION.tol, 4, "global"),
                           POSITION.tol)
    glb, _ = scene_glb(scene, {"walker.goal": goal}, name="walk")
    write_atomic(args.out, glb)
    speed = np.linalg.norm(np.diff(points, axis=0), axis=1) * RATE if len(t) > 1 else np.zeros(1)
    print(json.dumps({"out": str(args.out), "seconds": float(t[-1]), "metres": float(np.sum(speed) / RATE),
                      "top_speed_m_s": round(float(np.max(np.convolve(speed, np.ones(12) / 12, "same"))), 3),
                      "bytes": len(glb)}))


if __name__ == "__main__":
    main()
