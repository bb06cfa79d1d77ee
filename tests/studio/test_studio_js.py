"""The studio page's JavaScript: its node unit tests, and its track evaluation against
the model's (``Player.values``) to 1e-9, on random tracks and on recorded ones."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import ORIENTATION, AttributeType
from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack

ROOT = Path(__file__).resolve().parents[2]
NODE = shutil.which("node")
pytestmark = pytest.mark.skipif(NODE is None, reason="node is not installed (scripts/setup needs node 20)")


def test_node_unit_tests() -> None:
    """Every ``tests/studio/js/*.test.js`` passes under ``node --test``."""
    run = subprocess.run([NODE, "--test", "tests/studio/js/"], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    assert "# fail 0" in run.stdout and "# pass 0" not in run.stdout


def _page_worst(player: Player, times: np.ndarray, tmp_path: Path) -> float:
    """The largest difference between the page's evaluation and ``player.values`` at
    ``times``, through the document form the page receives (JSON)."""
    curves = [{"path": t.path, "order": t.spline.k + 1, "knots": np.asarray(t.spline.t).tolist(),
               "coef": np.asarray(t.spline.c).tolist(), "rotation": t.type.is_rotation}
              for t in player.tracks.values()]
    values = [player.values(float(t))[1].tolist() for t in times]
    dump = tmp_path / "dump.json"
    dump.write_text(json.dumps({"curves": curves, "times": times.tolist(), "values": values}))
    run = subprocess.run([NODE, str(ROOT / "tests/studio/js/match_player.mjs"), str(dump)], capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == 0, run.stderr[-2000:]
    result = json.loads(run.stdout)
    assert result["paths"] == player.values(0.0)[0]
    return float(result["worst"])


@st.composite
def _tracks(draw: st.DrawFn) -> list[tuple[int, int, bool, np.ndarray, np.ndarray]]:
    """Clamped splines of random order, dimension and knots (repeated knots included)."""
    out = []
    for _ in range(draw(st.integers(1, 4))):
        order = draw(st.integers(2, 6))
        rotation = draw(st.booleans())
        dim = 4 if rotation else draw(st.integers(1, 5))
        inner = draw(st.lists(st.floats(-5, 5, allow_nan=False), max_size=12))
        start, length = draw(st.floats(-3, 3)), draw(st.floats(0.01, 8))
        inner = sorted(start + (np.clip(inner, -5, 5) + 5) / 10 * length)
        inner = [x for x in inner if start < x < start + length]
        if inner and draw(st.booleans()):                    # a corner: a knot repeated
            inner += [inner[0]] * min(order - 2, 2)
            inner.sort()
        knots = np.r_[[start] * order, inner, [start + length] * order]
        seed = draw(st.integers(0, 2**31))
        coef = np.random.default_rng(seed).normal(size=(len(knots) - order, dim)) * 3
        if rotation:
            coef[:, 3] += 4                                   # keep clear of the zero quaternion
        out.append((order, dim, rotation, knots, coef))
    return out


@settings(max_examples=25, deadline=None)
@given(_tracks())
def test_page_evaluation_matches_player(tmp_path_factory: pytest.TempPathFactory, tracks: list) -> None:
    scene = Scene()
    player = Player(scene)
    obj = scene.add("thing")
    for j, (order, dim, rotation, knots, coef) in enumerate(tracks):
        kind = ORIENTATION if rotation else AttributeType.vector(dim)
        obj.add(f"a{j}", kind)
        player.add(ContinuousTrack(f"thing.a{j}", kind, BSpline(knots, coef, order - 1), kind.tol))
    lo, hi = player.span
    times = np.r_[np.linspace(lo - 1, hi + 1, 97), np.concatenate([tr[3] for tr in tracks])]   # at the knots too
    assert _page_worst(player, times, tmp_path_factory.mktemp("dump")) <= 1e-9


def test_page_evaluation_matches_player_on_a_recorded_take(tmp_path: Path) -> None:
    """Tracks the recorder made (a position and an orientation from one take), played by
    both at every sample time and between."""
    from scipy.spatial.transform import Rotation

    scene = Scene()
    scene.add("box")
    rec = Recorder(scene)
    rec.arm("box.position")
    rec.arm("box.orientation")
    rec.start()
    t = np.arange(600) / 60
    pos = np.c_[np.sin(t), np.cos(2 * t), 0.1 * t]
    quat = Rotation.from_rotvec(np.c_[t, 0.5 * np.sin(t), 0 * t]).as_quat()
    for i, ti in enumerate(t):
        rec.push("box.position", ti, pos[i])
        rec.push("box.orientation", ti, quat[i])
    player = Player(scene, rec.stop().values())
    times = np.r_[t, t[:-1] + 1 / 120]
    assert _page_worst(player, times, tmp_path) <= 1e-9
