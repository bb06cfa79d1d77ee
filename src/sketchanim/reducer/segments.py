"""The global method on a take cut at its pauses and breaks (:mod:`.features`).

Each piece between two features is reduced on its own, its ends held where it meets its
neighbours: at a break, both on the sample there; at a pause, both on the pause's value.
Pauses become constant pieces, and :func:`.splice.join` makes one spline of it all.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.reducer.features import Feature, FeatureOptions, detect
from sketchanim.reducer.global_method import GlobalLog, GlobalOptions, reduce_global
from sketchanim.reducer.metric import max_errors
from sketchanim.reducer.splice import hold, join
from sketchanim.reducer.starts import Held, held_interpolant, holding, polynomial_through


def _piece(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int, opts: GlobalOptions, angle: float,
           held: Held, log: GlobalLog) -> BSpline:
    """One piece between features, within tolerance and holding its ends if it can be."""
    bound = np.array([angle]) if angle else tol
    if len(times) >= order:
        spline, part = reduce_global(times, values, tol, order, opts, angle, held)
        log.iterations += part.iterations
        log.fits += part.fits
        if part.coarse_pass:
            log.coarse_pass = True
            # the least good outcome of any piece: "held" < "repaired" < "full pass"
            outcomes = ("held", "repaired", "full pass")
            log.coarse_outcome = max(log.coarse_outcome or "held", part.coarse_outcome or "held", key=outcomes.index)
        kept = holding(spline, held)
        if kept is not None and np.all(max_errors(kept(times), values, angle) <= bound):
            return kept
    # The caller's final check catches a miss here (and falls back to the interpolant);
    # whatever is returned starts and ends on the held values, so the pieces join.
    exact = held_interpolant(times, values, order, held)
    if exact is not None:
        return exact
    ends = values[[0, -1]].copy()
    for end, value in enumerate(held):
        if value is not None:
            ends[end] = value
    return polynomial_through(times[[0, -1]], ends, order)


def reduce_segmented(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int, opts: GlobalOptions,
                     angle: float, options: FeatureOptions) -> tuple[BSpline, list[Feature], GlobalLog]:
    """Find the take's features and reduce the pieces between them with the global
    method; the spline, the features, and the counts of the work done.

    >>> t = np.linspace(0, 2, 241)
    >>> x = np.c_[np.where(t < 1, np.sin(3 * t), np.sin(3.0))]     # moves, stops dead, holds
    >>> s, found, _ = reduce_segmented(t, x, np.array([1e-3]), 4, GlobalOptions(), 0.0, FeatureOptions())
    >>> [(f.kind, round(f.start, 3), f.end) for f in found]
    [('pause', 1.0, 2.0)]
    >>> still = t[t > found[0].start]                     # zero velocity, not a wobble
    >>> float(np.abs(s.derivative()(still)).max()), bool(np.abs(s(t) - x).max() <= 1e-3)
    (0.0, True)
    """
    pieces: list[BSpline] = []
    log = GlobalLog()
    part_t: list[np.ndarray] = []
    part_x: list[np.ndarray] = []
    left: np.ndarray | None = None
    pause: tuple[float, np.ndarray] | None = None

    def close(right: np.ndarray | None) -> None:
        nonlocal part_t, part_x
        t = np.concatenate(part_t) if part_t else np.zeros(0)
        if len(t) >= 2:
            pieces.append(_piece(t, np.concatenate(part_x), tol, order, opts, angle, (left, right), log))
        part_t, part_x = [], []

    ops, found = detect(times, values, tol, order, options, angle=angle)
    for op in ops:
        if op[0] == "samples":
            part_t.append(op[1])
            part_x.append(op[2])
        elif op[0] == "break":
            close(op[2])
            left = op[2]
        elif op[0] == "hold":
            close(op[2])
            pause = (op[1], op[2])
        else:
            assert pause is not None
            pieces.append(hold(pause[0], op[1], pause[1], order))
            left = pause[1]
    close(None)
    return join(pieces), found, log

