"""StreamReducer(keep=True): memory held beyond the curve it keeps, per sample.

Streams a smooth two-channel take (100 Hz) in batches of 1,000 and measures with
tracemalloc what the reducer holds at the end (after a warm-up take, so compiled
kernels are not counted), against keep=False and against the kept curve's own numbers
(knots + coefficients, float64).

    .venv/bin/python benchmarks/bench_keep_memory.py [samples ...]
"""

from __future__ import annotations

import sys
import tracemalloc

import numpy as np

import sketchanim


def held(n: int, keep: bool) -> tuple[int, int]:
    """Bytes held after streaming ``n`` samples, and the kept curve's bytes."""
    t = np.arange(n) / 100.0
    x = np.c_[np.sin(0.7 * t) + 0.3 * np.sin(2.3 * t), np.cos(0.5 * t)]
    tracemalloc.start()
    sr = sketchanim.StreamReducer(2, 0.01, keep=keep)
    for a in range(0, n, 1000):
        sr.extend(t[a : a + 1000], x[a : a + 1000])
    current, _ = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    curve = sr.finish().spline if keep else None
    return current, 0 if curve is None else (curve.t.nbytes + curve.c.nbytes)


def main(sizes: list[int]) -> None:
    held(20_000, True)                                   # warm-up: compile the kernels
    print(f"{'samples':>10} {'keep=True B':>12} {'keep=False B':>13} {'curve B':>9} {'B/sample beyond curve':>22}")
    for n in sizes:
        kept, curve = held(n, True)
        free, _ = held(n, False)
        print(f"{n:>10,} {kept:>12,} {free:>13,} {curve:>9,} {(kept - free - curve) / n:>22.3f}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [100_000, 400_000, 1_600_000])
