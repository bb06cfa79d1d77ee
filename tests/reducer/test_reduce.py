"""sketchanim.reduce: the tolerance holds at every sample, timing is kept, bad input is named."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import sketchanim
from sketchanim.errors import ArgumentError, InputError, SampleError
from sketchanim.paper import spiral
from sketchanim.reducer import Reduction

from signals import signals


def _most_coefficients(r: Reduction, n: int) -> int:
    """No more control points than samples (or the order), but for the bridges at
    jumps and where the curve would swing (each bridge, and each of the runs
    between them, may add order - 2)."""
    cuts = sum(f.kind in ("gap", "jump") for f in r.features)
    return max(n, r.order) + (r.order - 2) * (2 * cuts + 1) if cuts else max(n, r.order)


def _check_guarantee(r: Reduction, times: np.ndarray, values: np.ndarray, tol: np.ndarray) -> None:
    got = np.asarray(r.spline(times)).reshape(len(times), -1)
    err = np.abs(got - values.reshape(len(times), -1)).max(axis=0)
    assert np.all(err <= tol), f"error {err} over tolerance {tol}"
    assert np.allclose(err, r.max_error, rtol=1e-12, atol=0)
    # Time is the parameter: the curve spans exactly the take.
    k = r.spline.k
    assert r.spline.t[k] == times[0] and r.spline.t[-k - 1] == times[-1]


@given(signals(), st.integers(2, 5))
def test_every_sample_is_within_tolerance(sig, order):
    r = sketchanim.reduce(sig.times, sig.values, sig.tol, order=order)
    _check_guarantee(r, sig.times, sig.values, sig.tol)
    assert r.n_coefficients <= _most_coefficients(r, len(sig.times))
    assert r.order == order


@settings(max_examples=30)
@given(signals(max_n=200), st.integers(2, 5), st.sampled_from([0.0, 0.1, 0.5]))
def test_lm_start_keeps_the_guarantee(sig, order, split):
    r = sketchanim.reduce(sig.times, sig.values, sig.tol, order=order, start="lm", split=split)
    _check_guarantee(r, sig.times, sig.values, sig.tol)
    assert r.n_coefficients <= _most_coefficients(r, len(sig.times))


def test_lm_start_never_returns_more_control_points_than_samples():
    # Ten jumpy samples: the raised linear curve has 19 coefficients and nothing can go.
    t = np.arange(10) * 1e-3
    x = np.array([-0.35, 0.75, 0.25, -0.35, -1.19, 1.0, 0.32, -1.13, -4.84, 0.16])
    # Where the curve would swing between them, the intervals are bridged: a few more.
    r = sketchanim.reduce(t, x, 0.007, order=3, start="lm")
    _check_guarantee(r, t, x, np.array([0.007]))
    assert r.n_coefficients <= _most_coefficients(r, 10)


@settings(max_examples=25)
@given(signals(min_n=150, max_n=600, dims=(1, 3)), st.integers(2, 5))
def test_coarse_first_pass_keeps_the_guarantee(sig, order):
    # features off: pieces cut at pauses and breaks may be too short for a coarse pass
    r = sketchanim.reduce(sig.times, sig.values, sig.tol, order=order, coarse_samples=60, features=False)
    assert r.report["coarse_pass"]
    _check_guarantee(r, sig.times, sig.values, sig.tol)


def test_dense_noisy_take_repairs_the_coarse_curve():
    # The thinned copy misses some noise extremes; the repair refines knots there.
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 60.0, 6000)
    x = np.c_[np.sin(t / 5), 0.02 * t] + rng.normal(0.0, 0.01, (len(t), 2))
    r = sketchanim.reduce(t, x, 0.035, coarse_samples=1000, features=False)
    assert r.report["coarse_outcome"] == "repaired"
    _check_guarantee(r, t, x, np.array([0.035, 0.035]))
    assert r.n_coefficients < 100


@settings(max_examples=25)
@given(signals(max_n=150), st.integers(-9, 9))
def test_any_magnitude_works_alike(sig, exponent):
    # Everything runs in tolerance units, so only rounding of borderline accept/reject
    # decisions can differ between magnitudes.
    s = 10.0 ** exponent
    a = sketchanim.reduce(sig.times, sig.values, sig.tol)
    b = sketchanim.reduce(sig.times, sig.values * s, sig.tol * s)
    _check_guarantee(b, sig.times, sig.values * s, sig.tol * s)
    assert abs(b.n_coefficients - a.n_coefficients) <= max(1, a.n_coefficients // 10)


def test_spiral_needs_no_more_control_points_than_sisl():
    # SISL s1961 / s1940 give 18 on this case (benchmarks/bench_global.py measures it).
    t, x = spiral(1000)
    r = sketchanim.reduce(t, x, 0.1)
    _check_guarantee(r, t, x, np.array([0.1, 0.1]))
    assert r.n_coefficients <= 18


def test_constant_signal_is_one_polynomial_piece():
    t = np.linspace(0, 3, 50)
    r = sketchanim.reduce(t, np.full((50, 2), 7.25), 1e-6)
    assert r.n_coefficients == 4 and np.all(r.spline.c == 7.25)
    # evaluation sums B-splines that add up to one up to rounding: a few ulps of 7.25
    assert np.all(r.max_error <= 8 * np.spacing(7.25))


@pytest.mark.parametrize("order", [2, 3, 4, 5])
def test_two_samples_give_the_line_through_them(order):
    r = sketchanim.reduce([1.0, 3.0], [[0.0, 10.0], [4.0, 10.0]], 1e-9, order=order)
    assert r.order == order
    assert np.allclose(r.spline([1.0, 2.0, 3.0]), [[0, 10], [2, 10], [4, 10]], atol=1e-12)


def test_scalar_channel_evaluates_to_a_vector():
    t = np.linspace(0, 1, 30)
    r = sketchanim.reduce(t, np.sin(t), 1e-4)
    assert r.spline(t).shape == (30,)


def test_exact_duplicates_are_dropped_and_counted():
    t = [0.0, 0.1, 0.1, 0.2, 0.3, 0.3, 0.4]
    x = [0.0, 1.0, 1.0, 0.5, 0.2, 0.2, 0.0]
    r = sketchanim.reduce(t, x, 1e-3)
    assert r.report["duplicates_dropped"] == 2 and r.n_samples == 5


@pytest.mark.parametrize(
    ("times", "values", "tol", "match", "index"),
    [
        ([0, 1, np.nan, 3], [0, 1, 2, 3], 0.1, "sample 2, time", 2),
        ([0, 1, 2, 3], [[0, 0], [1, np.inf], [2, 2], [3, 3]], 0.1, "sample 1, channel 1", 1),
        ([0, 1, 0.5, 3], [0, 1, 2, 3], 0.1, "sample 2, time: time goes backwards", 2),
        ([0, 1, 1, 3], [0, 1, 2, 3], 0.1, "sample 2, time: same time 1.0 as sample 1", 2),
        ([0.0, 0.0], [1.0, 1.0], 0.1, "1 distinct samples, at least 2", None),
    ],
)
def test_bad_samples_are_named(times, values, tol, match, index):
    with pytest.raises(SampleError, match=match) as info:
        sketchanim.reduce(times, values, tol)
    assert info.value.index == index


@pytest.mark.parametrize(
    ("kwargs", "argument"),
    [
        ({"tol": 0.0}, "tol"),
        ({"tol": -1.0}, "tol"),
        ({"tol": [0.1, np.nan]}, "tol"),
        ({"tol": [0.1, 0.1, 0.1]}, "tol"),
        ({"order": 1}, "order"),
        ({"order": 3.5}, "order"),
        ({"method": "magic"}, "method"),
        ({"start": "middle"}, "start"),
        ({"split": 1.0}, "split"),
        ({"minimax_iterations": -1}, "minimax_iterations"),
        ({"exhaustive_below": 2.5}, "exhaustive_below"),
        ({"coarse_samples": 3}, "coarse_samples"),
        ({"values": [[1, 2], [3, 4], [5, 6]]}, "values"),
        ({"values": [["a", "b"]] * 4}, "values"),
        ({"times": [[0, 1, 2, 3]]}, "times"),
    ],
)
def test_bad_arguments_are_named(kwargs, argument):
    args = {"times": [0, 1, 2, 3], "values": [[0, 0], [1, 1], [2, 0], [3, 1]], "tol": 0.1, **kwargs}
    times, values, tol = args.pop("times"), args.pop("values"), args.pop("tol")
    with pytest.raises(ArgumentError) as info:
        sketchanim.reduce(times, values, tol, **args)
    assert info.value.argument == argument
    assert isinstance(info.value, ValueError)


@given(signals(max_n=80))
def test_json_round_trip(sig):
    r = sketchanim.reduce(sig.times, sig.values, sig.tol)
    back = Reduction.from_json(r.to_json())
    assert np.array_equal(back.spline.t, r.spline.t)
    assert np.array_equal(back.spline.c, r.spline.c)
    assert np.array_equal(back.max_error, r.max_error) and back.n_samples == r.n_samples


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (lambda d: d.update(schema="other"), "not a sketchanim.reduction"),
        (lambda d: d.update(version=99), "version 99"),
        (lambda d: d.pop("knots"), "'knots' is missing"),
        (lambda d: d.update(knots=d["knots"][::-1]), "'knots' must be non-decreasing"),
        (lambda d: d.update(coefficients="x"), "'coefficients' must be numbers"),
        (lambda d: d.update(order=0), "'order'"),
        (lambda d: d.update(tol=[0.1, 0.1]), r"'tol' and 'max_error' need 1 value\(s\) for metric 'channels'"),
        (lambda d: d.update(metric="rotation"), "'metric' must be 'channels', or 'rotation' with 4 channels"),
    ],
)
def test_json_errors_name_the_field(edit, match):
    import json

    t = np.linspace(0, 1, 20)
    doc = json.loads(sketchanim.reduce(t, np.sin(3 * t), 1e-3).to_json())
    edit(doc)
    with pytest.raises(InputError, match=match):
        Reduction.from_json(json.dumps(doc), source="take.json")


def test_json_syntax_error_names_the_line():
    with pytest.raises(InputError, match="take.json, line 2"):
        Reduction.from_json('{\n  "schema": ,\n}', source="take.json")
