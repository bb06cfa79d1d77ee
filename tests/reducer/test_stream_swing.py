"""The streaming reducer keeps the no-swing rule, exactly, in every piece it hands out,
and the bounds of its channels."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

import sketchanim
from sketchanim.errors import SampleError
from sketchanim.reducer import swing, window_kernel
from sketchanim.reducer.stream import Piece
from recordings import shared_cases
from signals import signals

#: What rounding may add to a swing: of the comparison (tolerances) and of the values.
ROUNDING_TOL = 1e-6


def pieces_swing(times: np.ndarray, values: np.ndarray, tol: np.ndarray, pieces: list[Piece],
                 bounds: tuple[np.ndarray, np.ndarray] | None = None) -> float:
    """The largest swing of any piece beyond the local range of the intervals it covers,
    in tolerances (after rounding allowances)."""
    lo, hi = swing.local_ranges(values, tol, bounds)
    scale = np.max(np.abs(values), axis=0) + tol
    worst = 0.0
    for piece in pieces:
        a = int(np.searchsorted(times, piece.start, side="left"))
        b = int(np.searchsorted(times, piece.end, side="right"))
        if b - a < 2:
            continue
        spline = piece.spline
        ex = swing.excess(spline, times[a:b], lo[a : b - 1], hi[a : b - 1])
        worst = max(worst, float(np.max((ex - 1e-12 * scale) / tol)))
    return worst


def streamed(times: np.ndarray, values: np.ndarray, tol: np.ndarray, **options) -> tuple[list[Piece], object]:
    pieces: list[Piece] = []
    sr = sketchanim.StreamReducer(values.shape[1], tol, on_piece=pieces.append, **options)
    sr.extend(times, values)
    return pieces, sr.finish()


@settings(max_examples=60)
@given(signals(max_n=300), st.integers(2, 5), st.integers(3, 40), st.booleans(), st.booleans())
def test_every_piece_stays_within_the_local_range_of_its_samples(sig, order: int, window: int,
                                                                  features: bool, grow: bool) -> None:
    t = sig.times - sig.times[0]         # the rule in the caller's units; see the offset test below
    pieces, r = streamed(t, sig.values, sig.tol, order=order, window=window, features=features, grow=grow)
    assert pieces_swing(t, sig.values, sig.tol, pieces) <= ROUNDING_TOL
    whole = r.spline if sig.values.shape[1] > 1 else BSpline(r.spline.t, r.spline.c[:, None], r.spline.k)
    whole_piece = Piece(np.asarray(whole.t), np.asarray(whole.c))
    assert pieces_swing(t, sig.values, sig.tol, [whole_piece]) <= ROUNDING_TOL
    assert np.all(r.max_error <= sig.tol)


@settings(max_examples=200)
@given(st.integers(2, 4), st.integers(3, 5), st.floats(-12, 6), st.integers(0, 2**32 - 1))
def test_a_take_shorter_than_the_order_does_not_swing_at_any_scale(n: int, order: int, log_scale: float,
                                                                  seed: int) -> None:
    """Fewer samples than the order make the polynomial through them, straightened where it
    swings; the swing is measured in tolerances whatever the values' scale."""
    rng = np.random.default_rng(seed)
    scale = 10.0 ** log_scale
    t = np.cumsum(rng.uniform(1e-3, 1e-2, n)) - 1e-3
    x = scale * rng.normal(size=(n, 1)) * rng.choice([1.0, 1e3], size=(n, 1))
    tol = np.array([scale * 10.0 ** rng.uniform(-3, 0)])
    pieces, r = streamed(t, x, tol, order=order, window=3)
    assert pieces_swing(t, x, tol, pieces) <= ROUNDING_TOL
    assert np.all(r.max_error <= tol)


def test_three_tiny_samples_with_a_step_do_not_swing() -> None:
    """The take hypothesis found: values near 1e-8 with a step of 800 tolerances of 5e-10;
    the cubic through them swung 100 tolerances past their range."""
    t = np.array([0.0, 0.001, 0.002])
    x = np.array([[-2.646e-8], [-2.479e-8], [-4.486e-7]])
    pieces, _ = streamed(t, x, np.array([5.14e-10]), window=3)
    assert pieces_swing(t, x, np.array([5.14e-10]), pieces) <= ROUNDING_TOL


