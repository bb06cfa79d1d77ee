"""The walker (sketchanim.motion.walk and the page's walk.js): what one tick costs, what
the page pays per frame, and what the walk does on generated paths.

    .venv/bin/python benchmarks/bench_walk.py [--seconds 20] [--walkers 10]

- Time per tick of one walker (``advance``), in Python and in node (the page's module),
  on ``--seconds`` long generated paths: standing, walking at 1.4 m/s, running at 4 m/s,
  past the fastest run (9.5 m/s), and random curves with pauses (0 to 8 m/s).
- The page's case, ``--walkers`` walkers in node: per 60 Hz frame while the goals are
  performed live (each walker advancing a frame's two ticks, then its joints' world
  positions), per frame in playback from walks computed once (a frame's rotations copied,
  its world positions), and one walker's whole path re-simulated after an edit.
- What the walk does, on straight paths from 0.5 to 8 m/s: each foot's cycle and stride
  against Boulic's (``1.346 sqrt(H / v)`` s, ``1.346 sqrt(v / H) H`` m, at the body's speed,
  which is the path's up to the fastest run), the planted toes' speed sampled at 60 Hz over the stance spans (median and largest), the hips' lowest and
  highest, the share of ticks with both feet off the ground, and ``behind``.
- For scale, motion capture measured the same way (``--data``, default ../shared/data):
  the BVH walk and dash, the lowest node of each foot taken as planted while within
  ``--contact`` (2 cm) of its lowest, its speed at the clip's rate.

Medians (and p99 for times) of one run on this machine.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from walk_paths import lifts, segments, straight, toe_speeds, world  # noqa: E402

from sketchanim.formats.bvh import read_bvh  # noqa: E402
from sketchanim.motion.walk import CYCLE, RATE, RV_FASTEST, advance, gait, humanoid, rig, start, walk  # noqa: E402

console = Console(width=max(Console().width, 150))
FIGURE = humanoid(1.75)
LEG = rig(FIGURE).leg


def random_path(seconds: float, seed: int) -> np.ndarray:
    """Random parts (pauses and moves at 0 to 8 m/s with turns) filling ``seconds``."""
    rng = np.random.default_rng(seed)
    parts = [(0.5, 0.0, 0.0)]
    while sum(p[0] for p in parts) < seconds:
        speed = 0.0 if rng.random() < 0.3 else float(rng.uniform(0.0, 8.0))
        parts.append((float(rng.uniform(0.5, 3.0)), speed, float(rng.uniform(-1.5, 1.5))))
    return segments(parts, heading=float(rng.uniform(-math.pi, math.pi)))[:int(seconds * RATE)]


def python_ticks(markers: np.ndarray) -> np.ndarray:
    """Seconds per ``advance`` call along ``markers``."""
    rows = markers.tolist()
    s = start(FIGURE, rows[0])
    out = np.empty(len(rows) - 1)
    for k in range(1, len(rows)):
        clock = time.perf_counter()
        s = advance(s, rows[k])
        out[k - 1] = time.perf_counter() - clock
    return out


def node_timings(cases: dict[str, np.ndarray], walkers: list[np.ndarray]) -> dict | None:
    node = shutil.which("node")
    if node is None:
        return None
    with tempfile.TemporaryDirectory() as folder:
        dump = Path(folder) / "cases.json"
        dump.write_text(json.dumps({"cases": [{"name": k, "markers": v.tolist()} for k, v in cases.items()],
                                    "walkers": [w.tolist() for w in walkers]}))
        run = subprocess.run([node, str(REPO / "benchmarks" / "bench_walk.mjs"), str(dump)], capture_output=True,
                             text=True, check=True)
    return json.loads(run.stdout)


def us(seconds: np.ndarray) -> str:
    return f"{np.median(seconds) * 1e6:.1f} / {np.percentile(seconds, 99) * 1e6:.1f}"


def quality_rows() -> list[tuple[str, ...]]:
    """What the walk does on straight paths at several speeds."""
    rows = []
    for v in (0.5, 0.9, 1.2, 1.4, 1.8, 2.1, 3.0, 4.0, 6.0, 8.0):
        w = walk(FIGURE, straight(v, 12.0))
        points = world(FIGURE, w)
        body = min(v, RV_FASTEST * LEG)                 # the body's speed: no faster than the fastest run
        g = gait(body, LEG)
        cycles, strides = [], []
        for side in (0, 1):
            beats = lifts(w, side)
            beats = beats[beats > 4 * RATE]
            cycles.extend(np.diff(beats) / RATE)
            toe = points[beats, FIGURE.index(("l_toe", "r_toe")[side]), 2]
            strides.extend(np.diff(toe))
        slides = np.concatenate(toe_speeds(FIGURE, w, points))
        steady = w.stance[int(4 * RATE):]
        rv = body / LEG
        behind = "; ".join(f"{a:.2f}-{b:.2f} s at {c:.1f} m/s" for a, b, c in w.behind) or "-"
        rows.append((f"{v:.1f}", f"{rv:.2f}", "run" if g.run else "walk",
                     f"{np.median(cycles):.3f}", f"{CYCLE * math.sqrt(LEG / body):.3f}",
                     f"{np.median(strides):.3f}", f"{CYCLE * math.sqrt(rv) * LEG:.3f}",
                     f"{np.median(slides) * 100:.2f} / {slides.max() * 100:.2f}",
                     f"{w.root[int(4 * RATE):, 1].min():.3f}-{w.root[int(4 * RATE):, 1].max():.3f}",
                     f"{(~steady.any(axis=1)).mean() * 100:.0f}%", behind))
    return rows


def mocap_rows(data: Path, contact: float) -> list[tuple[str, ...]]:
    """Planted toes in the BVH walk and dash: speed of each foot's lowest node while it
    is within ``contact`` m of its lowest (frames on either side both in contact)."""
    rows = []
    for name in ("bandai1_walk_happy_001.bvh", "bandai1_dash_normal_001.bvh"):
        path = data / "bvh" / name
        if not path.exists():
            continue
        clip = read_bvh(path)
        points = clip.world_positions() * (clip.guess_unit_m() or 1.0)
        speeds = []
        for side in "LR":
            nodes = np.array([clip.skeleton.index(n) for n in (f"Foot_{side}", f"Toes_{side}", f"Toes_{side}_End")])
            height = points[:, nodes, 1]
            lowest = nodes[height.argmin(axis=1)]
            down = height.min(axis=1) < height.min() + contact
            k = np.flatnonzero(down[:-1] & down[1:])
            speeds.append(np.linalg.norm(points[k + 1, lowest[k]] - points[k, lowest[k]], axis=1) / clip.frame_time)
        both = np.concatenate(speeds)
        rows.append((f"{name} (motion capture, {1 / clip.frame_time:.0f} Hz)",
                     f"{np.median(both) * 100:.1f}", f"{np.percentile(both, 90) * 100:.1f}", f"{len(both)}"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--walkers", type=int, default=10)
    parser.add_argument("--data", type=Path, default=REPO.parent / "shared" / "data")
    parser.add_argument("--contact", type=float, default=0.02)
    args = parser.parse_args()
    cases = {"standing": straight(0.0, args.seconds), "walking 1.4 m/s": straight(1.4, args.seconds),
             "running 4 m/s": straight(4.0, args.seconds), "behind, 9.5 m/s": straight(9.5, args.seconds),
             "random curves, pauses, 0-8 m/s": random_path(args.seconds, 0)}
    walkers = [random_path(args.seconds, 1 + i) for i in range(args.walkers)]
    page = node_timings(cases, walkers)

    table = Table(title=f"One walker: time per tick (120 Hz), {args.seconds:g} s paths, p50 / p99 microseconds")
    for col in ("path", "Python", "node (walk.js)"):
        table.add_column(col, justify="right")
    for name, markers in cases.items():
        python_ticks(markers[:240])                                       # warm up
        table.add_row(name, us(python_ticks(markers)),
                      us(np.array(page["perTick"][name]) / 1e3) if page else "no node")
    console.print(table)

    if page:
        table = Table(title=f"The page: {args.walkers} walkers on random {page['seconds']:g} s paths (node)")
        for col in ("per frame", "p50 ms", "p99 ms"):
            table.add_column(col, justify="right")
        for name, key in (("live: 2 ticks each + world positions", "live"),
                          ("playback: a frame's pose each + world positions", "playback")):
            ms = np.array(page[key])
            table.add_row(name, f"{np.median(ms):.3f}", f"{np.percentile(ms, 99):.3f}")
        table.add_row(f"an edit: one walker's {page['seconds']:g} s re-simulated", f"{page['simulate']:.1f}", "")
        console.print(table)

    table = Table(title=f"What the walk does on straight paths (humanoid 1.75 m, H = {LEG:.4f} m), steady from 4 s")
    for col in ("v m/s", "RV", "gait", "cycle s", "Boulic s", "stride m", "Boulic m", "toe slide cm/s p50 / max",
                "hips m", "flight", "behind"):
        table.add_column(col, justify="right")
    for row in quality_rows():
        table.add_row(*row)
    console.print(table)

    table = Table(title=f"Planted toes for scale: ours (stance spans, 60 Hz) and motion capture (within "
                        f"{args.contact * 100:g} cm of the ground)")
    for col in ("", "cm/s p50", "cm/s p90", "samples"):
        table.add_column(col, justify="right")
    w = walk(FIGURE, random_path(args.seconds, 0))
    ours = np.concatenate(toe_speeds(FIGURE, w))
    table.add_row("ours, random curves with pauses", f"{np.median(ours) * 100:.2f}",
                  f"{np.percentile(ours, 90) * 100:.2f}", f"{len(ours)}")
    for row in mocap_rows(args.data, args.contact):
        table.add_row(*row)
    console.print(table)


if __name__ == "__main__":
    main()
