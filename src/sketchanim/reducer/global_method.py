"""The global method: Lyche-Morken knot removal over the whole take, from either start.

For dense takes (far more samples than the curve will need knots) a coarse pass first
reduces an evenly thinned copy of the samples; its curve is then checked against every
sample, and where it misses (noise extremes the thinned copy did not hold), knots are
added at those samples, the curve re-fitted on all samples, and the removal loop run
again from there. Only if that repair fails does the full pass run. Either way the
answer is checked against all samples by the caller.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.reducer.approximate import PASS, Approximator, Fit
from sketchanim.reducer.lm import remove_knots
from sketchanim.reducer.metric import max_errors
from sketchanim.reducer.starts import FREE, Held, interpolant, sample_knots
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
    #: how a coarse pass ended: "held" (its curve held at every sample), "repaired",
    #: or "full pass" (the repair failed and all samples were reduced from the start)
    coarse_outcome: str | None = None


def _remove(ap: Approximator, knots: np.ndarray, coef: np.ndarray, opts: GlobalOptions, log: GlobalLog,
            pool: np.ndarray | None = None, start: Fit | None = None) -> Fit | None:
    """:func:`remove_knots` with these options, its rounds counted in ``log``."""
    fit, run = remove_knots(ap, knots, coef, exhaustive_below=opts.exhaustive_below,
                            minimax_iterations=opts.minimax_iterations, pool=pool, start=start)
    log.iterations += run.iterations
    return fit


def _paper(times: np.ndarray, values: np.ndarray, tol: np.ndarray, angle: float, order: int,
           opts: GlobalOptions, log: GlobalLog, held: Held) -> BSpline:
    ap = Approximator(times, values, tol, order, angle=angle, held=held)
    knots = sample_knots(times, order)
    fit = _remove(ap, knots, ap.scaled, opts, log)
    if fit is None:
        fit = ap.fit(knots)
    log.fits += ap.fits
    if fit is None:
        # the start itself is singular in floating point (a high order): the samples
        # as control polygon, for the caller's final check to judge
        return BSpline(knots, values.copy(), order - 1)
    return ap.spline(fit)


def _lm(times: np.ndarray, values: np.ndarray, tol: np.ndarray, angle: float, order: int,
        opts: GlobalOptions, log: GlobalLog, held: Held) -> BSpline:
    linear_knots = sample_knots(times, 2)
    linear = BSpline(linear_knots, values, 1)
    if opts.split > 0:
        linear = _paper(times, values, opts.split * tol, opts.split * angle, 2, opts, log, FREE)
    raised = elevate_degree(linear, order - 2)
    ap = Approximator(times, linear(times), (1.0 - opts.split) * tol, order, angle=(1.0 - opts.split) * angle,
                      held=held)
    fit = _remove(ap, raised.t, (raised.c - ap.center) / ap.tol, opts, log)
    log.fits += ap.fits
    result = raised if fit is None else ap.spline(fit)
    # The raised linear curve has order - 1 coefficients per piece: never return more
    # coefficients than samples when the samples' own interpolant needs one each.
    if len(result.c) > len(times):
        result = interpolant(times, values, order) or result
    return result


def _repair(coarse: BSpline, times: np.ndarray, values: np.ndarray, tol: np.ndarray, angle: float, order: int,
            opts: GlobalOptions, log: GlobalLog, held: Held, rounds: int = 32) -> BSpline | None:
    """Make the coarse pass's curve hold at every sample: refine the knots where it
    misses and re-fit, a few rounds; then remove what is not needed.
    ``None`` if it still misses."""
    ap = Approximator(times, values, tol, order, angle=angle, held=held)
    pool = np.unique(sample_knots(times, order)[order:-order])
    knots = coarse.t
    fit = None
    for _ in range(rounds):
        fit = ap.fit(knots)
        if fit is None or fit.passes:
            break
        # Halve the knot intervals holding a miss and their neighbours (at the nearest
        # sample time), so the spacing there shrinks each round until the curve follows.
        breaks = np.unique(knots)
        hit = np.searchsorted(breaks, times[fit.residual > PASS], side="right") - 1
        hit = np.unique(np.clip(np.concatenate([hit - 1, hit, hit + 1]), 0, len(breaks) - 2))
        middles = 0.5 * (breaks[hit] + breaks[hit + 1])
        nearest = pool[np.clip(np.searchsorted(pool, middles), 0, len(pool) - 1)]
        extra = np.setdiff1d(nearest, knots)
        if extra.size == 0:
            break
        knots = np.sort(np.concatenate([knots, extra]))
    if fit is None or not fit.passes:
        log.fits += ap.fits
        return None
    fit = _remove(ap, fit.knots, fit.coef, opts, log, pool=pool, start=fit)
    log.fits += ap.fits
    return ap.spline(fit)


def reduce_global(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int,
                  opts: GlobalOptions, angle: float = 0.0, held: Held = FREE) -> tuple[BSpline, GlobalLog]:
    """Reduce checked samples (shape (n,), (n, d)) to a spline within ``tol`` of each.

    With ``angle > 0`` the four channels are quaternions and each sample's rotation is
    kept within ``angle`` radians instead (:mod:`.metric`); ``tol`` then scales the fit.
    ``held`` asks every fit to keep its first and last coefficient at the given values
    (to rounding; None for a free end). The caller verifies the guarantee on the
    returned spline.

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
        coarse = run(times[idx], values[idx], tol, angle, order, opts, log, held)
        if np.all(max_errors(coarse(times), values, angle) <= (angle or tol)):
            log.coarse_outcome = "held"
            return coarse, log
        repaired = _repair(coarse, times, values, tol, angle, order, opts, log, held)
        if repaired is not None:
            log.coarse_outcome = "repaired"
            return repaired, log
        log.coarse_outcome = "full pass"
    return run(times, values, tol, angle, order, opts, log, held), log
