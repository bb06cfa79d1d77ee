"""The paper's experiments of section 2.2, re-run with this reducer.

* The spiral of Lyche-Morken's example 3.1 (1001 samples, window 10, tolerance 0.1 per
  component) under each window variant: figures 1 and 2.
* A "jump" camera motion (20 Hz, 111 samples over 5.9 s, position tolerance 40 mm per
  axis, Euler orientation 2 degrees) and a slow "long" one (482 samples over 29 s):
  tables 8 and 10, windows 5 to 50 and the global method last. The paper's recordings
  are not available, so :func:`jump_motion` and :func:`long_motion` synthesise motions
  that match its description; real camera paths from ../shared/data run beside them.
"""

from __future__ import annotations

import io
import time
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

from sketchanim.atomic import write_atomic  # noqa: E402
from sketchanim.formats.recordings import read_tum  # noqa: E402
from sketchanim.plot import plot_reduction  # noqa: E402
from sketchanim.reducer import Reduction, StreamReducer, reduce  # noqa: E402
from sketchanim.reducer.stream import CONSTRAINTS  # noqa: E402

WINDOWS = (5, 10, 20, 30, 50)
POSITION_TOL = 0.040                 # metres, per axis
ROTATION_TOL = np.deg2rad(2.0)       # radians, per Euler angle


@dataclass(frozen=True)
class Motion:
    """A camera take: times (n,), positions (n, 3) in metres, Euler angles (n, 3) in radians."""

    name: str
    times: np.ndarray
    positions: np.ndarray
    angles: np.ndarray


def spiral(n: int = 1001) -> tuple[np.ndarray, np.ndarray]:
    """Lyche-Morken's example 3.1: (t cos t, t sin t) for t in [0, 6 pi], time = t.

    >>> t, x = spiral(11); x.shape
    (11, 2)
    """
    t = np.linspace(0.0, 6.0 * np.pi, n)
    return t, np.c_[t * np.cos(t), t * np.sin(t)]


def jump_motion(seed: int = 0) -> Motion:
    """A hand-held camera that makes three jumps across an 8 m room: 111 samples at 20 Hz
    (5.9 s), low-pass filtered as the paper's input was, with the take-off impulses.

    >>> m = jump_motion(); len(m.times), round(float(m.times[-1] - m.times[0]), 2)
    (111, 5.5)
    """
    rng = np.random.default_rng(seed)
    t = np.arange(111) / 20.0
    x = np.interp(t, [0, 5.5], [-3.0, 3.0])
    y = np.interp(t, [0, 5.5], [1.0, -1.5])
    z = np.full_like(t, 1.7)
    for start in (0.6, 2.2, 3.8):                                   # three ballistic arcs
        u = (t - start) / 1.1
        arc = np.where((u > 0) & (u < 1), 4 * 0.9 * u * (1 - u), 0.0)
        z = z + arc
    yaw = np.interp(t, [0, 5.5], [0.2, -0.6]) + 0.1 * np.sin(2.1 * t)
    pitch = -0.25 * np.gradient(z, t) / 3.0
    roll = 0.03 * np.sin(1.3 * t)
    pos = np.c_[x, y, z] + rng.normal(0, 0.004, (len(t), 3))
    ang = np.c_[yaw, pitch, roll] + rng.normal(0, np.deg2rad(0.2), (len(t), 3))
    return Motion("jump (synthetic)", t, _smooth(pos), _smooth(ang))


def long_motion(seed: int = 1) -> Motion:
    """A very slow camera walk-through: 482 samples over 29 s (about 16.6 Hz).

    >>> m = long_motion(); len(m.times), round(float(m.times[-1]), 1)
    (482, 29.0)
    """
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 29.0, 482)
    s = t / 29.0
    pos = np.c_[3.5 * np.sin(2 * np.pi * 0.6 * s), 3.0 * np.cos(2 * np.pi * 0.45 * s) - 1.0,
                1.6 + 0.15 * np.sin(2 * np.pi * 1.5 * s)]
    ang = np.c_[2.4 * np.pi * s - 1.0, 0.15 * np.sin(2 * np.pi * 0.8 * s), 0.02 * np.sin(2 * np.pi * 2 * s)]
    pos = pos + rng.normal(0, 0.003, pos.shape)
    ang = ang + rng.normal(0, np.deg2rad(0.15), ang.shape)
    return Motion("long (synthetic)", t, _smooth(pos), _smooth(ang))


def tum_motion(path: Path) -> Motion:
    """The first 29 s of a TUM RGB-D camera path, orientation as unwrapped z-y-x Euler angles."""
    t, pos, quat = read_tum(path)
    keep = t - t[0] <= 29.0
    euler = Rotation.from_quat(quat[keep]).as_euler("ZYX")
    return Motion(f"{path.name} (real, first 29 s)", t[keep] - t[0], pos[keep], np.unwrap(euler, axis=0))


