"""The incremental reducer: guarantee, streaming = batch, continuity, bounded memory, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline
from scipy.linalg import solveh_banded

import sketchanim
from sketchanim.errors import ArgumentError, SampleError
from sketchanim.paper import spiral
from sketchanim.reducer import window_kernel
from sketchanim.reducer.stream import CONSTRAINTS
from signals import signals
from tolerance import within


# -- the kernel against scipy ---------------------------------------------------------

@given(st.integers(2, 6), st.integers(0, 2**32 - 1))
def test_kernel_basis_matches_scipy_design_matrix(order: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    inner = np.sort(rng.uniform(0, 1, rng.integers(0, 12)))
    knots = np.r_[[0.0] * order, inner, [1.0] * order]
    ts = np.sort(rng.uniform(0, 1, 40))
    first, rows = window_kernel.design(knots, order, ts)
    ours = np.zeros((len(ts), len(knots) - order))
    for s in range(len(ts)):
        ours[s, first[s] : first[s] + order] = rows[s]
    theirs = BSpline.design_matrix(ts, knots, order - 1).toarray()
    np.testing.assert_allclose(ours, theirs, atol=1e-12)


@given(st.integers(1, 30), st.integers(1, 6), st.integers(0, 2**32 - 1))
def test_kernel_banded_solve_matches_lapack(n: int, bandwidth: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    bandwidth = min(bandwidth, n)
    a = rng.normal(size=(n + 5, n))
    a[np.abs(np.subtract.outer(np.arange(n + 5), np.arange(n))) >= bandwidth] = 0.0
    m = a.T @ a + np.eye(n)
    m[np.abs(np.subtract.outer(np.arange(n), np.arange(n))) >= bandwidth] = 0.0
    m += n * bandwidth * np.eye(n)                       # keep it positive definite after banding
    rhs = rng.normal(size=(n, 2))
    band = np.zeros((n, bandwidth))
    for d in range(bandwidth):
        band[d:, d] = np.diag(m, -d)
    x = rhs.copy()
    assert window_kernel.solve_banded_spd(band, x)
    upper = np.zeros((bandwidth, n))
    for d in range(bandwidth):
        upper[bandwidth - 1 - d, d:] = np.diag(m, d)
    np.testing.assert_allclose(x, solveh_banded(upper, rhs), rtol=1e-9, atol=1e-12)


# -- the guarantee ---------------------------------------------------------------------

@settings(max_examples=80)
@given(signals(max_n=400), st.integers(2, 5), st.integers(3, 60), st.sampled_from(CONSTRAINTS), st.booleans())
def test_every_sample_within_tolerance(sig, order: int, window: int, constraints: str, grow: bool) -> None:
    sr = sketchanim.StreamReducer(sig.values.shape[1], sig.tol, order=order, window=window,
                                  constraints=constraints, grow=grow)
    sr.extend(sig.times, sig.values)
    r = sr.finish()
    assert within(r.spline(sig.times), sig.values, sig.tol)
    assert np.all(r.max_error <= sig.tol)
    # Each restart or cut (a C0 join, see StreamReducer._restart, _cut) adds order - 2 knots,
    # each straight interval (reducer/straighten.py) at most order - 1 at each end.
    extra = (order - 2) * (r.report["start_misses"] + r.report["cuts"]) + 2 * (order - 1) * r.report["straightened"]
    assert r.n_coefficients <= max(len(sig.times), order) + extra


def test_spiral_within_tolerance_and_close_to_global() -> None:
    t, x = spiral()
    inc = sketchanim.reduce(t, x, 0.1, method="incremental", window=20)
    glob = sketchanim.reduce(t, x, 0.1)
    assert within(inc.spline(t), x, np.array([0.1, 0.1]))
    assert inc.report.get("note") is None                    # no fallback to the interpolant
    assert inc.n_coefficients <= 1.4 * glob.n_coefficients


def test_paper_reference_lets_error_creep_and_says_so() -> None:
    t, x = spiral()
    sr = sketchanim.StreamReducer(2, 0.1, window=10, reference="curve", constraints="none")
    sr.extend(t, x)
    r = sr.finish()
    measured = np.abs(r.spline(t) - x).max(axis=0)
    np.testing.assert_allclose(r.max_error, measured, rtol=1e-9)


# -- streaming is batch, pieces are the curve ---------------------------------------------

@settings(max_examples=40)
@given(signals(max_n=300, dims=(1, 3)), st.integers(3, 30), st.lists(st.integers(1, 50), min_size=1, max_size=20))
def test_streaming_in_any_chunks_equals_batch(sig, window: int, chunks: list[int]) -> None:
    batch = sketchanim.reduce(sig.times, sig.values, sig.tol, method="incremental", window=window,
                              features=sketchanim.FeatureOptions(jumps=False))    # the stream cuts no jumps
    pieces = []
    sr = sketchanim.StreamReducer(sig.values.shape[1], sig.tol, window=window, on_piece=pieces.append, grow=True)
    i, c = 0, 0
    while i < len(sig.times):
        step = chunks[c % len(chunks)]
        if step == 1:
            sr.push(sig.times[i], sig.values[i])
        else:
            sr.extend(sig.times[i : i + step], sig.values[i : i + step])
        i, c = i + step, c + 1
    r = sr.finish()
    np.testing.assert_array_equal(r.spline.t, batch.spline.t)
    np.testing.assert_array_equal(np.asarray(r.spline.c).reshape(batch.spline.c.shape), batch.spline.c)
    # The pieces, in order, tile the curve and agree with it.
    assert pieces[0].start == sig.times[0] and pieces[-1].end == pieces[-1].knots[-1]
    for a, b in zip(pieces, pieces[1:]):
        assert a.end == b.start
    for p in pieces:
        u = np.linspace(p.start, p.end, 7)
        np.testing.assert_allclose(p.spline(u).reshape(7, -1), r.spline(u).reshape(7, -1),
                                   rtol=1e-9, atol=1e-9 * np.abs(sig.values).max())


@settings(max_examples=30)
@given(signals(min_n=30, max_n=300, dims=(1, 3)), st.integers(3, 5), st.integers(3, 30), st.booleans())
def test_splices_keep_the_curve_continuity(sig, order: int, window: int, grow: bool) -> None:
    pieces = []
    sr = sketchanim.StreamReducer(sig.values.shape[1], sig.tol, order=order, window=window,
                                  on_piece=pieces.append, grow=grow)
    sr.extend(sig.times, sig.values)
    sr.close()
    scale = np.abs(sig.values).max() + sig.tol.max()
    joins = 0
    for a, b in zip(pieces, pieces[1:]):
        at = a.end
        if b.end == at:
            continue
        # C^(order-2) at every splice; a restart (StreamReducer._restart), a cut
        # (StreamReducer._cut), a straight interval's ends, a break or either end of a
        # pause joins with C0, and says so with a repeated knot there.
        repeats = int(np.count_nonzero(b.knots == at))
        joins += repeats > 1
        for der in range(max(1, order - repeats)):
            left = a.spline(at, nu=der)
            right = b.spline(at, nu=der)
            span = b.end - at
            assert np.allclose(left, right, rtol=1e-6, atol=1e-6 * scale / span**der)
    features = sum(2 if f.kind == "pause" else 1 for f in sr.found)
    assert joins <= sr.stats.start_misses + sr.stats.cuts + 2 * sr.stats.straightened + features


def test_windows_grow_on_smooth_motion_and_shrink_where_it_is_hard() -> None:
    """A dense smooth take with a burst of fast motion: grown windows (``grow``) take the
    smooth stretches in far fewer windows, keep the tolerance, and where the motion is
    hard go back to ``window`` (which removes more there than a grown one would)."""
    t = np.arange(30_000) / 1000.0
    rng = np.random.default_rng(1)
    x = np.c_[np.sin(0.3 * t), np.cos(0.2 * t), 0.01 * t] + rng.normal(0, 1e-4, (len(t), 3))
    burst = (t > 12.0) & (t < 14.0)
    x[burst, 0] += 0.2 * np.sin(40.0 * t[burst]) * np.sin(np.pi * (t[burst] - 12.0) / 2.0)
    runs = {}
    for grow in (False, True):
        sr = sketchanim.StreamReducer(3, 1e-3, grow=grow)
        sr.extend(t, x)
        runs[grow] = (sr.finish(), sr.stats)
    (plain, plain_stats), (grown, grown_stats) = runs[False], runs[True]
    assert within(grown.spline(t), x, np.full(3, 1e-3))
    assert grown_stats.windows < plain_stats.windows / 3
    assert grown.report["max_window"] == 160 and plain.report["max_window"] == 20
    assert grown.n_coefficients <= plain.n_coefficients
    hard = lambda r: int(np.count_nonzero((r.spline.t > 12.0) & (r.spline.t < 14.0)))  # noqa: E731
    assert hard(grown) <= hard(plain) + 2


# -- bounded memory --------------------------------------------------------------------------

@settings(max_examples=30)
@given(signals(min_n=50, max_n=600, dims=(1, 2)), st.integers(2, 5), st.integers(3, 40),
       st.integers(2, 40), st.booleans())
def test_buffer_never_exceeds_its_bound(sig, order: int, window: int, max_span: int, grow: bool) -> None:
    sr = sketchanim.StreamReducer(sig.values.shape[1], sig.tol, order=order, window=window, max_span=max_span,
                                  keep=False, grow=grow)
    assert sr.buffer_bound == order * max_span + (max(window, max_span) if grow else window) + 2 * order
    for ti, xi in zip(sig.times, sig.values):
        sr.push(ti, xi)
        assert sr.buffered <= sr.buffer_bound
    sr.close()


def test_long_stream_keeps_a_bounded_buffer_and_finishes_pieces_as_it_goes() -> None:
    t = np.arange(200_000) / 120
    x = np.c_[np.sin(t), np.cos(0.7 * t), np.zeros_like(t)]     # a channel that never moves
    ends = []
    sr = sketchanim.StreamReducer(3, 0.01, window=20, keep=False, on_piece=lambda p: ends.append(p.end))
    for i in range(0, len(t), 5000):
        sr.extend(t[i : i + 5000], x[i : i + 5000])
        assert sr.buffered <= sr.buffer_bound
        assert ends and ends[-1] > t[i] - 10.0                  # the curve keeps up with the take
    sr.close()
    assert np.all(sr.max_error <= 0.01)
    with pytest.raises(ArgumentError, match="keep"):
        sr.finish()


# -- bad input ---------------------------------------------------------------------------------

def test_bad_sample_mid_stream_is_named_and_everything_before_it_kept() -> None:
    t, x = spiral(400)
    sr = sketchanim.StreamReducer(2, 0.1, window=10, grow=True)
    sr.extend(t[:200], x[:200])
    bad = x[200:260].copy()
    bad[17, 1] = np.nan
    with pytest.raises(SampleError, match=r"sample 217, channel 1: value is nan"):
        sr.extend(t[200:260], bad)
    with pytest.raises(SampleError, match=r"sample 218, time: time goes backwards"):
        sr.push(t[10], x[10])
    sr.extend(t[217:], x[217:])                                 # the stream goes on
    r = sr.finish()
    assert r.n_samples == 400
    assert within(r.spline(t), x, np.array([0.1, 0.1]))
    expected = sketchanim.reduce(t, x, 0.1, method="incremental", window=10)
    np.testing.assert_array_equal(r.spline.t, expected.spline.t)


def test_bad_arguments_are_named() -> None:
    with pytest.raises(ArgumentError, match="window"):
        sketchanim.StreamReducer(2, 0.1, window=0)
    with pytest.raises(ArgumentError, match="constraints"):
        sketchanim.StreamReducer(2, 0.1, constraints="tight")
    with pytest.raises(ArgumentError, match="tol"):
        sketchanim.StreamReducer(2, [0.1, -1.0])
    sr = sketchanim.StreamReducer(2, 0.1)
    with pytest.raises(ArgumentError, match=r"values.*\(1, 2\)"):
        sr.push(0.0, [1.0, 2.0, 3.0])


def test_one_sample_is_refused_as_reduce_refuses_it() -> None:
    sr = sketchanim.StreamReducer(2, 1e-6)
    sr.push(0.0, [1.0, 2.0])
    with pytest.raises(SampleError, match="1 distinct samples, at least 2"):
        sr.finish()
    with pytest.raises(SampleError, match="1 distinct samples, at least 2"):
        sketchanim.reduce([0.0], [[1.0, 2.0]], 1e-6)


@pytest.mark.parametrize("n", [2, 3, 4, 5, 9])
def test_short_takes(n: int) -> None:
    t = np.arange(n) * 0.1
    x = np.c_[np.sin(t), t**2]
    sr = sketchanim.StreamReducer(2, 1e-6, window=5)
    sr.extend(t, x)
    r = sr.finish()
    assert within(r.spline(t), x, np.array([1e-6, 1e-6]))
