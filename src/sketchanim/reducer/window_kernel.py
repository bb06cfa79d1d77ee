"""Compiled kernel of the incremental reducer: rank / remove / approximate in one window.

One window of the incremental method (paper, section 2.2) is a small problem: a few
dozen knots and the samples under them. Done with numpy and scipy calls, the overhead
of each call (a few microseconds, dozens of calls per fit, several fits per window) is
what costs, not the arithmetic; so the whole window runs in one function compiled by
numba. Numba cannot call scipy's ``BSpline``, so the kernel carries its own basis
evaluation (de Boor's triangle, tested against ``BSpline.design_matrix``) and a banded
Cholesky solve of the normal equations (tested against ``scipy.linalg.solveh_banded``).

Conventions of every function here: ``T`` is a local knot vector whose coefficient ``i``
belongs to the B-spline on ``T[i] .. T[i + k]``; values ``xs`` are already divided by
the tolerance, so every error is in tolerances and passes at :data:`PASS`; ``lim`` is a
per-sample factor on the tolerance (1, or less where the window keeps slack).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from sketchanim.reducer.approximate import PASS

#: Lawson re-weighting only starts when a fit misses by at most this (in tolerances).
MINIMAX_REACH = 1.5
#: Swing a removal may add on an interval, in tolerances (rounding of the evaluation).
SWING_SLACK = 1e-7
#: Knots whose removal weight is above this (in tolerances) are not tried: the window's
#: refit seldom absorbs them, and trying costs a fit each (measured by bench_stream).
WEIGHT_REACH = 2.5


@njit(cache=True, error_model="numpy")
def basis_values(T: np.ndarray, k: int, span: int, x: float, out: np.ndarray, scratch: np.ndarray) -> None:
    """Values at ``x`` of the ``k`` B-splines ``span - k + 1 .. span`` (``T[span] <= x <
    T[span + 1]``), written to ``out``; ``scratch`` is (2, k) workspace."""
    left = scratch[0]
    right = scratch[1]
    out[0] = 1.0
    for j in range(1, k):
        left[j] = x - T[span + 1 - j]
        right[j] = T[span + j] - x
        saved = 0.0
        for r in range(j):
            temp = out[r] / (right[r + 1] + left[j - r])
            out[r] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        out[j] = saved


@njit(cache=True, error_model="numpy")
def design(T: np.ndarray, k: int, ts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Spans and basis values of sorted times ``ts`` on ``T`` (clamped at both ends):
    ``first[s]`` is the index of the first non-zero B-spline at ``ts[s]`` and
    ``rows[s]`` the ``k`` values from there."""
    n = len(ts)
    rows = np.empty((n, k))
    first = np.empty(n, dtype=np.int64)
    scratch = np.empty((2, k))
    last_span = len(T) - k - 1
    span = k - 1
    for s in range(n):
        while span < last_span and T[span + 1] <= ts[s]:
            span += 1
        basis_values(T, k, span, ts[s], rows[s], scratch)
        first[s] = span - k + 1
    return first, rows


@njit(cache=True, error_model="numpy")
def evaluate(first: np.ndarray, rows: np.ndarray, coef: np.ndarray) -> np.ndarray:
    """The curve at the samples of :func:`design`'s ``first`` and ``rows``, shape (n, d)."""
    out = np.zeros((len(first), coef.shape[1]))
    for s in range(len(first)):
        for r in range(rows.shape[1]):
            for c in range(coef.shape[1]):
                out[s, c] += rows[s, r] * coef[first[s] + r, c]
    return out


@njit(cache=True, error_model="numpy")
def scaled_rotation_angle(v: np.ndarray, x: np.ndarray, scale: np.ndarray, center: np.ndarray) -> float:
    """Rotation angle (radians) between the quaternions ``center + scale * v`` and
    ``center + scale * x`` (any norm, either sign): twice the angle between the lines
    they span. The sine comes from Lagrange's identity, exact for small angles."""
    dot = 0.0
    cross2 = 0.0
    for i in range(4):
        p_i = center[i] + scale[i] * v[i]
        q_i = center[i] + scale[i] * x[i]
        dot += p_i * q_i
        for j in range(i + 1, 4):
            w = p_i * (center[j] + scale[j] * x[j]) - (center[j] + scale[j] * v[j]) * q_i
            cross2 += w * w
    return 2.0 * np.arctan2(np.sqrt(cross2), abs(dot))


