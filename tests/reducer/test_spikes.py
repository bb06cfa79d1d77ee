"""Pieces cut at pauses and breaks always join, whatever a lone sample next to them does:
a spike far outside the motion (within the documented range) beside a pause or a
break still gives a curve within tolerance, never an internal error; the reproducers in
../shared/repro (mutated real recordings) are reduced or refused by name."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import sketchanim
from sketchanim.errors import SampleError
from sketchanim.formats.csvio import read_samples_csv
from sketchanim.formats.recordings import read_svc, read_tum

from conftest import DATA
from signals import performances

REPRO = DATA.parent / "repro"


@settings(max_examples=40)
@given(performances(), st.integers(0, 2**32 - 1), st.floats(3.0, 11.0), st.integers(2, 5))
def test_a_spike_beside_a_feature_still_joins(perf, seed, exponent, order):
    # The class of the reproducers: a lone sample many orders of magnitude away, in a
    # piece whose ends are held by a pause or a break. Rounding at that magnitude must
    # not decide whether the pieces join.
    rng = np.random.default_rng(seed)
    x = perf.values.copy()
    i = int(rng.integers(1, len(x) - 1))
    x[i, int(rng.integers(x.shape[1]))] += rng.choice([-1.0, 1.0]) * perf.tol[0] * 10.0 ** exponent
    r = sketchanim.reduce(perf.times, x, perf.tol, order=order)
    err = np.abs(r.spline(perf.times) - x).max(axis=0)
    assert np.all(err <= perf.tol)


def _repro(name: str) -> Path:
    path = REPRO / name
    if not path.is_file():
        pytest.skip(f"reproducer not found at {path}")
    return path


@pytest.mark.realdata
def test_ngimu_spike_is_reduced_within_tolerance():
    table = read_samples_csv(_repro("pieces_ngimu_mutated.csv"))
    r = sketchanim.reduce(table.times, table.values, 1.0)
    assert np.all(np.abs(r.spline(table.times) - table.values) <= 1.0)


@pytest.mark.realdata
def test_pen_spike_beyond_the_range_is_named():
    d = read_svc(_repro("pieces_pen_mutated.svc"), columns=("y", "x", "t", "down", "az", "al", "p"), time_scale=1e-3)
    with pytest.raises(SampleError) as err:
        sketchanim.reduce(d["t"], np.c_[d["x"], d["y"]], 1.0)
    assert err.value.field == "channel 1" and err.value.index == 432


@pytest.mark.realdata
@pytest.mark.parametrize(("name", "index", "channel"), [("pieces_tum_mutated.txt", 474, 0),
                                                        ("linalg_tum_extreme.txt", 2905, 2)])
def test_tum_values_beyond_the_range_are_named(name, index, channel):
    t, p, _ = read_tum(_repro(name))
    with pytest.raises(SampleError) as err:
        sketchanim.reduce(t, p, 0.01)
    assert err.value.field == f"channel {channel}" and err.value.index == index


def test_numbers_out_of_range_are_named_in_batch_and_stream():
    t = np.arange(10.0)
    x = np.c_[np.sin(t), np.cos(t)]
    x[6, 1] = 1e308
    with pytest.raises(SampleError) as err:
        sketchanim.reduce(t, x, 0.01)
    assert (err.value.index, err.value.field) == (6, "channel 1")
    stream = sketchanim.StreamReducer(2, 0.01)
    stream.extend(t[:5], x[:5])
    with pytest.raises(SampleError) as err:
        stream.extend(t[5:], x[5:])
    assert (err.value.index, err.value.field) == (6, "channel 1")
    with pytest.raises(SampleError) as err:
        sketchanim.reduce(t * 1e300, x[:, :1], 0.01)
    assert (err.value.index, err.value.field) == (1, "time")
    # a wide but resolvable spread is reduced
    x[6, 1] = 1e9
    r = sketchanim.reduce(t, x, 0.01)
    assert np.all(np.abs(r.spline(t) - x) <= 0.01)
