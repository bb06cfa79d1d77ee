"""scipy's FITPACK smoothing spline with the smoothing factor bisected until the largest
error at the samples is within tolerance (sample times as parameters)."""

from __future__ import annotations

import time

import numpy as np
from scipy.interpolate import BSpline, make_splprep

from peers import PeerResult


def make_splprep_within(times: np.ndarray, values: np.ndarray, tol: np.ndarray, *, order: int = 4,
                        steps: int = 30) -> PeerResult:
    """Largest smoothing factor (bisected on a log scale) whose spline keeps every sample
    within ``tol``; channels are scaled to unit tolerance first."""
    clock = time.perf_counter()
    scaled = (values / tol).T
    n = len(times)
    def fit(s: float) -> tuple[BSpline, bool]:
        fitted, _ = make_splprep(scaled, u=times, k=order - 1, s=s)
        spline = BSpline(fitted.t, fitted.c, fitted.k)  # make_splprep's evaluates along axis 1
        ok = bool(np.abs(spline(times) - scaled.T).max() <= 1.0)
        return spline, ok

    best, _ = fit(0.0)
    lo, hi = np.log(1e-6 * n), np.log(float(n) * values.shape[1])
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        spline, ok = fit(float(np.exp(mid)))
        if ok:
            lo, best = mid, spline
        else:
            hi = mid
    seconds = time.perf_counter() - clock
    return PeerResult("scipy make_splprep (s bisected)", BSpline(best.t, best.c * tol, best.k), seconds)
