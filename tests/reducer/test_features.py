"""Pauses and breaks: found, held exactly still / kept as corners, tolerance on both sides,
streaming = batch, in both reducers and for rotations."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

import sketchanim
from sketchanim import FeatureOptions, Reduction
from sketchanim.errors import ArgumentError, InputError
from sketchanim.reducer.features import Feature
from sketchanim.reducer.swing import excess, local_ranges
from sketchanim.reducer.features import FeatureDetector
from sketchanim.reducer.splice import hold, join
from signals import Performance, performances

METHODS = ("global", "incremental")


def one_sided(spline: BSpline, c: float) -> tuple[np.ndarray, np.ndarray]:
    """The derivative at ``c`` from the left and from the right: scipy evaluates at a
    knot on the interval to its right, so the left one is the mirrored curve's."""
    mirrored = BSpline(-np.asarray(spline.t)[::-1], np.asarray(spline.c)[::-1], spline.k)
    return -mirrored.derivative()(-c), spline.derivative()(c)


def bridged(spline: BSpline, f: Feature) -> bool:
    """Whether ``spline`` is straight on the feature's span, or C1 at both its ends."""
    d = spline.derivative()
    inside = np.asarray(d(np.linspace(f.start, f.end, 9)[1:-1]))
    scale = 1e-7 * (1 + np.abs(inside).max())
    if np.all(np.abs(inside - inside[0]) <= scale):
        return True
    return all(np.allclose(*one_sided(spline, c), rtol=1e-6, atol=scale) for c in (f.start, f.end))


def check_features(r: Reduction, p: Performance) -> None:
    """Every promise about the features of ``r``, reduced from ``p``."""
    x = p.values
    err = np.abs(r.spline(p.times).reshape(x.shape) - x).max(axis=0)
    assert np.all(err <= p.tol), (err, p.tol)
    assert np.all(r.max_error <= p.tol)
    k = r.order
    knots = np.asarray(r.spline.t)
    for f in r.features:
        assert f.kind in ("pause", "break", "gap", "jump")
        assert p.times[0] <= f.start <= f.end <= p.times[-1]
        if f.kind in ("gap", "jump"):
            # bridged between the two sides: no sample in between, no swing, straight or C1
            assert not np.any((p.times > f.start) & (p.times < f.end))
            assert bridged(r.spline, f)
            i = int(np.searchsorted(p.times, f.start))
            lo, hi = local_ranges(x.reshape(len(p.times), -1), p.tol)
            room = excess(r.spline, p.times[i : i + 2], lo[i : i + 1], hi[i : i + 1])
            assert np.all(room <= 1e-9 * (1 + np.abs(x).max())), (f, room)
        elif f.kind == "pause":
            assert f.end > f.start
            inside = np.linspace(f.start, f.end, 50)[1:-1]
            # zero velocity, not a wobble: every coefficient acting there is the same
            assert np.all(r.spline.derivative()(inside) == 0.0)
            value = r.spline(inside)
            np.testing.assert_allclose(value, np.broadcast_to(value[0], value.shape), rtol=0, atol=1e-12 * (
                1 + np.abs(value).max()))
        else:
            assert np.count_nonzero(knots == f.start) >= k - 1
            left, right = one_sided(r.spline, f.start)
            assert not np.allclose(left, right, rtol=1e-9, atol=0), (left, right)


@given(performances(), st.sampled_from(METHODS))
@settings(max_examples=40)
def test_pauses_flat_breaks_sharp_tolerance_everywhere(p: Performance, method: str) -> None:
    r = sketchanim.reduce(p.times, p.values, p.tol, method=method)
    check_features(r, p)


