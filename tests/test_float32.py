"""float32's budgets: what a reducer may use of a tolerance so that a float32 file still
plays within it. Either the budget leaves float32's whole margin, or the tolerance is
refused naming its field; never a budget that leaves less than the margin."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import event, given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from sketchanim.errors import ArgumentError
from sketchanim.float32 import KEEP, REACH_S, float32_margin, margin_refusal, position_budget, rotation_budget
from sketchanim.mocap.clip_reduction import DERIVED_KEEP


def _path(n: int, size: float, speed: float, offset: float, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` samples at 30 Hz from ``offset`` s: a circle of radius ``speed`` about a
    point ``size`` from the origin, so both the size and the speed are as drawn."""
    t = offset + np.arange(n) / 30
    a = t - offset
    x = np.zeros((n, dim))
    x[:, 0] = size + speed * np.cos(a)
    x[:, 1] = speed * np.sin(a)
    return t, x


def _within_reach(t: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """Each sample's fastest step among those with an end within ``REACH_S`` of it,
    directly (the budgets may look further, never less far)."""
    near = np.abs(t[:, None] - t[None, :]) <= REACH_S                    # (sample, sample)
    touching = near[:, :-1] | near[:, 1:]                                 # (sample, step)
    return np.where(touching, steps[None, :], 0.0).max(axis=1, initial=0.0)


def _turns(q: np.ndarray, t: np.ndarray) -> np.ndarray:
    u = q / np.linalg.norm(q, axis=1, keepdims=True)
    return np.arccos(np.clip(np.abs(np.sum(u[1:] * u[:-1], axis=1)), 0, 1)) / np.diff(t)


@given(st.integers(2, 60), st.floats(0.0, 1e5), st.floats(0.0, 1e3), st.floats(0.0, 1e5), st.floats(0.0, 1e3),
       st.floats(1e-7, 10.0), st.sampled_from([2, 3]), st.sampled_from([KEEP, DERIVED_KEEP]))
def test_a_position_budget_leaves_the_margin_or_the_tolerance_is_refused(n, size, speed, offset, jump, tol, dim,
                                                                         keep):
    """The margin at every sample (its time, the fastest step within REACH_S) is left; a
    refusal only where even the whole take's fastest step at its last time would take
    more than ``1 - keep``. The path's first step may jump (a take from its rest pose)."""
    t, x = _path(n, size, speed, offset, dim)
    x[0, 0] += jump / 30
    steps = np.linalg.norm(np.diff(x, axis=0), axis=1) / np.diff(t)
    size = float(np.linalg.norm(x, axis=1).max())
    local = float(float32_margin(t, size, _within_reach(t, steps)).max())
    whole = float(float32_margin(t, size, float(steps.max(initial=0.0))))
    try:
        budget = position_budget(t, x, tol, subject="for track 'a.position'", keep=keep)
    except ArgumentError as refused:
        assert refused.argument == "tol" and str(refused).startswith(f"tol: {tol:.6g} for track 'a.position' ")
        assert "larger tolerance" in str(refused)
        assert whole > (1 - keep) * tol * (1 - 1e-9)    # refused only where the budget would keep less than asked
        event("refused")
        return
    assert budget + local <= tol * (1 + 1e-9) and budget >= keep * tol * (1 - 1e-12)


@given(st.integers(2, 60), st.floats(0.0, 20.0), st.floats(0.0, 1e5), st.floats(0.0, 1e3), st.floats(1e-6, 5.0),
       st.integers(0, 2**32 - 1))
def test_a_rotation_budget_leaves_the_margin_or_the_tolerance_is_refused(n, turn, offset, jump, tol_deg, seed):
    t = offset + np.arange(n) / 30
    start = Rotation.random(random_state=seed)
    q = (start * Rotation.from_euler("Z", turn * (t - offset)[:, None])).as_quat()
    q[0] = (start * Rotation.from_euler("Z", -jump / 30)).as_quat()
    steps = _turns(q, t)
    local = float(np.degrees(2 * float32_margin(t, 1.0, _within_reach(t, steps))).max())
    whole = float(np.degrees(2 * float32_margin(t, 1.0, float(steps.max(initial=0.0)))))
    try:
        budget = rotation_budget(t, q, tol_deg, field="rot_tol_deg", subject="for joint 'hips' rotation")
    except ArgumentError as refused:
        assert refused.argument == "rot_tol_deg" and "for joint 'hips' rotation" in str(refused)
        assert whole > tol_deg / 2 * (1 - 1e-9)
        event("refused")
        return
    assert budget + local <= tol_deg * (1 + 1e-9) and budget >= tol_deg / 2


def test_late_times_are_refused_with_the_advice_to_start_nearer_0_and_a_fine_tolerance_far_out_without_it():
    t, x = _path(60, 10.0, 2.0, 3600.0, 3)            # an hour into a recording
    with pytest.raises(ArgumentError, match=r"^tol: 0.0001 is less than twice what float32 may move it "
                                            r"\(.*within 1 s of 3601.97 s \(sample 59\)\): ask for a larger tolerance, "
                                            r"or start the times nearer 0$"):
        position_budget(t, x, 1e-4)
    assert position_budget(t - 3600.0, x, 1e-4) > 0.5e-4       # the same take from 0 keeps it
    t, x = _path(60, 1e5, 0.0, 0.0, 3)               # 100 km out, still
    with pytest.raises(ArgumentError, match=r"larger tolerance$"):
        position_budget(t, x, 1e-3)


def test_the_refusal_names_what_it_is_given():
    err = margin_refusal(0.01, 0.03, 0.001, "at frame 3 (600 s) of joint 'arm'", "moving", whose="the clip's times")
    assert err.argument == "tol"
    assert str(err) == ("tol: 0.01 at frame 3 (600 s) of joint 'arm' is less than twice what float32 may move it "
                        "(0.03: moving): ask for a larger tolerance, or start the clip's times nearer 0")
