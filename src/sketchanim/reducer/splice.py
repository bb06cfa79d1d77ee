"""Joining the pieces of a take cut at its pauses and breaks into one spline, and
cutting a spline in two.

Two clamped pieces that meet at time ``c`` on a shared value join exactly on a knot of
multiplicity ``order - 1`` at ``c``: the joined spline has the left piece's coefficients,
then the right piece's after its first (the shared value). Each piece is unchanged on its
own span (inserting ``c`` once more would split them apart again), the joined curve is
continuous at ``c``, and its one-sided derivatives there are the pieces' own.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError
from sketchanim.spline import insert_knots


def hold(start: float, end: float, value: ArrayLike, order: int) -> BSpline:
    """The constant spline ``value`` on ``[start, end]``, clamped at both ends.

    >>> s = hold(1.0, 2.0, [3.0, 4.0], 4)
    >>> s(np.array([1.0, 1.5, 2.0])).tolist(), s.derivative()(1.5).tolist()
    ([[3.0, 4.0], [3.0, 4.0], [3.0, 4.0]], [0.0, 0.0])
    """
    v = np.asarray(value, dtype=float).reshape(1, -1)
    return BSpline(np.r_[[start] * order, [end] * order], np.repeat(v, order, axis=0), order - 1)


def join(pieces: Sequence[BSpline]) -> BSpline:
    """One spline from clamped pieces, each starting where the one before ends, on the
    value it ends with (its last coefficient equals the next one's first).

    Raises :class:`ArgumentError` naming the first pair that does not meet.

    >>> left = BSpline(np.r_[[0.0] * 4, [1.0] * 4], np.c_[[0.0, 1.0, 2.0, 3.0]], 3)
    >>> right = BSpline(np.r_[[1.0] * 4, [2.0] * 4], np.c_[[3.0, 3.0, 1.0, 0.0]], 3)
    >>> s = join([left, right])
    >>> s.t.tolist(), s(np.array([0.5, 1.0, 1.5]))[:, 0].tolist() == [left(0.5)[0], 3.0, right(1.5)[0]]
    ([0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0], True)
    """
    if not pieces:
        raise ArgumentError("pieces", "needs at least one spline")
    if len(pieces) == 1:
        return pieces[0]
    k = pieces[0].k + 1
    knots = [np.asarray(pieces[0].t)]
    coef = [np.asarray(pieces[0].c)]
    for n, piece in enumerate(pieces[1:], start=1):
        t, c = np.asarray(piece.t), np.asarray(piece.c)
        if piece.k + 1 != k or t[0] != knots[-1][-1] or not np.array_equal(c[0], coef[-1][-1]):
            raise ArgumentError("pieces", f"piece {n} does not start where piece {n - 1} ends, on its value")
        knots[-1] = knots[-1][:-1]
        knots.append(t[k:])
        coef.append(c[1:])
    return BSpline(np.concatenate(knots), np.concatenate(coef), k - 1)


def snapped(s: BSpline, x: float) -> float:
    """``x``, or the knot of ``s`` a hair away from it (within 1e-9 of the knot span or
    8 rounding units): a cut there must not leave an interval of a few rounding units,
    where a piece's end derivative is all cancellation.

    >>> s = BSpline(np.r_[[0.0] * 4, 0.5, [2.0] * 4], np.c_[[0.0, 1.0, 3.0, 2.0, 1.0]], 3)
    >>> snapped(s, 0.5 + 1e-16), snapped(s, 0.6)
    (0.5, 0.6)
    """
    j = int(np.argmin(np.abs(s.t - x)))
    near = max(1e-9 * (s.t[-1] - s.t[0]), 8 * np.spacing(abs(x)))
    return float(s.t[j]) if abs(s.t[j] - x) <= near else x


def split(s: BSpline, at: float) -> tuple[BSpline, BSpline]:
    """``s`` cut exactly at ``snapped(s, at)`` (inside its span) into two clamped
    pieces, undone by :func:`join` (knot insertion: each piece is ``s`` on its side, to
    rounding).

    >>> s = BSpline(np.r_[[0.0] * 4, [2.0] * 4], np.c_[[0.0, 1.0, 3.0, 2.0]], 3)
    >>> left, right = split(s, 0.5)
    >>> bool(np.allclose(left(0.25), s(0.25))), bool(np.allclose(right(1.5), s(1.5))), float(left.t[-1]), float(right.t[0])
    (True, True, 0.5, 0.5)
    """
    k = s.k + 1
    at = snapped(s, at)
    have = int(np.sum(np.asarray(s.t) == at))
    s = insert_knots(s, [at] * (k - have)) if have < k else s
    i = int(np.searchsorted(s.t, at, side="left"))
    c = np.asarray(s.c)
    return BSpline(s.t[: i + k], c[:i], k - 1), BSpline(s.t[i:], c[i:], k - 1)
