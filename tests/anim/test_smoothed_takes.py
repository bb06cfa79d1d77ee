"""Smoothed takes: the curve holds the tolerance against the smoothed samples, the raw
samples stay in the take, the smoothing can be changed later; the recorder streams them
smoothed."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import EVENT, FLOAT, ORIENTATION, POSITION
from sketchanim.anim.layers import compose, recorded_over, resmoothed
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.anim.smoothed import smoothed_samples
from sketchanim.anim.tracks import Take
from sketchanim.errors import ArgumentError
from sketchanim.reducer.metric import rotation_angle
from sketchanim.reducer.smoothing import smooth
from tests.recordings import shared_cases
from tests.signals import performances


def jittered(n: int = 240, rate: float = 120.0, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A smooth 3-d path sampled at ``rate`` with timing jitter and 2 mm of hand jitter."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate + np.r_[0, rng.uniform(-0.3, 0.3, n - 2) / rate, 0]
    x = np.c_[np.sin(2 * t), 0.5 * t, np.cos(3 * t)] + rng.normal(0, 0.002, (n, 3))
    return t, x


@settings(max_examples=15)
@given(performances(dims=(3, 3)), st.sampled_from([0.01, 0.03, 0.1]))
def test_a_smoothed_take_holds_tol_against_its_smoothed_samples(perf, sigma):
    raw = perf.values.copy()
    take = Take(perf.times, perf.values, smoothing=sigma)
    tol = float(perf.tol[0])
    track = recorded_over("box.position", POSITION, None, take, tol, 4)
    assert np.abs(track.evaluate(perf.times) - smooth(perf.times, raw, sigma)).max() <= tol
    assert track.takes[0] is take and np.array_equal(take.values, raw)      # the raw samples are kept


def test_smoothing_takes_fewer_control_points_and_can_be_undone():
    t, x = jittered()
    take = Take(t, x)
    tol = 0.001
    raw = recorded_over("box.position", POSITION, None, take, tol, 4)
    smoothed = resmoothed(raw, 0.05, 4)
    assert smoothed.takes[0].smoothing == 0.05 and np.array_equal(smoothed.takes[0].values, x)
    assert np.abs(smoothed.evaluate(t) - smooth(t, x, 0.05)).max() <= tol
    assert np.abs(smoothed.evaluate(t) - x).max() > tol          # against the raw it need not hold
    assert smoothed.n_coefficients < raw.n_coefficients / 2
    back = resmoothed(smoothed, 0.0, 4)
    np.testing.assert_array_equal(back.spline.c, raw.spline.c)


def test_a_smoothed_punch_in_keeps_the_curve_outside_and_tol_inside():
    t, x = jittered()
    base = compose(POSITION, [Take(t, np.c_[np.sin(t), t, 0 * t])], 0.001, 4)
    inside = (t > 0.5) & (t < 1.5)
    take = Take(t[inside], x[inside], smoothing=0.03)
    curve = compose(POSITION, [Take(t, np.c_[np.sin(t), t, 0 * t]), take], 0.001, 4)
    outside = t < 0.4
    np.testing.assert_allclose(curve(t[outside]), base(t[outside]), atol=1e-12)
    mid = (t > 0.7) & (t < 1.3)                                   # past the fades
    target = smooth(t[inside], x[inside], 0.03)[(t[inside] > 0.7) & (t[inside] < 1.3)]
    assert np.abs(curve(t[mid]) - target).max() <= 0.001


def test_a_smoothed_orientation_stays_on_one_hemisphere_and_within_its_angle():
    t = np.linspace(0, 2, 241)
    rng = np.random.default_rng(3)
    q = Rotation.from_rotvec(np.c_[np.sin(t), 0.5 * t, 0 * t] + rng.normal(0, 0.005, (241, 3))).as_quat()
    q[::2] *= -1                                                  # every other sample signed the other way
    smoothed = smoothed_samples(ORIENTATION, t, q, 0.03)
    np.testing.assert_allclose(np.linalg.norm(smoothed, axis=1), 1.0)
    truth = Rotation.from_rotvec(np.c_[np.sin(t), 0.5 * t, 0 * t]).as_quat()
    assert np.degrees(rotation_angle(smoothed, truth)).max() < np.degrees(rotation_angle(q, truth)).max()
    track = recorded_over("box.orientation", ORIENTATION, None, Take(t, q, smoothing=0.03), 0.2, 4)
    assert np.degrees(rotation_angle(track.evaluate(t), smoothed)).max() <= 0.2 + 1e-9


@pytest.mark.parametrize("over", [False, True])
def test_the_recorder_streams_the_smoothed_samples_and_keeps_the_raw(over):
    scene = Scene()
    scene.add("box")
    rec = Recorder(scene)
    t, x = jittered(360)
    below = {}
    if over:
        rec.arm("box.position")
        rec.start()
        for ti in t:
            rec.push("box.position", ti, [np.sin(ti), ti, 0.0])
        below = rec.stop()
    rec.arm("box.position", tol=0.001, smoothing=0.04)
    rec.start(below)
    for i, ti in enumerate(t):
        rec.push_frame(ti, x[i]) if i % 2 else rec.push("box.position", ti, x[i])
    with warnings.catch_warnings():
        warnings.simplefilter("error")                            # the streamed curve, not a fallback
        track = rec.stop()["box.position"]
    take = track.takes[-1]
    assert take.smoothing == 0.04 and np.array_equal(take.values, x)
    assert len(track.takes) == 1 + over
    assert np.abs(track.evaluate(t) - smooth(t, x, 0.04)).max() <= 0.001      # the same span: no fades


def test_bad_smoothing_names_the_field():
    with pytest.raises(ArgumentError, match="smoothing"):
        Take(np.array([0.0, 1.0]), np.zeros((2, 1)), smoothing=-1.0)
    scene = Scene()
    scene.add("box")
    with pytest.raises(ArgumentError, match="smoothing"):
        Recorder(scene).arm("box.position", smoothing=float("nan"))
    scene.objects["box"].add("hit", EVENT)
    with pytest.raises(ArgumentError, match="smoothing"):
        Recorder(scene).arm("box.hit", smoothing=0.05)
    track = recorded_over("a.x", FLOAT, None, Take(np.array([0.0, 1.0]), np.zeros((2, 1))), 0.01, 4)
    with pytest.raises(ArgumentError, match="index"):
        resmoothed(track, 0.05, 4, index=3)


def test_real_pen_recording_smoothed_at_50_ms(data_dir):
    """A real pen recording (BDALab, mm, at its working tolerance): smoothed over 0.05 s,
    fewer control points than raw, and within tolerance of the smoothed samples."""
    name, t, xy, tol = next(c for c in shared_cases(data_dir) if c[0] == "BDALab pen (mm)")
    x = np.c_[xy, np.zeros(len(t))]
    raw = recorded_over("pen.position", POSITION, None, Take(t, x), tol, 4)
    smoothed = resmoothed(raw, 0.05, 4)
    err = np.abs(smoothed.evaluate(t) - smooth(t, x, 0.05)).max()
    print(f"{name}: {len(t)} samples, {raw.n_coefficients} control points raw, "
          f"{smoothed.n_coefficients} smoothed at 0.05 s (error {err:.4g} <= {tol})")
    assert err <= tol
    assert smoothed.n_coefficients < raw.n_coefficients


def test_the_recorder_streams_a_smoothed_orientation_as_the_batch_smooths_it():
    scene = Scene()
    scene.add("box")
    rec = Recorder(scene)
    rec.arm("box.orientation", tol=0.2, smoothing=0.03)
    t = np.arange(300) / 120
    rng = np.random.default_rng(5)
    q = Rotation.from_rotvec(np.c_[np.sin(t), 0.5 * t, 0 * t] + rng.normal(0, 0.004, (300, 3))).as_quat()
    q[1::3] *= -1                                                 # signs flipping as a device may send them
    rec.start()
    for ti, qi in zip(t, q):
        rec.push_frame(ti, qi)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        track = rec.stop()["box.orientation"]
    assert np.array_equal(track.takes[0].values, q)
    angle = np.degrees(rotation_angle(track.evaluate(t), smoothed_samples(ORIENTATION, t, q, 0.03)))
    assert angle.max() <= 0.2 + 1e-9
