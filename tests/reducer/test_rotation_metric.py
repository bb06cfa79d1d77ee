"""The compiled rotation arithmetic against scipy: the angle between two quaternions of
any norm and sign (reducer/metric.py), and glTF's spherical LINEAR mix of two keys
(reducer/linear_keys.py)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation, Slerp

from sketchanim.reducer.linear_keys import spherical_mix
from sketchanim.reducer.metric import rotation_angle


@settings(max_examples=60)
@given(st.integers(0, 2**32 - 1), st.sampled_from([1e-9, 1e-4, 0.1, 1.0, 3.0]), st.integers(1, 50))
def test_rotation_angle_is_scipys_magnitude_whatever_the_norm_and_sign(seed: int, spread: float, n: int) -> None:
    rng = np.random.default_rng(seed)
    p = Rotation.random(n, random_state=rng)
    q = p * Rotation.from_rotvec(rng.normal(0, spread, (n, 3)))
    scale = rng.uniform(0.1, 10.0, (n, 1)) * rng.choice([-1.0, 1.0], (n, 1))
    got = rotation_angle(p.as_quat() * scale, q.as_quat())
    np.testing.assert_allclose(got, (p.inv() * q).magnitude(), rtol=1e-9, atol=1e-12)


@settings(max_examples=60)
@given(st.integers(0, 2**32 - 1), st.floats(0.0, 3.1), st.lists(st.floats(0.0, 1.0), min_size=1, max_size=20))
def test_spherical_mix_is_scipys_slerp(seed: int, angle: float, at: list[float]) -> None:
    rng = np.random.default_rng(seed)
    a = Rotation.random(random_state=rng)
    axis = rng.normal(size=3)
    b = a * Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle)
    qa, qb = a.as_quat(), b.as_quat()
    qb = qb if qa @ qb >= 0 else -qb                                # on a's side, as the keys are put
    s = np.array(at)[:, None]
    mixed = spherical_mix(np.tile(qa, (len(s), 1)), np.tile(qb, (len(s), 1)), s)
    want = Slerp([0.0, 1.0], Rotation.from_quat([qa, qb]))(s[:, 0])
    np.testing.assert_allclose(np.linalg.norm(mixed, axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose((Rotation.from_quat(mixed).inv() * want).magnitude(), 0.0, atol=1e-7)
