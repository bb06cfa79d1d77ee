"""The rank step against brute-force removal, and the approximate step against scipy."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from scipy.interpolate import BSpline, make_lsq_spline

from sketchanim.reducer.approximate import Approximator
from sketchanim.reducer.rank import removal_weights
from sketchanim.spline import insert_knots, insertion_matrix


@st.composite
def knot_vectors(draw):
    order = draw(st.integers(2, 5))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    n_interior = draw(st.integers(1, 12))
    interior = np.sort(rng.choice(np.arange(1, 100), n_interior, replace=False) / 10.0)
    if draw(st.booleans()) and order > 2:          # a double knot
        interior = np.sort(np.r_[interior, interior[0]])
    knots = np.r_[[0.0] * order, interior, [10.0] * order]
    coef = rng.normal(0.0, 3.0, (len(knots) - order, draw(st.integers(1, 3))))
    return order, knots, coef


@given(knot_vectors())
def test_weight_is_the_least_squares_change_of_removing_that_knot(case):
    order, knots, coef = case
    weights = removal_weights(knots, coef, order)
    assert weights.shape == (len(coef) - order,)
    for i, j in enumerate(range(order, len(coef))):
        shorter = np.delete(knots, j)
        A = insertion_matrix(shorter, knots, order).toarray()
        d, *_ = np.linalg.lstsq(A, coef, rcond=None)
        change = np.abs(A @ d - coef).max()
        assert np.isclose(weights[i], change, rtol=1e-7, atol=1e-9)


def test_weights_are_zero_for_knots_the_curve_does_not_need():
    cubic = BSpline([0, 0, 0, 0, 1, 1, 1, 1], np.array([[0.0], [1.0], [3.0], [2.0]]), 3)
    refined = insert_knots(cubic, [0.2, 0.5, 0.7])
    assert np.all(removal_weights(refined.t, refined.c, 4) < 1e-12)


@given(st.integers(0, 2**32 - 1), st.integers(2, 5), st.integers(1, 3))
def test_fit_is_scipys_least_squares_spline(seed, order, dim):
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 5, 80))
    x = rng.normal(size=(80, dim))
    interior = np.quantile(t, np.linspace(0, 1, 9)[1:-1])
    knots = np.r_[[t[0]] * order, interior, [t[-1]] * order]
    tol = rng.uniform(0.1, 2.0, dim)
    ap = Approximator(t, x, tol, order)
    ours = ap.spline(ap.fit(knots))
    ref = make_lsq_spline(t, x, knots, k=order - 1)
    assert np.allclose(ours.c, ref.c, atol=1e-8)


def test_fit_reproduces_a_spline_of_its_own_space_exactly():
    t = np.linspace(0, 1, 300)
    truth = BSpline(np.r_[[0.0] * 4, 0.3, 0.6, [1.0] * 4], np.array([[0.0], [2.0], [-1.0], [1.0], [0.5], [3.0]]), 3)
    ap = Approximator(t, truth(t), np.array([1e-6]), 4)
    fit = ap.fit(truth.t)
    assert fit.error < 1e-6 and fit.passes


@given(st.integers(0, 2**32 - 1))
def test_minimax_reweighting_never_makes_the_fit_worse(seed):
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 10, 200))
    x = np.c_[np.sin(t) + 0.05 * rng.normal(size=200)]
    knots = np.r_[[0.0] * 4, 2.5, 5.0, 7.5, [10.0] * 4]
    knots[:4], knots[-4:] = t[0], t[-1]
    ap = Approximator(t, x, np.array([0.12]), 4)
    plain = ap.fit(knots)
    lawson = ap.fit(knots, minimax_iterations=10, minimax_reach=np.inf)
    assert lawson.error <= plain.error


@given(st.integers(0, 2**32 - 1), st.integers(2, 5), st.integers(1, 3))
def test_local_knot_removal_reports_the_truth_and_touches_only_its_window(seed, order, dim):
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 10, 400))
    x = np.cumsum(rng.normal(0, 0.05, (400, dim)), axis=0)
    knots = np.r_[[t[0]] * order, np.quantile(t, np.linspace(0, 1, 40)[1:-1]), [t[-1]] * order]
    tol = np.full(dim, 0.5)
    ap = Approximator(t, x, tol, order)
    base = ap.fit(knots, minimax_iterations=0)
    if not base.passes:
        return
    for index in rng.choice(np.arange(order, len(knots) - order), 8, replace=False):
        fit = ap.without_knot(base, int(index))
        if fit is None:
            continue
        assert np.array_equal(fit.knots, np.delete(knots, index))
        truth = np.abs(ap.spline(fit)(t) - x).max(axis=1) / 0.5
        assert np.allclose(fit.residual, truth, atol=1e-9) and truth.max() <= 1.0
        # coefficients far from the knot are those of the base fit
        far_left = int(index) - 2 * order - 1
        if far_left > 0:
            assert np.array_equal(fit.coef[:far_left], base.coef[:far_left])
        assert np.array_equal(fit.coef[int(index) + order :], base.coef[int(index) + order + 1 :])
