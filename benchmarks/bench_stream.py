"""Incremental reducer: per-window latency, throughput, memory, and control points vs peers.

Prints one table per question; run ``.venv/bin/python benchmarks/bench_stream.py [--quick]``.
Figures are one run on this machine: quote medians and ratios from the same run.
"""

from __future__ import annotations

import argparse
import resource
import sys
import time
import tracemalloc
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import sketchanim  # noqa: E402
from sketchanim.paper import spiral  # noqa: E402
from peers import sisl  # noqa: E402

console = Console(width=max(Console().width, 120))
DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def motion(n: int, seed: int = 0, start: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A smooth random 3-D take at 120 Hz with 1 mm of jitter (samples start .. start + n)."""
    rng = np.random.default_rng(seed)
    freq = rng.uniform(0.05, 1.5, (3, 4))
    amp = rng.normal(size=(3, 4))
    phase = rng.uniform(0, 6, (3, 4))
    t = (start + np.arange(n)) / 120.0
    x = np.einsum("jk,njk->nj", amp, np.sin(2 * np.pi * freq[None] * t[:, None, None] + phase[None]))
    noise = np.random.default_rng(seed + start).normal(0, 1e-3, x.shape)
    return t, x + noise


def chunks(n: int, chunk: int = 1000) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """The 3-D take of n samples, generated 1000 at a time (the whole take is never held)
    and handed out ``chunk`` samples at a time."""
    for start in range(0, n, 1000):
        t, x = motion(min(1000, n - start), start=start)
        for i in range(0, len(t), chunk):
            yield t[i : i + chunk], x[i : i + chunk]


def stream(n: int, window: int, chunk: int = 1000, features: bool = True, grow: bool = False
           ) -> tuple[float, sketchanim.StreamReducer]:
    """Stream n samples, ``chunk`` per call, generated on the fly (pieces dropped); wall
    seconds."""
    sr = sketchanim.StreamReducer(3, 0.01, window=window, keep=False, on_piece=lambda p: None, features=features,
                                  grow=grow)
    seconds = 0.0
    for t, x in chunks(n, chunk):
        clock = time.perf_counter()
        sr.extend(t, x)
        seconds += time.perf_counter() - clock
    clock = time.perf_counter()
    sr.close()
    return seconds + time.perf_counter() - clock, sr


def latency_table(n: int) -> None:
    table = Table(title=f"latency and throughput: 3-D take of {n:,} samples at 120 Hz, tol 0.01")
    for col in ("window", "grow", "pauses, breaks", "samples per call", "windows", "p50 ms", "p99 ms", "max ms",
                "samples/s", "control points"):
        table.add_column(col, justify="right")
    for window, grow, features, chunk in ((10, False, True, 1000), (20, False, True, 1000), (50, False, True, 1000),
                                          (20, False, False, 1000), (20, False, True, 1), (20, True, True, 1000)):
        seconds, sr = stream(n, window, chunk, features, grow)
        s = sr.stats
        table.add_row(str(window), "yes" if grow else "no", "on" if features else "off", str(chunk), f"{s.windows:,}",
                      f"{s.percentile_ms(50):.3f}", f"{s.percentile_ms(99):.3f}", f"{1e3 * s.max_window_seconds:.2f}",
                      f"{n / seconds:,.0f}", f"{s.samples - s.removed:,}")
    t, x = map(np.concatenate, zip(*chunks(n)))
    try:                       # the same take in one batch call to SISL (its own time, in C)
        peer = sisl.s1961(t, x, np.full(3, 0.01), split=0.0)
        table.add_row("SISL s1961, batch", "", "", "", "", "", "", "", f"{n / peer.seconds:,.0f}",
                      f"{peer.n_coefficients:,}")
    except Exception as err:   # the peer is optional: report, do not stop
        table.add_row("SISL s1961, batch", "", "", "", "", "", "", "", f"n/a ({type(err).__name__})", "")
    console.print(table)


def rss_mb() -> float:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def memory_table(sizes: list[int]) -> None:
    table = Table(title="memory while streaming (window 20, pieces dropped by the caller)")
    for col in ("samples", "seconds", "tracemalloc peak MB", "RSS after MB", "RSS growth from first MB"):
        table.add_column(col, justify="right")
    base = None
    for n in sizes:
        tracemalloc.start()
        seconds, _ = stream(n, 20)
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
        rss = rss_mb()
        base = rss if base is None else base
        table.add_row(f"{n:,}", f"{seconds:.1f}", f"{peak:.2f}", f"{rss:.1f}", f"{rss - base:+.1f}")
    console.print(table)


def cases() -> list[tuple[str, np.ndarray, np.ndarray, float]]:
    out = [("spiral, tol 0.1", *spiral(), 0.1)]
    t, x = motion(10_000, seed=3)
    out.append(("3-D take 10k, tol 0.01", t, x, 0.01))
    if DATA.is_dir():
        from recordings import shared_cases

        out += [c for c in shared_cases(DATA) if len(c[1]) >= 100]
    return out


def points_table() -> None:
    table = Table(title="control points: incremental vs global vs SISL s1961 (split 0), same inputs")
    for col in ("input", "n", "inc w10", "inc w20", "inc w50", "global", "w20 / global", "SISL s1961"):
        table.add_column(col, justify="right")
    ratios = []
    for name, t, x, tol in cases():
        inc = [sketchanim.reduce(t, x, tol, method="incremental", window=w).n_coefficients for w in (10, 20, 50)]
        glob = sketchanim.reduce(t, x, tol).n_coefficients
        try:
            peer = sisl.s1961(t, x, np.full(x.shape[1], tol), split=0.0)
            over = np.abs(peer.spline(t) - x).max() > tol * (1 + 1e-9)
            peer_text = f"{peer.n_coefficients}" + (" (over tol)" if over else "")
        except Exception as err:   # the peer is optional: report, do not stop
            peer_text = f"n/a ({type(err).__name__})"
        ratios.append(inc[1] / glob)
        table.add_row(name, str(len(t)), *map(str, inc), str(glob), f"{inc[1] / glob:.2f}", peer_text)
    table.add_row("median ratio", "", "", "", "", "", f"{np.median(ratios):.2f}", "")
    console.print(table)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="smaller streams (memory up to 1e6 samples)")
    args = parser.parse_args()
    stream(2000, 20)                     # load the compiled kernel before timing
    latency_table(20_000 if args.quick else 100_000)
    memory_table([100_000, 1_000_000] if args.quick else [100_000, 1_000_000, 10_000_000])
    points_table()


if __name__ == "__main__":
    main()
