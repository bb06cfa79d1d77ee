"""scipy's FITPACK smoothing spline with the smoothing factor bisected until the largest
error at the samples is within tolerance (sample times as parameters).

FITPACK can take many minutes on a long noisy take, so the search runs in a child
process with a wall-clock limit; past it, :class:`PeerTimeout` is raised.
"""

from __future__ import annotations

import multiprocessing
import time

import numpy as np
from scipy.interpolate import BSpline, make_splprep

from peers import PeerResult


class PeerTimeout(RuntimeError):
    """The peer did not finish within ``limit_s`` seconds."""

    def __init__(self, limit_s: float) -> None:
        self.limit_s = limit_s
        super().__init__(f"did not finish within {limit_s:g} s")


def _search(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int, steps: int) -> BSpline:
    scaled = (values / tol).T
    n = len(times)

    def fit(s: float) -> tuple[BSpline, bool]:
        fitted, _ = make_splprep(scaled, u=times, k=order - 1, s=s)
        spline = BSpline(fitted.t, fitted.c, fitted.k)  # make_splprep's evaluates along axis 1
        return spline, bool(np.abs(spline(times) - scaled.T).max() <= 1.0)

    best, _ = fit(0.0)
    lo, hi = np.log(1e-6 * n), np.log(float(n) * values.shape[1])
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        spline, ok = fit(float(np.exp(mid)))
        if ok:
            lo, best = mid, spline
        else:
            hi = mid
    return BSpline(best.t, best.c * tol, best.k)


def _child(conn, *args) -> None:  # type: ignore[no-untyped-def]
    spline = _search(*args)
    conn.send((spline.t, spline.c, spline.k))
    conn.close()


def make_splprep_within(times: np.ndarray, values: np.ndarray, tol: np.ndarray, *, order: int = 4,
                        steps: int = 30, limit_s: float = 120.0) -> PeerResult:
    """Largest smoothing factor (bisected on a log scale) whose spline keeps every sample
    within ``tol``; channels are scaled to unit tolerance first. The time is the whole
    search's. Raises :class:`PeerTimeout` past ``limit_s`` seconds."""
    clock = time.perf_counter()
    receive, send = multiprocessing.get_context("fork").Pipe(duplex=False)
    child = multiprocessing.get_context("fork").Process(
        target=_child, args=(send, times, values, tol, order, steps), daemon=True)
    child.start()
    send.close()
    try:
        if not receive.poll(limit_s):
            raise PeerTimeout(limit_s)
        t, c, k = receive.recv()
    finally:
        if child.is_alive():
            child.kill()
        child.join()
    return PeerResult("scipy make_splprep (s bisected)", BSpline(t, c, k), time.perf_counter() - clock)
