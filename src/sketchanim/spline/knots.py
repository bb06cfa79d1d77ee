"""Knot vectors: the knot-insertion matrix, knot insertion and degree elevation.

Orders, not degrees: order ``k`` is degree ``k - 1`` (4 is cubic), as in the paper.
Splines are :class:`scipy.interpolate.BSpline` objects, whose ``k`` is the degree.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline, make_interp_spline
from scipy.sparse import csr_array

from sketchanim.errors import ArgumentError


def _check_nested(coarse: np.ndarray, fine: np.ndarray, order: int) -> None:
    for name, knots in (("old_knots", coarse), ("new_knots", fine)):
        if len(knots) < 2 * order or knots[0] != knots[order - 1] or knots[-order] != knots[-1]:
            raise ArgumentError(name, f"must be clamped (first and last {order} knots equal); "
                                      "scipy.interpolate.insert refines other knot vectors")
    values, counts = np.unique(coarse, return_counts=True)
    fine_counts = np.searchsorted(fine, values, side="right") - np.searchsorted(fine, values, side="left")
    short = np.flatnonzero(fine_counts < counts)
    if short.size or coarse[0] != fine[0] or coarse[-1] != fine[-1]:
        where = f" (knot {values[short[0]]!r})" if short.size else " (end knots differ)"
        raise ArgumentError("new_knots", f"must contain every old knot with its multiplicity{where}")


def insertion_matrix(old_knots: ArrayLike, new_knots: ArrayLike, order: int) -> csr_array:
    """Exact knot-insertion matrix between nested knot vectors (Oslo algorithm 1).

    For a spline of order ``order`` with coefficients ``c`` on ``old_knots``, the same
    spline on the refined ``new_knots`` has coefficients ``A @ c``. Row ``i`` holds the
    discrete B-splines of the old knots at new knot ``i``: at most ``order`` entries,
    all non-negative, summing to one.

    Parameters
    ----------
    old_knots, new_knots : array_like
        Non-decreasing clamped knot vectors (first and last ``order`` knots equal);
        ``new_knots`` contains every knot of ``old_knots`` with at least its
        multiplicity, and the same end knots.
    order : int
        Spline order (degree + 1).

    Returns
    -------
    scipy.sparse.csr_array, shape (len(new_knots) - order, len(old_knots) - order)

    Examples
    --------
    >>> A = insertion_matrix([0, 0, 1, 1], [0, 0, 0.5, 1, 1], order=2)
    >>> A.toarray()
    array([[1. , 0. ],
           [0.5, 0.5],
           [0. , 1. ]])
    """
    tau = np.asarray(old_knots, dtype=float)
    t = np.asarray(new_knots, dtype=float)
    k = order
    _check_nested(tau, t, k)
    n_old = len(tau) - k
    n_new = len(t) - k
    rows = np.arange(n_new)
    # Interval of the old knots holding each new knot, kept within the spline's span.
    mu = np.clip(np.searchsorted(tau, t[:n_new], side="right") - 1, k - 1, n_old - 1)
    b = np.zeros((n_new, k))
    b[:, k - 1] = 1.0
    for r in range(1, k):
        x = t[rows + r]
        new_b = np.zeros_like(b)
        for p in range(k - 1 - r, k):
            j = mu - (k - 1) + p
            for col, jj, sign in ((p, j, 1.0), (p + 1, j + 1, -1.0)):
                if col >= k:
                    continue
                span = tau[jj + r] - tau[jj]
                safe = np.where(span > 0, span, 1.0)
                omega = np.where(span > 0, (x - tau[jj]) / safe, 0.0)
                new_b[:, p] += (omega if sign > 0 else 1.0 - omega) * b[:, col]
        b = new_b
    cols = mu[:, None] - (k - 1) + np.arange(k)[None, :]
    return csr_array((b.ravel(), (np.repeat(rows, k), cols.ravel())), shape=(n_new, n_old))


def insert_knots(spline: BSpline, knots: ArrayLike) -> BSpline:
    """The same spline with ``knots`` inserted (each value once per occurrence).

    >>> s = BSpline([0, 0, 0, 0, 1, 1, 1, 1], [0.0, 1.0, 3.0, 2.0], 3)
    >>> r = insert_knots(s, [0.25, 0.5])
    >>> len(r.c), bool(np.allclose(r(np.linspace(0, 1, 9)), s(np.linspace(0, 1, 9))))
    (6, True)
    """
    old = np.asarray(spline.t, dtype=float)
    new = np.sort(np.concatenate([old, np.asarray(knots, dtype=float).ravel()]))
    A = insertion_matrix(old, new, spline.k + 1)
    c = np.asarray(spline.c, dtype=float)
    flat = c.reshape(len(c), -1)
    return BSpline(new, (A @ flat).reshape((A.shape[0],) + c.shape[1:]), spline.k, spline.extrapolate)


def greville(knots: ArrayLike, order: int) -> np.ndarray:
    """Greville abscissae: averages of ``order - 1`` consecutive interior knots.

    >>> greville([0, 0, 0, 1, 2, 2, 2], 3)
    array([0. , 0.5, 1.5, 2. ])
    """
    t = np.asarray(knots, dtype=float)
    p = order - 1
    if p == 0:
        return t[:-1].copy()
    window = np.lib.stride_tricks.sliding_window_view(t[1:-1], p)
    return window.mean(axis=1)


def derivative(spline: BSpline) -> BSpline:
    """The first derivative, also of a spline with a knot of full multiplicity inside
    (scipy's :meth:`BSpline.derivative` refuses those): right-continuous there, as the
    spline is evaluated.

    >>> s = BSpline([0, 0, 1, 1, 2, 2], [0.0, 1.0, 3.0, 3.0], 1)     # a jump in slope at 1
    >>> derivative(s)([0.5, 1.5]).tolist()
    [1.0, 0.0]
    """
    t, c, p = np.asarray(spline.t, dtype=float), np.asarray(spline.c, dtype=float), spline.k
    if p == 0:
        return BSpline(t[1:-1], np.zeros_like(c[:-1] if len(c) > 1 else c), 0)
    width = (t[p + 1 : len(c) + p] - t[1 : len(c)]).reshape((-1,) + (1,) * (c.ndim - 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(width > 0, p * np.diff(c, axis=0) / np.where(width > 0, width, 1.0), 0.0)
    return BSpline(t[1:-1], d, p - 1)


def elevate_degree(spline: BSpline, times: int = 1) -> BSpline:
    """The same spline as one of higher degree (each knot's multiplicity rises by one).

    The elevated spline is the unique spline on the elevated knot vector that agrees
    with the original at the new Greville abscissae; the original lies in that space,
    so the two are the same function, up to rounding.

    Raises
    ------
    ArgumentError
        The spline jumps in value at an interior knot (multiplicity equal to its order).

    Examples
    --------
    >>> s = BSpline([0, 0, 1, 2, 2], [0.0, 1.0, 0.0], 1)      # a hat, order 2
    >>> e = elevate_degree(s, 2)                              # the same hat, cubic
    >>> e.k, bool(np.allclose(e([0.2, 1.0, 1.7]), s([0.2, 1.0, 1.7])))
    (3, True)
    """
    if times < 0:
        raise ArgumentError("times", f"must be >= 0, got {times}")
    t = np.asarray(spline.t, dtype=float)
    order = spline.k + 1
    values, counts = np.unique(t, return_counts=True)
    interior = counts[1:-1]
    if interior.size and interior.max() >= order:
        bad = values[1:-1][np.argmax(interior)]
        raise ArgumentError("spline", f"jumps in value at t={float(bad):g}; elevate each continuous piece")
    if times == 0:
        return spline
    new_t = np.repeat(values, counts + times)
    new_order = order + times
    # Averages of repeated end knots can round just outside the span: clip them back.
    sites = np.clip(greville(new_t, new_order), new_t[0], new_t[-1])
    c = np.asarray(spline.c, dtype=float)
    elevated = make_interp_spline(sites, spline(sites), k=new_order - 1, t=new_t)
    return BSpline(new_t, elevated.c.reshape((len(elevated.c),) + c.shape[1:]), new_order - 1, spline.extrapolate)
