"""Smoothing before reduction: properties of the batch and streaming smoothers."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.errors import ArgumentError
from sketchanim.reducer.smoothing import REACH, StreamSmoother, smooth


@st.composite
def takes(draw, min_size: int = 2):
    """Irregular increasing times (gaps from 1 ms to 0.2 s), values in 1-3 channels."""
    n = draw(st.integers(min_size, 80))
    gaps = draw(st.lists(st.floats(0.001, 0.2), min_size=n - 1, max_size=n - 1))
    t = draw(st.floats(-10, 10)) + np.r_[0.0, np.cumsum(gaps)]
    dim = draw(st.integers(1, 3))
    x = np.array(draw(st.lists(st.lists(st.floats(-100, 100), min_size=dim, max_size=dim),
                               min_size=n, max_size=n)))
    return t, x


sigmas = st.floats(0.001, 0.3)


@given(takes(), sigmas)
def test_lines_and_constants_are_kept(take, sigma):
    t, x = take
    a, b = x[0], x[-1]
    line = a + np.outer(t - t[0], b - a)
    scale = 1 + np.abs(line).max()
    np.testing.assert_allclose(smooth(t, line, sigma), line, atol=1e-7 * scale)
    np.testing.assert_array_equal(smooth(t, np.tile(a, (len(t), 1)), sigma), np.tile(a, (len(t), 1)))


@given(takes(), sigmas, st.data())
def test_stream_is_the_batch(take, sigma, data):
    t, x = take
    cuts = sorted(data.draw(st.lists(st.integers(0, len(t)), max_size=6)))
    s = StreamSmoother(x.shape[1], sigma)
    parts = [s.push(t[a:b], x[a:b]) for a, b in zip([0, *cuts], [*cuts, len(t)])]
    parts.append(s.close())
    np.testing.assert_array_equal(np.concatenate([p[0] for p in parts]), t)
    np.testing.assert_array_equal(np.vstack([p[1] for p in parts]), smooth(t, x, sigma))


@given(takes(), sigmas)
def test_stream_holds_back_only_the_window(take, sigma):
    """A sample comes out as soon as a sample 3 sigma later is in, and memory stays
    within the window."""
    t, x = take
    s = StreamSmoother(x.shape[1], sigma)
    out = 0
    for i in range(len(t)):
        out += len(s.push(t[i : i + 1], x[i : i + 1])[0])
        assert out == np.count_nonzero(t[: i + 1] + REACH * sigma <= t[i])
        assert np.all(s._t >= t[out if out <= i else i] - REACH * sigma - 1e-12)


@given(takes(), sigmas)
def test_no_new_overshoot(take, sigma):
    t, x = take
    y = smooth(t, x, sigma)
    for i in range(len(t)):
        near = (t >= t[i] - REACH * sigma) & (t <= t[i] + REACH * sigma)     # the window, as the smoother rounds it
        assert np.all(y[i] >= x[near].min(axis=0)) and np.all(y[i] <= x[near].max(axis=0))


@given(takes(), st.sampled_from([0, 0.0, None]))
def test_zero_is_the_identity(take, sigma):
    t, x = take
    np.testing.assert_array_equal(smooth(t, x, sigma), x)
    s = StreamSmoother(x.shape[1], sigma)
    got = s.push(t, x)
    np.testing.assert_array_equal(got[1], x)
    assert len(s.close()[0]) == 0


def test_jitter_is_reduced():
    """White jitter on a smooth path: the smoothed samples are closer to the path."""
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.005, 0.03, 300))
    path = np.c_[np.sin(2 * t), np.cos(t)]
    noisy = path + rng.normal(0, 0.01, path.shape)
    inner = slice(20, -20)
    before = np.sqrt(np.mean((noisy - path)[inner] ** 2))
    after = np.sqrt(np.mean((smooth(t, noisy, 0.03) - path)[inner] ** 2))
    assert after < 0.6 * before


@pytest.mark.parametrize("sigma", [-0.1, float("nan"), float("inf"), "x"])
def test_bad_sigma_names_the_field(sigma):
    with pytest.raises(ArgumentError, match="sigma"):
        smooth([0.0, 1.0], [[0.0], [1.0]], sigma)
    with pytest.raises(ArgumentError, match="sigma"):
        StreamSmoother(1, sigma)


def test_bad_samples_name_the_argument():
    with pytest.raises(ArgumentError, match="times"):
        smooth([0.0, 0.0], [[0.0], [1.0]], 0.1)
    with pytest.raises(ArgumentError, match="values"):
        smooth([0.0, 1.0], [[0.0]], 0.1)
    s = StreamSmoother(1, 0.1)
    s.push([0.0, 1.0], [[0.0], [1.0]])
    with pytest.raises(ArgumentError, match="times"):
        s.push([0.5], [[0.0]])
    with pytest.raises(ArgumentError, match="values"):
        s.push([2.0], [[0.0, 1.0]])


@settings(max_examples=20)
@given(st.floats(0.01, 0.1), st.sampled_from([120.0, 240.0, 1000.0]))
def test_half_power_at_0_13_over_sigma(sigma, rate):
    """The width the docs give: motion at 0.1325 / sigma Hz keeps half its power."""
    t = np.arange(int(40 * sigma * rate)) / rate
    x = np.c_[np.sin(2 * np.pi * 0.1325 / sigma * t)]
    inner = slice(int(4 * sigma * rate), -int(4 * sigma * rate))
    ratio = np.sqrt(np.mean(smooth(t, x, sigma)[inner] ** 2) / np.mean(x[inner] ** 2))
    assert abs(ratio - np.sqrt(0.5)) < 0.02
