"""The walker (sketchanim.motion.walk): planted feet that do not slide, cadence and step
length following Boulic's walking model, curves, stop and go, turning on the spot, start
and stop steps, running and falling behind past the fastest run, random paths, and the
page's copy (studio/web/js/walk.js) agreeing with it to 1e-6 rad."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation
from walk_paths import landings, lifts, segments, straight, toe_speeds, world

from sketchanim.errors import ArgumentError
from sketchanim.motion.skeleton import Skeleton
from sketchanim.motion.walk import (
    CYCLE,
    RATE,
    RV_FASTEST,
    RV_RUN,
    RV_SLOW,
    Walk,
    advance,
    gait,
    humanoid,
    rig,
    start,
    walk,
)

ROOT = Path(__file__).resolve().parents[2]
NODE = shutil.which("node")
SLIDE = 0.02          # m/s: the brief's bound on a planted toe's median speed
FIGURE = humanoid(1.75)
LEG = rig(FIGURE).leg


def heading_of(w: Walk) -> np.ndarray:
    """The hips' facing angle at each tick (0 faces +z)."""
    forward = Rotation.from_quat(w.rotations[:, 0]).apply([0.0, 0.0, 1.0])
    return np.arctan2(forward[:, 0], forward[:, 2])


def assert_planted(skeleton: Skeleton, w: Walk) -> np.ndarray:
    """Planted toes within the slide bound (median, per foot) and legs within reach;
    returns the joint positions."""
    points = world(skeleton, w)
    for speeds in toe_speeds(skeleton, w, points):
        assert len(speeds) == 0 or np.median(speeds) <= SLIDE
    r = rig(skeleton)
    for hip, ankle in (("l_thigh", "l_foot"), ("r_thigh", "r_foot")):
        d = np.linalg.norm(points[:, skeleton.index(hip)] - points[:, skeleton.index(ankle)], axis=1)
        assert d.max() <= r.thigh + r.shin + 1e-9
    return points


def test_humanoid_stands_on_its_toes() -> None:
    """Each toe is its foot's lowest node, on the ground at rest; the height is the
    figure's; the legs are straight below the hips; left is +x."""
    for height in (0.9, 1.75, 2.2):
        s = humanoid(height)
        rest = s.rest_positions()
        feet = [s.index(n) for n in ("l_foot", "l_toe", "r_foot", "r_toe")]
        assert rest[:, 1].min() == pytest.approx(0.0, abs=1e-12)
        assert rest[feet[1], 1] == pytest.approx(0.0, abs=1e-12) and rest[feet[3], 1] == pytest.approx(0.0, abs=1e-12)
        assert rest[feet[1], 1] < rest[feet[0], 1] and rest[feet[3], 1] < rest[feet[2], 1]
        assert 0.85 * height < rest[s.index("head"), 1] < 0.95 * height          # the skull's base
        assert rest[s.index("l_thigh"), 0] > 0 > rest[s.index("r_thigh"), 0]
        assert rig(s).leg == pytest.approx(0.53 * height)


def test_bad_input_is_an_argument_error() -> None:
    with pytest.raises(ArgumentError, match="height"):
        humanoid(-1.0)
    with pytest.raises(ArgumentError, match="markers"):
        walk(FIGURE, np.zeros((4, 2)))
    with pytest.raises(ArgumentError, match="markers"):
        walk(FIGURE, np.array([[0.0, 0, 0], [np.nan, 0, 0]]))
    with pytest.raises(ArgumentError, match="marker"):
        advance(start(FIGURE, [0, 0, 0]), [0.0, 1.0])
    with pytest.raises(ArgumentError, match="joint"):
        walk(Skeleton(("hips",), (-1,), np.zeros((1, 3))), np.zeros((3, 3)))


def test_walk_is_advance_in_a_loop() -> None:
    """start then advance tick by tick gives walk's rows: the pose is a function of the
    markers up to its tick only."""
    path = segments([(0.5, 0.0, 0.0), (2.0, 1.3, 0.6)])
    w = walk(FIGURE, path)
    s = start(FIGURE, path[0])
    for k in range(1, len(path)):
        s = advance(s, path[k])
    assert np.array_equal(s.rotations, w.rotations[-1]) and np.array_equal(s.root, w.root[-1])
    assert np.array_equal(walk(FIGURE, path[:100]).rotations, w.rotations[:100])


