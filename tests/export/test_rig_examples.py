"""The rig examples write valid .glb files: examples/reach.py (a chain whose goal leaves
its reach for a while) and examples/walk_path.py (a walker on a generated path, and on a
real TUM trajectory laid on the floor)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from clips import validate

ROOT = Path(__file__).resolve().parents[2]


def run(*args: str) -> dict:
    done = subprocess.run([sys.executable, *args], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout)


def test_reach_example(tmp_path: Path) -> None:
    summary = run("examples/reach.py", str(tmp_path / "reach.glb"))
    assert summary["joints"] == 5 and summary["seconds_out_of_reach"] > 1.0
    (report,) = validate(tmp_path / "reach.glb")
    assert report["numErrors"] == 0, report["messages"][:5]


def test_walk_path_example(tmp_path: Path) -> None:
    summary = run("examples/walk_path.py", str(tmp_path / "walk.glb"))
    assert summary["seconds"] > 9 and summary["top_speed_m_s"] > 2.0
    (report,) = validate(tmp_path / "walk.glb")
    assert report["numErrors"] == 0, report["messages"][:5]


@pytest.mark.realdata
def test_walk_path_example_on_a_real_trajectory(data_dir: Path, tmp_path: Path) -> None:
    summary = run("examples/walk_path.py", str(tmp_path / "tum.glb"), str(data_dir / "camera" / "freiburg1_xyz-groundtruth.txt"))
    assert summary["seconds"] > 10 and summary["metres"] > 1.0
    (report,) = validate(tmp_path / "tum.glb")
    assert report["numErrors"] == 0, report["messages"][:5]