def _smooth(x: np.ndarray) -> np.ndarray:
    kernel = np.array([1.0, 2.0, 1.0]) / 4.0
    padded = np.vstack([x[:1], x, x[-1:]])
    return np.stack([np.convolve(padded[:, j], kernel, mode="valid") for j in range(x.shape[1])], axis=1)


def spiral_variants(window: int = 10, tol: float = 0.1) -> dict[str, Reduction]:
    """The spiral under each window variant, plus the paper's own check against the
    window's starting curve instead of the samples (``curve check``)."""
    t, x = spiral()
    out = {}
    for name, options in [*((c, {"constraints": c}) for c in CONSTRAINTS),
                          ("none, curve check (paper)", {"constraints": "none", "reference": "curve"})]:
        sr = StreamReducer(2, tol, window=window, features=False, **options)
        sr.extend(t, x)
        out[name] = sr.finish()
    out["global"] = reduce(t, x, tol, features=False)
    return out


def window_table(motion: Motion, windows: tuple[int, ...] = WINDOWS) -> list[dict[str, object]]:
    """Tables 8 and 10: control points and times per window size, the global method last."""
    rows = []
    for window in windows:
        row: dict[str, object] = {"window": str(window)}
        for part, values, tol in (("position", motion.positions, POSITION_TOL),
                                  ("rotation", motion.angles, ROTATION_TOL)):
            sr = StreamReducer(3, tol, window=window, features=False)
            clock = time.perf_counter()
            sr.extend(motion.times, values)
            r = sr.finish()
            row[f"{part[:3]} pts"] = r.n_coefficients
            row[f"{part[:3]} win ms"] = 1e3 * r.timings["window_mean"]
            row[f"{part[:3]} total ms"] = 1e3 * (time.perf_counter() - clock)
            row[f"{part[:3]} ok"] = bool(np.all(r.max_error <= tol))
        rows.append(row)
    row = {"window": "global"}
    for part, values, tol in (("position", motion.positions, POSITION_TOL), ("rotation", motion.angles, ROTATION_TOL)):
        r = reduce(motion.times, values, tol, features=False)
        row[f"{part[:3]} pts"] = r.n_coefficients
        row[f"{part[:3]} win ms"] = float("nan")
        row[f"{part[:3]} total ms"] = 1e3 * r.timings["total"]
        row[f"{part[:3]} ok"] = bool(np.all(r.max_error <= tol))
    rows.append(row)
    return rows


def plot_spiral_curves(results: dict[str, Reduction], path: Path) -> Path:
    """Figure 1: samples and each variant's curve with its control polygon."""
    t, x = spiral()
    fine = np.linspace(t[0], t[-1], 4000)
    fig, axes = plt.subplots(1, len(results), figsize=(4.2 * len(results), 4.4))
    for ax, (name, r) in zip(axes, results.items()):
        c = np.asarray(r.spline.c)
        ax.plot(x[:, 0], x[:, 1], ".", ms=1.5, color="0.6")
        ax.plot(*r.spline(fine).T, "-", lw=1.0, color="C0")
        ax.plot(c[:, 0], c[:, 1], "o--", ms=3, lw=0.5, color="C3")
        ax.set_title(f"{name}\n{r.n_coefficients} points, max err {r.max_error.max():.3f}", fontsize=9)
        ax.set_aspect("equal")
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    plt.close(fig)
    return write_atomic(path, buffer.getvalue())


def run_experiments(out: Path, data: Path | None) -> dict[str, object]:
    """Run every experiment, write the PNGs into ``out`` and return the tables."""
    out.mkdir(parents=True, exist_ok=True)
    variants = spiral_variants()
    t, x = spiral()
    plot_spiral_curves(variants, out / "spiral_curves.png")
    for name, r in variants.items():
        slug = name.split(",")[0].replace("+", "_") + ("_curve_check" if "curve" in name else "")
        plot_reduction(t, x, r, out / f"spiral_errors_{slug}.png", channels=("x", "y"),
                       title=f"spiral, window 10, tol 0.1: {name}")
    motions = [jump_motion(), long_motion()]
    tum = None if data is None else data / "camera" / "freiburg1_xyz-groundtruth.txt"
    if tum is not None and tum.exists():
        motions.append(tum_motion(tum))
    tables = {}
    for motion in motions:
        tables[motion.name] = window_table(motion)
        best = StreamReducer(3, POSITION_TOL, window=20, features=False)
        best.extend(motion.times, motion.positions)
        slug = motion.name.split(" ")[0].replace(".txt", "")
        plot_reduction(motion.times, motion.positions, best.finish(), out / f"{slug}_positions.png",
                       channels=("x (m)", "y (m)", "z (m)"), title=f"{motion.name}: positions, window 20")
    spiral_rows = [{"variant": name, "points": r.n_coefficients, "max error x": float(r.max_error[0]),
                    "max error y": float(r.max_error[1]), "within tol": bool(np.all(r.max_error <= 0.1))}
                   for name, r in variants.items()]
    return {"spiral": spiral_rows, **tables}
