"""Studio server: how long from a take's release to its final curve, and what a batch of
samples costs the server, alone and under load.

    .venv/bin/python benchmarks/bench_studio_session.py [--repeats 7] [--load-repeats 3]

A take is performed through the studio's :class:`~sketchanim.studio.session.Session`
as a page does it, in real time: a position and an orientation (a grabbed object) at
60 frames a second, a batch every 6 frames (100 ms), for takes of 2, 10 and 30 seconds,
on a fresh track and as a punch-in over the track of the take before. Printed: the
median and worst time of handling one batch, and the median and worst release-to-final-
curve time (``take.end`` in, ``tracks`` out, measured in the session: what the page waits
for, less the socket), each over ``--repeats`` takes; the target is 100 ms. The project is
saved after the answer, as the app does; its time is printed beside.

Under load, the same takes go through a real server (uvicorn, in this process, its settings
as ``sketchanim studio`` has them) over a websocket: alone; while 20 other pages (in a
process of their own) send previews at their rate limit (each a drag of its own, relayed to
every other page); and with those and a page that never reads its socket (it is closed
after ``app.SEND_TIMEOUT``). Printed: release to final curve as the performing page sees it
(``take.end`` sent, ``tracks`` received), the samples' ack time, the project's save
(``Project.save`` in the server), the previews the pages got a second, the largest outgoing
queue of any page and the server process's resident memory.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import multiprocessing
import sys
import socket
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import uvicorn
from rich.console import Console
from rich.table import Table
from scipy.spatial.transform import Rotation

from sketchanim.project.store import Project
from sketchanim.studio import app as studio_app
from sketchanim.studio.app import create_app
from sketchanim.studio.serve import server_config
from sketchanim.studio.session import Session
from sketchanim.anim.warmup import warm_recorder

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from studio_browser import unread_socket  # noqa: E402

RATE, BATCH = 60.0, 6
#: Pages previewing at once under load, and the previews a second each sends (the rate limit's).
PREVIEWERS, PREVIEW_RATE = 20, studio_app.RATE


def perform(session: Session, name: str, start: float, seconds: float, seed: int) -> tuple[list[float], float, float]:
    """One take in real time; the batch times, the release-to-curve time and the save time (s)."""
    t = start + np.arange(int(seconds * RATE)) / RATE
    rows = rows_of(t, seed)
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


def rows_of(t: np.ndarray, seed: int) -> np.ndarray:
    """A grabbed object's position and orientation at times ``t``."""
    rng = np.random.default_rng(seed)
    w = rng.uniform(0.5, 2.0, 3)
    return np.c_[np.sin(w[0] * t), 0.5 + 0.3 * np.cos(w[1] * t), np.sin(w[2] * t),
                 Rotation.from_rotvec(np.c_[0.3 * t, np.sin(t), 0 * t]).as_quat()]


def preview_load(url: str, pages: int, rate: float, stop, counts) -> None:
    """``pages`` pages on ``url``, each dragging an object of its own at ``rate`` previews a
    second and reading what comes, until ``stop`` is set; ``counts``: previews received, errors received."""
    from websockets.asyncio.client import connect

    async def page(i: int) -> None:
        async with connect(url, max_size=None) as ws:
            async def read() -> None:
                async for text in ws:
                    kind = json.loads(text)["type"]
                    if kind in ("preview", "error"):
                        with counts.get_lock():
                            counts[kind == "error"] += 1

            reader = asyncio.ensure_future(read())
            start, n = time.perf_counter(), 0
            while not stop.is_set():
                due = int((time.perf_counter() - start) * rate * 0.98)
                for _ in range(due - n):
                    await ws.send(json.dumps({"type": "preview", "key": f"drag {i}", "path": "ball.position",
                                              "value": [np.sin(n / 50), 0.5, i]}))
                n = max(n, due)
                await asyncio.sleep(0.01)
            reader.cancel()

    async def run() -> None:
        await asyncio.gather(*(page(i) for i in range(pages)))

    asyncio.run(run())