@given(performances(), st.lists(st.integers(1, 60), min_size=1, max_size=12))
@settings(max_examples=30)
def test_streaming_with_features_equals_batch_and_pieces_match(p: Performance, chunks: list[int]) -> None:
    pieces = []
    sr = sketchanim.StreamReducer(p.values.shape[1], p.tol, on_piece=pieces.append, grow=True)
    i, c = 0, 0
    while i < len(p.times):
        step = chunks[c % len(chunks)]
        sr.extend(p.times[i : i + step], p.values[i : i + step])
        i, c = i + step, c + 1
    streamed = sr.finish()
    # the stream is the batch without its cuts at jumps (it keeps the no-swing bound itself)
    batch = sketchanim.reduce(p.times, p.values, p.tol, method="incremental", features=FeatureOptions(jumps=False))
    np.testing.assert_array_equal(streamed.spline.t, batch.spline.t)
    np.testing.assert_array_equal(streamed.spline.c.reshape(batch.spline.c.shape), batch.spline.c)
    assert streamed.features == batch.features
    check_features(streamed, p)
    # each piece is the final curve on its span, and they tile the take
    assert pieces[0].start == p.times[0] and pieces[-1].end == p.times[-1]
    for a, b in zip(pieces, pieces[1:]):
        assert a.end == b.start
    for piece in pieces:
        m = (p.times >= piece.start) & (p.times <= piece.end)
        if m.any():
            np.testing.assert_allclose(piece.spline(p.times[m]), streamed.spline(p.times[m]).reshape(m.sum(), -1),
                                       rtol=0, atol=1e-9 * (1 + np.abs(p.values).max()))


def test_planted_hold_and_corner_are_found() -> None:
    t = np.arange(0, 4, 1 / 120)
    x = np.c_[np.where(t < 1, t, 1.0) + np.where(t > 2, (t - 2) * 1.5, 0.0), np.where(t > 3, 3 - t, 0.0)]
    x[t > 3, 0] = 2.5 - (t[t > 3] - 3) * 2.0              # the move turns sharply at t = 3
    for method in METHODS:
        r = sketchanim.reduce(t, x, 1e-3, method=method)
        kinds = [(f.kind, round(f.start, 2), round(f.end, 2)) for f in r.features]
        assert kinds == [("pause", 1.0, 2.0), ("break", 3.0, 3.0)], kinds
        off = sketchanim.reduce(t, x, 1e-3, method=method, features=False)
        assert not any(f.kind in ("pause", "break") for f in off.features)
        assert r.n_coefficients < off.n_coefficients


def test_switches_and_thresholds() -> None:
    t = np.arange(0, 3, 1 / 120)
    x = np.c_[np.where(t < 1, t, 1.0)]                  # stops dead at 1, holds 2 s
    assert [f.kind for f in sketchanim.reduce(t, x, 1e-3).features] == ["pause"]
    assert sketchanim.reduce(t, x, 1e-3, features=FeatureOptions(pauses=False)).features[0].kind == "break"
    # a dead stop is left to the pause that follows; if it is too short to be one, the
    # corner is not kept either (the tolerance still holds)
    assert sketchanim.reduce(t, x, 1e-3, features=FeatureOptions(min_pause=2.5)).features == ()
    with pytest.raises(ArgumentError, match="min_pause"):
        FeatureOptions(min_pause=0)
    with pytest.raises(ArgumentError, match="break_window"):
        FeatureOptions(break_window=1)
    with pytest.raises(ArgumentError, match="features"):
        sketchanim.reduce(t, x, 1e-3, features="yes")


@given(st.integers(0, 2**32 - 1), st.sampled_from(["quaternion", "euler"]))
@settings(max_examples=20)
def test_rotation_holds_exactly_still(seed: int, mode: str) -> None:
    rng = np.random.default_rng(seed)
    t = np.arange(0, 3, 1 / 120)
    s = np.clip(t, 0.0, 1.0) + np.clip(t - 2.0, 0.0, None)   # turn, hold from 1 to 2, turn
    axis = rng.normal(0, 1, 3)
    speed = rng.uniform(0.3, 6.0)                            # rad/s: a move, not an idle drift
    q = Rotation.from_rotvec(np.outer(s, speed * axis / np.linalg.norm(axis))).as_quat()
    q *= rng.choice([-1.0, 1.0], len(q))[:, None]            # sign flips
    for method in METHODS:
        r = sketchanim.reduce_rotations(t, q, 0.5, mode=mode, method=method)
        pauses = [f for f in r.features if f.kind == "pause"]
        assert len(pauses) == 1 and pauses[0].start <= 1.01 and pauses[0].end >= 1.99, r.features
        inside = np.linspace(pauses[0].start, pauses[0].end, 20)[1:-1]
        assert np.all(r.spline.derivative()(inside) == 0.0)
        if mode == "quaternion":
            got = Rotation.from_quat(r.spline(t))
            assert np.degrees((got.inv() * Rotation.from_quat(q)).magnitude()).max() <= 0.5


