"""Random motion-like signals for property tests: smooth motion with noise, steps,
pauses, spikes and irregular sampling, at any magnitude."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from hypothesis import strategies as st


@dataclass
class Signal:
    times: np.ndarray
    values: np.ndarray
    tol: np.ndarray


@st.composite
def signals(draw, max_n: int = 300, dims: tuple[int, int] = (1, 4), min_n: int = 2) -> Signal:
    n = draw(st.integers(min_n, max_n))
    dim = draw(st.integers(*dims))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    irregular = draw(st.booleans())
    steps = rng.lognormal(0.0, 0.6, n - 1) if irregular else np.ones(n - 1)
    times = np.r_[0.0, np.cumsum(steps)] * draw(st.sampled_from([1e-3, 1 / 60, 1.0, 30.0]))
    times += draw(st.sampled_from([0.0, 12.5, 1.6e9]))  # clocks that do not start at 0
    u = np.linspace(0, 1, n)
    values = np.zeros((n, dim))
    for j in range(dim):
        for _ in range(rng.integers(1, 4)):
            values[:, j] += rng.normal() * np.sin(2 * np.pi * rng.uniform(0.2, 4) * u + rng.uniform(0, 6))
    if draw(st.booleans()):
        values += rng.normal(0, draw(st.sampled_from([1e-3, 1e-2, 0.1])), values.shape)
    if draw(st.booleans()):                       # steps
        at = rng.integers(0, n, rng.integers(1, 3))
        for a in at:
            values[a:] += rng.normal(0, 1, dim)
    if draw(st.booleans()) and n > 10:            # a pause: hold still
        a = rng.integers(0, n - 5)
        values[a : a + rng.integers(3, max(4, n // 3))] = values[a]
    if draw(st.booleans()):                       # spikes
        at = rng.integers(0, n, rng.integers(1, 4))
        values[at] += rng.normal(0, 2, (len(at), dim))
    scale = 10.0 ** draw(st.integers(-9, 9))
    values *= scale
    spread = np.ptp(values, axis=0)
    spread[spread == 0] = scale
    tol = spread * 10.0 ** rng.uniform(-3, -0.5, dim)
    return Signal(times, values, tol)


@dataclass
class Performance(Signal):
    """A :class:`Signal` with planted holds (time spans) and corners (times)."""

    holds: list[tuple[float, float]]
    corners: list[float]


@st.composite
def performances(draw, dims: tuple[int, int] = (1, 3)) -> Performance:
    """Motion in stretches: holds, straight moves and arcs, joined where the velocity
    jumps (corners), sampled at 60-240 Hz, maybe jittered and noisy."""
    dim = draw(st.integers(*dims))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    rate = draw(st.sampled_from([60.0, 120.0, 240.0]))
    kinds = draw(st.lists(st.sampled_from(["hold", "line", "arc"]), min_size=1, max_size=6))
    durations = rng.uniform(0.3, 1.2, len(kinds))
    edges = np.r_[0.0, np.cumsum(durations)]
    n = int(edges[-1] * rate) + 1
    times = np.arange(n) / rate
    if draw(st.booleans()):
        times[1:-1] += rng.uniform(-0.2, 0.2, n - 2) / rate
    values = np.zeros((n, dim))
    here = rng.normal(0, 1, dim)
    holds, corners = [], []
    for kind, a, b in zip(kinds, edges[:-1], edges[1:]):
        m = (times >= a) & (times < b) if b < edges[-1] else (times >= a)
        u = times[m] - a
        if kind == "hold":
            values[m] = here
            holds.append((a, b))
        elif kind == "line":
            v = rng.normal(0, 2, dim)
            values[m] = here + u[:, None] * v
            here = here + (b - a) * v
        else:
            w, amp = rng.uniform(2, 8), rng.uniform(0.2, 1.0, dim)
            values[m] = here + amp * np.sin(w * u)[:, None]
            here = here + amp * np.sin(w * (b - a))
        if a > 0:
            corners.append(a)
    tol = np.full(dim, draw(st.sampled_from([1e-3, 1e-2])))
    if draw(st.booleans()):
        values += rng.normal(0, 0.1 * tol[0], values.shape)
    return Performance(times, values, tol, holds, corners)



def spike_drag(seed: int = 0) -> Signal:
    """A mouse drag logged in pixels (tol 2 px) at uneven event intervals (4-33 ms),
    with the pointer glitching to 0 for one sample: x runs 536 -> 0 -> 538 there, the
    spike of issue 24's mouse log (the midpoint check let the curve dip 67 px below it)."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.choice([0.004, 0.008, 0.016, 0.017, 0.033], 120))
    t -= t[0]
    x = np.c_[500 + 40 * np.sin(6 * t), 300 + 60 * t]
    i = int(np.argmin(np.abs(x[:, 0] - 536)))
    x[i - 1, 0], x[i, 0], x[i + 1, 0] = 536.0, 0.0, 538.0
    return Signal(t, x, np.array([2.0, 2.0]))