async def perform_over_socket(url: str, name: str, start: float, seconds: float, seed: int,
                              sample: Callable[[], None]) -> tuple[list[float], float]:
    """One take in real time through the socket, as a page sends it; the samples' ack
    times and release to final curve (s). ``sample()`` is called at every batch."""
    from websockets.asyncio.client import connect

    t = start + np.arange(int(seconds * RATE)) / RATE
    rows = rows_of(t, seed)
    waiting: dict[str, asyncio.Future] = {}
    async with connect(url, max_size=None) as ws:
        async def read() -> None:
            async for text in ws:
                m = json.loads(text)
                key = str(m.get("id")) if m["type"] == "ack" else m["type"]
                if key in waiting and not waiting[key].done():
                    waiting[key].set_result(time.perf_counter())

        def expect(key: str) -> asyncio.Future:
            waiting[key] = asyncio.get_running_loop().create_future()
            return waiting[key]

        reader = asyncio.ensure_future(read())
        started = expect("take.started")
        await ws.send(json.dumps({"type": "take.begin", "take": name, "paths": ["box.position", "box.orientation"],
                                  "time": float(t[0])}))
        await started
        acks, clock = [], time.perf_counter()
        for i in range(0, len(t), BATCH):
            wait = clock + (i + BATCH) / RATE - time.perf_counter()
            if wait > 0:
                await asyncio.sleep(wait)
            acked = expect(str(i))
            sent = time.perf_counter()
            await ws.send(json.dumps({"type": "take.samples", "id": i, "take": name, "t": t[i:i + BATCH].tolist(),
                                      "values": rows[i:i + BATCH].tolist()}))
            acked.add_done_callback(lambda f, sent=sent: acks.append(f.result() - sent))
            sample()
        curve, ended = expect("tracks"), expect("take.ended")
        sent = time.perf_counter()
        await ws.send(json.dumps({"type": "take.end", "take": name}))
        release = await curve - sent
        await ended
        reader.cancel()
    return acks, release


def rss_mb() -> float:
    """This process's resident memory (MB)."""
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmRSS")) / 1024


def under_load(repeats: int) -> Table:
    """The takes through a real server, alone, under 20 previewing pages, and with a page
    that does not read."""
    table = Table(title=f"studio server under load: takes over a websocket; {PREVIEWERS} pages previewing at "
                        f"{PREVIEW_RATE:.0f}/s each")
    for column in ("load", "take", "release p50 ms", "release max ms", "ack p50 ms", "ack max ms", "save p50 ms",
                   "save max ms", "previews got /s", "max queue KiB", "rss MB"):
        table.add_column(column, justify="right")
    saves: list[float] = []
    real_save = Project.save

    def timed_save(self, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        c = time.perf_counter()
        real_save(self, *args, **kwargs)
        saves.append(time.perf_counter() - c)

    Project.save = timed_save
    spawn = multiprocessing.get_context("spawn")
    with tempfile.TemporaryDirectory() as folder:
        for load in ("none", "previews", "previews + slow reader"):
            app = create_app(Path(folder) / f"load-{len(load)}.sketchanim", warm=False)
            probe = socket.socket()
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
            probe.close()
            server = uvicorn.Server(server_config(app, host="127.0.0.1", port=port))
            thread = threading.Thread(target=server.run, daemon=True)
            thread.start()
            while not server.started:
                time.sleep(0.05)
            url = f"ws://127.0.0.1:{port}/ws"
            stop, counts = spawn.Event(), spawn.Array("l", 2)
            loader = None
            if load != "none":
                loader = spawn.Process(target=preview_load, args=(url, PREVIEWERS, PREVIEW_RATE, stop, counts))
                loader.start()
                time.sleep(2.0)                                  # the pages are connected and dragging
            stuck = unread_socket(port) if "slow" in load else None
            hub = app.state.hub
            biggest = [0]

            def sample() -> None:
                biggest[0] = max([biggest[0], *(c.queued for c in list(hub.clients.values()))])

            for seconds in (2.0, 10.0):
                acks, releases = [], []
                del saves[:]
                got, clock = counts[0], time.perf_counter()
                for r in range(repeats):
                    a, release = asyncio.run(perform_over_socket(url, f"take{r}", 1.0, seconds, r, sample))
                    acks += a
                    releases.append(release)
                    time.sleep(0.5)                              # the save after the take (at once, in the model thread)
                rate = (counts[0] - got) / (time.perf_counter() - clock)
                ms = lambda x, q: f"{1000 * np.percentile(x, q):.1f}" if len(x) else "-"   # noqa: E731
                table.add_row(load, f"{seconds:.0f} s", ms(releases, 50), ms(releases, 100), ms(acks, 50),
                              ms(acks, 100), ms(saves, 50), ms(saves, 100), f"{rate:.0f}", f"{biggest[0] / 1024:.0f}",
                              f"{rss_mb():.0f}")
            stop.set()
            if loader is not None:
                loader.join(30)
            if stuck is not None:
                stuck.close()
            server.should_exit = True
            thread.join(30)
            hub.session.close()
    Project.save = real_save
    return table


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--load-repeats", type=int, default=3)
    parser.add_argument("--skip-session", action="store_true", help="only the table under load")
    args = parser.parse_args()
    warm_recorder()
    table = Table(title=f"studio session: a position and an orientation at {RATE:.0f} Hz, batches of {BATCH}")
    for column in ("take", "over", "batch p50 ms", "batch max ms", "release p50 ms", "release max ms", "save p50 ms"):
        table.add_column(column, justify="right")
    with tempfile.TemporaryDirectory() as folder:
        for seconds in (2.0, 10.0, 30.0) if not args.skip_session else ():
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
    console = Console(width=200)
    console.print(table)
    console.print(under_load(args.load_repeats))


if __name__ == "__main__":
    main()
