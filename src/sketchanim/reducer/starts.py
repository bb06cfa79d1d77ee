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
