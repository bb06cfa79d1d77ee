"""Attribute bounds: refused outside them, kept by the recorder's tracks (no swing past
the samples either), by additive takes and punch-ins, and by what the player plays."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import BOUNDS, COLOR, FLOAT, FOV, INTENSITY, POSITION, SCALE, TYPES
from sketchanim.anim.layers import Take, punch_in
from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.errors import ArgumentError, SampleError
from sketchanim.reducer import swing


def lamp_scene() -> Scene:
    s = Scene()
    s.add("lamp", "light")
    s.add("cam", "camera")
    return s


def test_every_default_is_within_its_bounds_and_the_bounds_are_named() -> None:
    assert set(BOUNDS) == {"color", "intensity", "fov", "scale"}
    for kind in TYPES.values():
        if kind.continuous:
            assert kind.check(kind.default) is not None
    assert POSITION.bounds is None and FLOAT.bounds is None
    assert SCALE.bounds[0] > 0 and FOV.bounds == (1.0, 179.0)


@pytest.mark.parametrize("kind, value", [(COLOR, [1.0, 1.2, 0.0]), (COLOR, [-0.01, 0.5, 0.5]), (INTENSITY, [-1e-9]),
                                         (FOV, [180.0]), (FOV, [0.5]), (SCALE, [1.0, 0.0, 1.0])])
def test_a_value_outside_the_bounds_is_refused_naming_it(kind, value) -> None:
    with pytest.raises(ArgumentError, match=rf"lamp\.x: a {kind.name} keeps every channel in .*got \["):
        kind.check(value, "lamp.x")
    assert kind.check(value, "lamp.x", bounded=False).tolist() == value       # an additive take's offset


def record(path: str, times: np.ndarray, values: np.ndarray, tol: float, mode: str = "replace",
           framed: bool = False, sc: Scene | None = None, over: dict | None = None):
    sc = sc or lamp_scene()
    rec = Recorder(sc)
    rec.arm(path, tol=tol, mode=mode)
    rec.start(over)
    for t, x in zip(times, values):
        if framed:
            rec.push_frame(t, x)
        else:
            rec.push(path, t, x)
    return rec.stop()[path]


def no_swing(track: ContinuousTrack, times: np.ndarray, values: np.ndarray, tol: float) -> float:
    """How far the track leaves the local range of its samples, cut to its bounds, in
    tolerances (exactly)."""
    s = track.spline
    c = np.asarray(s.c).reshape(len(s.c), -1)
    lo, hi = swing.local_ranges(values, np.full(values.shape[1], tol),
                                tuple(np.full(values.shape[1], b) for b in track.type.bounds))
    return float(swing.excess(BSpline(s.t, c, s.k), times, lo, hi).max() / tol)


@settings(max_examples=15)
@given(st.integers(0, 2**32 - 1), st.booleans(), st.sampled_from([0.002, 0.005, 0.02]))
def test_a_recorded_colour_take_never_leaves_its_samples_range_or_0_1(seed: int, framed: bool, tol: float) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(30, 200))
    times = np.cumsum(rng.uniform(1 / 120, 1 / 20, n))              # a browser's uneven frames
    walk = np.cumsum(rng.normal(0, 0.08, (n, 3)), axis=0) + rng.uniform(0, 1, 3)
    values = np.clip(walk, 0.0, 1.0)                                  # slid into both ends and held there
    if rng.uniform() < 0.5:
        values[rng.integers(0, n, 2)] = rng.choice([0.0, 1.0], (2, 3))  # picker jumps
    track = record("lamp.color", times, values, tol, framed=framed)
    assert no_swing(track, times, values, tol) <= 1e-6
    dense = track.evaluate(np.linspace(times[0], times[-1], 5001))
    assert dense.min() >= -1e-7 * tol and dense.max() <= 1.0 + 1e-7 * tol
    assert np.abs(track.evaluate(times) - values).max() <= tol * (1 + 1e-9)


def test_an_intensity_take_never_dips_below_its_lowest_sample() -> None:
    # The case: a slider falls from 2 to its lowest, 0.3, rests and rises, at tol 0.01.
    times = np.arange(150) / 60.0
    values = np.r_[np.full(40, 2.0), np.linspace(2.0, 0.3, 6), np.full(8, 0.3), np.linspace(0.3, 3.0, 96)][:, None]
    track = record("lamp.intensity", times, values, 0.01)
    dense = track.evaluate(np.linspace(0, times[-1], 20001))
    assert dense.min() >= 0.3 - 0.01 * (1 + 1e-9)
    assert no_swing(track, times, values, 0.01) <= 1e-6


def test_an_additive_colour_take_is_clamped_to_0_1() -> None:
    sc = lamp_scene()
    times = np.arange(120) / 60.0
    below = record("lamp.color", times, np.tile(np.linspace(0.5, 0.95, 120)[:, None], (1, 3)), 0.005, sc=sc)
    offsets = np.tile(np.r_[np.linspace(0, 0.3, 60), np.linspace(0.3, -0.7, 60)][:, None], (1, 3))
    track = record("lamp.color", times, offsets, 0.005, mode="additive", sc=sc, over={"lamp.color": below})
    dense = track.evaluate(np.linspace(0, times[-1], 5001))
    assert dense.min() >= 0.0 and dense.max() <= 1.0 + 1e-9
    targets = np.clip(below.evaluate(times) + offsets, 0.0, 1.0)     # what was reduced: clamped targets
    assert np.abs(track.evaluate(times) - targets).max() <= 0.005 * (1 + 1e-9)


def test_a_punch_in_over_a_colour_keeps_0_1_at_its_seams() -> None:
    old = BSpline(np.r_[[0.0] * 2, [4.0] * 2], np.tile(np.c_[[0.2, 1.0]], (1, 3)), 1)   # reaches 1 at 4 s
    t = np.linspace(1.0, 3.5, 151)
    wave = np.clip(0.4 + 0.7 * np.sin(3 * t) ** 2, 0, 1)
    new = punch_in(COLOR, old, Take(t, np.c_[wave, wave, wave], "replace", 0.2), 0.005, 4)
    dense = new(np.linspace(0, 4, 40001))
    assert dense.min() >= 0.0 and dense.max() <= 1.0 + 1e-9


def test_a_frame_outside_the_bounds_is_refused_naming_the_attribute() -> None:
    rec = Recorder(lamp_scene())
    rec.arm("lamp.color")
    rec.start()
    rec.push_frame(0.0, [0.5, 0.5, 0.5])
    with pytest.raises(SampleError, match=r"lamp\.color.*outside the bounds"):
        rec.push_frame(0.1, [0.5, 1.5, 0.5])
    with pytest.raises(SampleError, match=r"lamp\.color"):
        rec.push("lamp.color", 0.2, [0.5, -0.1, 0.5])
    rec.push_frame(0.3, [0.6, 0.6, 0.6])
    assert rec.stop()["lamp.color"].n_coefficients >= 2


def test_the_player_clamps_a_bounded_track_that_rounding_pushes_past_its_bound() -> None:
    sc = lamp_scene()
    over = BSpline(np.r_[[0.0] * 4, [1.0] * 4], np.c_[[0.9, 1.2, 1.2, 0.9]], 3)   # peaks at 1.125
    track = ContinuousTrack("lamp.intensity", INTENSITY, BSpline(over.t, -over.c + 1.0, 3), 0.01)  # dips to -0.125
    player = Player(sc, [track])
    values = [player.values(t)[1][0] for t in np.linspace(0, 1, 101)]
    assert min(values) == 0.0 and max(values) == pytest.approx(0.1)
