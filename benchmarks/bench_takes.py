"""Takes from a pointer drag: compact and faithful at the tolerance the page sends?

    .venv/bin/python benchmarks/bench_takes.py [--seconds 2] [--pointer-hz 60] [--seed 0]

A scripted 2 s drag (320 px across, 90 px up and back: a smoothstep and a sine arch) is
reported by a pointer at ``--pointer-hz`` (integer pixels, each report with 0, 0.5, 1 or
2 px of Gaussian hand jitter, its time jittered by 1 ms) and sampled by a page whose
animation frames come at 15, 30 or 60 Hz with a browser's uneven frame times (each
interval 0.7 to 1.3 of the nominal one, one in twenty twice as long). Three ways of
turning the reports into a take's samples:

* ``frame``: each frame's sample is the pointer's last report, stamped with the frame's
  time (what the page did before it paired values with their times);
* ``events``: every report at its own time (the page with ``getCoalescedEvents()``);
* ``last event``: each frame's last report at its own time (a browser without coalesced
  events).

With ``events`` and ``last event`` a frame with no new report, 1.5 of the pointer's
median interval (at least 25 ms) after the last one, adds the resting pointer at the
start of the rest and at the frame's time, as the page does (``restMs`` in
``Performer.js``). The
samples go through the recorder (:class:`sketchanim.anim.recorder.Recorder`, as the studio
feeds it, one frame at a time) at the tolerance the page sends by default: 2 px at the
grabbed point's depth (``DEFAULT_STEPS`` in ``resolution.js``), here 2 x 0.015 scene
units. Printed: samples per control point, the curve's largest error against the samples
and against the hand's true path (the reports at their true times, between reports
linearly), the samples' own timing error against that path (rms and worst), and the worst
swing: how far the curve leaves the range of the four samples around an interval (its two
ends and one more on each side), checked at 64 points per interval. All in px, medians
over ``--runs`` seeds. A second table: the ``events`` take at 60 Hz with 1 px of jitter at
tolerances of 0.5 to 3 px (how the default was chosen).
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass

import numpy as np
from rich.console import Console
from rich.table import Table

from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene

#: Scene units per pixel at the grabbed point's depth in the studio's default view.
PIXEL = 0.015
#: The page's tolerance by default, in pixels (resolution.js: DEFAULT_STEPS).
DEFAULT_PX = 2.0
#: Milliseconds without a pointer report after which the pointer is at rest (Performer.js: REST).
REST_MS = 25.0
METHODS = ("frame", "events", "last event")


@dataclass
class Drag:
    """A drag as the pointer reported it: report times (s) and positions (whole px);
    the hand's path is the reports at their true times."""

    times: np.ndarray
    points: np.ndarray
    seconds: float

    def path(self, t: np.ndarray) -> np.ndarray:
        """The hand's path at ``t``: the reports, linearly between them, held outside."""
        return np.c_[np.interp(t, self.times, self.points[:, 0]), np.interp(t, self.times, self.points[:, 1])]


def smooth(u: np.ndarray) -> np.ndarray:
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3 - 2 * u)


def scripted_drag(seconds: float, hz: float, jitter: float, rng: np.random.Generator) -> Drag:
    """The pointer's reports of the scripted drag at ``hz`` with ``jitter`` px of hand
    jitter, rounded to whole pixels (with the rest before and after the motion)."""
    n = int(seconds * hz) + 1
    times = np.arange(n) / hz + rng.uniform(-1e-3, 1e-3, n)
    times[0] = 0.0
    times = np.maximum.accumulate(times + np.arange(n) * 1e-9)
    u = times / seconds
    xy = np.c_[320 * smooth(u), -90 * np.sin(np.pi * np.clip(u, 0, 1))]
    xy += rng.normal(0.0, jitter, xy.shape) if jitter > 0 else 0.0
    return Drag(times, np.round(xy), seconds)


def frame_times(seconds: float, hz: float, rng: np.random.Generator) -> np.ndarray:
    """Animation frames over the drag: uneven intervals around 1 / ``hz``."""
    out, t = [], rng.uniform(0, 1 / hz)
    while t < seconds + 2 / hz:
        out.append(t)
        step = (1 / hz) * rng.uniform(0.7, 1.3) * (2 if rng.random() < 0.05 else 1)
        t += step
    return np.array(out)


def samples(drag: Drag, frames: np.ndarray, method: str) -> tuple[np.ndarray, np.ndarray]:
    """The take's samples (times, px) the page would send, by ``method``."""
    times: list[float] = []
    rows: list[np.ndarray] = []
    previous = -np.inf
    for now in frames:
        fresh = np.flatnonzero((drag.times > previous) & (drag.times <= now))
        last = np.searchsorted(drag.times, now, side="right") - 1
        previous = now
        if last < 0:
            continue
        if method == "frame":
            picked = [(now, drag.points[last])]
        else:
            chosen = fresh if method == "events" else fresh[-1:]
            picked = [(drag.times[i], drag.points[i]) for i in chosen]
            paces = np.diff(drag.times[max(last - 16, 0): last + 1])
            rest = drag.times[last] + max(REST_MS, 1500 * float(np.median(paces)) if len(paces) else 0) / 1000
            if not picked and now >= rest:          # at rest since its last report
                picked = [(rest, drag.points[last]), (now, drag.points[last])]
        for t, p in picked:
            if not times or t > times[-1]:
                times.append(float(t))
                rows.append(p)
    return np.array(times), np.array(rows, dtype=float)


