"""Re-reducing a track from its raw takes at a new tolerance (the studio's tolerance
slider): how long, how many control points, and whether the server answers meanwhile.

    .venv/bin/python benchmarks/bench_rereduce.py [--repeats 5]

Takes of 60 s at 120 Hz (a hand's position: smooth motion with 0.3 mm of tremor and a
random walk; an orientation of the same kind), and the real TUM camera path (30 s at
100 Hz) when ../shared/data is there. For each tolerance: the control points and the
median time of :func:`~sketchanim.anim.layers.rereduced` with the windowed reducer the
model composes with, and of the global method (the fewest points) beside it. Then the
same through a studio server over its websocket: ``track.reduce`` sent to ``reduced``
received (preview, and the History step), and how long a ``ping`` sent right after it
waits for its ``pong`` (the model's thread is free while the reduction runs in its own).
Targets: release to new curve within 200 ms for a 60 s take; the ping unaffected.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import socket
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import uvicorn
from websockets.asyncio.client import connect
from rich.console import Console
from rich.table import Table
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import ORIENTATION, POSITION
from sketchanim.anim.layers import recorded_over, rereduced
from sketchanim.anim.tracks import Take
from sketchanim.anim.warmup import warm_recorder
from sketchanim.formats.recordings import read_tum
from sketchanim.project.store import Project
from sketchanim.studio.app import create_app
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.serve import server_config
from sketchanim.studio.takes import ORDER

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def hand(seconds: float, rate: float, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A performed position and orientation: smooth strokes, tremor and a slow drift."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, seconds, 1 / rate)
    strokes = np.c_[np.sin(0.9 * t) + 0.3 * np.sin(2.3 * t), 0.5 + 0.4 * np.cos(1.1 * t), 0.2 * np.sin(0.5 * t)]
    x = strokes + rng.normal(0, 0.0003, (len(t), 3)) + np.cumsum(rng.normal(0, 0.0002, (len(t), 3)), axis=0)
    q = Rotation.from_rotvec(np.c_[0.6 * np.sin(0.7 * t), 0.4 * np.cos(1.3 * t), 0.3 * t]
                             + rng.normal(0, 0.002, (len(t), 3))).as_quat()
    return t, x, q


def cases(data: Path) -> list[tuple[str, str, object, np.ndarray, np.ndarray, tuple[float, ...]]]:
    t, x, q = hand(60.0, 120.0, 1)
    out = [("hand 60 s 120 Hz", "box.position", POSITION, t, x, (0.001, 0.005, 0.02)),
           ("hand 60 s 120 Hz", "box.orientation", ORIENTATION, t, q, (0.2, 1.0, 4.0))]
    tum = data / "camera" / "freiburg1_xyz-groundtruth.txt"
    if tum.exists():
        tt, pos, quat = read_tum(tum)
        out.append(("TUM camera 30 s 100 Hz", "cam.position", POSITION, tt - tt[0], pos, (0.001, 0.005, 0.02)))
    return out


def timed(work, repeats: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = work()
        times.append(time.perf_counter() - start)
    return 1000 * float(np.median(times)), result


def model_table(repeats: int) -> Table:
    table = Table(title="re-reduction from the raw takes (rereduced), median of runs")
    for column in ("take", "path", "samples", "tol", "points", "ms", "global points", "global ms", "max error"):
        table.add_column(column, justify="right")
    for name, path, kind, t, x, tols in cases(DATA):
        track = recorded_over(path, kind, None, Take(t, x), tols[1], ORDER)
        for tol in tols:
            ms, made = timed(lambda: rereduced(track, tol, ORDER), repeats)
            global_ms, best = timed(lambda: rereduced(track, tol, ORDER, "global"), max(1, repeats // 2))
            table.add_row(name, path, str(len(t)), f"{tol:g}", str(made.track.n_coefficients), f"{ms:.0f}",
                          str(best.track.n_coefficients), f"{global_ms:.0f}", f"{made.error:.3g}")
    return table


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def over_socket(url: str, repeats: int) -> list[tuple[str, float, float]]:
    out = []
    async with connect(url, max_size=None) as ws:
        await ws.recv()
        for preview in (True, False):
            rounds, pings = [], []
            for r in range(repeats):
                tol = (0.002, 0.004)[r % 2]
                start = time.perf_counter()
                await ws.send(json.dumps({"type": "track.reduce", "paths": ["box.position"], "tol": tol,
                                          "preview": preview}))
                await ws.send(json.dumps({"type": "ping", "id": r}))
                while True:
                    m = json.loads(await ws.recv())
                    if m["type"] == "pong":
                        pings.append(time.perf_counter() - start)
                    if m["type"] == "reduced":
                        rounds.append(time.perf_counter() - start)
                        break
            out.append(("preview" if preview else "History step", 1000 * float(np.median(rounds)),
                        1000 * float(np.median(pings))))
    return out


def server_table(repeats: int) -> Table:
    t, x, _ = hand(60.0, 120.0, 2)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bench.sketchanim"
        with Project(path) as project:
            project.save(default_scene(), {"box.position": recorded_over("box.position", POSITION, None, Take(t, x),
                                                                          0.005, ORDER)})
        port = free_port()
        server = uvicorn.Server(server_config(create_app(path, warm=False), host="127.0.0.1", port=port))
        thread = threading.Thread(target=server.run, daemon=True)
        thread.start()
        while not server.started:
            time.sleep(0.05)
        try:
            rows = asyncio.run(over_socket(f"ws://127.0.0.1:{port}/ws", repeats))
        finally:
            server.should_exit = True
            thread.join(10)
    table = Table(title="the tolerance slider through a studio server: box.position, 60 s at 120 Hz")
    for column in ("track.reduce", "to reduced p50 ms", "a ping sent after it p50 ms"):
        table.add_column(column, justify="right")
    for row in rows:
        table.add_row(row[0], f"{row[1]:.0f}", f"{row[2]:.1f}")
    return table


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    warm_recorder()
    console = Console(width=200)
    console.print(model_table(args.repeats))
    console.print(server_table(args.repeats))


if __name__ == "__main__":
    sys.exit(main())
