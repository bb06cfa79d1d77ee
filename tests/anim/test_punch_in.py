"""Layered recording: punch-in replaces a track over the take's span only, joins it C1
and within tolerance; additive takes ride on the motion below; re-reduction from raw."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import FLOAT, ORIENTATION, POSITION, AttributeType
from sketchanim.anim.layers import compose, composition, punch_in, reduce_samples
from sketchanim.anim.tracks import Take
from sketchanim.errors import ArgumentError
from sketchanim.reducer.metric import rotation_angle
from tests.recordings import bvh_joint_rotations, moving_root
from tests.signals import performances


def one_sided(s: BSpline, x: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Value and first derivative of ``s`` just left and just right of ``x``."""
    flipped = BSpline(-s.t[::-1], s.c[::-1], s.k)
    d = s.derivative()
    return flipped(-x), -flipped.derivative()(-x), s(x), d(x)


def fade(times: np.ndarray, blend: float, left: bool, right: bool) -> np.ndarray:
    """The smoothstep fade the module describes, written out again for the check."""
    a, b = times[0], times[-1]
    blend = min(blend, (b - a) / 2)
    w = np.ones(len(times))
    if blend > 0:
        for on, u in ((left, (times - a) / blend), (right, (b - times) / blend)):
            if on:
                u = np.clip(u, 0, 1)
                w *= 3 * u**2 - 2 * u**3
    return w


def held(s: BSpline, t: np.ndarray) -> np.ndarray:
    return s(np.clip(t, s.t[s.k], s.t[-s.k - 1]))


def check_seams(old: BSpline, new: BSpline, a: float, b: float, scale: float) -> None:
    lo, hi = old.t[old.k], old.t[-old.k - 1]
    for x in (a, b):
        if lo < x < hi:
            v0, d0, v1, d1 = one_sided(new, x)
            assert np.allclose(v0, v1, rtol=0, atol=1e-9 * scale), (x, v0, v1)
            assert np.allclose(d0, d1, rtol=1e-6, atol=1e-9 * scale), (x, d0, d1)
            assert np.allclose(d0, one_sided(old, x)[1 if x == a else 3], rtol=1e-6, atol=1e-9 * scale)


@given(performances(dims=(1, 3)), st.integers(0, 2**32 - 1), st.sampled_from([0.0, 0.05, 0.2]),
       st.sampled_from(["inside", "overlap start", "overlap end", "after", "covers"]))
@settings(max_examples=50)
def test_punch_in_keeps_the_rest_joins_c1_and_keeps_the_take_within_tolerance(p, seed, blend, where) -> None:
    rng = np.random.default_rng(seed)
    dim, tol = p.values.shape[1], float(p.tol[0])
    kind = AttributeType.vector(dim, tol)
    old = reduce_samples(kind, p.times, p.values, tol, 4)
    span = p.times[-1] - p.times[0]
    a, b = {"inside": (0.3, 0.7), "overlap start": (-0.2, 0.4), "overlap end": (0.6, 1.3), "after": (1.2, 1.6),
            "covers": (-0.1, 1.1)}[where]
    t = np.arange(p.times[0] + a * span, p.times[0] + b * span, 1 / 120)
    if len(t) < 3:
        return
    # The performer grabs the object where it is and moves it away smoothly.
    u = (t - t[0]) / (t[-1] - t[0])
    bump = np.sin(np.pi * u)[:, None] * rng.normal(0, 1, dim) + rng.normal(0, 0.1 * tol, (len(t), dim))
    if blend > 0:
        bump += rng.normal(0, 1, dim)                       # far from the curve at the seams: only a fade joins
    x = held(old, t) + bump
    new = punch_in(kind, old, Take(t, x, blend=blend), tol, 4)
    scale = 1 + np.abs(p.values).max() + np.abs(x).max()
    lo, hi = old.t[old.k], old.t[-old.k - 1]
    # untouched outside the take
    out = p.times[(p.times < t[0]) | (p.times > t[-1])]
    assert np.allclose(new(out), held(old, out), rtol=0, atol=1e-9 * scale)
    # within tolerance of the faded take at every sample
    w = fade(t, blend, lo < t[0], t[-1] < hi)
    target = held(old, t) + w[:, None] * (x - held(old, t))
    assert np.all(np.abs(new(t) - target) <= tol * (1 + 1e-9))
    check_seams(old, new, t[0], t[-1], scale)


def test_a_take_far_from_the_curve_needs_a_blend() -> None:
    t = np.linspace(0, 2, 241)
    old = reduce_samples(FLOAT, t, np.c_[np.sin(t)], 0.001, 4)
    with pytest.raises(ArgumentError, match="take's start at 0.5 s is .* blend > 0"):
        punch_in(FLOAT, old, Take(t[60:120], np.c_[np.ones(60)], blend=0.0), 0.001, 4)


