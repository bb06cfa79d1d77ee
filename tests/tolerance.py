"""The one tolerance check of the tests: how far values are from samples, per channel
or as a rotation angle, and whether that is within a tolerance."""

from __future__ import annotations

import numpy as np

from sketchanim.reducer.metric import rotation_angle


def max_error(got: np.ndarray, x: np.ndarray, rotation: bool = False) -> np.ndarray:
    """The largest error of values ``got`` at samples ``x`` (n, d) or (n,): per channel
    (d,), or for quaternions (scalar-last) the largest geodesic angle in degrees, (1,)."""
    n = len(x)
    got, x = np.asarray(got, dtype=float).reshape(n, -1), np.asarray(x, dtype=float).reshape(n, -1)
    if rotation:
        return np.array([float(np.degrees(rotation_angle(got, x)).max())])
    return np.abs(got - x).max(axis=0)


def within(got: np.ndarray, x: np.ndarray, tol: float | np.ndarray, *, rotation: bool = False,
           slack: float = 0.0) -> bool:
    """Every value of ``got`` within ``tol`` (per channel, or degrees) of ``x``, give or
    take ``slack`` of the tolerance."""
    return bool(np.all(max_error(got, x, rotation) <= np.asarray(tol, dtype=float) * (1 + slack)))
