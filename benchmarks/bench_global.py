"""Global reduction vs the peers: control points, max error and median time, one table.

    .venv/bin/python benchmarks/bench_global.py [--quick] [--repeats N]
    .venv/bin/python benchmarks/bench_global.py --swing       # the reducer table


Cases: the Archimedean spiral (t cos t, t sin t), t in [0, 6 pi], tol 0.1, n = 1k, 10k,
100k; a noisy synthetic 3-D take; and, when ../shared/data is present, a BVH root-position track, a pen stroke and
the TUM hand-held camera path. Methods: ours (paper start, LM start), SISL s1961 (split
0 and 0.1) and s1940, scipy make_splprep with the smoothing factor bisected. Times are
medians over repeats (FITPACK's whole search: one run), taken in one run on this machine;
SISL's is its own call alone.

``--swing`` prints the reducer table instead: over every channel group of ../shared/data
(tests/recordings.py), seven TUM segments with dropped frames and the mouse-log spike,
the control points of ours (features on), of ours with ``features=False`` and of SISL
s1961 at the same tolerance, and each curve's worst swing beyond its samples' local
range (``swing.excess`` with tolerance 0, over the tolerance: <= 1 keeps the no-swing
bound). The swing check is loaded from this tree's file, so the same script measures
an older ``sketchanim`` on PYTHONPATH (``git worktree add /tmp/before f42d35a``, then
``PYTHONPATH=/tmp/before/src``).
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

import sketchanim
from sketchanim.paper import spiral
from peers import PeerResult, fitpack, sisl

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data"
sys.path.insert(0, str(REPO / "tests"))


def cases(quick: bool) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]:
    sizes = [1000] if quick else [1000, 10_000, 100_000]
    out = [(f"spiral n={n}", *spiral(n), np.array([0.1, 0.1])) for n in sizes]
    if not quick:
        # Beyond the cases: a noisy 3-D take (sigma 0.01) at 4 sigma tolerance,
        # where the curve must follow a few noise extremes.
        rng = np.random.default_rng(0)
        t = np.linspace(0.0, 20.0, 10_000)
        x = np.c_[np.sin(t), np.cos(1.3 * t), 0.3 * t] + rng.normal(0.0, 0.01, (len(t), 3))
        out.append(("noisy 3-D take, tol 4 sigma", t, x, np.full(3, 0.04)))
    if DATA.is_dir() and not quick:
        from recordings import shared_cases

        real = {name: (t, x, tol) for name, t, x, tol in shared_cases(DATA)}
        for name in ("cmu_01_01_playground_jumps.bvh root", "PaHaW pen (tablet units)", "tum positions (m)"):
            t, x, tol = real[name]
            out.append((name, t, x, np.full(x.shape[1], tol)))
    return out


def ours(start: str) -> Callable[[np.ndarray, np.ndarray, np.ndarray], PeerResult]:
    def run(t: np.ndarray, x: np.ndarray, tol: np.ndarray) -> PeerResult:
        clock = time.perf_counter()
        r = sketchanim.reduce(t, x, tol, start=start)
        return PeerResult(f"sketchanim ({start} start)", r.spline, time.perf_counter() - clock)
    return run


METHODS: list[tuple[str, Callable[..., PeerResult]]] = [
    ("ours", ours("paper")),
    ("ours", ours("lm")),
    ("sisl", lambda t, x, tol: sisl.s1961(t, x, tol, split=0.0)),
    ("sisl", lambda t, x, tol: sisl.s1961(t, x, tol, split=0.1)),
    ("sisl", sisl.s1940),
    ("scipy", fitpack.make_splprep_within),
]


def measure(method: Callable[..., PeerResult], t: np.ndarray, x: np.ndarray, tol: np.ndarray,
            repeats: int) -> tuple[PeerResult, float]:
    runs = [method(t, x, tol) for _ in range(repeats)]
    return runs[0], statistics.median(r.seconds for r in runs)


def swing_cases() -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]:
    """The reducer table's cases: ../shared/data, TUM with dropped frames, the spike."""
    from recordings import shared_cases, tum_dropped_frames
    from signals import spike_drag

    out = [(name, t, x.reshape(len(t), -1), np.full(x.reshape(len(t), -1).shape[1], tol))
           for name, t, x, tol in shared_cases(DATA)]
    for seed in range(7):
        t, x = tum_dropped_frames(DATA, seed)
        out.append((f"TUM dropped frames #{seed}", t, x, np.full(3, 0.005)))
    spike = spike_drag()
    out.append(("mouse drag, spike 536 -> 0 -> 538 (px)", spike.times, spike.values, spike.tol))
    return out


