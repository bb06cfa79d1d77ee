"""Kinematics of a :class:`~sketchanim.motion.skeleton.Skeleton`: where its joints are in
the world for given local rotations and translations (forward kinematics; inverse
kinematics, a pose from goals, joins it here).

Conventions as :mod:`sketchanim.motion.skeleton`'s: ``world_j = world_parent * local_j``,
a local transform ``T(translation) R(rotation)``, quaternions scalar-last.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numba import njit
from scipy.spatial.transform import Rotation

if TYPE_CHECKING:                       # the skeleton's clips use these kinematics
    from sketchanim.motion.skeleton import Skeleton


def world_pose(skeleton: Skeleton, rotations: np.ndarray, translations: np.ndarray) -> tuple[list[Rotation], np.ndarray]:
    """Forward kinematics: each joint's world rotation (a ``Rotation`` of n frames) and
    world position (n, J, 3), from local rotations (n, J, 4, scalar-last) and
    translations (n, J, 3).

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("a", "b"), (-1, 0), np.array([[0.0, 0, 0], [1.0, 0, 0]]))
    >>> q = np.array([[[0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)], [0, 0, 0, 1.0]]])
    >>> turns, positions = world_pose(s, q, np.array([[[0.0, 0, 0], [1.0, 0, 0]]]))
    >>> positions[0, 1].round(12).tolist(), round(float(np.degrees(turns[1].magnitude()[0])), 6)
    ([0.0, 1.0, 0.0], 90.0)
    """
    n, j = rotations.shape[:2]
    world_rot: list[Rotation] = []
    out = np.empty((n, j, 3))
    for i, p in enumerate(skeleton.parents):
        local = Rotation.from_quat(rotations[:, i])
        if p < 0:
            world_rot.append(local)
            out[:, i] = translations[:, i]
        else:
            world_rot.append(world_rot[p] * local)
            out[:, i] = out[:, p] + world_rot[p].apply(translations[:, i])
    return world_rot, out


def world_matrices(skeleton: Skeleton, rotations: np.ndarray, translations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Forward kinematics as :func:`world_pose`, with each joint's world rotation as a
    matrix (n, J, 3, 3): cheaper where many frames are measured (the chain is walked in
    a compiled kernel). Quaternions of any norm are normalised.

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("a", "b"), (-1, 0), np.array([[0.0, 0, 0], [1.0, 0, 0]]))
    >>> q = np.array([[[0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)], [0, 0, 0, 1.0]]])
    >>> turns, positions = world_matrices(s, q, np.array([[[0.0, 0, 0], [1.0, 0, 0]]]))
    >>> positions[0, 1].round(12).tolist()
    [0.0, 1.0, 0.0]
    """
    n, j = rotations.shape[:2]
    local = Rotation.from_quat(rotations.reshape(-1, 4)).as_matrix().reshape(n, j, 3, 3)
    return _down_the_chains(np.asarray(skeleton.parents, dtype=np.int64), local,
                            np.ascontiguousarray(translations, dtype=float))


@njit(cache=True, error_model="numpy")
def _down_the_chains(parents: np.ndarray, local: np.ndarray, translations: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray]:
    """World rotation matrices (n, J, 3, 3) and positions (n, J, 3) from local rotation
    matrices and translations, joints in order (each after its parent)."""
    n, j = local.shape[0], local.shape[1]
    turns = np.empty_like(local)
    out = np.empty((n, j, 3))
    for f in range(n):
        for i in range(j):
            p = parents[i]
            if p < 0:
                turns[f, i] = local[f, i]
                out[f, i] = translations[f, i]
                continue
            for a in range(3):
                for b in range(3):
                    turns[f, i, a, b] = (turns[f, p, a, 0] * local[f, i, 0, b] + turns[f, p, a, 1] * local[f, i, 1, b]
                                         + turns[f, p, a, 2] * local[f, i, 2, b])
                out[f, i, a] = out[f, p, a] + (turns[f, p, a, 0] * translations[f, i, 0]
                                               + turns[f, p, a, 1] * translations[f, i, 1]
                                               + turns[f, p, a, 2] * translations[f, i, 2])
    return turns, out


def shell_error(turns: np.ndarray, positions: np.ndarray, source_turns: np.ndarray, source_positions: np.ndarray,
                shell: float) -> np.ndarray:
    """How far a point ``shell`` from each joint is from the source's at most:
    the joints' distance from the source's ``positions`` (..., 3) plus ``shell`` times
    the :func:`chord` of their rotations' difference (``turns``, (..., 3, 3)). With a
    shell of 3 cm this is the Animation Compression Library's error metric.

    >>> z = Rotation.from_euler("z", [[0.0], [60.0]], degrees=True).as_matrix()
    >>> round(float(shell_error(z[1], np.array([0.3, 0.0, 0.0]), z[0], np.zeros(3), 2.0)), 12)
    2.3
    """
    error = np.linalg.norm(positions - source_positions, axis=-1)
    if shell:
        error += shell * chord(turns, source_turns)
    return error


def chord(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """How far a point a unit from the origin moves between rotation matrices ``a`` and
    ``b`` (..., 3, 3) at most: ``2 sin(angle / 2)`` of the turn from one to the other,
    computed without cancellation for small angles (``|a - b|`` over root 2).

    >>> z = Rotation.from_euler("z", [[0.0], [60.0]], degrees=True).as_matrix()
    >>> round(float(chord(z[0], z[1])), 12)
    1.0
    """
    return np.sqrt(np.sum((a - b) ** 2, axis=(-2, -1)) / 2)