@settings(max_examples=8, deadline=None)
@given(st.floats(RV_SLOW, RV_RUN * 0.95), st.sampled_from([1.5, 1.75, 1.9]))
def test_cadence_and_step_length_follow_boulic(rv: float, height: float) -> None:
    """On a straight walk at v = RV H, once steady, each foot's cycle lasts Boulic's
    1.346 sqrt(H / v) (to 3%: the ticks round each phase), so its stride is
    1.346 sqrt(RV) H; the feet alternate half a cycle apart; planted toes hold."""
    figure = humanoid(height)
    leg = rig(figure).leg
    v = rv * leg
    w = walk(figure, straight(v, 8.0))
    assert_planted(figure, w)
    cycle = CYCLE * math.sqrt(leg / v)
    for side in (0, 1):
        steady = lifts(w, side)[lifts(w, side) > 3.0 * RATE]
        assert len(steady) >= 3
        assert np.median(np.diff(steady)) / RATE == pytest.approx(cycle, rel=0.03)
        planted = landings(w, side)
        planted = planted[planted > 3.0 * RATE]
        toe = world(figure, w)[planted, figure.index(("l_toe", "r_toe")[side]), 2]
        assert np.median(np.diff(toe)) / leg == pytest.approx(CYCLE * math.sqrt(rv), rel=0.03)
    left, right = lifts(w, 0), lifts(w, 1)
    left = left[left > 3.0 * RATE]
    gap = (right[np.searchsorted(right, left[0])] - left[0]) / RATE
    assert gap == pytest.approx(cycle / 2, rel=0.1)
    assert w.stance.any(axis=1).all()                     # walking: a foot is always down


@pytest.mark.parametrize("rv", [3.0, 5.0, 7.0])
def test_running_has_a_flight_phase(rv: float) -> None:
    """Above the walk-run speed the figure runs: each foot planted less than half the
    cycle, both off the ground between, at Boulic's cycle carried on; no toe slides."""
    v = rv * LEG
    w = walk(FIGURE, straight(v, 6.0))
    assert_planted(FIGURE, w)
    steady = w.stance[int(3.0 * RATE):]
    assert (~steady.any(axis=1)).mean() > 0.05
    assert steady.mean() < 0.5
    assert not w.behind
    for side in (0, 1):
        beats = lifts(w, side)[lifts(w, side) > 3.0 * RATE]
        assert np.median(np.diff(beats)) / RATE == pytest.approx(gait(v, LEG).cycle, rel=0.05)


def test_curved_path_faces_along_it() -> None:
    """A circle of 3 m radius at 1.5 m/s: the body faces the tangent (within the turn's
    lag), the feet plant and step on both sides, no toe slides."""
    path = segments([(0.5, 0.0, 0.0), (11.5, 1.5, 0.5)])
    w = walk(FIGURE, path)
    assert_planted(FIGURE, w)
    tangent = np.arctan2(np.gradient(path[:, 0]), np.gradient(path[:, 2]))
    error = np.angle(np.exp(1j * (heading_of(w) - tangent)))[int(4 * RATE):]
    assert np.abs(error).max() < 0.15
    assert all(len(lifts(w, side)) >= 8 for side in (0, 1))


