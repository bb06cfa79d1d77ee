"""The *approximate* step: weighted discrete least squares of the samples on a knot vector.

The normal equations of a B-spline fit are banded (bandwidth = order), so each fit costs
O(n * order^2) to assemble from scipy's sparse design matrix and O(K * order^2) to solve
with LAPACK's banded Cholesky (``scipy.linalg.solveh_banded``); nothing N x N is formed.

The error is always measured against the fitted samples themselves, in units of the
tolerance. When a plain fit misses the tolerance by a little, Lawson's iteration
re-weights the samples where the error is largest, which moves the least-squares fit
towards the minimax (L-infinity) one and lets knots go that a plain fit would keep.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline
from scipy.linalg import LinAlgError, solveh_banded
from scipy.sparse import csr_array

from sketchanim.reducer.metric import rotation_angle

#: A fit passes when every scaled error is at most this (a hair under one tolerance,
#: so that rounding in the final evaluation cannot push a sample over).
PASS = 1.0 - 1e-9


@dataclass(frozen=True)
class Fit:
    """A least-squares spline on one knot vector.

    Attributes
    ----------
    knots : ndarray, shape (K + order,)
    coef : ndarray, shape (K, d)
        Coefficients in tolerance units, around the samples' centre.
    error : float
        Largest error over all samples, in tolerances: |fit - sample| / tol over
        channels, or the rotation angle over ``angle`` (see :class:`Approximator`).
    residual : ndarray, shape (n,)
        Per sample, that error.
    """

    knots: np.ndarray
    coef: np.ndarray
    error: float
    residual: np.ndarray

    @property
    def passes(self) -> bool:
        """Whether every sample is within tolerance."""
        return self.error <= PASS


class Approximator:
    """Least-squares fits of fixed samples on candidate knot vectors.

    Parameters
    ----------
    times : ndarray, shape (n,)
        Increasing sample times.
    values : ndarray, shape (n, d)
        Values to approximate.
    tol : ndarray, shape (d,)
        Tolerance per channel; errors are reported in these units.
    order : int
        Spline order.
    angle : float
        If > 0, the values are quaternions and the error of a sample is the rotation
        angle of the fit's normalised value from it, in units of ``angle`` (radians);
        ``tol`` then only scales the least squares.
    held : (array_like or None, array_like or None)
        Values (caller's units, shape (d,)) that the first and the last coefficient keep
        in every fit, or None for a free end: where a take cut at a pause or a break
        meets the piece before or after (:mod:`.splice`).

    Examples
    --------
    >>> t = np.linspace(0, 1, 50)
    >>> ap = Approximator(t, np.c_[np.sin(3 * t)], np.array([0.01]), order=4)
    >>> fit = ap.fit(np.r_[[0.0] * 4, 0.5, [1.0] * 4])
    >>> fit.passes, fit.coef.shape
    (True, (5, 1))
    """

    def __init__(self, times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int, *,
                 angle: float = 0.0, held: tuple[ArrayLike | None, ArrayLike | None] = (None, None)) -> None:
        self.times = np.asarray(times, dtype=float)
        self.order = order
        self.angle = angle
        self.tol = np.asarray(tol, dtype=float)
        self.center = 0.5 * (values.min(axis=0) + values.max(axis=0))
        self.values = np.asarray(values, dtype=float)
        self.scaled = (self.values - self.center) / self.tol
        #: (coefficient index, scaled value) of each held end
        self.held = [(end, (np.asarray(v, dtype=float) - self.center) / self.tol)
                     for end, v in zip((0, -1), held) if v is not None]
        self.fits = 0

    def fit(self, knots: ArrayLike, *, minimax_iterations: int = 0, minimax_reach: float = 1.5) -> Fit | None:
        """Fit on ``knots``; ``None`` if the knots leave a coefficient without data.

        Parameters
        ----------
        knots : array_like
            Knot vector whose interior knots the samples support.
        minimax_iterations : int
            Lawson re-weightings to try when the plain fit misses the tolerance.
        minimax_reach : float
            Only re-weight when the plain fit's error is at most this (in tolerances).
        """
        kn = np.asarray(knots, dtype=float)
        design = BSpline.design_matrix(self.times, kn, self.order - 1, extrapolate=True)
        weights = np.ones(len(self.times))
        best: Fit | None = None
        for _ in range(minimax_iterations + 1):
            self.fits += 1
            try:
                coef = self._solve(design, weights, len(kn) - self.order)
            except LinAlgError:
                return best
            per_sample = self._deviation(design @ coef, slice(None))
            error = float(per_sample.max())
            if best is None or error < best.error:
                best = Fit(kn, coef, error, per_sample)
            if best.passes or best.error > minimax_reach:
                break
            weights = weights * np.maximum(per_sample, 1e-3 * error)
            weights *= len(weights) / weights.sum()
        return best

    def without_knot(self, fit: Fit, index: int, radius: int | None = None) -> Fit | None:
        """``fit`` with knot ``fit.knots[index]`` removed, re-fitting only nearby coefficients.

        Removing a knot changes only the B-splines around it, so only the ``radius``
        (default: the order) coefficients on either side of them are re-fitted, by least
        squares on the samples they act on, with the others held. Those samples are
        checked; every other sample keeps its value. ``None`` if the local problem has
        too little data or the result misses the tolerance.
        """
        k = self.order
        r = k if radius is None else radius
        knots = np.delete(fit.knots, index)
        n_coef = len(knots) - k
        # New coefficient i is old i (i < index - k) or old i + 1 (i >= index); the k in
        # between, and `r` more on either side, are re-fitted.
        coef = np.delete(fit.coef, index - k, axis=0)
        for end, value in self.held:
            coef[end] = value
        lo = max(index - k - r, 1 if self._holds(0) else 0)
        hi = min(index - 1 + r, n_coef - (2 if self._holds(-1) else 1))
        if hi < lo:
            return None
        s0 = np.searchsorted(self.times, knots[lo], side="left")
        s1 = np.searchsorted(self.times, knots[hi + k], side="right")
        if s1 - s0 < hi - lo + 1:
            return None
        self.fits += 1
        # B-splines depend only on their own knots: the local span gives the same basis
        # for every coefficient that acts on these samples (columns first .. ).
        first = max(lo - k + 1, 0)
        design = BSpline.design_matrix(self.times[s0:s1], knots[first : min(hi + 2 * k, len(knots))],
                                       k - 1, extrapolate=True).toarray()
        local = coef[first : first + design.shape[1]]
        free = slice(lo - first, hi - first + 1)
        target = self.scaled[s0:s1] - design @ local + design[:, free] @ local[free]
        solution, _, rank, _ = np.linalg.lstsq(design[:, free], target, rcond=None)
        if rank < hi - lo + 1:
            return None
        coef[lo : hi + 1] = solution
        resid = self._deviation(design @ coef[first : first + design.shape[1]], slice(s0, s1))
        if resid.max() > PASS:
            return None
        residual = fit.residual.copy()
        residual[s0:s1] = resid
        return Fit(knots, coef, float(residual.max()), residual)

    def _holds(self, end: int) -> bool:
        return any(e == end for e, _ in self.held)

    def _deviation(self, fitted: np.ndarray, rows: slice) -> np.ndarray:
        """Per sample of ``rows``, how far the scaled ``fitted`` values are from it, in
        tolerances: the largest channel difference, or the rotation angle over ``angle``."""
        if self.angle > 0:
            return rotation_angle(fitted * self.tol + self.center, self.values[rows]) / self.angle
        return np.abs(fitted - self.scaled[rows]).max(axis=1)

    def spline(self, fit: Fit) -> BSpline:
        """The fit as a spline in the caller's units."""
        return BSpline(fit.knots, fit.coef * self.tol + self.center, self.order - 1)

    def _solve(self, design: csr_array, weights: np.ndarray, n_coef: int) -> np.ndarray:
        # `design` is scipy's CSR design matrix: row i holds the `order` non-zero basis
        # values of sample i, in consecutive columns from first[i]. Samples are sorted, so
        # rows sharing a first column are contiguous and summed with one reduceat.
        k = self.order
        first = design.indices[::k]
        basis = design.data.reshape(-1, k)
        starts = np.flatnonzero(np.r_[True, first[1:] != first[:-1]])
        weighted = basis * weights[:, None]
        # Sums over each knot interval (indexed by its first coefficient), zero where an
        # interval holds no sample, so the bands below are contiguous slice additions.
        intervals = n_coef - k + 1
        gram = np.zeros((intervals, k, k))
        gram[first[starts]] = np.add.reduceat(np.einsum("na,nb->nab", weighted, basis), starts, axis=0)
        moments = np.zeros((intervals, k, self.scaled.shape[1]))
        moments[first[starts]] = np.add.reduceat(np.einsum("na,nd->nad", weighted, self.scaled), starts, axis=0)
        # Upper banded form for solveh_banded: ab[k-1-d, j] = N[j-d, j].
        ab = np.zeros((k, n_coef))
        rhs = np.zeros((n_coef, self.scaled.shape[1]))
        for a in range(k):
            rhs[a : a + intervals] += moments[:, a]
            for d in range(k - a):
                ab[k - 1 - d, a + d : a + d + intervals] += gram[:, a, a + d]
        for end, value in self.held:
            # Coefficient j is known: move its column to the right-hand side and leave
            # the equation coef[j] = value in its place.
            j = end % n_coef
            for d in range(1, k):
                if j - d >= 0:
                    rhs[j - d] -= ab[k - 1 - d, j] * value
                    ab[k - 1 - d, j] = 0.0
                if j + d < n_coef:
                    rhs[j + d] -= ab[k - 1 - d, j + d] * value
                    ab[k - 1 - d, j + d] = 0.0
            ab[k - 1, j] = 1.0
            rhs[j] = value
        return solveh_banded(ab, rhs, check_finite=False)
