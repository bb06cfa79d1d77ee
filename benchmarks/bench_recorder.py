"""Recorder: can it keep up with 1,000 armed channels performed at 120 Hz?

    .venv/bin/python benchmarks/bench_recorder.py [--channels 1000] [--rate 120] [--seconds 20]

A synthetic performer drives ``--channels`` armed attributes (three quarters positions,
one quarter orientations: a crowd of rigid bodies) in real time: one frame of all of them
per tick of the wall clock, pushed with ``Recorder.push_frame``. The recorder's worker
reducer processes reduce them while the take goes on. Printed, from one run on this
machine: how long a push takes the caller, how far behind the capture the reducers were
when they took each batch (lag percentiles), the busiest reducer process's load (its
busy time over the take's length: under 100% it keeps up), the samples per second that
load means it could take, and how long ``stop()`` took to hand back finished tracks.
Then the same at a few smaller channel counts; and how long ``stop()`` takes to hand back
a punch-in (a position and an orientation recorded over existing tracks) for takes of
2, 10 and 60 seconds, pushed as fast as they come and stopped once the reducers are idle.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from rich.console import Console
from rich.table import Table
from scipy.spatial.transform import Rotation

from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene


def performance(channels: int, seed: int = 0) -> tuple[Scene, Recorder, callable]:
    """A scene of ``channels`` armed attributes and a function giving a frame at t."""
    rng = np.random.default_rng(seed)
    scene = Scene()
    rec = Recorder(scene)
    n_rot = channels // 4
    for i in range(channels):
        scene.add(f"b{i}")
        rec.arm(f"b{i}.orientation" if i < n_rot else f"b{i}.position")
    freq = rng.uniform(0.2, 1.5, (channels, 3))
    phase = rng.uniform(0, 6, (channels, 3))

    def frame(t: float) -> np.ndarray:
        wave = np.sin(freq * t + phase)
        quats = Rotation.from_rotvec(wave[:n_rot]).as_quat()
        return np.concatenate([quats.reshape(-1), wave[n_rot:].reshape(-1)])

    return scene, rec, frame


def run(channels: int, rate: float, seconds: float) -> dict[str, float]:
    _, rec, frame = performance(channels)
    frames = [frame(i / rate) for i in range(int(seconds * rate))]
    rec.start()
    push = np.empty(len(frames))
    begin = time.perf_counter()
    late = 0
    for i, x in enumerate(frames):
        due = begin + i / rate
        wait = due - time.perf_counter()
        if wait > 0:
            time.sleep(wait)
        else:
            late += 1
        clock = time.perf_counter()
        rec.push_frame(i / rate, x)
        push[i] = time.perf_counter() - clock
    captured = time.perf_counter()
    tracks = rec.stop()
    finish = time.perf_counter() - captured
    lags = np.array([lag for lag, _ in rec.lags]) * 1e3
    samples = len(frames) * channels
    busiest = max(rec.busy)
    return {
        "channels": channels,
        "push_p50_us": np.median(push) * 1e6,
        "push_p99_us": np.percentile(push, 99) * 1e6,
        "lag_p50_ms": np.median(lags),
        "lag_p99_ms": np.percentile(lags, 99),
        "lag_max_ms": lags.max(),
        "batches": len(lags),
        "late_ticks": late,
        "load": busiest / (captured - begin),
        "capacity": samples / busiest,
        "workers": len(rec.busy),
        "stop_ms": finish * 1e3,
        "points": sum(t.n_coefficients for t in tracks.values()),
        "samples": samples,
    }


def punch_in(seconds: float) -> float:
    """Milliseconds ``stop()`` takes for a punch-in of ``seconds`` over two tracks."""
    scene = Scene()
    scene.add("b")
    rec = Recorder(scene)
    rec.arm("b.position")
    rec.arm("b.orientation")
    t = np.arange(0, seconds + 2, 1 / 120)
    turn = np.c_[np.sin(t), 0.3 * t, 0 * t]
    rec.start()
    for ti, q in zip(t, Rotation.from_rotvec(turn).as_quat()):
        rec.push_frame(ti, np.r_[np.sin(ti), np.cos(ti), 0.1 * ti, q])
    tracks = rec.stop()
    rec.start(tracks)
    inside = (t >= 1) & (t <= 1 + seconds)
    for ti, q in zip(t[inside], Rotation.from_rotvec(turn[inside] + 0.2).as_quat()):
        rec.push_frame(ti, np.r_[np.sin(ti) + 0.2 * np.sin(3 * ti), np.cos(ti), 0.1 * ti, q])
    time.sleep(2.0)                                     # the reducers catch up
    clock = time.perf_counter()
    rec.stop()
    return (time.perf_counter() - clock) * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--channels", type=int, default=1000)
    parser.add_argument("--rate", type=float, default=120.0)
    parser.add_argument("--seconds", type=float, default=20.0)
    args = parser.parse_args()
    rows = [run(n, args.rate, args.seconds) for n in sorted({10, 100, args.channels})]
    table = Table(title=f"Recorder at {args.rate:g} Hz for {args.seconds:g} s (one run; lag: capture to reducer)")
    for name in ("armed channels", "push p50 us", "push p99 us", "lag p50 ms", "lag p99 ms", "lag max ms",
                 "batches", "late ticks", "reducers", "busiest load", "capacity samples/s", "stop() ms",
                 "points / samples"):
        table.add_column(name, justify="right")
    for r in rows:
        table.add_row(str(r["channels"]), f"{r['push_p50_us']:.0f}", f"{r['push_p99_us']:.0f}",
                      f"{r['lag_p50_ms']:.1f}", f"{r['lag_p99_ms']:.1f}", f"{r['lag_max_ms']:.1f}",
                      str(r["batches"]), str(r["late_ticks"]), str(r["workers"]), f"{r['load']:.0%}",
                      f"{r['capacity']:,.0f}", f"{r['stop_ms']:.0f}",
                      f"{r['points']:,} / {r['samples']:,}")
    console = Console(width=200)
    console.print(table)
    punch = Table(title="stop() of a punch-in over two tracks (one run)")
    punch.add_column("take seconds", justify="right")
    punch.add_column("stop() ms", justify="right")
    for seconds in (2, 10, 60):
        punch.add_row(str(seconds), f"{punch_in(seconds):.1f}")
    console.print(punch)


if __name__ == "__main__":
    main()
