"""Recorder: can it keep up with 1,000 armed channels performed at 120 Hz?

    .venv/bin/python benchmarks/bench_recorder.py [--channels 1000] [--rate 120] [--seconds 20]

A synthetic performer drives ``--channels`` armed attributes (three quarters positions,
one quarter orientations: a crowd of rigid bodies) in real time: one frame of all of them
per tick of the wall clock, pushed with ``Recorder.push_frame``. The recorder's worker
reduces them while the take goes on. Printed, from one run on this machine: how long a
push takes the caller, how far behind the capture the worker was when it took each batch
(lag percentiles), samples per second reduced, and how long ``stop()`` took to hand back
finished tracks. Then the same at a few smaller channel counts.
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
    return {
        "channels": channels,
        "push_p50_us": np.median(push) * 1e6,
        "push_p99_us": np.percentile(push, 99) * 1e6,
        "lag_p50_ms": np.median(lags),
        "lag_p99_ms": np.percentile(lags, 99),
        "lag_max_ms": lags.max(),
        "batches": len(lags),
        "late_ticks": late,
        "samples_per_s": samples / (captured - begin + finish),
        "stop_ms": finish * 1e3,
        "points": sum(t.n_coefficients for t in tracks.values()),
        "samples": samples,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--channels", type=int, default=1000)
    parser.add_argument("--rate", type=float, default=120.0)
    parser.add_argument("--seconds", type=float, default=20.0)
    args = parser.parse_args()
    rows = [run(n, args.rate, args.seconds) for n in sorted({10, 100, args.channels})]
    table = Table(title=f"Recorder at {args.rate:g} Hz for {args.seconds:g} s (one run; lag: capture to reducer)")
    for name in ("armed channels", "push p50 us", "push p99 us", "lag p50 ms", "lag p99 ms", "lag max ms",
                 "batches", "late ticks", "samples/s", "stop() ms", "points / samples"):
        table.add_column(name, justify="right")
    for r in rows:
        table.add_row(str(r["channels"]), f"{r['push_p50_us']:.0f}", f"{r['push_p99_us']:.0f}",
                      f"{r['lag_p50_ms']:.1f}", f"{r['lag_p99_ms']:.1f}", f"{r['lag_max_ms']:.1f}",
                      str(r["batches"]), str(r["late_ticks"]), f"{r['samples_per_s']:,.0f}", f"{r['stop_ms']:.0f}",
                      f"{r['points']:,} / {r['samples']:,}")
    Console(width=200).print(table)


if __name__ == "__main__":
    main()
