"""Two-bone analytic IK (sketchanim.motion.twobone): a target in reach is reached, one out
of reach is pointed at, the middle joint bends toward the front, frames are rotations."""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from sketchanim.motion.twobone import frame_quaternion, local_frame, two_bone

coords = st.floats(-2.0, 2.0, allow_nan=False)
points = st.tuples(coords, coords, coords)


def end_of(root: tuple, frames: tuple, upper: float, lower: float) -> tuple[np.ndarray, np.ndarray]:
    """The middle joint and the end: each bone runs along its frame's -y."""
    middle = np.array(root) - upper * np.array(frames[0][1])
    return middle, middle - lower * np.array(frames[1][1])


@settings(max_examples=60, deadline=None)
@given(points, points, st.floats(0.1, 1.0), st.floats(0.1, 1.0), points)
@example((0.0, 0.0, 2.0**-24), (0.0, 1.0, 1.0), 1.0, 0.5, (0.0, 1.0, 1.0))   # front 4e-8 off the limb's line
def test_reaches_or_points_at_the_target(root: tuple, target: tuple, upper: float, lower: float,
                                         front: tuple) -> None:
    frames = two_bone(root, target, upper, lower, front)
    for f in frames:
        m = np.array(f).T                                   # columns -> matrix
        assert np.allclose(m.T @ m, np.eye(3), atol=1e-9) and np.linalg.det(m) > 0
    middle, end = end_of(root, frames, upper, lower)
    d = np.linalg.norm(np.subtract(target, root))
    if abs(upper - lower) + 1e-3 < d < upper + lower - 1e-3:
        assert np.allclose(end, target, atol=1e-9)
    elif d >= upper + lower and d > 1e-9:                  # out of reach: straight, toward it
        direction = np.subtract(target, root) / d
        assert np.allclose((end - np.array(root)) / np.linalg.norm(end - np.array(root)), direction, atol=1e-6)
    axis = np.subtract(target, root) / d if d > 1e-9 else np.array([0.0, -1.0, 0.0])
    side = np.array(front) - np.dot(front, axis) * axis
    if np.linalg.norm(side) > 1e-3 and abs(upper - lower) + 1e-3 < d < upper + lower - 1e-3:
        assert np.dot(middle - np.array(root), side) >= -1e-9          # the middle joint bends toward the front


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1, 1, allow_nan=False), min_size=8, max_size=8))
def test_local_frame_and_quaternion_agree_with_scipy(values: list[float]) -> None:
    """``frame_quaternion(local_frame(a, b))`` is ``a^-1 b``'s quaternion (w >= 0)."""
    q = np.reshape(values, (2, 4)) + [0, 0, 0, 0.01]
    a, b = Rotation.from_quat(q[0]), Rotation.from_quat(q[1])
    columns = lambda r: tuple(tuple(c) for c in r.as_matrix().T)  # noqa: E731
    got = np.array(frame_quaternion(local_frame(columns(a), columns(b))))
    want = (a.inv() * b).as_quat()
    want = want if want[3] >= 0 else -want
    assert got[3] >= 0 and np.allclose(got, want, atol=1e-9) or np.isclose(got[3], 0, atol=1e-9)
