"""Whole-clip reduction within a distance in the world: every joint's position, and every
point at a ``shell`` distance from a joint (a vertex its skin could carry), stays within
``tol`` of the source at every frame.

One angle for every joint spends the same accuracy on the hips, whose turn moves the
whole body, as on a toe, whose turn moves a few centimetres; and the errors of a chain
add up. Here each joint's angle follows from how far its turn reaches: a joint whose
descendants reach ``r`` starts at ``tol / (r + shell)``. The errors are then measured by
forward kinematics; the joints above any joint or shell point still out of tolerance
are tightened, and the clip reduced again. After :data:`ROUNDS` rounds, the joints
above any that still miss get an angle that provably keeps their chains within ``tol``
(a chain's errors at most add up: ``sum of budget / (depth * (r + shell)) * (r + shell)``),
and if a chain still misses (a joint it shares with one just tightened was reduced
again), every joint gets it, so the result always holds; it is checked at every frame.
``r`` follows the source's longest translations where a joint's translation channels
carry it further than its offset.
"""

from __future__ import annotations

import numpy as np

from sketchanim.mocap.clip_reduction import ReducedClip, clip_tracks, joint_position, joint_rotation
from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Clip
from sketchanim.errors import ArgumentError

#: Of the distance, what the translating joints' curves may use (shared among the moving
#: ones down a chain); the rotations get what they leave.
TRANSLATION_SHARE = 0.25

#: The largest angle any joint is given, degrees (a joint that reaches nothing, a leaf).
MAX_ANGLE_DEG = 30.0

#: Rounds of measuring and tightening before the provable angles.
ROUNDS = 6


def reduce_clip_world(clip: Clip, tol: float, shell: float, *, method: str = "global") -> ReducedClip:
    """Reduce ``clip`` so that every joint, and every point ``shell`` from a joint, is
    within the distance ``tol`` (clip units) of the source in the world at every frame.

    Examples
    --------
    >>> from scipy.spatial.transform import Rotation
    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("hips", "knee", "toe"), (-1, 0, 1), np.array([[0.0, 90, 0], [0, -45, 0], [0, -45, 0]]))
    >>> t = np.arange(240) / 120
    >>> clip = Clip.still(s, t)
    >>> clip.rotations[:, 0] = Rotation.from_euler("Z", 0.3 * np.sin(3 * t)[:, None]).as_quat()
    >>> clip.rotations[:, 1] = Rotation.from_euler("X", np.sin(5 * t)[:, None]).as_quat()
    >>> r = reduce_clip_world(clip, 0.5, 3.0)
    >>> bool(r.world_errors(clip, 3.0).max() <= 0.5)
    True
    """
    for name, value in (("tol", tol), ("shell", shell)):
        if not np.isfinite(value) or value < 0 or (name == "tol" and value == 0):
            raise ArgumentError(name, f"must be a positive distance, got {value!r}")
    sk = clip.skeleton
    chains = sk.chains()
    varying = clip.translating & np.any(np.ptp(clip.translations, axis=0) > 0, axis=-1)
    moving = max(sum(bool(varying[a]) for a in chain) for chain in chains)
    share = TRANSLATION_SHARE * tol / max(moving, 1)
    translations = {int(i): joint_position(clip, int(i), share, method) for i in np.flatnonzero(clip.translating)}
    moved = {i: r.report["max_distance"] for i, r in translations.items()}
    budget = tol - max(sum(moved.get(a, 0.0) for a in chain) for chain in chains)
    turning = max(max(sum(bool(clip.rotating[a]) for a in chain) for chain in chains), 1)
    arm = sk.reach(clip.bones()) + shell
    cap = np.radians(MAX_ANGLE_DEG)
    angle = np.minimum(budget / np.maximum(arm, 1e-300), cap)
    provable = np.minimum(budget / np.maximum(turning * arm, 1e-300), cap)
    source = world_pose(sk, clip.rotations, clip.translations)
    rotations, made = {}, {}
    for round in range(ROUNDS + 2):
        for i in np.flatnonzero(clip.rotating):
            if made.get(int(i)) != angle[i]:
                rotations[int(i)] = joint_rotation(clip, int(i), float(np.degrees(angle[i])), method)
                made[int(i)] = angle[i]
        reduced = clip_tracks(clip, rotations, translations)
        worst = reduced.world_errors(clip, shell, source=source).max(axis=0)
        over = np.flatnonzero(worst > tol)
        if not over.size:
            return reduced
        if round >= ROUNDS:                          # the last resort: every chain provably within
            angle = np.minimum(angle, provable)
            continue
        factor = np.ones(len(sk))                    # each joint tightened once, by its worst descendant
        for d in over:
            factor[chains[d]] = np.minimum(factor[chains[d]], np.clip(0.95 * tol / worst[d], 0.5, 0.95))
        tight = factor < 1
        if round < ROUNDS - 1:
            angle[tight] *= factor[tight]
        else:
            angle[tight] = np.minimum(angle[tight], provable[tight])
    raise AssertionError(f"world errors up to {worst.max():.6g} > {tol:.6g} after the provable angles")
