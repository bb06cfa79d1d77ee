"""The curve editor's edits keep their promises on any spline: a moved point, a moved key
or a removed knot change the curve only on the spans they touch; a key lands where it was
put; the knots (so the continuity) stay as they were."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import ORIENTATION, POSITION
from sketchanim.anim.edits import moved_key, moved_points, with_knots, without_knots
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.errors import ArgumentError
from sketchanim.spline import derivative
from tests.anim.test_anim_model import random_spline

orders = st.sampled_from([2, 3, 4, 5])


def track_of(seed: int, order: int, n: int) -> ContinuousTrack:
    return ContinuousTrack("box.position", POSITION, random_spline(np.random.default_rng(seed), order, 3, n), 0.005)


def changed_only_within(before: ContinuousTrack, after: ContinuousTrack, lo: float, hi: float) -> None:
    """The two curves agree (to rounding) outside [lo, hi], sampled densely and at the knots."""
    t = np.unique(np.r_[np.linspace(before.start, before.end, 2001), before.spline.t])
    outside = (t < lo - 1e-9) | (t > hi + 1e-9)
    assert np.allclose(before.evaluate(t[outside]), after.evaluate(t[outside]), atol=1e-9, rtol=0)


@given(st.integers(0, 2**32 - 1), orders, st.integers(0, 12), st.lists(st.floats(-3, 3), min_size=3, max_size=3))
@settings(max_examples=60, deadline=None)
def test_a_moved_point_changes_the_curve_only_on_its_span(seed, order, n_extra, value) -> None:
    track = track_of(seed, order, order + n_extra)
    i = seed % track.n_coefficients
    moved = moved_points(track, {i: value})
    t = track.spline.t
    changed_only_within(track, moved, t[i], t[i + order])
    assert np.array_equal(moved.spline.t, t) and moved.edited and not track.edited
    assert np.allclose(moved.spline.c[i], value)


@given(st.integers(0, 2**32 - 1), orders, st.integers(0, 12), st.floats(0, 1),
       st.lists(st.floats(-3, 3), min_size=3, max_size=3), st.lists(st.floats(-5, 5), min_size=3, max_size=3),
       st.sampled_from(["value", "slope", "both"]))
@settings(max_examples=80, deadline=None)
def test_a_moved_key_lands_where_it_is_put_and_changes_only_the_spans_around_it(seed, order, n_extra, at, value,
                                                                                 slope, what) -> None:
    track = track_of(seed, order, order + n_extra)
    time = track.start + at * (track.end - track.start)
    want_value = value if what != "slope" else None
    want_slope = slope if what != "value" and order > 1 else None
    if want_value is None and want_slope is None:
        want_value = value
    s = track.spline
    k, knots = s.k, np.asarray(s.t)
    span = int(np.clip(np.searchsorted(knots, time, side="right") - 1, k, len(knots) - k - 2))
    basis = BSpline(knots, np.eye(len(s.c)), k)
    rows = [r for r, wanted in ((basis(time), want_value), (derivative(basis)(time), want_slope)) if wanted is not None]
    reachable = np.linalg.matrix_rank(np.array(rows)) == len(rows)     # e.g. no slope but 0 where a linear piece ends
    keyed = moved_key(track, time, want_value, want_slope)
    changed_only_within(track, keyed, knots[span - k], knots[span + k + 1])
    assert np.array_equal(keyed.spline.t, knots)
    if reachable and want_value is not None:
        assert np.allclose(keyed.spline(time), want_value, atol=1e-7)
    if reachable and want_slope is not None:
        assert np.allclose(derivative(keyed.spline)(time), want_slope, atol=1e-6)


@given(st.integers(0, 2**32 - 1), orders, st.integers(1, 12))
@settings(max_examples=60, deadline=None)
def test_a_removed_knot_changes_the_curve_only_on_the_spans_it_bounded(seed, order, n_extra) -> None:
    track = track_of(seed, order, order + n_extra)
    knots = np.asarray(track.spline.t)
    inner = [j for j in range(order, len(knots) - order) if knots[order - 1] < knots[j] < knots[-order]]
    if not inner:
        return
    j = inner[seed % len(inner)]
    fewer = without_knots(track, [j])
    assert fewer.n_coefficients == track.n_coefficients - 1
    assert np.array_equal(fewer.spline.t, np.delete(knots, j))
    changed_only_within(track, fewer, knots[j - order], knots[j + order])


@given(st.integers(0, 2**32 - 1), orders, st.integers(0, 8), st.lists(st.floats(0.01, 0.99), min_size=1, max_size=4))
@settings(max_examples=40, deadline=None)
def test_inserted_knots_keep_the_curve(seed, order, n_extra, where) -> None:
    track = track_of(seed, order, order + n_extra)
    times = [track.start + w * (track.end - track.start) for w in where]
    more = with_knots(track, times)
    t = np.linspace(track.start, track.end, 500)
    assert more.n_coefficients == track.n_coefficients + len(times)
    assert np.allclose(more.evaluate(t), track.evaluate(t), atol=1e-9)


def test_an_orientation_key_takes_a_unit_quaternion_on_the_curves_side_and_no_slope() -> None:
    rng = np.random.default_rng(4)
    s = random_spline(rng, 4, 4, 9)
    c = np.array(s.c) + [0, 0, 0, 3]
    track = ContinuousTrack("box.orientation", ORIENTATION, BSpline(s.t, c, 3), 0.5)
    q = np.array([0.0, 0.0, np.sin(0.3), np.cos(0.3)])
    side = -q if np.dot(q, track.spline(2.0)) < 0 else q
    keyed = moved_key(track, 2.0, -side)            # the same rotation, the other sign
    assert np.allclose(keyed.evaluate([2.0])[0], side, atol=1e-9)
    with pytest.raises(ArgumentError, match="value only"):
        moved_key(track, 2.0, None, [0, 0, 0, 1])
    with pytest.raises(ArgumentError, match="within"):
        moved_key(track, 99.0, q)


@pytest.mark.realdata
def test_edits_of_a_real_camera_path_stay_local(data_dir):
    from sketchanim.anim.layers import recorded_over
    from sketchanim.anim.tracks import Take
    from sketchanim.formats.recordings import read_tum

    t, pos, _ = read_tum(data_dir / "camera" / "freiburg1_xyz-groundtruth.txt")
    track = recorded_over("cam.position", POSITION, None, Take(t - t[0], pos), 0.002, 4)
    knots, order = np.asarray(track.spline.t), track.spline.k + 1
    i = track.n_coefficients // 2
    changed_only_within(track, moved_points(track, {i: track.spline.c[i] + 0.05}), knots[i], knots[i + order])
    time = float(knots[i + 1] + 0.3 * (knots[i + 2] - knots[i + 1]))
    keyed = moved_key(track, time, track.evaluate([time])[0] + 0.02, [0.1, 0, 0])
    span = int(np.searchsorted(knots, time, side="right") - 1)
    changed_only_within(track, keyed, knots[span - order + 1], knots[span + order])
    assert np.allclose(keyed.evaluate([time])[0], track.evaluate([time])[0] + 0.02)
    j = i + 2
    changed_only_within(track, without_knots(track, [j]), knots[j - order], knots[j + order])