@settings(max_examples=40)
@given(signals(max_n=300, dims=(1, 3)), st.integers(3, 40), st.sampled_from([0.0, 12.5, 1.6e9]))
def test_bounded_channels_stay_in_bounds(sig, window: int, offset: float) -> None:
    lo, hi = np.min(sig.values, axis=0), np.max(sig.values, axis=0)
    values = np.clip(sig.values, lo + 0.2 * (hi - lo), hi - 0.2 * (hi - lo))    # samples resting on the bounds
    bounds = (lo + 0.2 * (hi - lo), hi - 0.2 * (hi - lo))
    t = sig.times - sig.times[0] + offset
    pieces, r = streamed(t, values, sig.tol, window=window, bounds=bounds)
    allowance = ROUNDING_TOL * sig.tol + 1e-12 * np.max(np.abs(values), axis=0)
    curve = np.concatenate([p.spline(np.linspace(p.start, p.end, 50)) for p in pieces])
    assert len(curve) and np.all(curve >= bounds[0] - allowance) and np.all(curve <= bounds[1] + allowance)
    exact = swing.excess(Piece(*_columns(r.spline)).spline, t, *_box(bounds, len(t)))
    assert np.all(exact <= allowance)


def _columns(s: BSpline) -> tuple[np.ndarray, np.ndarray]:
    c = np.asarray(s.c)
    return np.asarray(s.t), c if c.ndim == 2 else c[:, None]


def _box(bounds: tuple[np.ndarray, np.ndarray], n: int) -> tuple[np.ndarray, np.ndarray]:
    return np.tile(bounds[0], (n - 1, 1)), np.tile(bounds[1], (n - 1, 1))


def test_a_colour_step_and_an_intensity_dip_stay_in_range() -> None:
    # The cases: a colour channel sliding to 1 and back, an intensity falling to
    # its lowest value and rising, both at 60 Hz with the jitter of a slider.
    t = np.arange(180) / 60.0
    rng = np.random.default_rng(4)
    colour = np.clip(np.r_[np.linspace(0.3, 1.0, 40), np.ones(50), np.linspace(1.0, 0.0, 30), np.zeros(60)]
                     + rng.normal(0, 0.002, 180), 0.0, 1.0)[:, None]
    _, r = streamed(t, colour, np.array([0.005]), bounds=(0.0, 1.0))
    dense = np.linspace(0, t[-1], 20001)
    assert 0.0 <= r.spline(dense).min() and r.spline(dense).max() <= 1.0
    intensity = np.r_[np.full(60, 2.0), np.full(5, 0.3), np.linspace(0.3, 3.0, 115)][:, None]
    _, r = streamed(t, intensity, np.array([0.01]), bounds=(0.0, np.inf))
    assert r.spline(dense).min() >= 0.3 - 0.01 * (1 + 1e-9)


def test_a_sample_outside_the_bounds_is_refused_by_index() -> None:
    sr = sketchanim.StreamReducer(1, 0.01, bounds=(0.0, 1.0))
    with pytest.raises(SampleError, match=r"sample 3.*outside the bounds"):
        sr.extend(np.arange(5.0), np.c_[[0.1, 0.2, 0.3, 1.5, 0.2]])
    assert sr.taken == 3
    sr.extend([5.0, 6.0], [[0.4], [0.5]])                # and goes on
    assert sr.finish().n_samples == 5


@settings(max_examples=60)
@given(st.integers(2, 6), st.integers(0, 2**32 - 1))
def test_kernel_excess_matches_the_reference_check(order: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    times = np.sort(rng.choice(np.linspace(0, 10, 200), rng.integers(order + 2, 40), replace=False))
    inner = np.sort(rng.choice(times[1:-1], rng.integers(0, len(times) - 2), replace=False))
    knots = np.r_[[times[0]] * order, inner, [times[-1]] * order]
    coef = rng.normal(size=(len(knots) - order, 2))
    values = rng.normal(size=(len(times), 2))
    lo, hi = swing.local_ranges(values, np.array([0.1, 0.2]))
    ours = window_kernel.interval_excess(knots, order, coef, times, lo, hi, 0, window_kernel.power_form(order))
    theirs = swing.excess(BSpline(knots, coef, order - 1), times, lo, hi).max(axis=1)
    np.testing.assert_allclose(ours, theirs, atol=1e-9)


def test_shared_recordings_streamed_without_swing(data_dir) -> None:
    checked = 0
    for name, times, values, tol in shared_cases(data_dir):
        t = times - times[0]
        tols = np.broadcast_to(np.asarray(tol, dtype=float), (values.shape[1],))
        pieces, r = streamed(t, values, tols)
        assert pieces_swing(t, values, tols, pieces) <= ROUNDING_TOL, name
        assert np.all(r.max_error <= tols), name
        checked += 1
    assert checked