def swing_table(console: Console) -> None:
    """Print the reducer table (see the module's docstring)."""
    spec = importlib.util.spec_from_file_location("swing", REPO / "src" / "sketchanim" / "reducer" / "swing.py")
    assert spec is not None and spec.loader is not None
    swing = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(swing)
    table = Table(title="The reducer: control points and worst swing beyond the local range (in tolerances)")
    for col in ("case", "n", "ours", "features=False", "SISL s1961", "ours swing", "features=False swing",
                "SISL swing"):
        table.add_column(col, justify="left" if col == "case" else "right")
    totals = np.zeros(3, dtype=int)
    for name, t, x, tol in swing_cases():
        print(f"{name} ...", file=sys.stderr, flush=True)
        splines = [sketchanim.reduce(t, x, tol).spline, sketchanim.reduce(t, x, tol, features=False).spline,
                   sisl.s1961(t, x, tol).spline]
        lo, hi = swing.local_ranges(x, np.zeros_like(tol))
        counts = [len(s.c) for s in splines]
        swings = [float(np.max(swing.excess(s, t, lo, hi) / tol)) for s in splines]
        totals += counts
        table.add_row(name, str(len(t)), *map(str, counts), *(f"{v:.3g}" for v in swings))
    table.add_section()
    table.add_row("total", "", *map(str, totals), "", "", "")
    console.print(table)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="spiral n=1000 only, one repeat")
    parser.add_argument("--repeats", type=int, default=5, help="timing repeats (FITPACK's search runs once)")
    parser.add_argument("--swing", action="store_true", help="the reducer table (needs ../shared/data)")
    args = parser.parse_args()
    if args.swing:
        swing_table(Console(width=170))
        return
    console = Console(width=170)
    table = Table(title="Global reduction: control points and median time (this machine, one run)")
    for col in ("case", "n", "method", "control points", "max err / tol", "median ms"):
        table.add_column(col, justify="left" if col in ("case", "method") else "right")
    verdicts = []
    for name, t, x, tol in cases(args.quick):
        results = {}
        for family, method in METHODS:
            # FITPACK's bisected search takes seconds to minutes: timed once.
            repeats = 1 if args.quick or family == "scipy" else args.repeats
            print(f"{name}: {family} ...", file=sys.stderr, flush=True)
            try:
                res, seconds = measure(method, t, x, tol, repeats)
            except fitpack.PeerTimeout as timeout:
                table.add_row(name, str(len(t)), "scipy make_splprep (s bisected)", "-",
                              "-", f"> {1e3 * timeout.limit_s:.0f} (stopped)")
                continue
            err = float(np.max(res.max_error(t, x) / tol))
            results[res.name] = (res.n_coefficients, err, seconds, family)
            flag = "" if err <= 1.0 else "  (over tolerance)"
            table.add_row(name, str(len(t)), res.name, str(res.n_coefficients), f"{err:.3f}{flag}",
                          f"{1e3 * seconds:.1f}")
        table.add_section()
        best_sisl = min(v[0] for v in results.values() if v[3] == "sisl" and v[1] <= 1.0 + 1e-9)
        fastest_sisl = min(v[2] for v in results.values() if v[3] == "sisl")
        mine = results["sketchanim (paper start)"]
        verdicts.append(f"{name}: {mine[0]} control points vs SISL's best {best_sisl} "
                        f"({'<=' if mine[0] <= best_sisl else '>'}); time {1e3 * mine[2]:.1f} ms = "
                        f"{mine[2] / fastest_sisl:.2f}x SISL's fastest")
    console.print(table)
    for line in verdicts:
        console.print(line)


if __name__ == "__main__":
    main()
