"""Whole-clip reduction within a distance in the world: every joint's position, and every
point at a ``shell`` distance from a joint (a vertex its skin could carry), stays within
``tol`` of the source at every frame, and planted end joints within
``CONTACT_SHARE * tol`` on the frames they are planted (:mod:`sketchanim.mocap.contacts`).

One angle for every joint spends the same accuracy on the hips, whose turn moves the
whole body, as on a toe, whose turn moves a few centimetres; and the errors of a chain
add up. Here each joint's angle follows from how far its turn reaches: a joint whose
descendants reach ``r`` starts at its chain's bound over ``(r + shell)`` and a part of the
chain's depth (:data:`~sketchanim.mocap.clip_reduction.START_SPREAD`). The errors are then
measured by forward kinematics, and the joints above any joint or shell point still out
of its bound are tightened by the measured ratio, until the angles that provably keep
every chain within it (:func:`~sketchanim.mocap.clip_reduction.tighten`); the result is
checked at every frame. ``r`` follows the source's longest translations where a joint's
translation channels carry it further than its offset. The translating joints' curves
get :data:`~sketchanim.mocap.clip_reduction.TRANSLATION_SHARE` of the distance, shared
among the moving ones down a chain.
"""

from __future__ import annotations

import numpy as np

from sketchanim.errors import ArgumentError
from sketchanim.mocap.clip_reduction import (ORDER, TRANSLATION_SHARE, ReducedClip, contact_angles, held_frames,
                                             joint_position, most_moving, on_chains, sliding_kept, tighten)
from sketchanim.motion.skeleton import Clip

#: The largest angle any joint is given, degrees (a joint that reaches nothing, a leaf).
MAX_ANGLE_DEG = 30.0


def reduce_clip_world(clip: Clip, tol: float, shell: float, *, method: str = "incremental", order: int = ORDER,
                      contacts: np.ndarray | None = None) -> ReducedClip:
    """Reduce ``clip`` so that every joint, and every point ``shell`` from a joint, is
    within the distance ``tol`` (clip units) of the source in the world at every frame,
    and within ``CONTACT_SHARE * tol`` where the source plants an end joint on the ground
    (``contacts``, by default :func:`~sketchanim.mocap.contacts.planted`; less
    where it still slides: :func:`~sketchanim.mocap.clip_reduction.sliding_kept`), as
    curves of ``order`` (:data:`~sketchanim.mocap.clip_reduction.ORDER`: straight pieces).

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
    held = held_frames(clip, contacts)
    held_chain = on_chains(clip, held.any(axis=0))
    share = TRANSLATION_SHARE * tol / most_moving(clip, np.ones(len(clip.skeleton), bool))
    cap = np.radians(MAX_ANGLE_DEG)

    def reduced(clip: Clip, held: np.ndarray, planted_share: float, framed: np.ndarray) -> ReducedClip:
        translations = {int(i): joint_position(clip, int(i), share * (planted_share if held_chain[i] else 1.0), method,
                                               order=order,
                                               why=f" (its share of tol {tol:.6g} in the world)")
                        for i in np.flatnonzero(clip.translating)}
        bound = np.where(held, planted_share * tol, np.where(framed[:, None], tol, np.inf))    # tol at the frames
        start, provable = contact_angles(clip, translations, bound, shell)
        return tighten(clip, translations, np.minimum(start, cap), np.minimum(provable, cap), bound, shell, method,
                       framed, order=order, why=f"to hold the joints within tol {tol:.6g} in the world")

    return sliding_kept(clip, held, reduced)
