"""Articulated-chain IK: time per tick (target: 0.2 ms for 8 joints, so 120 Hz has room).

    .venv/bin/python benchmarks/bench_ik.py [--seconds 10] [--repeats 7]

Chains of 2, 5 and 8 joints (one reach of 1.65, balls at the ends, hinges between, 150
degree limits, as the scene's default chain) follow ``--seconds`` of a 120 Hz goal path
that leaves the reach and comes back. Per tick, the median over ``--repeats`` runs:

- Python ``motion.ik.solve`` (plain floats) and ``motion.ik.step`` called tick by tick
  (numpy arrays in and out, as a caller holding poses would);
- node ``ik.js`` ``solve`` and ``step`` (benchmarks/bench_ik.mjs, after a warm-up run);
- for ``solve``, the process's CPU time per tick as well as the wall clock's: on a machine
  shared with other work the wall clock counts the time others had the core.

and why plain floats: one pose's forward kinematics by the numpy-vectorised ``points``
against the plain-float loop the solver runs, and one ``numpy.linalg.eigh`` of a 3 x 3
against the solver's Jacobi (each iteration needs one or two of them).
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from sketchanim.motion import ik

REPO = Path(__file__).resolve().parents[1]
console = Console(width=max(Console().width, 120))


def chain_of(joints: int) -> ik.Chain:
    """``joints`` equal segments reaching 1.65, balls at both ends, hinges between."""
    hinges = tuple(0 < i < joints - 1 for i in range(joints))
    return ik.Chain((1.65 / joints,) * joints, (np.radians(150.0),) * joints, hinges)


def goal_path(seconds: float) -> np.ndarray:
    """A Lissajous figure around the chain, out of its reach (1.65) for part of each lap."""
    t = np.arange(int(seconds * ik.RATE)) / ik.RATE
    return np.c_[1.2 * np.sin(1.1 * t), 1.0 + 0.9 * np.sin(0.7 * t + 1.0), 1.1 * np.cos(1.3 * t)]


def python_times(chain: ik.Chain, goals: np.ndarray, repeats: int) -> tuple[float, float, float]:
    """Median seconds per tick of ``solve`` (wall clock, CPU) and of ``step`` tick by tick."""
    solves, cpus, steps = [], [], []
    for _ in range(repeats):
        cpu, clock = time.process_time(), time.perf_counter()
        ik.solve(chain, goals)
        solves.append(time.perf_counter() - clock)
        cpus.append(time.process_time() - cpu)
        pose, previous = ik.rest(chain), None
        clock = time.perf_counter()
        for goal in goals:
            pose = ik.step(chain, pose, goal, previous)
            previous = goal
        steps.append(time.perf_counter() - clock)
    return tuple(float(np.median(x)) / len(goals) for x in (solves, cpus, steps))


def node_times(chains: list[ik.Chain], goals: np.ndarray, repeats: int) -> list[tuple[float, ...]] | None:
    """Median seconds per tick of ik.js ``solve`` (wall clock, CPU) and ``step`` for each chain
    (None: no node)."""
    node = shutil.which("node")
    if node is None:
        return None
    spec = {"chains": [{"lengths": list(c.lengths), "limits": list(c.limits), "hinges": list(c.hinges)}
                       for c in chains], "goals": goals.ravel().tolist(), "repeats": repeats}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "spec.json"
        path.write_text(json.dumps(spec))
        run = subprocess.run([node, str(REPO / "benchmarks/bench_ik.mjs"), str(path)], capture_output=True,
                             text=True, check=True)
    return [tuple(float(np.median(r[key])) / len(goals) for key in ("solve", "cpu", "step"))
            for r in json.loads(run.stdout)]


def per_call(call, repeats: int = 20000) -> float:
    """Median seconds of ``call()`` over batches of 100."""
    batches = []
    for _ in range(repeats // 100):
        clock = time.perf_counter()
        for _ in range(100):
            call()
        batches.append((time.perf_counter() - clock) / 100)
    return float(np.median(batches))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    goals = goal_path(args.seconds)
    chains = [chain_of(j) for j in (2, 5, 8)]
    nodes = node_times(chains, goals, args.repeats)
    table = Table(title=f"chain IK, ms per tick (median of {args.repeats} runs over {len(goals)} ticks, "
                        f"{ik.ITERATIONS} iterations a tick)")
    for column in ("joints", "Python solve", "Python solve CPU", "Python step", "node solve", "node solve CPU",
                   "node step"):
        table.add_column(column, justify="right")
    for i, chain in enumerate(chains):
        py = python_times(chain, goals, args.repeats)
        js = nodes[i] if nodes else (float("nan"),) * 3
        table.add_row(str(len(chain.lengths)), *(f"{s * 1e3:.4f}" for s in (*py, *js)))
    console.print(table)
    if nodes is None:
        console.print("node is not installed: no page timings", style="yellow")

    chain = chains[-1]
    pose = ik.solve(chain, goals[:240])[-1]
    flat = pose.ravel().tolist()
    p = ik._prepare(chain)
    pos, world = [0.0] * (3 * p.n + 3), [0.0] * (4 * p.n)
    tips = ik.points(chain, pose)
    a = tips.T @ tips                                        # a symmetric 3 x 3 as J J^T is
    small = Table(title="why plain floats: one call at 8 joints, microseconds (median)")
    small.add_column("operation")
    small.add_column("numpy", justify="right")
    small.add_column("plain floats", justify="right")
    small.add_row("forward kinematics of one pose", f"{per_call(lambda: ik.points(chain, pose)) * 1e6:.2f}",
                  f"{per_call(lambda: ik._forward(p, flat, pos, world)) * 1e6:.2f}")
    small.add_row("eigen-decomposition of a 3 x 3", f"{per_call(lambda: np.linalg.eigh(a)) * 1e6:.2f}",
                  f"{per_call(lambda: ik._jacobi(a.ravel().tolist())) * 1e6:.2f}")
    console.print(small)


if __name__ == "__main__":
    sys.exit(main())
