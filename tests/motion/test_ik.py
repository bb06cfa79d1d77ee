"""Articulated-chain IK (``sketchanim.motion.ik``) and its page twin (``web/js/ik.js``).

What is promised, each a property over random chains (2 to 8 joints, lengths 0.1 to 1,
hinges and balls mixed, random limits) and goal paths:

- **Reach.** A goal that moves along reachable places -- the effector of a pose path from
  the rest pose to a random pose within the limits (every joint at most 0.7 of its limit,
  bent to the rest bend's side -- its axis's x >= 0 --, limits of at least 0.8 rad) over 2 s -- and is
  then held still for 2 s is reached within 1e-3 scene units. (A goal on the far side of a
  singularity or of a limit from the rest pose may be a local minimum for any Jacobian
  method; the bounds below still hold there.)
- **Out of reach.** A goal held 1.1 to 3 reaches away, in a direction the base alone can
  point the chain in within its limit (0.1 rad to spare), gives after 4 s a straight chain
  (every joint after the base within 1e-3 rad of straight) pointing at it within 1e-3 rad.
- **Every tick, every path** (any limits down to 0.05 rad, goals anywhere, jumps included):
  finite unit quaternions, limits held (hinges about x only), the effector's move at most the
  goal's move plus ``CATCH_UP`` reaches per second, each joint's turn at most
  ``ITERATIONS * MAX_TURN`` (36 rad/s).
- **Page and model agree** on random chains and paths to 1e-6 rad (they are the same
  floating-point operations in the same order, so in fact to the bit).
"""

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

from sketchanim.errors import ArgumentError
from sketchanim.motion import ik

ROOT = Path(__file__).resolve().parents[2]
NODE = shutil.which("node")
TICK = 1.0 / ik.RATE


@st.composite
def chains(draw: st.DrawFn, low: float = 0.05) -> ik.Chain:
    """A chain of 2 to 8 joints, lengths 0.1 to 1, limits from ``low`` to pi."""
    n = draw(st.integers(2, 8))
    lengths = draw(st.lists(st.floats(0.1, 1.0), min_size=n, max_size=n))
    limits = draw(st.lists(st.floats(low, math.pi), min_size=n, max_size=n))
    hinges = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    return ik.Chain(tuple(lengths), tuple(limits), tuple(hinges))


