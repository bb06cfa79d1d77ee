"""Studio server: how long from a take's release to its final curve, and what a batch of
samples costs the server.

    .venv/bin/python benchmarks/bench_studio_session.py [--repeats 7]

A take is performed through the studio's :class:`~sketchanim.studio.session.Session`
as a page does it, in real time: a position and an orientation (a grabbed object) at
60 frames a second, a batch every 6 frames (100 ms), for takes of 2, 10 and 30 seconds,
on a fresh track and as a punch-in over the track of the take before. Printed: the
median and worst time of handling one batch, and the median and worst release-to-final-
curve time (``take.end`` in, ``tracks`` out, measured in the session: what the page waits
for, less the socket), each over ``--repeats`` takes; the target is 100 ms. The project is
saved after the answer, as the app does; its time is printed beside.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table
from scipy.spatial.transform import Rotation

from sketchanim.studio.session import Session
from sketchanim.anim.warmup import warm_recorder

RATE, BATCH = 60.0, 6


def perform(session: Session, name: str, start: float, seconds: float, seed: int) -> tuple[list[float], float, float]:
    """One take in real time; the batch times, the release-to-curve time and the save time (s)."""
    rng = np.random.default_rng(seed)
    t = start + np.arange(int(seconds * RATE)) / RATE
    w = rng.uniform(0.5, 2.0, 3)
    rows = np.c_[np.sin(w[0] * t), 0.5 + 0.3 * np.cos(w[1] * t), np.sin(w[2] * t),
                 Rotation.from_rotvec(np.c_[0.3 * t, np.sin(t), 0 * t]).as_quat()]
    session.begin_take(1, name, ["box.position", "box.orientation"], "replace", 0.1, float(t[0]), 1.0, {}, None, 0.25)
    batches = []
    clock = time.perf_counter()
    for i in range(0, len(t), BATCH):
        wait = clock + (i + BATCH) / RATE - time.perf_counter()
        if wait > 0:
            time.sleep(wait)
        c = time.perf_counter()
        session.samples(1, name, t[i:i + BATCH], rows[i:i + BATCH].tolist())
        batches.append(time.perf_counter() - c)
    c = time.perf_counter()
    session.end_take(1, name, None)
    release = time.perf_counter() - c
    c = time.perf_counter()
    session.save()
    return batches, release, time.perf_counter() - c


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    warm_recorder()
    table = Table(title=f"studio session: a position and an orientation at {RATE:.0f} Hz, batches of {BATCH}")
    for column in ("take", "over", "batch p50 ms", "batch max ms", "release p50 ms", "release max ms", "save p50 ms"):
        table.add_column(column, justify="right")
    with tempfile.TemporaryDirectory() as folder:
        for seconds in (2.0, 10.0, 30.0):
            for over in ("fresh", "punch-in"):
                batches, releases, saves = [], [], []
                for r in range(args.repeats if seconds < 30 else max(2, args.repeats // 3)):
                    session = Session(Path(folder) / f"b{seconds}{over}{r}.sketchanim")
                    if over == "punch-in":
                        perform(session, "base", 0.0, seconds + 2.0, r + 100)
                    b, release, save = perform(session, "take", 1.0, seconds, r)
                    batches += b
                    releases.append(release)
                    saves.append(save)
                    session.close()
                ms = lambda x, q: f"{1000 * np.percentile(x, q):.1f}"          # noqa: E731
                table.add_row(f"{seconds:.0f} s", over, ms(batches, 50), ms(batches, 100), ms(releases, 50),
                              ms(releases, 100), ms(saves, 50))
    Console().print(table)


if __name__ == "__main__":
    main()