def test_stop_and_go_idles_with_both_feet_planted() -> None:
    """Walking, then a 3 s pause, then walking on: after a settle (stop steps, within
    1.5 s of the stop) both feet stay planted and none steps until the path moves again;
    stepping starts again within half a second of it."""
    path = segments([(0.5, 0.0, 0.0), (3.0, 1.3, 0.0), (3.0, 0.0, 0.0), (3.0, 1.3, 0.0)], smooth=0.2)
    w = walk(FIGURE, path)
    assert_planted(FIGURE, w)
    speed = np.linalg.norm(np.diff(path, axis=0), axis=1) * RATE
    stop = np.flatnonzero(speed[int(3 * RATE):] < 1e-9)[0] + int(3 * RATE)
    go = np.flatnonzero(speed[stop:] > 1e-9)[0] + stop
    settle = stop + int(1.5 * RATE)
    assert w.stance[settle:go + 1].all()
    last = max(lifts(w, side)[lifts(w, side) < go].max() for side in (0, 1))
    assert stop - 0.5 * RATE < last < settle              # stop steps as the path stops
    first = min(lifts(w, side)[lifts(w, side) > go].min() for side in (0, 1))
    assert first - go < 0.5 * RATE
    # Standing: the feet side by side under the hips (within the idle drift threshold).
    points = world(FIGURE, w)[settle]
    feet = points[[FIGURE.index("l_foot"), FIGURE.index("r_foot")]]
    assert abs(feet[0, 2] - feet[1, 2]) < 0.1 * LEG


def test_start_and_stop_steps() -> None:
    """From standing: the first step within 0.4 s of the path starting, a foot down the
    whole time; at the end, both feet planted and the body standing on the marker."""
    path = straight(1.4, 4.0, rest=1.0)
    path = np.r_[path, np.repeat(path[-1:], int(2 * RATE), axis=0)]
    w = walk(FIGURE, path)
    assert_planted(FIGURE, w)
    moves = np.flatnonzero(np.diff(path[:, 2]) > 0)[0]
    first = min(lifts(w, 0).min(), lifts(w, 1).min())
    assert 0 < first - moves < 0.4 * RATE
    assert w.stance[:moves + 1].all() and w.stance[-int(0.5 * RATE):].all()
    assert np.allclose(w.root[-1, [0, 2]], path[-1, [0, 2]])


def test_turn_on_the_spot() -> None:
    """The path comes to rest, then goes back the way it came: the body turns round on
    the spot (a quarter turn within 0.5 m of where it stopped, the path having started
    back; the half turn within 1.5 s), the feet step through the turn, and no planted
    toe slides."""
    path = segments([(0.5, 0.0, 0.0), (3.0, 1.2, 0.0), (1.0, 0.0, 0.0), (3.0, -1.2, 0.0)], smooth=0.6)
    w = walk(FIGURE, path)
    assert_planted(FIGURE, w)
    heading = np.unwrap(heading_of(w))
    assert abs(heading[0]) < 1e-9 and abs(abs(heading[-1]) - math.pi) < 0.05
    turning = np.flatnonzero(np.abs(heading) > 0.1)
    turning = turning[(turning > 4 * RATE)]
    rest = path[int(4.0 * RATE), [0, 2]]
    half = turning[np.abs(heading[turning]) < math.pi / 2]
    assert np.linalg.norm(w.root[half][:, [0, 2]] - rest, axis=1).max() < 0.5
    assert np.flatnonzero(np.abs(heading) > math.pi - 0.05)[0] - turning[0] < 1.5 * RATE
    during = [((lifts(w, s) > turning[0]) & (lifts(w, s) < turning[0] + 2 * RATE)).sum() for s in (0, 1)]
    assert min(during) >= 1


def test_faster_than_the_fastest_run_falls_behind() -> None:
    """A path at 9.5 m/s (beyond the fastest run, RV_FASTEST H = 6.96 m/s): ``behind``
    says from when and how fast; the body runs at the fastest run behind the marker,
    catches it up once the path stops, and no planted toe slides."""
    fastest = RV_FASTEST * LEG
    path = straight(9.5, 4.0, rest=0.5)
    path = np.r_[path, np.repeat(path[-1:], int(3 * RATE), axis=0)]
    w = walk(FIGURE, path)
    assert_planted(FIGURE, w)
    assert len(w.behind) == 1
    begin, end, speed = w.behind[0]
    assert 0.5 < begin < 1.0 and 4.0 < end < 7.0 and speed == pytest.approx(9.5, rel=1e-6)
    body = np.linalg.norm(np.diff(w.root[:, [0, 2]], axis=0), axis=1) * RATE
    assert body.max() <= fastest * (1 + 1e-9)
    k = np.arange(len(path))
    outside = (k < round(begin * RATE)) | (k > round(end * RATE))
    assert np.allclose(w.root[outside][:, [0, 2]], path[outside][:, [0, 2]], atol=1e-9)


