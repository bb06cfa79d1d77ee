"""Orientation channels: the geodesic bound in quaternion mode, Euler mode, streaming."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import sketchanim
from sketchanim.errors import ArgumentError, InputError, SampleError
from sketchanim.motion import continuous_quaternions, euler_angles
from sketchanim.reducer import window_kernel
from sketchanim.reducer.metric import rotation_angle
from recordings import rotation_cases


def geodesic_deg(curve: np.ndarray, quats: np.ndarray, scalar_first: bool = False) -> np.ndarray:
    """Rotation angle between the curve's normalised values and the samples, by scipy."""
    a = Rotation.from_quat(curve / np.linalg.norm(curve, axis=1)[:, None], scalar_first=scalar_first)
    b = Rotation.from_quat(quats, scalar_first=scalar_first)
    return np.degrees((a.inv() * b).magnitude())


@st.composite
def rotation_streams(draw, max_n: int = 300):
    """Random orientation takes: smooth turns, fast spins of many turns, sudden
    180-degree flips, noise, quaternion sign flips, irregular sampling."""
    n = draw(st.integers(2, max_n))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    steps = rng.lognormal(0.0, 0.5, n - 1) if draw(st.booleans()) else np.ones(n - 1)
    t = np.r_[0.0, np.cumsum(steps)] / 120.0
    u = np.linspace(0.0, 1.0, n)[:, None]
    rotvec = np.zeros((n, 3))
    for _ in range(rng.integers(1, 4)):
        rotvec += rng.normal(0, 1.5, 3) * np.sin(2 * np.pi * rng.uniform(0.2, 3) * u + rng.uniform(0, 6))
    rot = Rotation.from_rotvec(rotvec)
    if draw(st.booleans()):                      # spin: many full turns about one axis
        turns = draw(st.integers(2, 20))
        rot = Rotation.from_rotvec(np.outer(u[:, 0] * turns * 2 * np.pi, rng.normal(size=3) / 1.7)) * rot
    if draw(st.booleans()) and n > 4:            # a sudden half turn
        at = rng.integers(1, n - 1)
        axis = rng.normal(size=3)
        rot = Rotation.concatenate([rot[:at], Rotation.from_rotvec(np.pi * axis / np.linalg.norm(axis)) * rot[at:]])
    q = rot.as_quat()
    if draw(st.booleans()):
        q = q + rng.normal(0, 1e-3, q.shape)
    q *= np.where(rng.random(n) < 0.3, -1.0, 1.0)[:, None]          # sign flips: same rotations
    q *= rng.uniform(0.5, 2.0, n)[:, None] if draw(st.booleans()) else 1.0   # any norm
    tol = float(10.0 ** rng.uniform(-1.5, 0.8))
    return t, q, tol


@given(st.integers(0, 2**32 - 1))
def test_rotation_angle_matches_scipy_and_the_kernel(seed: int) -> None:
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(50, 4))
    q = Rotation.random(50, rng=rng).as_quat() * rng.choice([-1.0, 1.0], (50, 1))
    q[:5] = p[:5] * rng.uniform(0.1, 3, (5, 1))                       # same rotation, other norm
    ours = rotation_angle(p, q)
    theirs = (Rotation.from_quat(p).inv() * Rotation.from_quat(q)).magnitude()
    np.testing.assert_allclose(ours, theirs, atol=1e-9)
    one, zero = np.ones(4), np.zeros(4)
    kernel = [window_kernel.scaled_rotation_angle(p[i], q[i], one, zero) for i in range(50)]
    np.testing.assert_allclose(kernel, ours, atol=1e-12)


@settings(max_examples=60)
@given(rotation_streams(), st.sampled_from(["global", "incremental"]), st.integers(3, 40))
def test_every_sample_within_the_angle(stream, method: str, window: int) -> None:
    t, q, tol = stream
    r = sketchanim.reduce_rotations(t, q, tol, method=method, window=window)
    assert r.metric == "rotation" and r.spline(t).shape == (len(t), 4)
    err = geodesic_deg(r.spline(t), q)
    assert err.max() <= tol * (1 + 1e-9)
    assert np.degrees(r.max_error[0]) <= tol and np.degrees(r.tol[0]) == pytest.approx(tol)


