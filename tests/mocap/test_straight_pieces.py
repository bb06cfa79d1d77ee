"""A clip's curves as straight pieces (the default order, glTF's LINEAR keys): every
rotation within its angle at every frame both as glTF plays it (spherically) and as
Blender's F-curves do (component-wise), every position within its distance; a joint whose
spherical play would miss gets a cubic curve."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from clips import assert_within, clips
from sketchanim.mocap.clip_reduction import ORDER, joint_rotation, reduce_clip
from sketchanim.motion.rotations import spherical
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.reducer.metric import rotation_angle


@settings(max_examples=25, deadline=None)
@given(clips(), st.sampled_from([0.05, 0.5, 2.0]), st.sampled_from([0.1, 0.5, 5.0]))
def test_a_clip_plays_within_its_tolerances_both_ways(clip: Clip, tol: float, rot_tol_deg: float) -> None:
    reduced = reduce_clip(clip, tol, rot_tol_deg, contacts=np.zeros((len(clip.times), len(clip.skeleton)), bool))
    assert ORDER == 2 and {c.spline.k for c in reduced.tracks.values()} <= {1, 3}
    assert all(c.spline.k == 1 for c in reduced.tracks.values() if not c.is_rotation)
    for way in (True, False):
        assert_within(reduced.sample(clip.times, spherical=way), clip, tol, rot_tol_deg)


@settings(max_examples=200, deadline=None)
@given(st.integers(5, 80), st.floats(0.5, 20.0), st.integers(0, 2**32 - 1))
def test_a_joint_plays_spherically_within_its_angle(n: int, tol_deg: float, seed: int) -> None:
    """Large angles, keys far apart: where spherical and component-wise play part most."""
    rng = np.random.default_rng(seed)
    clip = Clip.still(Skeleton(("root",), (-1,), np.zeros((1, 3))), np.sort(rng.uniform(0, 2, n)))
    w = rng.normal(size=(3, 3)) * rng.uniform(0.5, 4)
    t = clip.times
    clip.rotations[:, 0] = Rotation.from_rotvec(np.c_[w[0, 2] * np.sin(w[0, 0] * t + w[0, 1]),
                                                      w[1, 2] * np.sin(w[1, 0] * t), w[2, 0] * t]).as_quat()
    r = joint_rotation(clip, 0, tol_deg)
    ways = [r.spline(t)] + ([spherical(r.spline, t)] if r.spline.k == 1 else [])
    angle = max(rotation_angle(played, clip.rotations[:, 0]).max() for played in ways)
    assert np.degrees(angle) <= tol_deg and np.isclose(angle, r.max_error[0], rtol=1e-9, atol=1e-12)


def test_a_turn_whose_spherical_play_misses_gets_a_cubic_curve() -> None:
    """Samples on the straight line between two rotations 100 degrees apart, component-wise:
    the straight piece through them plays spherically more than 1 degree away, so the
    joint is cubic."""
    rng = np.random.default_rng(297)
    a = Rotation.from_rotvec(0.3 * rng.normal(size=3)).as_quat()
    b = Rotation.from_rotvec(1.5 * rng.normal(size=3)).as_quat()
    clip = Clip.still(Skeleton(("root",), (-1,), np.zeros((1, 3))), np.linspace(0, 1, 9))
    clip.rotations[:, 0] = a + clip.times[:, None] * (np.sign(a @ b) * b - a)
    r = joint_rotation(clip, 0, 1.0)
    assert r.spline.k == 3 and np.degrees(r.max_error[0]) <= 1.0
    assert np.degrees(rotation_angle(r.spline(clip.times), clip.rotations[:, 0]).max()) <= 1.0
