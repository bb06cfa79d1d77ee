"""Global Lyche-Morken knot removal (section 2.1 of the paper): rank, remove, approximate.

Each iteration ranks the interior knots of the current curve (:mod:`.rank`), then looks
for the shortest knot vector, among candidates built from that ranking, on which a
least-squares fit of the samples stays within tolerance (:mod:`.approximate`). The
error is always measured against the samples, never against the previous iterate.

Candidates, tried in this order until one has fewer knots than the current curve:

1. *spread*: ``m`` knots that share the total weight^(1/order) equally. A knot's
   removal weight grows like (spacing^order x the local derivative of that order), so
   weight^(1/order) / spacing is the knot density that equidistributes the error, the
   aim of LM's grouping of equal-weight knots. The knots are re-placed among all the
   starting knot positions (the sample times), not only the surviving ones, so the
   first, coarse guess is corrected once the curve's weights become informative. The
   smallest passing ``m`` is found by galloping and bisection.
2. *lowest*: drop the ``r`` knots with the lowest keys (weight / the room the current
   fit leaves near the knot), never two neighbours in one round, the largest ``r``
   that passes (bisection for long knot vectors; counts 1, 2, ... for short ones, as
   2.2.1 argues).
3. *single*: knots one at a time, lowest first (at most ``exhaustive_below`` or an
   eighth of the knots per round, skipping knots that failed while nothing near them
   changed), each kept out if the curve still passes without it and those already out.
   Short knot vectors re-fit globally with Lawson re-weighting (a near-minimax fit), so
   that knots go that a plain least-squares fit would keep; long ones re-fit only the
   coefficients near the knot, and check only the samples those act on.

The loop stops when no candidate removes a knot.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sketchanim.reducer.approximate import Approximator, Fit
from sketchanim.reducer.rank import removal_weights

#: Knots removed in one round of the *lowest* family are at least this many places apart.
SEPARATION = 2
#: Removal weights below this many rounding units of the largest coefficient are noise.
ROUNDING_UNITS = 64


@dataclass
class RemovalLog:
    """What one run of the loop did: iterations (rounds that removed knots), fits solved."""

    iterations: int = 0
    fits: int = 0


def _slack(times: np.ndarray, knots: np.ndarray, order: int, residual: np.ndarray) -> np.ndarray:
    """Per interior knot j, the least slack (1 - error, in tolerances) of the current fit
    over the samples that the coefficients changed by removing j act on."""
    j = np.arange(order, len(knots) - order)
    lo = np.searchsorted(times, knots[j - order], side="left")
    hi = np.searchsorted(times, knots[j + order], side="right")
    slack = 1.0 - residual
    bounds = np.stack([lo, np.maximum(hi, lo + 1)], axis=1).ravel()
    bounds = np.minimum(bounds, len(times))
    padded = np.r_[slack, np.inf]
    return np.minimum.reduceat(padded, bounds)[::2]


class _Candidates:
    """Knot vectors derived from one ranking of the current curve."""

    def __init__(self, ap: Approximator, knots: np.ndarray, weights: np.ndarray, pool: np.ndarray,
                 residual: np.ndarray | None) -> None:
        self.ap = ap
        self.order = ap.order
        self.ends = (knots[: self.order], knots[len(knots) - self.order :])
        self.inner = knots[self.order : len(knots) - self.order]
        self.weights = weights
        self.pool = pool
        # Removal order: how far removing a knot moves the curve, against the room the
        # current fit leaves there (without a fit yet, all the tolerance is room).
        if residual is None:
            self.keys = self.weights
        else:
            room = _slack(ap.times, knots, self.order, residual)
            self.keys = self.weights / np.maximum(room, 1e-12)

    def _test(self, inner: np.ndarray, minimax: int = 0) -> Fit | None:
        fit = self.ap.fit(np.concatenate([self.ends[0], inner, self.ends[1]]), minimax_iterations=minimax)
        return fit if fit is not None and fit.passes else None

    def _spread_inner(self, m: int) -> np.ndarray:
        """m knots from the pool, equidistributing weight^(1/order) over time."""
        if m <= 0 or self.pool.size == 0:
            return np.zeros(0)
        u = self.inner
        share = np.minimum(self.weights, 1e300) ** (1.0 / self.order)
        if not share.sum() > 0:
            share = np.ones_like(share)
        # Each knot's share is spread evenly between the midpoints to its neighbours.
        lo_end, hi_end = self.ends[0][-1], self.ends[1][0]
        edges = np.concatenate([[lo_end], 0.5 * (u[1:] + u[:-1]), [hi_end]])
        mass = np.concatenate([[0.0], np.cumsum(share)])
        pool_mass = np.interp(self.pool, edges, mass)
        targets = (np.arange(m) + 0.5) / m * mass[-1]
        picks = np.clip(np.searchsorted(pool_mass, targets), 0, self.pool.size - 1)
        return self.pool[np.unique(picks)]

    def spread(self, gallop_up: bool) -> Fit | None:
        n = len(self.inner)
        cache: dict[int, Fit | None] = {}

        def passes(m: int) -> bool:
            if m not in cache:
                cache[m] = self._test(self._spread_inner(m))
            return cache[m] is not None

        # Bracket the smallest passing m in (fail, ok], then bisect.
        if gallop_up:
            fail, step, ok = -1, 1, None
            m = 0
            while m < n:
                if passes(m):
                    ok = m
                    break
                fail, m = m, m + step
                step *= 2
            if ok is None:
                return None
        else:
            ok, step, fail = None, 1, -1
            m = n - 1
            while m >= 0:
                if not passes(m):
                    fail = m
                    break
                ok, m = m, m - step
                step *= 2
            if ok is None:
                return None
        while ok - fail > 1:
            mid = (ok + fail) // 2
            if passes(mid):
                ok = mid
            else:
                fail = mid
        return cache[ok]

    def lowest(self, exhaustive_below: int) -> Fit | None:
        # Lowest weights first, skipping the neighbours of knots already picked, so each
        # removal's local change is measured on a curve its neighbours still hold.
        picked: list[int] = []
        taken = np.zeros(len(self.weights) + 2, dtype=bool)
        for j in np.argsort(self.keys, kind="stable"):
            if not taken[j - SEPARATION + 1 : j + SEPARATION + 2].any():
                picked.append(int(j))
                taken[j + 1] = True
        order = np.asarray(picked, dtype=np.intp)
        n = len(order)

        def removing(r: int) -> Fit | None:
            return self._test(np.delete(self.inner, order[:r]))

        best = None
        if n <= exhaustive_below:
            for r in range(1, n + 1):
                fit = removing(r)
                if fit is None:
                    break
                best = fit
            return best
        # Bisect for the largest passing count, once the smallest one is known to pass.
        best = removing(1)
        lo, hi = (1, n) if best is not None else (0, 0)
        while lo < hi:
            mid = (lo + hi + 1) // 2
            fit = removing(mid)
            if fit is not None:
                lo, best = mid, fit
            else:
                hi = mid - 1
        return best

    def single(self, base: Fit | None, limit: int, minimax: int,
               failed: np.ndarray) -> tuple[Fit | None, np.ndarray]:
        """Try knots one at a time, lowest key first, skipping the values in ``failed``,
        keeping each removal that still passes with those kept before it.

        Short knot vectors re-fit globally (with ``minimax`` Lawson steps); long ones,
        given the current ``base`` fit, re-fit only around the knot.
        Returns the last passing fit and the knot values whose removal failed.
        """
        ranked = np.argsort(self.keys, kind="stable")
        ranked = ranked[~np.isin(self.inner[ranked], failed)][:limit]
        local = base is not None and minimax == 0
        removed: list[int] = []
        misses: list[float] = []
        best = base if local else None
        for j in ranked:
            if local:
                assert best is not None
                # the knot's index in the current vector (last of equal values)
                index = int(np.searchsorted(best.knots, self.inner[j], side="right")) - 1
                fit = self.ap.without_knot(best, index)
            else:
                fit = self._test(np.delete(self.inner, removed + [int(j)]), minimax)
            if fit is not None:
                removed.append(int(j))
                best = fit
            else:
                misses.append(float(self.inner[j]))
        return (best if removed else None), np.asarray(misses)


def _still_failed(failed: np.ndarray, old_inner: np.ndarray, new_inner: np.ndarray, order: int) -> np.ndarray:
    """Failed knot values whose neighbourhood (``order`` knots either side) lost no knot."""
    gone = np.flatnonzero(~np.isin(old_inner, new_inner))
    if gone.size == 0 or failed.size == 0:
        return failed
    lo = old_inner[np.maximum(gone - order, 0)]
    hi = old_inner[np.minimum(gone + order, len(old_inner) - 1)]
    near = np.zeros(len(failed), dtype=bool)
    pos = np.searchsorted(lo, failed, side="right") - 1
    ok = pos >= 0
    # Intervals are sorted, so the last one starting at or before a value reaches furthest.
    near[ok] = failed[ok] <= hi[pos[ok]]
    return failed[~near]


def remove_knots(
    ap: Approximator,
    knots: np.ndarray,
    rank_coef: np.ndarray,
    *,
    exhaustive_below: int = 32,
    minimax_iterations: int = 8,
    pool: np.ndarray | None = None,
    start: Fit | None = None,
) -> tuple[Fit | None, RemovalLog]:
    """Run rank / remove / approximate until no knot can go.

    Parameters
    ----------
    ap : Approximator
        The samples and tolerance every candidate is checked against.
    knots : ndarray
        Starting knot vector; its distinct interior values are where knots may be placed.
    rank_coef : ndarray, shape (K, d)
        Coefficients of the starting curve in tolerance units (ranked in iteration 0).
    exhaustive_below : int
        Knot vectors with at most this many interior knots try removal counts one by one
        and fit single-knot removals globally with Lawson re-weighting; it is also the
        least number of single knots tried per round.
    minimax_iterations : int
        Lawson re-weightings in the single-knot stage (0 for plain least squares).
    pool : ndarray, optional
        Where spread knots may be placed (default: the distinct interior knots given).
    start : Fit, optional
        A passing fit on ``knots`` (with ``rank_coef`` its coefficients) to improve on:
        its residuals guide the first round, which then looks for small changes.

    Returns
    -------
    (Fit or None, RemovalLog)
        The last passing fit (``None`` if no candidate ever passed) and the log.

    Examples
    --------
    >>> t = np.linspace(0, 1, 200)
    >>> ap = Approximator(t, np.c_[t ** 3 - t], np.array([1e-6]), order=4)
    >>> knots = np.r_[[0.0] * 4, t[2:-2], [1.0] * 4]
    >>> fit, log = remove_knots(ap, knots, ap.scaled)
    >>> len(fit.coef)          # a cubic needs no interior knot
    4
    """
    order = ap.order
    if pool is None:
        pool = np.unique(knots[order : len(knots) - order])
    log = RemovalLog()
    fits_before = ap.fits
    best = start
    coef = rank_coef
    failed = np.zeros(0)
    while len(knots) > 2 * order:
        # Weights at rounding level (flat stretches) are set to zero, so that their order
        # is by position and the same at any magnitude.
        weights = removal_weights(knots, coef, order)
        floor = ROUNDING_UNITS * np.finfo(float).eps * np.abs(coef).max(initial=0.0)
        weights[weights <= floor] = 0.0
        candidates = _Candidates(ap, knots, weights, pool, None if best is None else best.residual)
        fit = candidates.spread(gallop_up=best is None)
        if fit is None:
            fit = candidates.lowest(exhaustive_below)
        if fit is None:
            short = len(knots) - 2 * order <= exhaustive_below
            limit = max(exhaustive_below, (len(knots) - 2 * order) // 8)
            fit, misses = candidates.single(best, limit, minimax_iterations if short else 0, failed)
            failed = np.union1d(failed, misses)
        if fit is None:
            break
        failed = _still_failed(failed, candidates.inner, fit.knots[order : len(fit.knots) - order], order)
        best, knots, coef = fit, fit.knots, fit.coef
        log.iterations += 1
    log.fits = ap.fits - fits_before
    return best, log
