"""The peers the benchmarks compare against build and run, and we stay ahead of them
on the reference spiral (counts only: timings belong to benchmarks/, not to tests)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import sketchanim
from sketchanim.paper import spiral as paper_spiral

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
sys.path.insert(0, str(BENCH))

from peers import fitpack, sisl  # noqa: E402


@pytest.fixture(scope="module")
def spiral():
    return *paper_spiral(1000), np.array([0.1, 0.1])


def test_sisl_runs_and_we_need_no_more_control_points(spiral):
    t, x, tol = spiral
    peers = [sisl.s1961(t, x, tol, split=0.0), sisl.s1961(t, x, tol, split=0.1), sisl.s1940(t, x, tol)]
    for peer in peers:
        assert 10 <= peer.n_coefficients <= 40 and peer.seconds > 0
    ours = sketchanim.reduce(t, x, tol)
    assert ours.n_coefficients <= min(p.n_coefficients for p in peers)


def test_fitpack_search_keeps_the_tolerance(spiral):
    t, x, tol = spiral
    peer = fitpack.make_splprep_within(t, x, tol, steps=12)
    assert np.all(peer.max_error(t, x) <= tol)
    assert sketchanim.reduce(t, x, tol).n_coefficients <= peer.n_coefficients


def test_benchmark_script_prints_its_table():
    done = subprocess.run([sys.executable, str(BENCH / "bench_global.py"), "--quick"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "SISL s1940" in done.stdout and "control points vs SISL's best" in done.stdout


def test_fitpack_search_is_stopped_at_its_time_limit(spiral):
    t, x, tol = spiral
    with pytest.raises(fitpack.PeerTimeout) as info:
        fitpack.make_splprep_within(t, x, tol, limit_s=0.001)
    assert info.value.limit_s == 0.001