@njit(cache=True, error_model="numpy")
def solve_banded_spd(band: np.ndarray, rhs: np.ndarray) -> bool:
    """Solve ``M x = rhs`` in place for symmetric positive definite ``M`` of bandwidth
    ``k`` held as ``band[i, i - j] = M[i, j]`` (``0 <= i - j < k``); ``band`` becomes its
    Cholesky factor. False if ``M`` is not numerically positive definite."""
    n, k = band.shape
    for i in range(n):
        for j in range(max(0, i - k + 1), i + 1):
            s = band[i, i - j]
            for m in range(max(0, i - k + 1), j):
                s -= band[i, i - m] * band[j, j - m]
            if i == j:
                if not s > 1e-12 * band[i, 0]:    # band[i, 0] still holds M[i, i]
                    return False
                band[i, 0] = np.sqrt(s)
            else:
                band[i, i - j] = s / band[j, 0]
    d = rhs.shape[1]
    for i in range(n):
        for c in range(d):
            s = rhs[i, c]
            for m in range(max(0, i - k + 1), i):
                s -= band[i, i - m] * rhs[m, c]
            rhs[i, c] = s / band[i, 0]
    for i in range(n - 1, -1, -1):
        for c in range(d):
            s = rhs[i, c]
            for m in range(i + 1, min(n, i + k)):
                s -= band[m, m - i] * rhs[m, c]
            rhs[i, c] = s / band[i, 0]
    return True


@njit(cache=True, error_model="numpy")
def fit(T: np.ndarray, k: int, coef: np.ndarray, f0: int, f1: int, ts: np.ndarray, xs: np.ndarray,
        lim: np.ndarray, weights: np.ndarray, resid: np.ndarray, metric: tuple) -> float:
    """Least-squares fit of ``coef[f0:len(coef) - f1]`` to the samples with the first
    ``f0`` and the last ``f1`` coefficients held.

    Writes the coefficients into ``coef`` and each sample's error in tolerances,
    divided by its ``lim``, into ``resid``; returns the largest such ratio (``inf`` when
    the free coefficients are not determined by the samples). ``metric`` is ``(angle,
    scale, center)``: with ``angle == 0`` the error is the largest channel difference
    (each channel is scaled by its tolerance); with ``angle > 0`` the four channels are
    a quaternion and the error is its rotation angle over ``angle``."""
    first, rows = design(T, k, ts)
    nc = len(T) - k
    nu = max(nc - f0 - f1, 0)
    d = xs.shape[1]
    band = np.zeros((nu, k))
    rhs = np.zeros((nu, d))
    target = np.empty(d)
    for s in range(len(ts)):
        f = first[s]
        for c in range(d):
            target[c] = xs[s, c]
        for r in range(k):
            if f + r < f0 or f + r >= f0 + nu:
                for c in range(d):
                    target[c] -= rows[s, r] * coef[f + r, c]
        w = weights[s]
        for r in range(k):
            a = f + r - f0
            if a < 0 or a >= nu:
                continue
            wb = w * rows[s, r]
            for c in range(d):
                rhs[a, c] += wb * target[c]
            for q in range(max(0, f0 - f), r + 1):
                band[a, r - q] += wb * rows[s, q]
    if nu > 0:
        if not solve_banded_spd(band, rhs):
            return np.inf
        for i in range(nu):
            for c in range(d):
                coef[f0 + i, c] = rhs[i, c]
    values = evaluate(first, rows, coef)
    angle, scale, center = metric
    worst = 0.0
    for s in range(len(ts)):
        if angle > 0.0:
            e = scaled_rotation_angle(values[s], xs[s], scale, center) / angle
        else:
            e = 0.0
            for c in range(d):
                e = max(e, abs(values[s, c] - xs[s, c]))
        resid[s] = e / lim[s]
        worst = max(worst, resid[s])
    return worst


