"""The global method: Lyche-Morken knot removal over the whole take, from either start.

For dense takes (far more samples than the curve will need knots) a coarse pass first
reduces an evenly thinned copy of the samples; its curve is then checked, and if need
be re-fitted, against every sample. Only if that fails does the full pass run. Either
way the answer is checked against all samples by the caller.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.reducer.approximate import Approximator
from sketchanim.reducer.lm import remove_knots
from sketchanim.reducer.starts import sample_knots
from sketchanim.spline import elevate_degree

STARTS = ("paper", "lm")


@dataclass(frozen=True)
class GlobalOptions:
    """Settings of the global method.

    Attributes
    ----------
    start : {"paper", "lm"}
        Starting curve: samples as control polygon (paper), or LM's reduced
        piecewise-linear interpolant raised to the target degree.
    split : float
        For ``start="lm"``: the linear pass gets ``split * tol``, the second pass the rest.
    minimax_iterations : int
        Lawson re-weightings when testing single knots (0: plain least squares).
    exhaustive_below : int
        Knot vectors this short try every removal count instead of bisecting.
    coarse_samples : int or None
        Thin takes longer than twice this to about this many samples for a first pass.
    """

    start: str = "paper"
    split: float = 0.1
    minimax_iterations: int = 8
    exhaustive_below: int = 32
    coarse_samples: int | None = 8192


@dataclass
class GlobalLog:
    """Counts for the report."""

    iterations: int = 0
    fits: int = 0
    coarse_pass: bool = False
    coarse_accepted: bool = False


def _paper(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int,
           opts: GlobalOptions, log: GlobalLog) -> BSpline:
    ap = Approximator(times, values, tol, order)
    knots = sample_knots(times, order)
    fit, run = remove_knots(ap, knots, ap.scaled, exhaustive_below=opts.exhaustive_below,
                            minimax_iterations=opts.minimax_iterations)
    log.iterations += run.iterations
    if fit is None:
        fit = ap.fit(knots)
    log.fits += ap.fits
    return ap.spline(fit)


def _lm(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int,
        opts: GlobalOptions, log: GlobalLog) -> BSpline:
    linear_knots = sample_knots(times, 2)
    linear = BSpline(linear_knots, values, 1)
    if opts.split > 0:
        linear = _paper(times, values, opts.split * tol, 2, opts, log)
    raised = elevate_degree(linear, order - 2)
    ap = Approximator(times, linear(times), (1.0 - opts.split) * tol, order)
    fit, run = remove_knots(ap, raised.t, (raised.c - ap.center) / ap.tol,
                            exhaustive_below=opts.exhaustive_below,
                            minimax_iterations=opts.minimax_iterations)
    log.iterations += run.iterations
    log.fits += ap.fits
    return raised if fit is None else ap.spline(fit)


def reduce_global(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int,
                  opts: GlobalOptions) -> tuple[BSpline, GlobalLog]:
    """Reduce checked samples (shape (n,), (n, d)) to a spline within ``tol`` of each.

    The caller verifies the guarantee on the returned spline.

    Examples
    --------
    >>> t = np.linspace(0, 1, 100)
    >>> x = np.c_[np.sin(2 * np.pi * t)]
    >>> spline, log = reduce_global(t, x, np.array([1e-3]), 4, GlobalOptions())
    >>> bool(np.abs(spline(t) - x).max() <= 1e-3), len(spline.c) < 20
    (True, True)
    """
    run = _paper if opts.start == "paper" else _lm
    log = GlobalLog()
    n = len(times)
    if opts.coarse_samples and n > 2 * opts.coarse_samples:
        log.coarse_pass = True
        step = -(-n // opts.coarse_samples)
        idx = np.unique(np.r_[np.arange(0, n, step), n - 1])
        coarse = run(times[idx], values[idx], tol, order, opts, log)
        if np.all(np.abs(coarse(times) - values) <= tol):
            log.coarse_accepted = True
            return coarse, log
        ap = Approximator(times, values, tol, order)
        fit = ap.fit(coarse.t, minimax_iterations=max(opts.minimax_iterations, 1))
        log.fits += ap.fits
        if fit is not None and fit.passes:
            log.coarse_accepted = True
            return ap.spline(fit), log
    return run(times, values, tol, order, opts, log), log
