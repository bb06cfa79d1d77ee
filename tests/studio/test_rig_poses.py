"""The page's chains and walkers are the model's: rigs.js (what the viewport draws) gives the
pose ``anim/rigs.py`` ``rig_clip`` gives, at any time (on the ticks and between them), to
1e-6 rad and 1e-6 m, on random goal curves, chain structures and walker heights, up to
the time the model's own pose turns on rounding: a redundant chain relaxing out of reach
can turn a 1e-12 change of its goal into tenths of a radian, and from then on no port
follows it."""

from __future__ import annotations

import json
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.rigs import rig_clip, ticks
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.reducer.metric import rotation_angle

ROOT = Path(__file__).resolve().parents[2]
NODE = shutil.which("node")
pytestmark = pytest.mark.skipif(NODE is None, reason="node is not installed (scripts/setup needs node 20)")


def curve(path: str, rng: np.random.Generator, seconds: float, scale: float, flat: bool) -> ContinuousTrack:
    """A random clamped cubic over [0.2, 0.2 + seconds]."""
    inner = np.sort(rng.uniform(0.2, 0.2 + seconds, rng.integers(0, 6)))
    knots = np.r_[[0.2] * 4, inner, [0.2 + seconds] * 4]
    coef = rng.normal(0.0, scale, (len(knots) - 4, 3))
    if flat:
        coef[:, 1] = 0.0
    return ContinuousTrack(path, POSITION, BSpline(knots, coef, 3), 0.005)


def page_poses(dump: dict) -> list[dict]:
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "dump.json").write_text(json.dumps(dump))
        run = subprocess.run([NODE, str(ROOT / "tests/studio/js/rig_poses.mjs"), str(Path(tmp) / "dump.json")],
                             capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout)


#: The relative change of the goal's and base's control points that stands for rounding.
ROUNDING = 1e-12


def rounding_spread(scene: Scene, tracks: dict[str, Track], times: np.ndarray, clip) -> tuple[np.ndarray, np.ndarray]:
    """How far rounding alone moves the model's pose: ``rig_clip`` with every curve's
    control points scaled by ``1 - ROUNDING`` and ``1 + ROUNDING``, the largest angle of
    each joint from ``clip``'s at each time (n, J) and the root's distance (n,)."""
    angle, root = np.zeros(clip.rotations.shape[:2]), np.zeros(len(times))
    for scale in (1 - ROUNDING, 1 + ROUNDING):
        moved = {p: ContinuousTrack(t.path, t.type, BSpline(t.spline.t, t.spline.c * scale, t.spline.k), t.tol)
                 for p, t in tracks.items()}
        other = rig_clip(scene, moved, "rig", times)
        for j in range(angle.shape[1]):
            angle[:, j] = np.maximum(angle[:, j], rotation_angle(other.rotations[:, j], clip.rotations[:, j]))
        root = np.maximum(root, np.linalg.norm(other.translations[:, 0] - clip.translations[:, 0], axis=1))
    return angle, root


def as_page(track: Track | None, value: np.ndarray) -> dict | list[float]:
    """A track as the page's document holds it (evaluate.js's Curve), or the attribute's value."""
    if not isinstance(track, ContinuousTrack):
        return np.asarray(value, dtype=float).tolist()
    s = track.spline
    return {"path": track.path, "order": s.k + 1, "knots": np.asarray(s.t).tolist(),
            "coef": np.asarray(s.c).tolist(), "rotation": False}


@settings(max_examples=20, deadline=None)
@given(st.sampled_from(["chain", "walker"]), st.integers(0, 2 ** 32 - 1), st.floats(0.5, 3.0), st.booleans())
def test_the_page_poses_rigs_as_the_model_does(kind: str, seed: int, seconds: float, moving_base: bool) -> None:
    rng = np.random.default_rng(seed)
    scene = Scene()
    scene.add("rig", kind)
    tracks: dict[str, Track] = {}
    if kind == "chain":
        joints = int(rng.integers(2, 9))
        lengths = np.zeros(8)
        lengths[:joints] = rng.uniform(0.1, 0.6, joints)
        scene.set("rig.lengths", lengths)
        scene.set("rig.limits", rng.uniform(10, 180, 8))
        scene.set("rig.hinges", (rng.random(8) < 0.5).astype(float))
        tracks["rig.goal"] = curve("rig.goal", rng, seconds, 0.8 * lengths.sum(), False)
        if moving_base:
            tracks["rig.position"] = curve("rig.position", rng, seconds / 2, 0.3, False)
    else:
        scene.set("rig.height", [float(rng.uniform(1.2, 2.0))])
        tracks["rig.goal"] = curve("rig.goal", rng, seconds, 2.5, True)
    end = float(ticks(tracks)[-1])
    times = np.sort(np.r_[rng.uniform(-0.3, end, 40), np.arange(0, end, 0.37)])
    clip = rig_clip(scene, tracks, "rig", times)
    dump = {"kind": kind, "times": times.tolist(),
            "goal": as_page(tracks.get("rig.goal"), scene.get("rig.goal")),
            "base": as_page(tracks.get("rig.position"), scene.get("rig.position")) if kind == "chain" else None}
    if kind == "chain":
        dump.update({a: np.asarray(scene.get(f"rig.{a}")).tolist() for a in ("lengths", "limits", "hinges")})
    else:
        dump["height"] = float(scene.get("rig.height")[0])
    shown = page_poses(dump)
    turning = np.flatnonzero(clip.rotating)
    page = np.array([np.reshape(p["rotations"], (-1, 4)) for p in shown])
    assert page.shape[1] == len(turning)
    spread, root = rounding_spread(scene, tracks, times, clip)
    steady = np.maximum.accumulate(np.maximum(spread.max(axis=1), root)) <= 1e-6     # until rounding rules it
    for j in turning:
        angle = rotation_angle(page[:, j], clip.rotations[:, j])[steady]
        assert np.all(angle <= 1e-6 + 4 * spread[steady, j]), clip.skeleton.names[j]
    if kind == "walker":
        off = np.linalg.norm(np.array([p["root"] for p in shown]) - clip.translations[:, 0], axis=1)[steady]
        assert np.all(off <= 1e-6 + 4 * root[steady])