@njit(cache=True, error_model="numpy")
def fit_minimax(T: np.ndarray, k: int, coef: np.ndarray, f0: int, f1: int, ts: np.ndarray, xs: np.ndarray,
                lim: np.ndarray, iterations: int, metric: tuple) -> float:
    """:func:`fit`, then up to ``iterations`` Lawson re-weightings while it misses by a
    little (towards the minimax fit); ``coef`` ends as the best fit found."""
    n = len(ts)
    weights = np.ones(n)
    resid = np.empty(n)
    best = fit(T, k, coef, f0, f1, ts, xs, lim, weights, resid, metric)
    if best <= PASS or iterations == 0 or best > MINIMAX_REACH:
        return best
    kept = coef.copy()
    for _ in range(iterations):
        err = best if best < np.inf else 1.0
        total = 0.0
        for s in range(n):
            weights[s] *= max(resid[s], 1e-3 * err)
            total += weights[s]
        weights *= n / total
        e = fit(T, k, coef, f0, f1, ts, xs, lim, weights, resid, metric)
        if e < best:
            best = e
            kept[:] = coef
        if best <= PASS:
            break
    coef[:] = kept
    return best


@njit(cache=True, error_model="numpy")
def local_ranges(xs: np.ndarray, before: np.ndarray, widen: np.ndarray, low: np.ndarray,
                 high: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The range each interval between samples ``xs`` must stay in (the rule of
    :func:`sketchanim.reducer.swing.local_ranges`): the least and greatest of the samples
    ``s - 1 .. s + 2`` around interval ``s``, widened by ``widen``, cut to ``low``,
    ``high``; ``before`` (zero or one row) is the sample before ``xs[0]``. Shape (n - 1, d)."""
    n, d = xs.shape
    lo = np.empty((max(n - 1, 0), d))
    hi = np.empty((max(n - 1, 0), d))
    for s in range(n - 1):
        for c in range(d):
            a = min(xs[s, c], xs[s + 1, c])
            b = max(xs[s, c], xs[s + 1, c])
            if s > 0:
                a = min(a, xs[s - 1, c])
                b = max(b, xs[s - 1, c])
            elif len(before):
                a = min(a, before[0, c])
                b = max(b, before[0, c])
            if s + 2 < n:
                a = min(a, xs[s + 2, c])
                b = max(b, xs[s + 2, c])
            lo[s, c] = max(a - widen[c], low[c])
            hi[s, c] = min(b + widen[c], high[c])
    return lo, hi


@njit(cache=True, error_model="numpy")
def power_form(k: int) -> np.ndarray:
    """The matrix that takes a polynomial of order ``k``'s values at ``k`` equally spaced
    points of [0, 1] (ends included) to its coefficients in powers of the parameter."""
    z = np.linspace(0.0, 1.0, k)
    return np.linalg.inv(np.vander(z, k, increasing=True))


@njit(cache=True, error_model="numpy")
def interval_excess(T: np.ndarray, k: int, coef: np.ndarray, ts: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                    s0: int, vinv: np.ndarray) -> np.ndarray:
    """How far the curve leaves ``[lo[s], hi[s]]`` anywhere on ``[ts[s], ts[s + 1]]``,
    for the intervals ``s >= s0`` (earlier ones: 0), in its worst channel; exactly: on
    each polynomial piece the curve is sampled at ``k`` points, which give its power
    form (``vinv``: :func:`power_form`), and checked at the ends and at the real roots
    of its derivative."""
    n = len(ts)
    d = coef.shape[1]
    out = np.zeros(max(n - 1, 0))
    z = np.linspace(0.0, 1.0, k)
    vals = np.empty((k, d))
    p = np.zeros((k, d))
    b = np.empty(k)
    scratch = np.empty((2, k))
    roots = np.empty(max(k - 2, 1) * d)                  # the derivative's roots on the span, in z
    nr = 0
    last = len(T) - k - 1
    span = k - 1
    formed = -1                                          # the span whose power form p holds
    a = 0.0
    h = 1.0
    for s in range(s0, n - 1):
        u0 = ts[s]
        end = ts[s + 1]
        worst = 0.0
        while u0 < end:
            while span < last and T[span + 1] <= u0:
                span += 1
            u1 = end if span == last else min(end, T[span + 1])
            if formed != span:                            # once per polynomial piece
                a = T[span]
                h = max(T[span + 1], end) - a if span == last else T[span + 1] - a
                for m in range(k):
                    basis_values(T, k, span, a + h * z[m], b, scratch)
                    for c in range(d):
                        acc = 0.0
                        for r in range(k):
                            acc += b[r] * coef[span - k + 1 + r, c]
                        vals[m, c] = acc
                p[:] = vinv @ vals                        # power form in z = (u - a) / h, (k, d)
                nr = 0
                if k >= 3:
                    for c in range(d):
                        # roots of the derivative sum_q (q + 1) p[q + 1] z^q
                        if k == 4:                        # quadratic: no allocation
                            r1, r2 = _quadratic_roots(p[1, c], 2.0 * p[2, c], 3.0 * p[3, c])
                            roots[nr] = r1
                            roots[nr + 1] = r2
                            nr += 2
                        else:
                            for zr in _derivative_roots(p[:, c]):
                                roots[nr] = zr
                                nr += 1
                formed = span
            z0 = (u0 - a) / h
            z1 = (u1 - a) / h
            worst = max(worst, _at(p, z0, lo, hi, s), _at(p, z1, lo, hi, s))
            for q in range(nr):
                if z0 < roots[q] < z1:                     # (NaN: no root)
                    worst = max(worst, _at(p, roots[q], lo, hi, s))
            u0 = u1
        out[s] = worst
    return out


@njit(cache=True, error_model="numpy")
def _at(p: np.ndarray, z: float, lo: np.ndarray, hi: np.ndarray, s: int) -> float:
    """How far the polynomial of power form ``p`` (k, d) is outside ``[lo[s], hi[s]]``
    at ``z``, in its worst channel (0 inside)."""
    e = 0.0
    for c in range(p.shape[1]):
        acc = 0.0
        for q in range(p.shape[0] - 1, -1, -1):
            acc = acc * z + p[q, c]
        e = max(e, acc - hi[s, c], lo[s, c] - acc)
    return e


@njit(cache=True, error_model="numpy")
def _quadratic_roots(c0: float, c1: float, c2: float) -> tuple[float, float]:
    """The real roots of ``c0 + c1 z + c2 z^2`` (NaN where there are fewer)."""
    scale = max(abs(c0), abs(c1), abs(c2))
    if scale == 0.0:
        return np.nan, np.nan
    if abs(c2) <= 1e-14 * scale:
        return (-c0 / c1 if abs(c1) > 1e-14 * scale else np.nan), np.nan
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return np.nan, np.nan
    q = -0.5 * (c1 + np.copysign(np.sqrt(disc), c1))
    return q / c2, (c0 / q if q != 0.0 else np.nan)


@njit(cache=True, error_model="numpy")
def _derivative_roots(p: np.ndarray) -> np.ndarray:
    """Real roots of the derivative of the polynomial ``sum_q p[q] z^q``."""
    k = len(p)
    dq = np.empty(k - 1)
    for q in range(k - 1):
        dq[q] = (q + 1) * p[q + 1]
    top = k - 2
    scale = 0.0
    for q in range(k - 1):
        scale = max(scale, abs(dq[q]))
    while top > 0 and abs(dq[top]) <= 1e-14 * scale:
        top -= 1
    if top == 0 or scale == 0.0:
        return np.empty(0)
    if top == 1:
        return np.array([-dq[0] / dq[1]])
    if top == 2:
        r1, r2 = _quadratic_roots(dq[0], dq[1], dq[2])
        return np.array([r1, r2])
    r = np.roots(dq[: top + 1][::-1].astype(np.complex128))
    out = np.empty(len(r))
    m = 0
    for x in r:
        if abs(x.imag) <= 1e-12 * max(1.0, abs(x.real)):
            out[m] = x.real
            m += 1
    return out[:m]


@njit(cache=True, error_model="numpy")
def removal_weight(T: np.ndarray, k: int, coef: np.ndarray, j: int) -> float:
    """Lyche-Morken weight of knot ``T[j]`` (see :mod:`.rank`, whose closed form this is)."""
    a = np.ones(k)
    b = np.ones(k)
    for m in range(1, k):
        i = j - k + m
        span = T[i + k] - T[i]
        alpha = (T[j] - T[i]) / span if span > 0 else 1.0
        a[m] = alpha
        b[m - 1] = 1.0 - alpha
    v = np.empty(k + 1)
    for r in range(k + 1):
        p = -1.0 if r % 2 else 1.0
        for m in range(r):
            p *= a[m]
        for m in range(r, k):
            p *= b[m]
        v[r] = p
    norm2 = 0.0
    vmax = 0.0
    for r in range(k + 1):
        norm2 += v[r] * v[r]
        vmax = max(vmax, abs(v[r]))
    if norm2 == 0.0:
        return np.inf
    proj = 0.0
    for c in range(coef.shape[1]):
        s = 0.0
        for r in range(k + 1):
            s += v[r] * coef[j - k + r, c]
        proj = max(proj, abs(s))
    return vmax * proj / norm2


@njit(cache=True, error_model="numpy")
def _admissible_order(T: np.ndarray, k: int, coef: np.ndarray, held: int, cand: np.ndarray, counts: np.ndarray,
                      max_span: int) -> np.ndarray:
    """Candidate knots by increasing weight up to :data:`WEIGHT_REACH`, leaving out any
    whose removal together with the lighter ones before it would put more than
    ``max_span`` samples between two remaining knots, and no more than leave the
    ``held`` coefficients. A prefix of the result is the set "remove the j lightest"."""
    idx = np.flatnonzero(cand)
    w = np.empty(len(idx))
    for q in range(len(idx)):
        w[q] = removal_weight(T, k, coef, idx[q])
    removed = np.zeros(len(T), dtype=np.bool_)
    out = np.empty(len(idx), dtype=np.int64)
    n = 0
    for q in np.argsort(w, kind="mergesort"):
        if w[q] > WEIGHT_REACH:
            break
        j = idx[q]
        # Knot j joins intervals j-1 and j, and any removed neighbours' runs.
        total = counts[j - 1] + counts[j]
        lo = j - 1
        while removed[lo]:
            lo -= 1
            total += counts[lo]
        hi = j + 1
        while removed[hi]:
            total += counts[hi]
            hi += 1
        if total <= max_span:
            removed[j] = True
            out[n] = j
            n += 1
    return out[: max(0, min(n, len(T) - k - held))]


@njit(cache=True, error_model="numpy")
def _without(T: np.ndarray, k: int, coef: np.ndarray, f0: int, f1: int,
             drop: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Knot vector without the knots ``drop``, and a coefficient array holding the first
    ``f0`` coefficients (those are unchanged by removing knots at index >= f0 + k) and
    the last ``f1`` (held values)."""
    keep = np.ones(len(T), dtype=np.bool_)
    keep[drop] = False
    T2 = T[keep]
    c2 = np.zeros((len(T2) - k, coef.shape[1]))
    c2[:f0] = coef[:f0]
    if f1 > 0:
        c2[len(c2) - f1 :] = coef[len(coef) - f1 :]
    return T2, c2


@njit(cache=True, error_model="numpy")
def _within(T: np.ndarray, k: int, coef: np.ndarray, ts: np.ndarray, lo: np.ndarray, hi: np.ndarray, s0: int,
            allowed: np.ndarray, vinv: np.ndarray) -> bool:
    """Whether the curve leaves no interval's range by more than ``allowed`` there."""
    ex = interval_excess(T, k, coef, ts, lo, hi, s0, vinv)
    for s in range(s0, len(ex)):
        if ex[s] > allowed[s]:
            return False
    return True


@njit(cache=True, error_model="numpy")
def reduce_window(T: np.ndarray, k: int, coef: np.ndarray, f0: int, f_back: int, f1: int, ts: np.ndarray,
                  xs: np.ndarray, lim: np.ndarray, cand_lo: int, cand_hi: int, max_span: int,
                  exhaustive_below: int, minimax_iterations: int, reference_curve: bool, metric: tuple,
                  low: np.ndarray, high: np.ndarray):
    """Remove as many of the knots ``T[cand_lo:cand_hi]`` as the tolerance and the
    no-swing rule allow.

    ``coef[:f0]`` is held (the curve left of the window, and pinned coefficients);
    ``coef[f0:f_back]`` holds the previous window's values, used as held coefficients
    only if no fit of the window from ``f0`` stays within tolerance; the last ``f1``
    coefficients are held too (a value the curve must end on). Rounds of: rank
    the remaining candidates on the current fit; find the largest count ``j`` whose
    ``j`` lightest knots can go (all of them first; then every count below ``exhaustive_below``
    candidates, else bisection); if none, try the knots one by one; stop when a round removes nothing.
    Every accepted fit keeps every sample within ``lim`` tolerances, and on every
    interval between samples ``s`` the curve goes no further outside ``[low[s], high[s]]``
    (:func:`local_ranges`) than the window's starting curve does (:func:`interval_excess`;
    only the intervals after ``T[f0]`` change).

    With ``reference_curve`` (the paper's own check) fits and checks are against the
    window's starting curve at the sample times instead of the samples.

    Returns ``(T, coef, removed, fits, start_error, start_swing)``: the reduced knots
    and fit, the number of knots removed, the number of least-squares fits, the starting
    curve's error (> ``PASS`` means even the window's starting curve misses), and how far
    the starting curve leaves each interval's range (the most the result does).
    """
    n = len(ts)
    fits = 0
    c = coef.copy()
    start = fit_minimax(T, k, c, f0, f1, ts, xs, lim, minimax_iterations, metric)
    fits += 1
    if start > PASS and f_back > f0:
        c2 = coef.copy()
        back = fit_minimax(T, k, c2, f_back, f1, ts, xs, lim, minimax_iterations, metric)
        fits += 1
        if back < start:
            start = back
            c = c2
    target = xs
    if reference_curve:
        first, rows = design(T, k, ts)
        target = evaluate(first, rows, c)
    cand = np.zeros(len(T), dtype=np.bool_)
    cand[cand_lo:cand_hi] = True
    removed = 0
    vinv = power_form(k)
    allowed = interval_excess(T, k, c, ts, low, high, 0, vinv)
    if start > PASS:
        return T, c, removed, fits, start, allowed
    s0 = max(0, np.searchsorted(ts, T[f0], side="right") - 1)
    for s in range(len(allowed)):
        allowed[s] += SWING_SLACK
    while cand.any():
        counts = np.zeros(len(T), dtype=np.int64)
        span = k - 1
        for s in range(n):
            while span < len(T) - k - 1 and T[span + 1] <= ts[s]:
                span += 1
            counts[span] += 1
        order = _admissible_order(T, k, c, f0 + f1, cand, counts, max_span)
        best_j = 0
        best_T = T
        best_c = c
        # Largest j in [1, len(order)] whose j lightest knots can go: all of them first
        # (on smooth motion they usually can), then down one by one or by bisection.
        lo, hi = 0, len(order)
        exhaustive = np.sum(cand) < exhaustive_below
        top = True
        while hi > lo:
            j = hi if exhaustive or top else (lo + hi + 1) // 2
            top = False
            T2, c2 = _without(T, k, c, f0, f1, order[:j])
            fits += 1
            if fit_minimax(T2, k, c2, f0, f1, ts, target, lim, minimax_iterations, metric) <= PASS \
                    and _within(T2, k, c2, ts, low, high, s0, allowed, vinv):
                best_j, best_T, best_c = j, T2, c2
                lo = j
                if exhaustive:
                    break
            else:
                hi = j - 1
        if best_j == 0:
            for q in range(1, len(order)):
                T2, c2 = _without(T, k, c, f0, f1, order[q:q + 1])
                fits += 1
                if fit_minimax(T2, k, c2, f0, f1, ts, target, lim, 0, metric) <= PASS \
                        and _within(T2, k, c2, ts, low, high, s0, allowed, vinv):
                    best_j, best_T, best_c = 1, T2, c2
                    order = order[q:q + 1]
                    break
        if best_j == 0:
            break
        keep = np.ones(len(T), dtype=np.bool_)
        keep[order[:best_j]] = False
        cand = cand[keep]
        T, c = best_T, best_c
        removed += best_j
    for s in range(len(allowed)):
        allowed[s] -= SWING_SLACK
    return T, c, removed, fits, start, allowed


@njit(cache=True, error_model="numpy")
def errors(T: np.ndarray, k: int, coef: np.ndarray, ts: np.ndarray, xs: np.ndarray, metric: tuple) -> np.ndarray:
    """Largest error over the samples in the caller's units: per channel (shape (d,),
    ``|curve - sample|``), or with an angle metric the rotation angle (shape (1,))."""
    first, rows = design(T, k, ts)
    values = evaluate(first, rows, coef)
    angle, scale, center = metric
    out = np.zeros(1 if angle > 0.0 else xs.shape[1])
    for s in range(len(ts)):
        if angle > 0.0:
            out[0] = max(out[0], scaled_rotation_angle(values[s], xs[s], scale, center))
        else:
            for c in range(xs.shape[1]):
                out[c] = max(out[c], abs(values[s, c] - xs[s, c]) * scale[c])
    return out


@njit(cache=True, error_model="numpy")
def window_step(k: int, kt: np.ndarray, kc: np.ndarray, bt: np.ndarray, bx: np.ndarray, bn: int, a: int,
                b: int, m: int, f0: int, f_back: int, end_tol: float, final: bool, max_span: int,
                exhaustive_below: int, minimax_iterations: int, reference_curve: bool, origin: float,
                scale: np.ndarray, center: np.ndarray, angle: float, end: np.ndarray, before: np.ndarray,
                widen: np.ndarray, low: np.ndarray, high: np.ndarray):
    """One window of the stream, from the held state to the next.

    ``kt`` are the knots from the first that acts on the window through the end of
    the last window, ``kc`` the coefficients of their first ``2k - 1`` B-splines, and
    ``bt[:bn]``, ``bx[:bn]`` the held samples (scaled), of which ``a .. b - 1`` become
    knots. A window takes the ``m`` knots after the past context as candidates; a
    final one takes all of them and ends the curve at the last sample.

    Returns ``(knots, coef, removed, fits, start_error, advance, done, max_error,
    piece_knots, piece_coef, lo, hi, start_swing)``: the window's reduced knots and coefficients (clamped at
    the last sample used), the knots removed, the fits made, the starting curve's
    error, how many window coefficients became final, how many held samples are
    finished (the first ``done``) and their largest error per channel, and the
    finished curve: the window's coefficients up to the last final one, with their
    knots; the ranges of the no-swing rule over the intervals between the samples used,
    and how far the window's starting curve left them (the most its result can). The
    error and the finished curve are in the caller's units (times
    ``origin + t``, values ``center + scale * x``); ``angle`` > 0 bounds the rotation
    angle of quaternion samples instead of each channel (see :func:`fit`). A final
    window with one row of ``end`` (scaled) ends the curve on that value. ``before``
    (zero or one row), ``widen``, ``low`` and ``high`` (scaled) give the ranges of the
    no-swing rule (:func:`local_ranges`).
    """
    metric = (angle, scale, center)
    f1 = len(end) if final else 0
    used = bn if final else b + k - k // 2
    nk = len(kt)
    knots = np.empty(nk + (b - a) + k)
    knots[:nk] = kt
    knots[nk : nk + b - a] = bt[a:b]
    knots[nk + b - a :] = bt[used - 1]
    coef = np.zeros((len(knots) - k, bx.shape[1]))
    coef[: len(kc)] = kc
    if f1 > 0:
        coef[len(coef) - 1] = end[0]
    cand_lo = 2 * k - 1
    cand_hi = len(knots) - k if final else cand_lo + m
    ts = bt[:used]
    xs = bx[:used]
    lim = np.ones(used)
    if not final and end_tol < 1.0:
        for s in range(used):
            if ts[s] >= knots[cand_hi]:
                lim[s] = end_tol
    lo, hi = local_ranges(xs, before, widen, low, high)
    knots, coef, removed, fits, start, start_swing = reduce_window(
        knots, k, coef, f0, f_back, f1, ts, xs, lim, cand_lo, cand_hi, max_span, exhaustive_below,
        minimax_iterations, reference_curve, metric, lo, hi)
    if final:
        advance = len(coef) - (k - 1)
        done = bn
    else:
        advance = cand_hi - cand_lo - removed
        done = np.searchsorted(bt[:bn], knots[advance + k - 1])
    max_error = errors(knots, k, coef, bt[:done], bx[:done], metric)
    stop = k - 1 + advance
    piece_knots = knots[: stop + k] + origin
    piece_coef = coef[:stop] * scale + center
    return (knots, coef, removed, fits, start, advance, done, max_error, piece_knots, piece_coef, lo, hi,
            start_swing)