def _unit(v: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    norm = float(np.linalg.norm(v))
    return v / norm if norm > 1e-3 else fallback


@st.composite
def poses(draw: st.DrawFn, chain: ik.Chain) -> np.ndarray:
    """A pose within the limits: each joint at most 0.7 of its limit, bent to the side the
    rest bend is on (its axis's x >= 0), so that the way there from rest is not through
    the straight chain."""
    out = []
    for limit, hinge in zip(chain.limits, chain.hinges):
        angle = draw(st.floats(0.0, 0.7)) * limit
        axis = np.array([1.0, 0, 0]) if hinge else _unit(
            np.array([draw(st.floats(0, 1)), draw(st.floats(-1, 1)), draw(st.floats(-1, 1))]), np.array([0.0, 0, 1]))
        out.append(np.r_[axis * math.sin(angle / 2), math.cos(angle / 2)])
    return np.array(out)


def nlerp(a: np.ndarray, b: np.ndarray, ticks: int) -> np.ndarray:
    """Poses from a to b (joint by joint on the shorter arc), ``ticks`` of them."""
    s = np.linspace(0.0, 1.0, ticks)[:, None, None]
    b = np.where(np.sum(a * b, axis=-1, keepdims=True) < 0, -b, b)
    q = (1 - s) * a + s * b
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


@st.composite
def paths(draw: st.DrawFn, chain: ik.Chain, ticks: int = 240) -> np.ndarray:
    """Goals anywhere: a few sinusoids up to two reaches out, and jumps."""
    reach = sum(chain.lengths)
    t = np.arange(ticks) * TICK
    goals = np.tile(np.array(draw(st.lists(st.floats(-1.5, 1.5), min_size=3, max_size=3))) * reach, (ticks, 1))
    for _ in range(draw(st.integers(1, 3))):
        amp = np.array(draw(st.lists(st.floats(-1, 1), min_size=3, max_size=3))) * reach
        freq, phase = draw(st.floats(0.1, 3.0)), draw(st.floats(0, 2 * math.pi))
        goals += np.sin(2 * math.pi * freq * t + phase)[:, None] * amp
    for _ in range(draw(st.integers(0, 2))):
        at = draw(st.integers(0, ticks - 1))
        goals[at:] += np.array(draw(st.lists(st.floats(-2, 2), min_size=3, max_size=3))) * reach
    return goals


def turn_angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation angle from each quaternion of ``a`` to ``b`` (sign-free)."""
    dot = np.abs(np.sum(a * b, axis=-1))
    vector = a[..., 3:] * b[..., :3] - b[..., 3:] * a[..., :3] - np.cross(a[..., :3], b[..., :3])
    cross = np.linalg.norm(vector, axis=-1)
    return 2 * np.arctan2(cross, dot)


def effector(chain: ik.Chain, pose: np.ndarray) -> np.ndarray:
    return ik.points(chain, pose)[..., -1, :]


@settings(max_examples=40, deadline=None)
@given(st.data())
def test_reachable_goals_are_reached(data: st.DataObject) -> None:
    chain = data.draw(chains(low=0.8))
    target = data.draw(poses(chain))
    goals = effector(chain, np.concatenate([nlerp(ik.rest(chain), target, 240), np.repeat(target[None], 240, 0)]))
    solved = ik.solve(chain, goals)
    error = np.linalg.norm(effector(chain, solved[-1]) - goals[-1])
    assert error < 1e-3, f"{error} from a goal held 2 s"


@settings(max_examples=30, deadline=None)
@given(st.data())
def test_goals_out_of_reach_point_a_straight_chain_at_them(data: st.DataObject) -> None:
    chain = data.draw(chains(low=0.8))
    reach = sum(chain.lengths)
    tilt = data.draw(st.floats(0.0, 1.0)) * max(chain.limits[0] - 0.1, 0.0)
    if chain.hinges[0]:
        tilt *= data.draw(st.sampled_from([-1.0, 1.0]))
        direction = np.array([0.0, math.cos(tilt), math.sin(tilt)])
    else:
        around = data.draw(st.floats(0, 2 * math.pi))
        direction = np.array([math.sin(tilt) * math.cos(around), math.cos(tilt), math.sin(tilt) * math.sin(around)])
    goal = direction * reach * data.draw(st.floats(1.1, 3.0))
    solved = ik.solve(chain, np.tile(goal, (480, 1)))
    assert np.isfinite(solved).all()
    bends = turn_angles(solved[-1, 1:], np.array([0.0, 0, 0, 1]))
    assert bends.max() < 1e-3, f"bent {bends.max()} rad"
    tip = effector(chain, solved[-1])
    off = math.acos(min(1.0, float(tip @ direction) / float(np.linalg.norm(tip))))
    assert off < 1e-3, f"points {off} rad off the goal"


def test_a_base_swung_near_its_limit_keeps_no_twist() -> None:
    """A goal 2.9 rad from up, the base's limit 3.0: the swing there must not leave the base
    twisted about its segment (its angle then more than pointing needs, held at the limit,
    and the chain bent to make up; found by hypothesis)."""
    chain = ik.Chain((0.75, 1.0, 0.5, 0.5), (3.0, 0.875, 0.875, 2.0), (False,) * 4)
    goal = np.array([math.sin(2.9), math.cos(2.9), 0.0]) * 2 * sum(chain.lengths)
    solved = ik.solve(chain, np.tile(goal, (480, 1)))
    assert turn_angles(solved[-1, 1:], np.array([0.0, 0, 0, 1])).max() < 1e-3
    assert abs(turn_angles(solved[-1, 0], np.array([0.0, 0, 0, 1])) - 2.9) < 1e-3


def check_ticks(chain: ik.Chain, goals: np.ndarray, solved: np.ndarray) -> None:
    """The bounds every tick keeps, from the rest pose."""
    assert np.isfinite(solved).all()
    np.testing.assert_allclose(np.linalg.norm(solved, axis=-1), 1.0, atol=1e-12)
    angles = turn_angles(solved, np.array([0.0, 0, 0, 1]))
    assert (angles <= np.array(chain.limits) + 1e-9).all(), "a limit is passed"
    hinges = np.array(chain.hinges)
    assert (solved[:, hinges, 1:3] == 0).all(), "a hinge turned about another axis than x"
    reach = sum(chain.lengths)
    poses = np.concatenate([ik.rest(chain)[None], solved])
    tips = effector(chain, poses)
    moved = np.linalg.norm(np.diff(tips, axis=0), axis=1)
    steps = np.linalg.norm(np.diff(np.concatenate([goals[:1], goals]), axis=0), axis=1)
    allowed = steps + ik.CATCH_UP * reach * TICK
    assert (moved <= allowed + 1e-9).all(), f"the effector jumped {np.max(moved - allowed)} beyond its allowance"
    turns = turn_angles(poses[1:], poses[:-1])
    assert turns.max() <= ik.ITERATIONS * ik.MAX_TURN + 1e-9, f"a joint turned {turns.max()} rad in a tick"


@settings(max_examples=40, deadline=None)
@given(st.data())
def test_every_tick_keeps_the_limits_and_the_speed_bounds(data: st.DataObject) -> None:
    chain = data.draw(chains())
    goals = data.draw(paths(chain))
    check_ticks(chain, goals, ik.solve(chain, goals))


def test_singular_goals_on_the_chain_axis_are_reached() -> None:
    """Straight (out of reach above), then a goal straight down the axis inside the reach,
    then straight below: the straight chain is singular along itself, and still bends."""
    chain = ik.Chain.from_slots([0.5, 0.4, 0.3, 0.25, 0.2, 0, 0, 0], [150] * 8, [0, 1, 1, 1, 0, 0, 0, 0])
    stays = [np.tile(g, (360, 1)) for g in ([0.0, 3.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.2, 0.0])]
    goals = np.concatenate(stays)
    solved = ik.solve(chain, goals)
    tips = effector(chain, solved)
    assert abs(tips[359, 1] - 1.65) < 1e-6
    for end in (719, 1079):
        assert np.linalg.norm(tips[end] - goals[end]) < 1e-6
    check_ticks(chain, goals, solved)


def test_a_limit_near_pi_is_not_jumped_across() -> None:
    """A hinge limited to 3.125 rad folded past pi by an update is brought back on the side it
    came from, not to the far side of its limit (a turn of more than the bound; found by
    hypothesis)."""
    chain = ik.Chain((1.0, 0.5, 0.5, 0.75, 1.0, 0.5, 0.75), (1.0, 3.125, 1.0, 1.0, 1.0, 1.0, 2.0),
                     (True, True, False, False, False, False, False))
    t = np.arange(240) * TICK
    goals = np.c_[np.full_like(t, 4.375), np.zeros_like(t), 5 * np.sin(2 * math.pi * t + 1)]
    check_ticks(chain, goals, ik.solve(chain, goals))


def test_solve_is_step_after_step() -> None:
    chain = ik.Chain((0.6, 0.5, 0.4), (2.0, 1.0, 2.5), (False, True, False))
    goals = np.c_[np.linspace(0.2, 1.5, 50), np.linspace(1.0, -0.5, 50), np.zeros(50)]
    pose, previous = ik.rest(chain), None
    solved = ik.solve(chain, goals)
    for k, goal in enumerate(goals):
        pose = ik.step(chain, pose, goal, previous)
        previous = goal
        np.testing.assert_array_equal(pose, solved[k])


def test_from_slots_reads_the_scene_encoding() -> None:
    chain = ik.Chain.from_slots([0.5, 0.4, 0.3, 0.0, 0.7, 0, 0, 0], [90, 180, 45, 150, 150, 150, 150, 150],
                                [0, 1, 0.6, 1, 0, 0, 0, 0])
    assert chain.lengths == (0.5, 0.4, 0.3)
    np.testing.assert_allclose(chain.limits, [math.pi / 2, math.pi, math.pi / 4])
    assert chain.hinges == (False, True, True)


@pytest.mark.parametrize(("lengths", "limits", "hinges", "field"), [
    ([0.5, 0.0, 0.3], [90, 90, 90], [0, 0, 0], "lengths"),
    ([0.5, float("nan"), 0.3], [90, 90, 90], [0, 0, 0], "lengths"),
    ([0.5, -0.4, 0.3], [90, 90, 90], [0, 0, 0], "lengths"),
    ([0.5, 0.4, 0.3], [90, 0, 90], [0, 0, 0], "limits"),
    ([0.5, 0.4, 0.3], [90, 190, 90], [0, 0, 0], "limits"),
    ([0.5, 0.4, 0.3], [90, 90], [0, 0, 0], "limits"),
    ([0.5, 0.4, 0.3], [90, 90, 90], [0, float("inf"), 0], "hinges"),
    ([0.1] * 9, [90] * 9, [0] * 9, "lengths"),
])
def test_from_slots_names_the_bad_field(lengths: list, limits: list, hinges: list, field: str) -> None:
    with pytest.raises(ArgumentError) as err:
        ik.Chain.from_slots(lengths, limits, hinges)
    assert err.value.argument == field


def test_bad_goals_and_poses_are_refused() -> None:
    chain = ik.Chain((1.0, 1.0), (1.0, 1.0), (False, False))
    with pytest.raises(ArgumentError, match="goals"):
        ik.solve(chain, [[0.0, 1.0, float("nan")]])
    with pytest.raises(ArgumentError, match="goal"):
        ik.step(chain, ik.rest(chain), [0.0, 1.0])
    with pytest.raises(ArgumentError, match="pose"):
        ik.step(chain, np.zeros((3, 4)), [0.0, 1.0, 0.0])


@pytest.mark.skipif(NODE is None, reason="node is not installed (scripts/setup needs node 20)")
@settings(max_examples=10, deadline=None)
@given(st.data())
def test_page_and_model_agree(tmp_path_factory: pytest.TempPathFactory, data: st.DataObject) -> None:
    cases, want = [], []
    for _ in range(5):
        chain = data.draw(chains())
        goals = data.draw(paths(chain, 180))
        cases.append({"lengths": list(chain.lengths), "limits": list(chain.limits), "hinges": list(chain.hinges),
                      "goals": goals.ravel().tolist()})
        want.append(ik.solve(chain, goals))
    dump = tmp_path_factory.mktemp("ik") / "dump.json"
    dump.write_text(json.dumps({"cases": cases}))
    run = subprocess.run([NODE, str(ROOT / "tests/studio/js/solve_chain.mjs"), str(dump)], capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == 0, run.stderr[-2000:]
    for mine, page in zip(want, json.loads(run.stdout)["poses"]):
        worst = turn_angles(mine, np.reshape(page, mine.shape)).max()
        assert worst <= 1e-6, f"page and model differ by {worst} rad"
