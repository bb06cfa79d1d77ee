"""How far a curve is from its samples: channel by channel, or as a rotation angle.

The reducers measure every sample against a tolerance. By default each channel has its
own (``|curve - sample| <= tol`` per channel). With an angle, the four channels are a
quaternion and what is bounded is the rotation between the curve's value, normalised,
and the sample: the geodesic angle on SO(3), whatever the curve's norm and sign. That
is what a renderer that normalises a component-wise quaternion spline shows (glTF's
CUBICSPLINE rotation sampler does exactly this).
"""

from __future__ import annotations

import numpy as np
from numba import njit


def rotation_angle(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rotation angle (radians, in [0, pi]) between quaternions ``p`` and ``q``, row by row.

    Neither needs unit norm, and ``q`` and ``-q`` are the same rotation.

    >>> q = np.array([[0.0, 0.0, 0.0, 1.0]])
    >>> half = np.radians(10) / 2
    >>> p = 3.0 * np.array([[0.0, 0.0, np.sin(half), -np.cos(half)]])   # any norm, either sign
    >>> float(np.degrees(rotation_angle(p, q))[0]).__round__(9)
    10.0
    """
    p = np.ascontiguousarray(np.asarray(p, dtype=float).reshape(-1, 4))
    q = np.ascontiguousarray(np.asarray(q, dtype=float).reshape(-1, 4))
    return _angles(p, q)


@njit(cache=True, error_model="numpy")
def _angles(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """:func:`rotation_angle` of rows (n, 4), compiled: twice the angle between the lines
    the quaternions span, its sine from Lagrange's identity over the channel pairs
    (``|p|^2 |q|^2 - (p . q)^2`` without cancellation)."""
    out = np.empty(len(p))
    for r in range(len(p)):
        dot = 0.0
        cross2 = 0.0
        for i in range(4):
            dot += p[r, i] * q[r, i]
            for j in range(i + 1, 4):
                w = p[r, i] * q[r, j] - p[r, j] * q[r, i]
                cross2 += w * w
        out[r] = 2.0 * np.arctan2(np.sqrt(cross2), abs(dot))
    return out


def max_errors(curve: np.ndarray, samples: np.ndarray, angle: float = 0.0) -> np.ndarray:
    """Largest error over the samples: per channel (shape (d,)), or with ``angle > 0``
    the largest rotation angle in radians (shape (1,)).

    >>> max_errors(np.array([[0.0, 1.0], [1.0, 1.5]]), np.array([[0.1, 1.0], [1.0, 1.0]]))
    array([0.1, 0.5])
    """
    curve = np.asarray(curve, dtype=float).reshape(len(samples), -1)
    samples = np.asarray(samples, dtype=float).reshape(len(curve), -1)
    if not len(samples):
        return np.zeros(1 if angle > 0 else samples.shape[1])
    if angle > 0:
        return np.array([rotation_angle(curve, samples).max()])
    return np.abs(curve - samples).max(axis=0)