@settings(max_examples=30)
@given(rotation_streams(), st.lists(st.integers(1, 60), min_size=1, max_size=10), st.booleans(),
       st.sampled_from(["quaternion", "euler"]))
def test_streaming_rotations_equal_the_batch(stream, chunks: list[int], scalar_first: bool, mode: str) -> None:
    t, q, tol = stream
    batch = sketchanim.reduce_rotations(t, q, tol, method="incremental", scalar_first=scalar_first, mode=mode,
                                        features=sketchanim.FeatureOptions(jumps=False))   # the stream cuts no jumps
    rs = sketchanim.RotationStream(tol, scalar_first=scalar_first, mode=mode, grow=True)
    i, c = 0, 0
    while i < len(t):
        step = chunks[c % len(chunks)]
        rs.extend(t[i : i + step], q[i : i + step])
        i, c = i + step, c + 1
    r = rs.finish()
    assert r.report["mode"] == mode
    if mode == "quaternion" and batch.report.get("gaps"):
        # The stream keeps its raw quaternion components from swinging; the batch checks the
        # curve as it plays, normalised, and bridges where that still swings.
        from sketchanim.motion.rotations import continuous_quaternions
        from sketchanim.reducer.swing import local_ranges, swinging
        qs = continuous_quaternions(q)                       # the signs only: either component order
        lo, hi = local_ranges(qs, np.full(4, 2 * np.sin(np.radians(tol) / 4)))
        assert swinging(r.spline, t, lo, hi, normalised=True).size
        return
    np.testing.assert_array_equal(r.spline.t, batch.spline.t)
    np.testing.assert_array_equal(r.spline.c, batch.spline.c)


def test_sign_flips_and_norms_do_not_change_the_curve() -> None:
    t = np.linspace(0, 3, 361)
    q = Rotation.from_rotvec(np.c_[np.sin(t), t, 0.3 * t]).as_quat()
    messy = q * np.where(np.arange(len(t)) % 3 == 0, -2.0, 0.7)[:, None]
    a = sketchanim.reduce_rotations(t, q, 0.2)
    b = sketchanim.reduce_rotations(t, messy, 0.2)
    # The same rotations: the same curve, up to the sign the first sample chose.
    np.testing.assert_allclose(-b.spline(t), a.spline(t), atol=1e-9)
    fixed = continuous_quaternions(messy)
    assert np.all(np.einsum("nc,nc->n", fixed[1:], fixed[:-1]) > 0)


@settings(max_examples=40)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["ZXY", "XYZ", "YXZ", "ZYX", "zxy"]),
       st.sampled_from(["global", "incremental"]))
def test_euler_mode_unwraps_and_keeps_each_axis(seed: int, seq: str, method: str) -> None:
    rng = np.random.default_rng(seed)
    n = 400
    t = np.arange(n) / 60.0
    angles = np.c_[np.linspace(0, rng.uniform(2, 12) * np.pi, n),             # spins: many turns
                   np.pi / 2 - 10.0 ** rng.uniform(-4, -1) * (1.5 + np.sin(3 * t)),  # near gimbal lock
                   rng.uniform(-1, 1) * np.sin(t)]
    q = Rotation.from_euler(seq, angles).as_quat()
    unwrapped = euler_angles(q, seq)
    assert np.all(np.abs(np.diff(unwrapped, axis=0)) < np.pi)                 # no 2 pi jumps
    assert rotation_angle(Rotation.from_euler(seq, unwrapped).as_quat(), q).max() < 1e-6     # the same rotations
    r = sketchanim.reduce_rotations(t, q, 0.5, mode="euler", seq=seq, method=method)
    assert r.spline(t).shape == (n, 3) and r.metric == "channels"
    assert np.all(np.abs(r.spline(t) - unwrapped) <= np.radians(0.5))


