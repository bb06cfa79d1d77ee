"""The walker's figure: a humanoid skeleton generated in code (no model files), in a
human's proportions, and the measures of it the walk uses (:class:`Rig`).

Conventions as :mod:`sketchanim.motion.skeleton`'s (``T(offset) R(rotation)``, scalar-last
quaternions); the figure stands on y = 0 facing +z, its left side on +x. The page's copy
is ``studio/web/js/humanoid.js``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sketchanim.errors import ArgumentError
from sketchanim.motion.skeleton import Skeleton

Vec = tuple[float, float, float]

#: The humanoid's joints, parents before children.
JOINTS = ("hips", "spine", "chest", "neck", "head",
          "l_shoulder", "l_upper_arm", "l_forearm", "l_hand",
          "r_shoulder", "r_upper_arm", "r_forearm", "r_hand",
          "l_thigh", "l_shin", "l_foot", "l_toe",
          "r_thigh", "r_shin", "r_foot", "r_toe")
PARENTS = ("", "hips", "spine", "chest", "neck",
           "chest", "l_shoulder", "l_upper_arm", "l_forearm",
           "chest", "r_shoulder", "r_upper_arm", "r_forearm",
           "hips", "l_thigh", "l_shin", "l_foot",
           "hips", "r_thigh", "r_shin", "r_foot")

#: Rest offsets as fractions of the height (left side; the right mirrors x).
_OFFSETS = {"hips": (0, 0.56, 0), "spine": (0, 0.06, 0), "chest": (0, 0.12, 0), "neck": (0, 0.12, 0),
            "head": (0, 0.05, 0), "l_shoulder": (0.02, 0.09, 0), "l_upper_arm": (0.1, 0, 0),
            "l_forearm": (0, -0.17, 0), "l_hand": (0, -0.15, 0), "l_thigh": (0.055, -0.03, 0),
            "l_shin": (0, -0.245, 0), "l_foot": (0, -0.245, 0), "l_toe": (0, -0.04, 0.11)}


def humanoid(height: float = 1.75) -> Skeleton:
    """A humanoid skeleton of ``height`` metres, generated in code: root ``hips``, spine,
    chest, neck, head, shoulders, upper arms, forearms, hands and legs
    ``hips -> l_thigh -> l_shin -> l_foot -> l_toe`` (and ``r_``). It stands on y = 0 facing
    +z, left side on +x, arms hanging; each toe is its foot's lowest node, on the ground.

    >>> s = humanoid(1.75)
    >>> len(s), s.names[0], round(float(s.rest_positions()[s.index("l_toe")][1]), 12)
    (21, 'hips', 0.0)
    """
    if not (math.isfinite(height) and 0.2 <= height <= 5.0):
        raise ArgumentError("height", f"must be 0.2 to 5 m, got {height!r}")
    offsets = []
    for name in JOINTS:
        x, y, z = _OFFSETS["l_" + name[2:] if name.startswith("r_") else name]
        offsets.append((-x if name.startswith("r_") else x, y, z))
    return Skeleton(JOINTS, tuple(JOINTS.index(p) if p else -1 for p in PARENTS), np.array(offsets) * height)


@dataclass(frozen=True)
class Rig:
    """What the walk needs of a humanoid skeleton (see :func:`rig`), in metres.

    >>> r = rig(humanoid(1.75))
    >>> r.joints, r.hip[0][0] > 0 > r.hip[1][0]
    (21, True)
    """

    joints: int                      # J
    index: tuple[int, ...]           # hips, spine, l/r upper arm, l/r forearm, l/r thigh, l/r shin, l/r foot
    hip: tuple[Vec, Vec]             # each thigh joint's offset from the hips
    thigh: float
    shin: float
    toe: Vec                         # the toe's offset from the ankle (the same both sides)
    ankle: float                     # ankle height above the ground, foot flat
    leg: float                       # H: hip joint height above the ground at rest
    pelvis: float                    # the hips' rest height above the ground


def rig(skeleton: Skeleton) -> Rig:
    """The walk's view of ``skeleton``: one with :func:`humanoid`'s joint names, shins and
    ankles straight below their parents at rest.

    >>> r = rig(humanoid(2.0))
    >>> round(r.leg, 12), round(r.thigh, 12), round(r.ankle, 12)
    (1.06, 0.49, 0.08)
    """
    names = ("hips", "spine", "l_upper_arm", "r_upper_arm", "l_forearm", "r_forearm",
             "l_thigh", "r_thigh", "l_shin", "r_shin", "l_foot", "r_foot")
    index = tuple(skeleton.index(n) for n in names)
    for n in ("l_toe", "r_toe"):
        skeleton.index(n)
    o = np.asarray(skeleton.offsets, dtype=float)
    for n in ("l_shin", "r_shin", "l_foot", "r_foot"):
        x, y, z = o[skeleton.index(n)]
        if x != 0 or z != 0 or not y < 0:
            raise ArgumentError("skeleton", f"joint {n!r} must be straight below its parent at rest")
    if not np.array_equal(o[skeleton.index("l_toe")] * [-1, 1, 1], o[skeleton.index("r_toe")]) or \
            o[skeleton.index("l_toe"), 1] >= 0:
        raise ArgumentError("skeleton", "the toes must mirror each other, below the ankles")
    rest = skeleton.rest_positions()
    ground = float(rest[skeleton.index("l_toe"), 1])
    toe = tuple(float(v) for v in o[skeleton.index("l_toe")])
    return Rig(len(skeleton), index,
               (tuple(float(v) for v in o[index[6]]), tuple(float(v) for v in o[index[7]])),  # type: ignore[arg-type]
               float(-o[index[8], 1]), float(-o[index[10], 1]), toe,  # type: ignore[arg-type]
               float(-toe[1]), float(rest[index[6], 1]) - ground, float(rest[index[0], 1]) - ground)
