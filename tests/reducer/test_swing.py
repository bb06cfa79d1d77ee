"""The exact no-swing check against dense sampling, on splines of every degree."""

import numpy as np
from hypothesis import given, settings, strategies as st
from scipy.interpolate import BSpline

from sketchanim.reducer.swing import excess, local_ranges, swinging


@st.composite
def splines_and_samples(draw):
    degree = draw(st.integers(1, 5))
    inner = draw(st.integers(0, 6))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    knots = np.r_[[0.0] * (degree + 1), np.sort(rng.uniform(0, 1, inner)), [1.0] * (degree + 1)]
    coef = rng.normal(size=(inner + degree + 1, draw(st.integers(1, 3))))
    times = np.r_[0.0, np.sort(rng.uniform(0, 1, draw(st.integers(0, 12)))), 1.0]
    times = np.unique(times)
    return BSpline(knots, coef, degree), times, rng


def _dense_excess(spline, times, lo, hi, per=20000):
    out = np.zeros_like(lo)
    for i in range(len(times) - 1):
        knots = spline.t[(spline.t > times[i]) & (spline.t < times[i + 1])]
        v = spline(np.r_[np.linspace(times[i], times[i + 1], per), knots])
        out[i] = np.maximum(np.max(np.maximum(v - hi[i], lo[i] - v), axis=0), 0.0)
    return out


@settings(max_examples=60, deadline=None)
@given(splines_and_samples())
def test_excess_never_misses_what_dense_sampling_finds_and_finds_no_more(case):
    spline, times, rng = case
    values = spline(times) + rng.normal(scale=0.05, size=(len(times), spline.c.shape[1]))
    lo, hi = local_ranges(values, np.full(values.shape[1], 0.01))
    exact = excess(spline, times, lo, hi)
    dense = _dense_excess(spline, times, lo, hi)
    assert np.all(exact >= dense - 1e-12)
    assert np.all(exact <= dense + 1e-4 * (1 + np.abs(spline.c).max()))


@settings(max_examples=60, deadline=None)
@given(splines_and_samples(), st.integers(1, 5))
def test_chunks_give_the_same_answer(case, chunk):
    spline, times, rng = case
    values = spline(times)
    lo, hi = local_ranges(values, np.full(values.shape[1], 1e-3))
    whole = excess(spline, times, lo, hi)
    assert np.allclose(whole, excess(spline, times, lo, hi, chunk=chunk), rtol=0, atol=1e-12 * (1 + np.abs(spline.c).max()))


def test_the_interpolant_through_samples_is_within_and_bounds_cut_the_range():
    t = np.linspace(0, 1, 6)
    x = np.c_[[0.0, 0.2, 1.0, 1.0, 0.8, 0.0]]
    linear = BSpline(np.r_[t[0], t, t[-1]], x, 1)
    lo, hi = local_ranges(x, np.array([0.01]))
    assert swinging(linear, t, lo, hi).size == 0
    lo, hi = local_ranges(x, np.array([0.01]), (np.array([0.0]), np.array([0.9])))
    assert swinging(linear, t, lo, hi).tolist() == [1, 2, 3]     # the samples at 1.0 are beyond the bound
