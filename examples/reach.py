"""A five-joint chain reaching for a goal that leaves its reach for a while, as a .glb.

    .venv/bin/python examples/reach.py OUT.glb

The goal follows a generated 3D path (a loop around the chain, rising and falling) that
goes past the chain's reach for about two seconds and comes back; the chain follows it
(damped least squares, :mod:`sketchanim.motion.ik`), points at it while out of reach, and
catches it again without a jump. The pose is baked into the file
(:mod:`sketchanim.export.rig_bake`). Prints a summary: how long the goal was out of
reach, the file's bytes.
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

RATE = 120.0
DURATION = 8.0


def goal_path(reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Times (n,) and goal points (n, 3): a loop around the base at 0.6..0.85 of the
    reach, swelling to 1.3 of it between 3 and 5 s."""
    t = np.arange(int(DURATION * RATE) + 1) / RATE
    swell = np.exp(-(((t - 4.0) / 0.8) ** 4))
    radius = reach * (0.6 + 0.25 * np.sin(0.9 * t) ** 2 + 0.7 * swell)
    angle = 0.8 * t
    height = 0.6 + 0.35 * np.sin(1.3 * t)
    direction = np.c_[np.cos(angle) * np.sqrt(1 - height ** 2), height, np.sin(angle) * np.sqrt(1 - height ** 2)]
    return t, radius[:, None] * direction


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="the .glb to write")
    args = parser.parse_args()
    scene = Scene()
    scene.add("arm", "chain")
    reach = float(np.sum(scene.get("arm.lengths")))
    t, points = goal_path(reach)
    scene.set("arm.goal", points[0])
    goal = ContinuousTrack("arm.goal", POSITION, reduce_samples(POSITION, t, points, POSITION.tol, 4, "global"),
                           POSITION.tol)
    glb, _ = scene_glb(scene, {"arm.goal": goal}, name="reach")
    write_atomic(args.out, glb)
    outside = np.linalg.norm(points, axis=1) > reach
    print(json.dumps({"out": str(args.out), "joints": int(np.count_nonzero(scene.get("arm.lengths"))),
                      "reach": reach, "seconds_out_of_reach": round(float(np.count_nonzero(outside) / RATE), 3),
                      "bytes": len(glb)}))


if __name__ == "__main__":
    main()
