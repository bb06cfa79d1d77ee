"""Gaps are kept as gaps, and no curve overshoots between samples: at the midpoint of
every sample interval the curve lies within the range of the four samples around it,
widened by the tolerance (both methods, hypothesis motion and every real recording)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import sketchanim
from sketchanim.reducer import FeatureOptions

from recordings import shared_cases
from signals import signals


def overshoot(reduction: sketchanim.Reduction, times: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Per interval, how far (in tolerances) the curve's midpoint lies outside the range
    of the four samples around it widened by the tolerance (<= 0: inside)."""
    x = values.reshape(len(times), -1)
    mid = np.asarray(reduction.spline(0.5 * (times[1:] + times[:-1]))).reshape(len(times) - 1, -1)
    idx = np.clip(np.arange(len(times) - 1)[:, None] + np.arange(-1, 3)[None, :], 0, len(times) - 1)
    around = x[idx]                                         # (n - 1, 4, d)
    tol = np.asarray(reduction.tol)
    out = np.maximum(mid - around.max(axis=1) - tol, around.min(axis=1) - tol - mid)
    return out / tol


@pytest.mark.parametrize("method", ["global", "incremental"])
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(sig=signals(max_n=200, min_n=12), gap_at=st.floats(0.1, 0.9),
       gap_len=st.one_of(st.just(0.0), st.floats(8, 200)))
def test_no_overshoot_between_samples(method, sig, gap_at, gap_len):
    times = sig.times.copy()
    step = np.median(np.diff(times))
    cut = int(gap_at * (len(times) - 1))
    times[cut + 1 :] += gap_len * step                      # a gap, or none
    r = sketchanim.reduce(times, sig.values, sig.tol, method=method)
    assert np.all(r.max_error <= sig.tol)
    assert np.all(overshoot(r, times, sig.values) <= 1e-9)
    if gap_len:
        assert any(f.kind in ("gap", "jump") and f.start == times[cut] for f in r.features), r.features


@pytest.mark.realdata
@pytest.mark.parametrize("method", ["global", "incremental"])
def test_no_overshoot_on_real_recordings(data_dir, method):
    for name, times, values, tol in shared_cases(data_dir):
        r = sketchanim.reduce(times, values, tol, method=method)
        worst = overshoot(r, times, values).max()
        assert worst <= 1e-9, f"{name}: the curve leaves the samples' range by {worst:.3g} tolerances"


def test_gap_is_bridged_between_its_sides():
    t = np.r_[np.linspace(0, 5, 501), np.linspace(17, 20, 301)]
    x = np.c_[np.sin(3 * t), np.cos(2 * t)]
    for method in ("global", "incremental"):
        r = sketchanim.reduce(t, x, 1e-3, method=method)
        assert [(f.kind, f.start, f.end) for f in r.features if f.kind == "gap"] == [("gap", 5.0, 17.0)]
        inside = r.spline(np.linspace(5, 17, 500))
        lo, hi = np.minimum(x[500], x[501]) - 1e-3, np.maximum(x[500], x[501]) + 1e-3
        assert np.all((inside >= lo) & (inside <= hi))
        assert np.all(r.max_error <= 1e-3)


def test_gap_cutting_can_be_turned_off():
    t = np.r_[np.linspace(0, 1, 50), np.linspace(9, 10, 50)]
    r = sketchanim.reduce(t, np.sin(t), 1e-3, features=FeatureOptions(gap=None))
    assert not any(f.kind == "gap" for f in r.features)
    with pytest.raises(ValueError, match="gap"):
        FeatureOptions(gap=0.5)


def test_a_step_across_a_gap_is_listed_as_the_gap():
    t = np.r_[np.linspace(0, 1, 50), np.linspace(9, 10, 50)]
    x = np.where(t < 5, 0.0, 3.0) + 0.1 * np.sin(t)
    r = sketchanim.reduce(t, x, 1e-3)
    assert [f.kind for f in r.features if f.start == 1.0] == ["gap"]
