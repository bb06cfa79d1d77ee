"""The *rank* step of Lyche-Morken knot removal: how far the curve moves if one knot goes.

Removing knot ``t[j]`` from a spline of order ``k`` leaves ``k + 1`` coefficients,
``c[j-k] .. c[j]``, to be represented by ``k`` coefficients on the shorter knot vector
through the knot-insertion relation ``c = M d`` (``M`` is (k+1) x k and bidiagonal).
The least-squares residual of that local system is the change in the coefficients,
and so (B-splines sum to one) it bounds how far the curve moves. It lies along the
left null vector ``v`` of ``M``, which has a closed form: each component is a signed
product of the insertion weights, so no system is solved and every knot is ranked at
once with array operations.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def removal_weights(knots: ArrayLike, coef: ArrayLike, order: int) -> np.ndarray:
    """Weight of each interior knot: the max-norm change of the coefficients if that
    knot alone is removed and the neighbouring coefficients are re-fitted.

    Parameters
    ----------
    knots : array_like, shape (K + order,)
        Knot vector.
    coef : array_like, shape (K, d)
        Coefficients, each channel already divided by its tolerance so that the
        weights of different channels compare fairly.
    order : int
        Spline order.

    Returns
    -------
    ndarray, shape (K - order,)
        Weight of interior knots ``knots[order] .. knots[K - 1]``; 0 means the knot can
        go without changing the curve.

    Examples
    --------
    A cubic with a knot it does not need ranks it at zero:

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.spline import insert_knots
    >>> s = insert_knots(BSpline([0, 0, 0, 0, 1, 1, 1, 1], [[0.0], [1.0], [3.0], [2.0]], 3), [0.5])
    >>> bool(removal_weights(s.t, s.c, 4)[0] < 1e-12)
    True
    """
    t = np.asarray(knots, dtype=float)
    c = np.asarray(coef, dtype=float)
    c = c.reshape(len(c), -1)
    k = order
    K = len(c)
    j = np.arange(k, K)
    if j.size == 0:
        return np.zeros(0)
    # Insertion weights alpha_m of rows m = 1 .. k-1 (coefficients j-k+1 .. j-1).
    i = j[:, None] + np.arange(1 - k, 0)[None, :]
    span = t[i + k] - t[i]
    alpha = np.where(span > 0, (t[j][:, None] - t[i]) / np.where(span > 0, span, 1.0), 1.0)
    ones = np.ones((len(j), 1))
    a = np.hstack([ones, alpha])            # a_0 .. a_{k-1}: diagonal entries
    b = np.hstack([1.0 - alpha, ones])      # b_1 .. b_k: sub-diagonal entries
    # v_r = (-1)^r * prod_{m<r} a_m * prod_{m>r} b_m, for r = 0 .. k.
    left = np.hstack([ones, np.cumprod(a, axis=1)])
    right = np.hstack([np.cumprod(b[:, ::-1], axis=1)[:, ::-1], ones])
    v = left * right
    v[:, 1::2] *= -1.0
    norm2 = np.einsum("nr,nr->n", v, v)
    local = c[j[:, None] + np.arange(-k, 1)[None, :]]          # (N, k+1, d)
    proj = np.abs(np.einsum("nr,nrd->nd", v, local)).max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.abs(v).max(axis=1) * proj / norm2
    return np.where(norm2 > 0, w, np.inf)
