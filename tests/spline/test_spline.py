"""Exactness of knot insertion, degree elevation and Bezier / Hermite conversion."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError
from sketchanim.spline import (
    HermiteKeys,
    elevate_degree,
    from_hermite,
    insert_knots,
    insertion_matrix,
    to_bezier,
    to_hermite,
)


@st.composite
def splines(draw, orders=(2, 5), max_mult=None, dims=(1, 3)):
    """A random spline: order, interior knots (some repeated), coefficients."""
    order = draw(st.integers(*orders))
    dim = draw(st.integers(*dims))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    n_distinct = draw(st.integers(0, 8))
    cap = order - 1 if max_mult is None else max_mult
    values = np.sort(rng.uniform(0.0, 10.0, n_distinct))
    mults = rng.integers(1, cap + 1, n_distinct) if n_distinct else np.zeros(0, int)
    interior = np.repeat(values, mults)
    knots = np.r_[[0.0] * order, interior, [10.0] * order]
    coef = rng.normal(0.0, 5.0, (len(knots) - order, dim))
    return BSpline(knots, coef, order - 1)


# New knots on a 0.01 grid strictly inside the span, each at most once (so they also
# land on existing knots and raise multiplicities, but never past the order).
new_knots = st.lists(st.integers(1, 999).map(lambda i: i / 100), unique=True, max_size=10)


def _points(spline: BSpline, count: int = 97) -> np.ndarray:
    t = spline.t
    return np.r_[np.linspace(t[0], t[-1], count), np.unique(t)]


@given(splines(), new_knots.filter(bool))
def test_insertion_keeps_the_curve(spline, new):
    refined = insert_knots(spline, new)
    x = _points(spline)
    assert np.allclose(refined(x), spline(x), rtol=1e-10, atol=1e-10)
    assert len(refined.c) == len(spline.c) + len(new)


@given(splines(), new_knots)
def test_insertion_matrix_rows_are_convex_weights(spline, new):
    fine = np.sort(np.r_[spline.t, new])
    A = insertion_matrix(spline.t, fine, spline.k + 1).toarray()
    assert np.all(A >= -1e-12)
    assert np.allclose(A.sum(axis=1), 1.0)
    assert np.all((A > 1e-14).sum(axis=1) <= spline.k + 1)


def test_insertion_matrix_matches_boehm_by_hand():
    # Inserting 0.5 into a quadratic on [0, 1]: Boehm's weights are 1, 1/2, 1/2, 1.
    A = insertion_matrix([0, 0, 0, 1, 1, 1], [0, 0, 0, 0.5, 1, 1, 1], 3).toarray()
    assert np.allclose(A, [[1, 0, 0], [0.5, 0.5, 0], [0, 0.5, 0.5], [0, 0, 1]])


def test_insertion_matrix_rejects_knots_that_are_not_nested():
    with pytest.raises(ArgumentError, match="new_knots"):
        insertion_matrix([0, 0, 0.5, 1, 1], [0, 0, 0.4, 1, 1], 2)


def test_insertion_matrix_refuses_unclamped_knots():
    # A piece cut from the middle of a curve: the Oslo rows near its ends are undefined.
    with pytest.raises(ArgumentError, match="old_knots.*clamped"):
        insertion_matrix([0, 1, 2, 3, 4, 5, 6, 7], [0, 1, 2, 3, 3.5, 4, 5, 6, 7], 4)


@given(splines(), st.integers(1, 3))
def test_degree_elevation_keeps_the_curve(spline, times):
    up = elevate_degree(spline, times)
    x = _points(spline)
    scale = 1 + np.abs(spline.c).max()
    assert up.k == spline.k + times
    assert np.allclose(up(x), spline(x), rtol=0, atol=1e-9 * scale)
    # every distinct knot gains `times` in multiplicity
    v0, c0 = np.unique(spline.t, return_counts=True)
    v1, c1 = np.unique(up.t, return_counts=True)
    assert np.array_equal(v0, v1) and np.array_equal(c1, c0 + times)


def test_degree_elevation_refuses_value_jumps():
    jump = BSpline([0, 0, 1, 1, 2, 2], [0.0, 1.0, 5.0, 6.0], 1)
    with pytest.raises(ArgumentError, match="jumps in value at t=1"):
        elevate_degree(jump)


def _bezier_eval(points: np.ndarray, a: float, b: float, x: np.ndarray) -> np.ndarray:
    order = len(points)
    return BSpline(np.r_[[a] * order, [b] * order], points, order - 1)(x)


@given(splines())
def test_bezier_segments_reproduce_each_piece(spline):
    bez = to_bezier(spline)
    assert len(bez.points) == len(bez.breaks) - 1
    scale = 1 + np.abs(spline.c).max()
    for (a, b), pts in zip(zip(bez.breaks[:-1], bez.breaks[1:]), bez.points):
        x = np.linspace(a, b, 11)
        assert np.allclose(_bezier_eval(pts, a, b, x), spline(x), atol=1e-9 * scale)


def _hermite_eval(keys: HermiteKeys, x: np.ndarray) -> np.ndarray:
    i = np.clip(np.searchsorted(keys.times, x, side="right") - 1, 0, len(keys.times) - 2)
    t0, t1 = keys.times[i], keys.times[i + 1]
    h = (t1 - t0)[:, None]
    s = ((x - t0) / (t1 - t0))[:, None]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return (h00 * keys.values[i] + h10 * h * keys.out_tangents[i]
            + h01 * keys.values[i + 1] + h11 * h * keys.in_tangents[i + 1])


@given(splines(orders=(4, 4), max_mult=3))
def test_hermite_keys_are_exact(spline):
    keys = to_hermite(spline)
    x = np.linspace(spline.t[0], spline.t[-1], 201)
    scale = 1 + np.abs(spline.c).max()
    assert np.allclose(_hermite_eval(keys, x), spline(x), atol=1e-9 * scale)
    back = from_hermite(keys)
    assert np.allclose(back(x), spline(x), atol=1e-9 * scale)


def test_hermite_tangents_are_one_sided_at_a_corner():
    # A C0 cubic (triple knot at 1): the curve turns there, tangents differ.
    corner = BSpline([0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2], [0.0, 1 / 3, 2 / 3, 1.0, 1.0, 1.0, 1.0], 3)
    keys = to_hermite(corner)
    assert keys.times.tolist() == [0.0, 1.0, 2.0]
    assert np.isclose(keys.in_tangents[1], 1.0) and np.isclose(keys.out_tangents[1], 0.0)


def test_hermite_needs_a_continuous_cubic():
    with pytest.raises(ArgumentError, match="cubic"):
        to_hermite(BSpline([0, 0, 0, 1, 1, 1], [0.0, 1.0, 2.0], 2))
    jump = BSpline([0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2], [0, 0, 0, 0, 5, 5, 5, 5.0], 3)
    with pytest.raises(ArgumentError, match="jumps in value at t=1"):
        to_hermite(jump)