def test_features_in_json_round_trip_and_bad_ones_named() -> None:
    t = np.arange(0, 3, 1 / 120)
    r = sketchanim.reduce(t, np.c_[np.where(t < 1, t, 1.0)], 1e-3)
    back = Reduction.from_json(r.to_json())
    assert back.features == r.features and back.features
    doc = r.to_json().replace('"kind": "pause"', '"kind": "nap"')
    with pytest.raises(InputError, match="features.*item 0"):
        Reduction.from_json(doc)


def test_join_refuses_pieces_that_do_not_meet() -> None:
    a = hold(0.0, 1.0, [1.0], 4)
    with pytest.raises(ArgumentError, match="piece 1"):
        join([a, hold(1.0, 2.0, [2.0], 4)])
    assert join([a, hold(1.0, 2.0, [1.0], 4)])(np.array([0.0, 1.5, 2.0])).tolist() == [[1.0], [1.0], [1.0]]


def test_idle_drift_is_not_a_pause_stops_after_moves_are_even_far_into_a_stream() -> None:
    """A channel drifting within a few tolerances has no pauses (but at the take's start);
    a stop after a move is one, wherever it falls in a long stream (the detector drops
    old samples on the way)."""
    tol = 1e-3
    t = np.arange(0, 120, 1 / 120)
    x = 1.5 * tol * np.sin(0.7 * t)                    # idling: a drift over 3 tolerances
    stops = np.arange(10.0, 120.0, 20.0)
    for s in stops:                                    # a 0.5 s move of 50 tolerances, then still
        x += 50 * tol * np.clip((t - s) / 0.5, 0, 1)
        x[(t > s + 0.5) & (t < s + 2.5)] = x[np.searchsorted(t, s + 0.5)]
    x = np.c_[x]
    sr = sketchanim.StreamReducer(1, tol, keep=True)
    held_back = 0
    for i in range(0, len(t), 97):
        sr.extend(t[i : i + 97], x[i : i + 97])
        held_back = max(held_back, sr.pending)
    streamed = sr.finish()
    assert held_back <= 2.5 * 120 + 97               # bounded look-ahead: about a pause and a call
    batch = sketchanim.reduce(t, x, tol, method="incremental")
    assert streamed.features == batch.features
    pauses = [f for f in batch.features if f.kind == "pause"]
    assert pauses[0].start == 0.0                      # the take starts still: a pause
    assert len(pauses) == 1 + len(stops), pauses
    for f, s in zip(pauses[1:], stops):
        assert s + 0.45 <= f.start <= s + 0.55 and f.end >= s + 2.4, (f, s)
    check_features(batch, Performance(t, x, np.array([tol]), [], []))


@pytest.mark.parametrize("idle", [0.0, 2e-3])
def test_detector_memory_and_look_ahead_stay_bounded_while_the_take_holds_still(idle: float) -> None:
    """A move, then two minutes of stillness (one long pause) or of idling (no pause after
    the first), one sample per call: the detector's store and what it holds back stay
    bounded."""
    t = np.arange(0, 120, 1 / 120)
    x = np.c_[np.minimum(t, 1.0) + idle * np.sin(0.7 * t)]    # a move, then still or idling
    det = FeatureDetector(1, np.array([1e-3]), 4, FeatureOptions())
    stored = pending = 0
    for i in range(len(t)):
        det.extend(t[i : i + 1], x[i : i + 1])
        stored, pending = max(stored, det.stored), max(pending, det.pending)
    det.close()
    assert stored <= 4096 + 2 * 120 and pending <= 120     # the store slides at 4096
    # the stop after the move is a pause: to the end, or until the idling leaves its band
    assert [f.kind for f in det.found] == ["pause"] and det.found[0].start == pytest.approx(1.0, abs=0.01)
    assert det.found[0].end == t[-1] if idle == 0 else det.found[0].end < 10