@given(st.integers(0, 2**32 - 1), st.sampled_from(["replace", "additive"]), st.sampled_from([0.0, 0.1]))
@settings(max_examples=25)
def test_orientation_punch_in_joins_c1_within_the_angle(seed, mode, blend) -> None:
    rng = np.random.default_rng(seed)
    t = np.arange(0, 3, 1 / 120)
    q = Rotation.from_rotvec(np.c_[np.sin(t * rng.uniform(0.5, 2)), 0.4 * t, np.cos(rng.uniform(0.5, 2) * t)]).as_quat()
    old = reduce_samples(ORIENTATION, t, q, 0.5, 4)
    s = t[(t >= 1.0) & (t <= 2.0)]
    u = (s - s[0]) / (s[-1] - s[0])
    turn = Rotation.from_rotvec(np.sin(np.pi * u)[:, None] * rng.normal(0, 0.5, 3))
    base = held(old, s)
    x = turn.as_quat() if mode == "additive" else (turn * Rotation.from_quat(base)).as_quat()
    new = punch_in(ORIENTATION, old, Take(s, x, mode, blend), 0.5, 4)
    target = (turn * Rotation.from_quat(base)).as_quat()
    w = fade(s, blend, True, True)
    if blend and mode == "additive":  # the offset fades as a slerp towards identity
        target = (Rotation.from_rotvec(w[:, None] * turn.as_rotvec()) * Rotation.from_quat(base)).as_quat()
    elif blend:  # a replacing take fades as a normalised lerp from the curve (S + w (take - S))
        b = base / np.linalg.norm(base, axis=1, keepdims=True)
        x = target * np.where(np.sum(target * b, axis=1) < 0, -1.0, 1.0)[:, None]
        target = b + w[:, None] * (x - b)
    assert np.degrees(rotation_angle(new(s), target)).max() <= 0.5 * (1 + 1e-9)
    out = t[(t < 1.0) | (t > 2.0)]
    assert np.allclose(new(out), held(old, out), atol=1e-12)
    check_seams(old, new, s[0], s[-1], 1.0)


def test_additive_layers_add_and_compose_replays_takes_at_any_tolerance() -> None:
    t = np.arange(0, 4, 1 / 120)
    base = np.c_[np.sin(t), np.cos(t), 0.1 * t]
    s = t[(t >= 1) & (t <= 3)]
    offset = np.c_[0.3 * np.sin(np.pi * (s - 1) / 2), np.zeros(len(s)), np.zeros(len(s))]
    takes = [Take(t, base), Take(s, offset, "additive", blend=0.0)]
    for tol in (0.01, 0.001):
        made = composition(POSITION, takes, tol, 4)
        assert np.abs(made.curve(made.times) - made.targets).max() <= tol * (1 + 1e-9)
        # the layer's targets are the offsets on the curve below (itself within tol of the base)
        expected = np.r_[base[t < 1], base[(t >= 1) & (t <= 3)] + offset, base[t > 3]]
        assert np.abs(made.curve(t) - expected).max() <= 2 * tol * (1 + 1e-9)
    coarse, fine = (len(compose(POSITION, takes, tol, 4).c) for tol in (0.01, 0.001))
    assert coarse < fine                                    # re-reduced from raw, not from the coarse curve


def test_additive_take_on_an_empty_track_offsets_the_default() -> None:
    t = np.linspace(0, 1, 121)
    curve = compose(POSITION, [Take(t, np.c_[t, 0 * t, 0 * t], "additive")], 0.001, 4)
    assert np.abs(curve(t) - np.c_[t, 0 * t, 0 * t]).max() <= 0.001


def test_punch_in_on_real_recordings(data_dir) -> None:
    """A correction recorded over the middle of real root motion and a real joint."""
    for bvh in sorted((data_dir / "bvh").glob("*.bvh"))[:3]:
        t, pos = moving_root(bvh)
        old = reduce_samples(POSITION, t, pos, 0.5, 4)
        a, b = np.searchsorted(t, [t[0] + 0.3 * (t[-1] - t[0]), t[0] + 0.6 * (t[-1] - t[0])])
        s = t[a:b]
        x = pos[a:b] + np.sin(np.pi * (s - s[0]) / (s[-1] - s[0]))[:, None] * np.array([5.0, 0.0, -3.0])
        new = punch_in(POSITION, old, Take(s, x), 0.5, 4)
        w = fade(s, 0.1, True, True)
        target = held(old, s) + w[:, None] * (x - held(old, s))
        assert np.abs(new(s) - target).max() <= 0.5 * (1 + 1e-9), bvh.name
        check_seams(old, new, s[0], s[-1], 1 + np.abs(pos).max())
        out = np.r_[t[:a], t[b:]]
        assert np.allclose(new(out), old(out), atol=1e-9 * (1 + np.abs(pos).max())), bvh.name
        name, tj, q = bvh_joint_rotations(bvh, limit=1)[0]
        old = reduce_samples(ORIENTATION, tj, q, 0.5, 4)
        sj = tj[a:b]
        turn = Rotation.from_rotvec(np.sin(np.pi * (sj - sj[0]) / (sj[-1] - sj[0]))[:, None] * [0.0, 0.3, 0.0])
        new = punch_in(ORIENTATION, old, Take(sj, turn.as_quat(), "additive"), 0.5, 4)
        check_seams(old, new, sj[0], sj[-1], 1.0)
        w = fade(sj, 0.1, True, True)
        target = (Rotation.from_rotvec(w[:, None] * turn.as_rotvec()) * Rotation.from_quat(held(old, sj))).as_quat()
        assert np.degrees(rotation_angle(new(sj), target)).max() <= 0.5 * (1 + 1e-9), (bvh.name, name)