def test_bad_rotation_samples_are_named_and_the_stream_goes_on() -> None:
    t = np.arange(300) / 100.0
    q = Rotation.from_rotvec(np.c_[np.sin(t), t, 0 * t]).as_quat()
    bad = q.copy()
    bad[150] = 0.0
    with pytest.raises(SampleError, match="sample 150, quaternion: has norm 0"):
        sketchanim.reduce_rotations(t, bad, 0.5)
    rs = sketchanim.RotationStream(0.5)
    with pytest.raises(SampleError, match="sample 150"):
        rs.extend(t, bad)
    rs.extend(t[151:200], q[151:200])
    with pytest.raises(SampleError, match="sample 200"):                      # time going back
        rs.push(t[100], q[100])
    rs.extend(t[200:], q[200:])
    r = rs.finish()
    keep = np.r_[0:150, 151:300]
    assert r.n_samples == len(keep)
    assert geodesic_deg(r.spline(t[keep]), q[keep]).max() <= 0.5
    with pytest.raises(ArgumentError, match="mode"):
        sketchanim.reduce_rotations(t, q, 0.5, mode="matrix")
    with pytest.raises(ArgumentError, match="seq"):
        sketchanim.reduce_rotations(t, q, 0.5, mode="euler", seq="ZZQ")
    with pytest.raises(ArgumentError, match="quats"):
        sketchanim.reduce_rotations(t, q[:, :3], 0.5)
    with pytest.raises(ArgumentError, match="angle"):
        sketchanim.reduce(t, q[:, :3], 0.1, angle=0.1)


def test_rotation_reduction_round_trips_through_json() -> None:
    t = np.linspace(0, 2, 200)
    r = sketchanim.reduce_rotations(t, Rotation.from_rotvec(np.c_[t, 0 * t, t]).as_quat(), 1.0)
    back = sketchanim.Reduction.from_json(r.to_json())
    assert back.metric == "rotation" and np.array_equal(back.max_error, r.max_error)
    doc = r.to_json().replace('"metric": "rotation"', '"metric": "box"')
    with pytest.raises(InputError, match="'metric'"):
        sketchanim.Reduction.from_json(doc)


def test_real_orientations_keep_the_angle(data_dir) -> None:
    cases = rotation_cases(data_dir)
    assert len(cases) >= 10
    for name, t, q, scalar_first in cases:
        for method in ("global", "incremental"):
            r = sketchanim.reduce_rotations(t, q, 0.5, scalar_first=scalar_first, method=method)
            err = geodesic_deg(r.spline(t), q, scalar_first)
            assert err.max() <= 0.5 * (1 + 1e-9), f"{name} {method}: {err.max()} degrees"
        rs = sketchanim.RotationStream(0.5, scalar_first=scalar_first)
        for chunk in np.array_split(np.arange(len(t)), max(1, len(t) // 50)):
            rs.extend(t[chunk], q[chunk])
        assert geodesic_deg(rs.finish().spline(t), q, scalar_first).max() <= 0.5 * (1 + 1e-9), name


@settings(max_examples=100)
@given(st.integers(1, 30), st.integers(0, 2**32 - 1), st.floats(1e-6, 3.0))
def test_slerped_is_scipys_slerp_held_outside(n: int, seed: int, turn: float) -> None:
    """Keys of any sign and norm, any angle apart up to a half turn (the shorter way)."""
    from scipy.spatial.transform import Slerp

    from sketchanim.motion.rotations import slerped
    from sketchanim.reducer.metric import rotation_angle

    rng = np.random.default_rng(seed)
    times = np.cumsum(rng.uniform(0.01, 1.0, n))
    keys = Rotation.from_rotvec(np.cumsum(rng.normal(0, turn / 2, (n, 3)), axis=0))
    quats = keys.as_quat() * rng.choice([-1.0, 1.0], (n, 1)) * rng.uniform(0.5, 2.0, (n, 1))
    at = np.r_[times[0] - 1.0, rng.uniform(times[0], times[-1], 50), times, times[-1] + 1.0]
    ours = slerped(times, quats, at)
    assert np.allclose(np.linalg.norm(ours, axis=1), 1.0)
    theirs = (Slerp(times, keys)(np.clip(at, times[0], times[-1])) if n > 1 else keys[[0] * len(at)]).as_quat()
    assert rotation_angle(ours, theirs).max() <= 1e-9
