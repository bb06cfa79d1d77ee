"""Generated ground paths for the walker (sketchanim.motion.walk): the marker at each
tick, (n, 3), y the ground height; and what a walk does on them (planted toes' speeds,
steps). Shared by tests/motion/test_walk.py and benchmarks/bench_walk.py."""

from __future__ import annotations

import numpy as np

from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Skeleton
from sketchanim.motion.walk import RATE, Walk


def straight(speed: float, seconds: float, rest: float = 0.5) -> np.ndarray:
    """Standing ``rest`` s, then along +z at ``speed`` m/s, easing in over 0.5 s."""
    t = np.arange(int(round(seconds * RATE))) / RATE
    z = np.cumsum(speed * np.clip((t - rest) / 0.5, 0.0, 1.0)) / RATE
    return np.c_[np.zeros_like(t), np.zeros_like(t), z]


def segments(parts: list[tuple[float, float, float]], heading: float = 0.0, slope: float = 0.0,
             smooth: float = 0.4) -> np.ndarray:
    """A path of ``parts`` (seconds, speed m/s, turn rate rad/s) one after the other, the
    speed and turn rate eased between parts over ``smooth`` s (a moving average), starting
    at the origin facing ``heading``; the ground rising ``slope`` m per m travelled."""
    speed = np.concatenate([np.full(max(1, int(round(d * RATE))), v) for d, v, _ in parts])
    turn = np.concatenate([np.full(max(1, int(round(d * RATE))), w) for d, _, w in parts])
    width = max(1, int(round(smooth * RATE)))
    kernel = np.ones(width) / width
    pad = lambda a: np.r_[np.full(width, a[0]), a, np.full(width, a[-1])]  # noqa: E731
    speed = np.convolve(pad(speed), kernel, "same")[width:-width]
    turn = np.convolve(pad(turn), kernel, "same")[width:-width]
    angle = heading + np.cumsum(turn) / RATE
    step = np.c_[np.sin(angle), np.cos(angle)] * speed[:, None] / RATE
    xz = np.cumsum(step, axis=0) - step[0]
    travelled = np.cumsum(np.abs(speed)) / RATE
    return np.c_[xz[:, 0], slope * travelled, xz[:, 1]]


def world(skeleton: Skeleton, w: Walk) -> np.ndarray:
    """Joint positions (n, J, 3) by forward kinematics, the root at the walk's root."""
    n = len(w.root)
    translations = np.broadcast_to(skeleton.offsets, (n, len(skeleton), 3)).copy()
    translations[:, 0] = w.root
    return world_pose(skeleton, w.rotations, translations)[1]


def toe_speeds(skeleton: Skeleton, w: Walk, points: np.ndarray | None = None) -> list[np.ndarray]:
    """Each toe's speed (m/s) between samples at 60 Hz both inside one stance span."""
    points = world(skeleton, w) if points is None else points
    out = []
    for side, toe in enumerate(("l_toe", "r_toe")):
        planted = w.stance[:, side]
        k = np.arange(0, len(planted) - 2, 2)
        held = planted[k] & planted[k + 1] & planted[k + 2]
        p = points[:, skeleton.index(toe)]
        out.append(np.linalg.norm(p[k + 2] - p[k], axis=1)[held] * 60.0)
    return out


def lifts(w: Walk, side: int) -> np.ndarray:
    """The ticks foot ``side`` lifts."""
    s = w.stance[:, side]
    return np.flatnonzero(s[:-1] & ~s[1:]) + 1


def landings(w: Walk, side: int) -> np.ndarray:
    s = w.stance[:, side]
    return np.flatnonzero(~s[:-1] & s[1:]) + 1
