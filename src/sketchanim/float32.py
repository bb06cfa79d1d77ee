"""What storing a curve in float32 costs its tolerance: the budget a reducer may use so
that a file played in float32 still stays within the tolerance.

A client plays a file's keys and key times as float32, and computes in float32 (Blender
evaluates F-curves in float32, three.js keeps float32 results). So every curve meant for
a file is reduced, or checked, against the tolerance less what float32 can move it
(:func:`float32_margin`): mocap reductions aim at these budgets, and the scene export
refits a track that is not within them.
"""

from __future__ import annotations

import numpy as np

#: float32's unit roundoff: storing a number as float32 moves it by at most this, relative.
EPS32 = 2.0**-24

#: float32 roundings a played value may gather: its keys, a client's own float32
#: arithmetic (a joint's world position, down its chain).
ROUNDINGS = 16

#: float32 roundings of time a played value may gather, each moving it by its speed times
#: the rounding: the key times on either side, the time played, the fraction between keys.
TIME_ROUNDINGS = 4


def float32_margin(times: np.ndarray, size: float, speed: float | np.ndarray) -> float | np.ndarray:
    """How far a curve of values up to ``size`` (a norm), moving at up to ``speed`` per
    second over ``times``, may move once stored and played in float32: ``ROUNDINGS``
    roundings of its values, and ``TIME_ROUNDINGS`` of its times (a time rounded moves
    the value by the speed times the rounding).

    ``speed`` is one number for the whole curve (the margin then holds at its latest
    time), or one per time (n, ...): the margin at each time, from that time's speed and
    how late it is.

    >>> m = float32_margin(np.array([0.0, 30.0]), 200.0, 300.0)     # a hips in cm, 30 s
    >>> bool(1e-4 < m < 1e-2)
    True
    >>> per = float32_margin(np.array([0.0, 30.0]), 200.0, np.array([300.0, 300.0]))
    >>> bool(per[1] == m and per[0] < m)
    True
    """
    late = np.abs(np.asarray(times, dtype=float))
    if np.ndim(speed):
        span = late.reshape(late.shape + (1,) * (np.ndim(speed) - 1))
    else:
        span = float(late.max()) if len(late) else 0.0
    return EPS32 * (ROUNDINGS * size + TIME_ROUNDINGS * speed * span)


def position_budget(times: np.ndarray, points: np.ndarray, tol: float) -> float:
    """The distance a reducer may use of ``tol`` for points (n, d) sampled at ``times``
    (n,) so that the float32 file still plays within ``tol`` (:func:`float32_margin`;
    never less than half of ``tol``).

    >>> t = np.arange(100) / 30
    >>> 0.49 < position_budget(t, np.c_[100 * np.sin(t), 90 + 0 * t, t], 0.5) < 0.5
    True
    """
    x = np.asarray(points, dtype=float).reshape(len(times), -1)
    speed = float((np.linalg.norm(np.diff(x, axis=0), axis=1) / np.diff(times)).max()) if len(times) > 1 else 0.0
    return tol - min(float32_margin(times, float(np.linalg.norm(x, axis=1).max()), speed), tol / 2)


def rotation_budget(times: np.ndarray, quats: np.ndarray, tol_deg: float) -> float:
    """The angle (degrees) a reducer may use of ``tol_deg`` for quaternions (n, 4)
    sampled at ``times`` (n,), so that the float32 file still plays within ``tol_deg``:
    an error ``e`` in a unit quaternion turns it by up to ``2 e`` radians.

    >>> from scipy.spatial.transform import Rotation
    >>> t = np.arange(100) / 30
    >>> q = Rotation.from_euler("Z", 3 * t[:, None]).as_quat()
    >>> 0.499 < rotation_budget(t, q, 0.5) < 0.5
    True
    """
    q = np.asarray(quats, dtype=float)
    turn = np.arccos(np.clip(np.abs(np.sum(q[1:] * q[:-1], axis=1)) / (np.linalg.norm(q[1:], axis=1)
                                                                     * np.linalg.norm(q[:-1], axis=1)), 0, 1))
    speed = float((turn / np.diff(times)).max()) if len(times) > 1 else 0.0     # of the unit quaternion, per s
    margin = float(np.degrees(2 * float32_margin(times, 1.0, speed)))
    return tol_deg - min(margin, tol_deg / 2)
