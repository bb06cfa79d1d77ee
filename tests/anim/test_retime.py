"""Retiming tracks and takes, deleting a range, copying and pasting a piece (anim/retime.py,
anim/take_edits.py's shift and scale): times map exactly, values follow them, undo restores."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, note, settings
from hypothesis import strategies as st

from sketchanim.anim.attributes import BOOL, FLOAT, POSITION, SCALE
from sketchanim.anim.commands import Change
from sketchanim.anim.edits import without_range
from sketchanim.anim.history import History
from sketchanim.anim.layers import recomposed, recorded_over
from sketchanim.anim.player import Player
from sketchanim.anim.retime import piece, pasted, retimed
from sketchanim.anim.scene import Scene
from sketchanim.anim.take_edits import edited_takes
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take
from sketchanim.errors import ArgumentError
from tests.anim.test_anim_model import random_spline
from tests.conftest import DATA
from tests.recordings import shared_cases

factors = st.floats(0.2, 5.0)
times = st.floats(-10.0, 10.0)


def recorded(seed: int, n: int = 121) -> ContinuousTrack:
    """A position track of two takes (a replace over 0..2 s, an additive bump over 0.5..1.2 s)."""
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2, n))
    t = np.unique(np.r_[0.0, t, 2.0])
    base = np.c_[np.sin(2 * t + seed % 7), np.cos(t), 0.3 * t]
    track = recorded_over("box.position", POSITION, None, Take(t, base), 0.005, 4)
    mid = t[(t > 0.5) & (t < 1.2)]
    return recorded_over("box.position", POSITION, track, Take(mid, np.c_[0 * mid, 0.1 * np.sin(9 * mid), 0 * mid],
                                                               "additive"), 0.005, 4)


def close(a: np.ndarray, b: np.ndarray, scale: float = 1.0) -> bool:
    """Equal within a few rounding units of ``scale``."""
    return bool(np.all(np.abs(np.asarray(a) - np.asarray(b)) <= 8 * np.spacing(max(scale, 1.0))))


@given(st.integers(0, 2**32 - 1), factors, times, times)
@settings(max_examples=40)
def test_a_retimed_curve_maps_its_knots_and_takes_exactly_and_keeps_its_values(seed, f, pivot, shift) -> None:
    rng = np.random.default_rng(seed)
    track = ContinuousTrack("box.position", POSITION, random_spline(rng, 4, 3, 10), 0.005,
                            (Take(np.array([0.0, 1.0, 2.5]), np.zeros((3, 3))),), edited=bool(seed % 2))
    out = retimed(track, f, pivot, shift)
    move = lambda t: pivot + f * (np.asarray(t) - pivot) + shift                      # noqa: E731
    scale = abs(pivot) + abs(shift) + f * 10
    assert close(out.spline.t, move(track.spline.t), scale)
    assert np.all(np.diff(out.spline.t) >= 0)
    assert close(out.takes[0].times, move(track.takes[0].times), scale) and np.all(np.diff(out.takes[0].times) > 0)
    assert out.edited == track.edited and out.takes[0].blend == pytest.approx(track.takes[0].blend * f)
    x = rng.uniform(track.start, track.end, 50)
    assert np.abs(out.evaluate(move(x)) - track.evaluate(x)).max() <= 1e-9 * (1 + np.abs(track.spline.c).max())


@given(st.integers(0, 2**32 - 1), factors, times, times)
@settings(max_examples=30)
def test_a_retimed_discrete_track_keeps_its_order_and_values(seed, f, pivot, shift) -> None:
    rng = np.random.default_rng(seed)
    ts = np.sort(rng.uniform(0, 5, 8)).tolist()
    track = DiscreteTrack("lamp.on", BOOL, ts, [bool(i % 2) for i in range(8)])
    out = retimed(track, f, pivot, shift)
    assert close(out.times, [pivot + f * (t - pivot) + shift for t in ts], abs(pivot) + abs(shift) + 5 * f)
    assert out.values == track.values and out.times == sorted(out.times)


@given(st.integers(0, 2**16), factors, st.floats(-3, 3))
@settings(max_examples=8)
def test_composing_a_retimed_track_again_gives_the_retimed_motion(seed, f, shift) -> None:
    track = recorded(seed)
    out = retimed(track, f, 0.5, shift)
    again = recomposed(out)
    t = np.linspace(track.start, track.end, 200)
    moved = 0.5 + f * (t - 0.5) + shift
    # both are within the tolerance of the same (retimed) targets: twice it apart at most
    assert np.abs(again.evaluate(moved) - track.evaluate(t)).max() <= 2 * track.tol + 1e-9


@given(st.integers(0, 2**16), st.sampled_from(["shift", "scale"]), st.floats(-2, 2), factors)
@settings(max_examples=8)
def test_a_take_shifted_or_scaled_alone_moves_only_its_times(seed, op, by, f) -> None:
    track = recorded(seed)
    takes = edited_takes(track.takes, 1, op, by=by, factor=f, pivot=0.7)
    old, new = track.takes[1].times, takes[1].times
    want = old + by if op == "shift" else 0.7 + f * (old - 0.7)
    assert close(new, want, 5) and np.all(np.diff(new) > 0)
    assert takes[0] is track.takes[0] and np.array_equal(takes[1].values, track.takes[1].values)
    recomposed(track, takes)                          # the track composes from them


def test_take_shift_and_scale_name_what_is_missing_or_wrong() -> None:
    track = recorded(1)
    with pytest.raises(ArgumentError, match="^by"):
        edited_takes(track.takes, 0, "shift")
    with pytest.raises(ArgumentError, match="^factor"):
        edited_takes(track.takes, 0, "scale", factor=-1.0)
    with pytest.raises(ArgumentError, match="^factor"):
        retimed(track, 0.0)


@given(st.integers(0, 2**32 - 1), st.floats(0.2, 2.0), st.floats(0.3, 2.0))
@settings(max_examples=30)
def test_delete_range_then_undo_restores_bit_for_bit(seed, t0, width) -> None:
    rng = np.random.default_rng(seed)
    scene = Scene()
    scene.add("box")
    scene.add("lamp", "light")
    player = Player(scene, [ContinuousTrack("box.position", POSITION, random_spline(rng, 4, 3, 12), 0.005),
                            DiscreteTrack("lamp.on", BOOL, [0.5, 1.5, 3.0], [False, True, False])])
    history = History(player)
    before = {p: t for p, t in player.tracks.items()}
    copies = {"knots": np.array(before["box.position"].spline.t), "coef": np.array(before["box.position"].spline.c),
              "times": list(before["lamp.on"].times), "values": list(before["lamp.on"].values)}
    history.run(Change(player, "delete range", {p: without_range(t, t0, t0 + width) for p, t in before.items()}))
    assert history.labels == (["delete range"], [])
    assert [t for t in player.tracks["lamp.on"].times if t0 < t < t0 + width] == []
    history.undo()
    after = player.tracks
    assert after["box.position"] is before["box.position"] and after["lamp.on"] is before["lamp.on"]
    assert np.array_equal(after["box.position"].spline.t, copies["knots"])
    assert np.array_equal(after["box.position"].spline.c, copies["coef"])
    assert after["lamp.on"].times == copies["times"] and after["lamp.on"].values == copies["values"]


@given(st.integers(0, 2**16), st.floats(0.1, 0.8), st.floats(0.4, 1.0), st.floats(-0.5, 2.5))
@settings(max_examples=10)
def test_a_pasted_piece_keeps_its_values_within_tolerance(seed, t0, width, at) -> None:
    track = recorded(seed)
    clip = piece(track, t0, t0 + width)
    assert clip.length == pytest.approx(width) and clip.track.start == 0.0
    x = np.linspace(t0, t0 + width, 60)
    assert np.abs(clip.track.evaluate(x - t0) - track.evaluate(x)).max() <= 1e-9
    target = recorded(seed + 1)
    out = pasted(target, clip, at)
    assert out.takes[-1].name == "paste" and len(out.takes) == len(target.takes) + 1
    taken = out.takes[-1]
    inner = taken.times[(taken.times >= at + taken.blend) & (taken.times <= at + clip.length - taken.blend)]
    assert np.abs(out.evaluate(inner) - clip.track.evaluate(inner - at)).max() <= target.tol + 1e-9
    far = np.r_[np.linspace(target.start, at - 0.01, 20), np.linspace(at + clip.length + 0.01, target.end, 20)]
    margin = 1e-6                            # a paste within it of the track's start cuts nothing there (snapped)
    far = far[(far >= target.start) & (far <= target.end) & ((far < at - margin) | (far > at + clip.length + margin))]
    note(f"at {at}, piece {clip.length}, far {far.tolist()}")
    assert np.abs(out.evaluate(far) - target.evaluate(far)).max() <= 1e-9          # untouched outside


def test_a_discrete_piece_pastes_its_values_and_removes_those_it_covers() -> None:
    lamp = DiscreteTrack("lamp.on", BOOL, [0.0, 1.0, 2.0, 3.0], [True, False, True, False])
    clip = piece(lamp, 0.5, 2.5)
    assert clip.track.times == [0.5, 1.5] and clip.length == 2.0
    out = pasted(lamp, clip, 2.2)
    assert out.times == [0.0, 1.0, 2.0, 2.7, 3.7] and out.values == [True, False, True, False, True]
    assert lamp.times == [0.0, 1.0, 2.0, 3.0]                                          # not changed in place


def test_paste_refuses_another_type_naming_both_paths() -> None:
    track = recorded(2)
    other = ContinuousTrack("box.scale", SCALE, track.spline, 0.005)
    with pytest.raises(ArgumentError, match=r"^piece: .*box\.position.*box\.scale"):
        pasted(other, piece(track, 0.2, 0.8), 0.0)
    with pytest.raises(ArgumentError, match="^piece"):
        pasted(DiscreteTrack("lamp.on", BOOL, [0.0], [True]), piece(track, 0.2, 0.8), 0.0)
    with pytest.raises(ArgumentError, match="^range"):
        piece(track, 5.0, 6.0)


def _real_take() -> tuple[str, np.ndarray, np.ndarray, float]:
    """A real pen recording (BDALab, mm) if ../shared/data is there, else a synthetic scribble."""
    if DATA.is_dir():
        name, t, xy, tol = next(c for c in shared_cases(DATA) if c[0] == "BDALab pen (mm)")
        return name, t - t[0], np.c_[xy, np.zeros(len(t))], tol
    t = np.arange(0, 6, 1 / 200)
    return "synthetic scribble (no ../shared/data)", t, np.c_[40 * np.sin(3 * t), 30 * np.sin(5 * t + 1), 0 * t], 0.1


def test_real_recording_retimed_cut_and_pasted() -> None:
    name, t, x, tol = _real_take()
    track = recorded_over("pen.position", POSITION, None, Take(t, x), tol, 4)
    slow = retimed(track, 1.5, pivot=t[0], shift=0.25)
    mapped = t[0] + 1.5 * (t - t[0]) + 0.25
    assert np.abs(slow.evaluate(mapped) - track.evaluate(t)).max() <= 1e-9 * np.abs(x).max()
    assert np.abs(recomposed(slow).evaluate(mapped) - x).max() <= tol + 1e-9
    mid = (track.start + track.end) / 2
    clip = piece(track, mid - 0.5, mid + 0.5)
    out = pasted(track, clip, track.start + 0.2)
    taken = out.takes[-1]                  # the piece sampled: kept within tolerance, but at the faded seams
    inner = taken.times[(taken.times > taken.start + taken.blend) & (taken.times < taken.end - taken.blend)]
    err = np.abs(out.evaluate(inner) - clip.track.evaluate(inner - taken.start)).max()
    print(f"{name}: {len(t)} samples, retimed x1.5 and pasted 1 s (error {err:.4g} <= {tol})")
    assert err <= tol + 1e-9


def test_float_track_without_takes_retimes_too() -> None:
    rng = np.random.default_rng(3)
    track = ContinuousTrack("a.x", FLOAT, random_spline(rng, 4, 1, 6), 0.01)
    assert retimed(track, shift=2.0).start == pytest.approx(track.start + 2.0)