def local_swing(curve: np.ndarray, t: np.ndarray, x: np.ndarray, dense: int = 64) -> float:
    """How far (in the samples' units) the curve leaves the range of the four samples
    around each interval, at ``dense`` points per interval; ``curve(times) -> values``."""
    worst = 0.0
    u = np.linspace(0, 1, dense + 1)[1:-1]
    inside = (t[:-1, None] + (t[1:] - t[:-1])[:, None] * u).reshape(-1)
    values = curve(inside).reshape(len(t) - 1, len(u), -1)
    for i in range(len(t) - 1):
        near = x[max(i - 1, 0): i + 3]
        lo, hi = near.min(axis=0), near.max(axis=0)
        beyond = np.maximum(values[i] - hi, lo - values[i]).max()
        worst = max(worst, float(beyond))
    return worst


def record(t: np.ndarray, px: np.ndarray, tol_px: float) -> dict[str, float]:
    """The take through the recorder at ``tol_px``: its figures, in px."""
    scene = Scene()
    scene.add("box")
    rec = Recorder(scene)
    rec.arm("box.position", tol=tol_px * PIXEL)
    rec.start()
    world = np.c_[px * PIXEL, np.zeros(len(t))]
    for ti, row in zip(t, world):
        rec.push_frame(ti, row)
    track = rec.stop()["box.position"]
    played = track.evaluate(t)[:, :2] / PIXEL
    return {"track": track, "samples": len(t), "cp": track.n_coefficients,
            "err": float(np.abs(played - px).max())}


def measure(seconds: float, pointer_hz: float, frame_hz: float, jitter: float, method: str, tol_px: float,
            seed: int) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    drag = scripted_drag(seconds, pointer_hz, jitter, rng)
    frames = frame_times(seconds, frame_hz, rng)
    t, px = samples(drag, frames, method)
    out = record(t, px, tol_px)
    track = out.pop("track")
    true = drag.path(t)
    timing = np.linalg.norm(px - true, axis=1)
    dense = np.linspace(t[0], t[-1], 4000)
    out["true err"] = float(np.abs(track.evaluate(dense)[:, :2] / PIXEL - drag.path(dense)).max())
    out["timing rms"] = float(np.sqrt(np.mean(timing**2)))
    out["timing max"] = float(timing.max())
    out["swing"] = local_swing(lambda s: track.evaluate(s)[:, :2] / PIXEL, t, px)
    return out


def medians(runs: list[dict[str, float]]) -> dict[str, float]:
    return {k: float(np.median([r[k] for r in runs])) for k in runs[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--pointer-hz", type=float, default=60.0)
    parser.add_argument("--runs", type=int, default=3, help="seeds per row (medians)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    console = Console(width=150)
    table = Table(title=f"A {args.seconds:g} s drag, pointer at {args.pointer_hz:g} Hz, tolerance {DEFAULT_PX:g} px "
                        f"({DEFAULT_PX * PIXEL:g} scene units); medians of {args.runs} runs; errors in px")
    for column in ("jitter px", "frames Hz", "samples from", "samples", "CP", "samples/CP", "max err", "err vs hand",
                   "timing rms", "timing max", "worst swing"):
        table.add_column(column, justify="right")
    for jitter in (0.0, 0.5, 1.0, 2.0):
        for frame_hz in (15.0, 30.0, 60.0):
            for method in METHODS:
                m = medians([measure(args.seconds, args.pointer_hz, frame_hz, jitter, method, DEFAULT_PX,
                                     args.seed + r) for r in range(args.runs)])
                table.add_row(f"{jitter:g}", f"{frame_hz:g}", method, f"{m['samples']:.0f}", f"{m['cp']:.0f}",
                              f"{m['samples'] / m['cp']:.1f}", f"{m['err']:.2f}", f"{m['true err']:.2f}",
                              f"{m['timing rms']:.2f}", f"{m['timing max']:.2f}", f"{m['swing']:.3f}")
        table.add_section()
    console.print(table)
    sweep = Table(title="The events take at 60 Hz frames, 1 px of jitter, by tolerance (medians; px)")
    for column in ("tol px", "samples", "CP", "samples/CP", "max err", "err vs hand", "worst swing"):
        sweep.add_column(column, justify="right")
    for tol in (0.5, 1.0, 1.5, 2.0, 3.0):
        m = medians([measure(args.seconds, args.pointer_hz, 60.0, 1.0, "events", tol, args.seed + r)
                     for r in range(args.runs)])
        sweep.add_row(f"{tol:g}", f"{m['samples']:.0f}", f"{m['cp']:.0f}", f"{m['samples'] / m['cp']:.1f}",
                      f"{m['err']:.2f}", f"{m['true err']:.2f}", f"{m['swing']:.3f}")
    console.print(sweep)


if __name__ == "__main__":
    main()
