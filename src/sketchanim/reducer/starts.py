"""Starting curves for knot removal.

* the paper's (section 2.2.4): the samples themselves are the control polygon, and the
  knots come from the sample times;
* Lyche-Morken's original: the piecewise-linear interpolant, reduced, then raised to
  the target degree (built in :mod:`.global_method`, which runs the reduction).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline, make_interp_spline

from sketchanim.reducer.approximate import Approximator
from sketchanim.spline import elevate_degree

#: Values the first and last coefficient keep, or None (see :class:`Approximator`).
Held = tuple[np.ndarray | None, np.ndarray | None]
FREE: Held = (None, None)


def sample_knots(times: np.ndarray, order: int) -> np.ndarray:
    """Knot vector with one coefficient per sample: end knots repeated ``order`` times,
    interior knots at sample times ``order // 2 .. n - order + order // 2 - 1``.

    Interpolation at the samples on these knots is well posed (Schoenberg-Whitney), and
    every knot is a sample time, so any subset of them keeps data under every B-spline.

    >>> sample_knots(np.arange(6.0), 4)
    array([0., 0., 0., 0., 2., 3., 5., 5., 5., 5.])
    """
    n = len(times)
    half = order // 2
    return np.concatenate([[times[0]] * order, times[half : n - order + half], [times[-1]] * order])


def polynomial_through(times: np.ndarray, values: np.ndarray, order: int) -> BSpline:
    """The polynomial of degree n - 1 through n < order samples, as a spline of ``order``.

    >>> s = polynomial_through(np.array([0.0, 1.0]), np.array([[1.0], [3.0]]), 4)
    >>> s.k, s(np.array([0.5])).round(12).tolist()
    (3, [[2.0]])
    """
    n = len(times)
    line = make_interp_spline(times, values, k=n - 1, t=np.r_[[times[0]] * n, [times[-1]] * n])
    return elevate_degree(line, order - n)


def interpolant(times: np.ndarray, values: np.ndarray, order: int) -> BSpline | None:
    """The spline of ``order`` through every sample, on :func:`sample_knots` (one
    coefficient per sample); ``None`` if the system is singular.

    >>> t = np.linspace(0, 1, 6); x = np.c_[np.sin(t)]
    >>> bool(np.allclose(interpolant(t, x, 4)(t), x))
    True
    """
    ap = Approximator(times, values, np.ones(values.shape[1]), order)
    fit = ap.fit(sample_knots(times, order))
    return None if fit is None else ap.spline(fit)


#: A held end may differ from its value by this many rounding units before it is set.
ROUNDING = 1e-9


def holding(spline: BSpline, held: Held) -> BSpline | None:
    """``spline`` with its end coefficients set exactly to the held values (each of
    ``held`` an array or None), or ``None`` if they are further from them than rounding
    (at the magnitude of the spline's coefficients).

    >>> s = holding(BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[1.0, 2.0 + 1e-15]], 1), (None, np.array([2.0])))
    >>> s.c[:, 0].tolist()
    [1.0, 2.0]
    """
    c = np.array(spline.c, dtype=float)
    # rounding at the magnitude the fit works in: a far sample moves its centre
    magnitude = np.abs(c).max(axis=0)
    for end, value in zip((0, -1), held):
        if value is not None:
            scale = np.maximum(1.0, np.maximum(np.abs(value), magnitude))
            if not np.all(np.abs(c[end] - value) <= ROUNDING * scale):
                return None
            c[end] = value
    return BSpline(spline.t, c, spline.k)


def held_interpolant(times: np.ndarray, values: np.ndarray, order: int, held: Held) -> BSpline | None:
    """A spline through every sample whose end coefficients are the held values (each
    within tolerance of its end sample): on :func:`sample_knots`, or the
    polynomial through the samples for fewer than ``order``. ``None`` if singular.

    >>> t = np.linspace(0, 1, 8); x = np.c_[t ** 2]
    >>> s = held_interpolant(t, x, 4, (np.array([0.001]), None))
    >>> float(s.c[0, 0]), bool(np.allclose(s(t[1:]), x[1:]))
    (0.001, True)
    """
    x = values.copy()
    for end, value in zip((0, -1), held):
        if value is not None:
            x[end] = value
    if len(times) < order:
        spline = polynomial_through(times, x, order)
    else:
        ap = Approximator(times, x, np.ones(x.shape[1]), order, held=held)
        fit = ap.fit(sample_knots(times, order))
        if fit is None:
            return None
        spline = ap.spline(fit)
    return holding(spline, held)