@st.composite
def random_paths(draw: st.DrawFn) -> np.ndarray:
    """Smooth random ground paths: 2 to 5 parts of 0.4 to 2.5 s, each a pause or a
    move at 0 to 8 m/s with a turn rate, on a gentle random slope."""
    parts = [(0.5, 0.0, 0.0)]
    for _ in range(draw(st.integers(2, 5))):
        pause = draw(st.booleans())
        speed = 0.0 if pause else draw(st.floats(0.0, 8.0))
        parts.append((draw(st.floats(0.4, 2.5)), speed, draw(st.floats(-2.0, 2.0))))
    return segments(parts, heading=draw(st.floats(-math.pi, math.pi)), slope=draw(st.floats(-0.1, 0.1)),
                    smooth=draw(st.floats(0.1, 0.6)))


@settings(max_examples=25, deadline=None)
@given(random_paths(), st.sampled_from([1.2, 1.75, 2.0]))
def test_random_paths(path: np.ndarray, height: float) -> None:
    """Any smooth path with pauses at 0 to 8 m/s, any figure: no NaN, unit quaternions,
    planted toes within the slide bound, legs within reach, the body on the marker except
    where ``behind`` says the path outran the fastest run, the hips above the ground."""
    figure = humanoid(height)
    w = walk(figure, path)
    assert np.isfinite(w.rotations).all() and np.isfinite(w.root).all()
    assert np.allclose(np.linalg.norm(w.rotations, axis=-1), 1.0)
    assert_planted(figure, w)
    k = np.arange(len(path))
    behind = np.zeros(len(path), bool)
    for begin, end, _ in w.behind:
        behind |= (k >= round(begin * RATE)) & (k <= round(end * RATE))
    gap = np.linalg.norm(w.root[:, [0, 2]] - path[:, [0, 2]], axis=1)
    assert gap[~behind].max(initial=0.0) <= 1e-9
    assert (w.root[:, 1] >= path[:, 1] + 0.6 * rig(figure).leg).all()


def _page_walk(path: np.ndarray, height: float, tmp_path: Path) -> dict:
    dump = tmp_path / "walk.json"
    dump.write_text(json.dumps({"height": height, "markers": path.tolist()}))
    run = subprocess.run([NODE, str(ROOT / "tests/studio/js/walk_path.mjs"), str(dump)], capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout)


@pytest.mark.skipif(NODE is None, reason="node is not installed (scripts/setup needs node 20)")
@settings(max_examples=10, deadline=None)
@given(random_paths(), st.sampled_from([1.6, 1.75, 1.85]))
def test_page_walk_matches(tmp_path_factory: pytest.TempPathFactory, path: np.ndarray, height: float) -> None:
    """The page's walk.js on the same markers: every joint's rotation within 1e-6 rad,
    the root within 1e-9 m, the same stance and the same ``behind``; its worldPoints
    are world_pose's joint positions (to 1e-9 m)."""
    figure = humanoid(height)
    w = walk(figure, path)
    page = _page_walk(path, height, tmp_path_factory.mktemp("walk"))
    q = np.array(page["rotations"]).reshape(w.rotations.shape)
    angle = (Rotation.from_quat(q.reshape(-1, 4)).inv() * Rotation.from_quat(w.rotations.reshape(-1, 4))).magnitude()
    assert angle.max() <= 1e-6
    assert np.abs(np.array(page["root"]).reshape(-1, 3) - w.root).max() <= 1e-9
    assert np.array_equal(np.array(page["stance"], bool).reshape(-1, 2), w.stance)
    assert np.allclose(np.array(page["behind"]).reshape(-1, 3), np.array(w.behind).reshape(-1, 3), rtol=0, atol=1e-9)
    assert np.abs(np.array(page["points"]).reshape(len(path), -1, 3) - world(figure, w)).max() <= 1e-9
