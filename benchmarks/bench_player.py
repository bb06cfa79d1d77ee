"""Player: every track of a scene evaluated at one time (the target: 1,000 tracks in 1 ms).

    .venv/bin/python benchmarks/bench_player.py [--tracks 1000] [--points 200]

A scene of objects and lights with cubic position, orientation and colour tracks of
``--points`` control points each over 60 s; per call at random times: the packed,
compiled evaluation (``Player.values``), the same plus writing into the scene
(``Player.apply``), and for comparison one scipy ``BSpline`` call per track. Median and
p99 of one run on this machine.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from rich.console import Console
from rich.table import Table
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import COLOR, ORIENTATION, POSITION
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack


def scene_with_tracks(n_tracks: int, points: int, seed: int = 0) -> tuple[Scene, list[ContinuousTrack]]:
    """Half positions, three tenths orientations, the rest light colours."""
    rng = np.random.default_rng(seed)
    scene = Scene()
    tracks = []
    kinds = [POSITION] * (n_tracks // 2) + [ORIENTATION] * (3 * n_tracks // 10)
    kinds += [COLOR] * (n_tracks - len(kinds))
    for i, kind in enumerate(kinds):
        name = f"o{i}"
        scene.add(name, "light" if kind is COLOR else "object")
        knots = np.r_[[0.0] * 4, np.sort(rng.uniform(0, 60, points - 4)), [60.0] * 4]
        coef = rng.normal(0, 1, (points, kind.dim)) + (np.array([0, 0, 0, 3.0]) if kind.is_rotation else 0)
        tracks.append(ContinuousTrack(f"{name}.{kind.name}", kind, BSpline(knots, coef, 3), kind.tol))
    return scene, tracks


def timed(call, times: np.ndarray) -> np.ndarray:
    out = np.empty(len(times))
    for i, t in enumerate(times):
        clock = time.perf_counter()
        call(t)
        out[i] = time.perf_counter() - clock
    return out * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--tracks", type=int, default=1000)
    parser.add_argument("--points", type=int, default=200)
    args = parser.parse_args()
    scene, tracks = scene_with_tracks(args.tracks, args.points)
    player = Player(scene, tracks)
    clock = time.perf_counter()
    player.values(0.0)                                   # packs the tracks (and loads the kernel)
    first = time.perf_counter() - clock
    times = np.random.default_rng(1).uniform(-1, 61, 2000)

    def apply(t: float) -> None:
        player.seek(t)
        player.apply()

    rows = [("Player.values (packed, compiled)", timed(player.values, times)),
            ("Player.apply (values + write into the scene)", timed(apply, times)),
            ("one scipy BSpline call per track", timed(lambda t: [c.evaluate([t]) for c in tracks], times[:200]))]
    table = Table(title=f"{args.tracks:,} tracks of {args.points} control points, one time per call "
                        f"(first call, packing: {first * 1e3:.0f} ms)")
    for col in ("", "p50 ms", "p99 ms", "max ms", "tracks per ms (p50)"):
        table.add_column(col, justify="right")
    for name, ms in rows:
        table.add_row(name, f"{np.median(ms):.3f}", f"{np.percentile(ms, 99):.3f}", f"{ms.max():.3f}",
                      f"{args.tracks / np.median(ms):,.0f}")
    Console(width=120).print(table)


if __name__ == "__main__":
    main()
