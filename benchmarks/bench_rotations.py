"""Orientation channels: quaternion mode vs Euler mode vs the four components reduced alone.

    .venv/bin/python benchmarks/bench_rotations.py [--tol-deg 0.5] [--method global]

For each real orientation channel in ../shared/data (TUM camera, NGIMU, BVH joint
rotations converted to quaternions) and a synthetic spinning take: control points, the
largest geodesic error (degrees, measured with scipy's Rotation on the normalised curve)
and the time of each mode, in one run on this machine.

- quaternion: ``reduce_rotations`` (the geodesic angle is the bound);
- Euler ZXY: the paper's mode, each unwrapped angle within the tolerance (the geodesic
  error is then not bounded by it, so it is measured);
- Euler ZXY at the bound: the same, with the per-axis tolerance bisected (to 2%) to the
  largest that keeps the geodesic error within the tolerance: the fair comparison at
  the same angular tolerance (a third of it always does, as the three axes' errors add);
- components: the four quaternion components reduced as plain channels, each within
  sin(tol / 2), with no angle bound (measured as well).

Every mode finds pauses and breaks (the default). A second table shows what they change
in quaternion mode: control points and error with them and without, and what was found.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table
from scipy.spatial.transform import Rotation

import sketchanim

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data"
sys.path.insert(0, str(REPO / "tests"))

from recordings import rotation_cases  # noqa: E402

console = Console(width=max(Console().width, 160))


def spinning_take(n: int = 2400) -> tuple[str, np.ndarray, np.ndarray, bool]:
    """20 s at 120 Hz: a wobbling spin of eight turns with 0.05 degree jitter."""
    t = np.arange(n) / 120.0
    spin = Rotation.from_rotvec(np.outer(t / t[-1] * 16 * np.pi, [0.3, 0.9, 0.3]))
    wobble = Rotation.from_rotvec(np.c_[0.4 * np.sin(1.3 * t), 0.2 * np.sin(0.7 * t), 0.3 * np.cos(0.5 * t)])
    jitter = Rotation.from_rotvec(np.random.default_rng(0).normal(0, np.radians(0.05) / np.sqrt(3), (n, 3)))
    return "synthetic spin (8 turns)", t, (jitter * spin * wobble).as_quat(), False


def geodesic_deg(curve_quats: np.ndarray, quats: np.ndarray, scalar_first: bool) -> float:
    a = Rotation.from_quat(curve_quats, scalar_first=scalar_first)
    return float(np.degrees((a.inv() * Rotation.from_quat(quats, scalar_first=scalar_first)).magnitude()).max())


def euler(t: np.ndarray, q: np.ndarray, scalar_first: bool, axis_tol: float, tol: float,
          method: str) -> tuple[int, float, float]:
    """Euler mode with ``axis_tol`` per angle: points, max geodesic degrees, seconds."""
    clock = time.perf_counter()
    r = sketchanim.reduce_rotations(t, q, axis_tol, scalar_first=scalar_first, mode="euler", seq="ZXY",
                                    method=method)
    seconds = time.perf_counter() - clock
    curve = Rotation.from_euler("ZXY", r.spline(t)).as_quat(scalar_first=scalar_first)
    return r.n_coefficients, geodesic_deg(curve, q, scalar_first), seconds


def run_modes(t: np.ndarray, q: np.ndarray, scalar_first: bool, tol: float, method: str) -> dict[str, tuple]:
    """(control points, max geodesic degrees, seconds) for each mode."""
    out = {}
    clock = time.perf_counter()
    r = sketchanim.reduce_rotations(t, q, tol, scalar_first=scalar_first, method=method)
    out["quaternion"] = (r.n_coefficients, geodesic_deg(r.spline(t), q, scalar_first), time.perf_counter() - clock)
    out["Euler ZXY"] = euler(t, q, scalar_first, tol, tol, method)
    # A third of the tolerance per axis always holds: the three angles' errors add up.
    best = euler(t, q, scalar_first, tol / 3, tol, method)
    low, high = 1 / 3, 1.0
    while high - low > 0.02:
        mid = 0.5 * (low + high)
        trial = euler(t, q, scalar_first, mid * tol, tol, method)
        if trial[1] <= tol:
            best, low = trial, mid
        else:
            high = mid
    out["Euler ZXY at the bound"] = best
    clock = time.perf_counter()
    signed = sketchanim.motion.continuous_quaternions(q)
    r = sketchanim.reduce(t, signed, np.sin(np.radians(tol) / 2), method=method)
    out["components"] = (r.n_coefficients, geodesic_deg(r.spline(t), q, scalar_first), time.perf_counter() - clock)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tol-deg", type=float, default=0.5)
    parser.add_argument("--method", choices=sketchanim.reducer.METHODS, default="global")
    args = parser.parse_args()
    cases = [spinning_take()] + (rotation_cases(DATA) if DATA.is_dir() else [])
    modes = ("quaternion", "Euler ZXY", "Euler ZXY at the bound", "components")
    table = Table(title=f"orientation channels at {args.tol_deg} degrees, {args.method} method: "
                        "control points / max geodesic error (deg) / seconds")
    table.add_column("channel")
    table.add_column("n", justify="right")
    for mode in modes:
        table.add_column(mode, justify="right")
    totals = dict.fromkeys(modes, 0)
    wins = 0
    over = dict.fromkeys(modes, 0)
    for name, t, q, scalar_first in cases:
        res = run_modes(t, q, scalar_first, args.tol_deg, args.method)
        for mode, (pts, err, _) in res.items():
            totals[mode] += pts
            over[mode] += err > args.tol_deg * (1 + 1e-9)
        wins += res["quaternion"][0] <= res["Euler ZXY at the bound"][0]
        table.add_row(name, str(len(t)), *(f"{p} / {e:.3f} / {s:.2f}" for p, e, s in res.values()))
    table.add_row("total points", "", *(str(totals[m]) for m in modes))
    table.add_row("channels over the tolerance", "", *(str(over[m]) for m in modes))
    console.print(table)
    console.print(f"quaternion mode needs no more points than Euler mode at the same geodesic bound on {wins} "
                  f"of {len(cases)} channels")
    console.print(feature_table(cases, args.tol_deg, args.method))


def feature_table(cases: list, tol: float, method: str) -> Table:
    """Quaternion mode with pauses and breaks found (the default) and without."""
    table = Table(title=f"pauses and breaks, quaternion mode at {tol} degrees, {method} method")
    for column in ("channel", "points on", "points off", "on / off", "max err on (deg)", "max err off (deg)",
                   "pauses", "paused s", "breaks"):
        table.add_column(column, justify="left" if column == "channel" else "right")
    sums = [0, 0]
    for name, t, q, scalar_first in cases:
        on, off = (sketchanim.reduce_rotations(t, q, tol, scalar_first=scalar_first, method=method, features=f)
                   for f in (True, False))
        pauses = [f for f in on.features if f.kind == "pause"]
        sums[0] += on.n_coefficients
        sums[1] += off.n_coefficients
        table.add_row(name, str(on.n_coefficients), str(off.n_coefficients),
                      f"{on.n_coefficients / off.n_coefficients:.2f}",
                      f"{geodesic_deg(on.spline(t), q, scalar_first):.3f}",
                      f"{geodesic_deg(off.spline(t), q, scalar_first):.3f}", str(len(pauses)),
                      f"{sum(f.end - f.start for f in pauses):.1f}", str(len(on.features) - len(pauses)))
    table.add_row("total", str(sums[0]), str(sums[1]), f"{sums[0] / sums[1]:.2f}", "", "", "", "", "")
    return table


if __name__ == "__main__":
    main()
