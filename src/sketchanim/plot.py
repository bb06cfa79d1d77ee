"""Report figures in the style of the paper's figures 2 and 7: each channel's samples,
curve and control points, and its error inside the tolerance band."""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from sketchanim.atomic import write_atomic  # noqa: E402
from sketchanim.reducer import Reduction  # noqa: E402
from sketchanim.spline import greville  # noqa: E402


def plot_reduction(
    times: np.ndarray,
    values: np.ndarray,
    reduction: Reduction,
    path: str | os.PathLike[str],
    channels: Sequence[str] | None = None,
    title: str | None = None,
) -> Path:
    """Draw one row per channel (component | error with tolerance band) to a file in
    the format its extension names (.png, .svg, .pdf, .jpg, ...; PNG without one).

    Control points are drawn at their Greville abscissae; the reduction's pauses are
    shaded, its gaps and jumps hatched, and its breaks marked with a vertical line.
    The file is written atomically.

    >>> import tempfile, pathlib, sketchanim
    >>> t = np.linspace(0, 1, 40); x = np.c_[np.sin(6 * t)]
    >>> out = plot_reduction(t, x, sketchanim.reduce(t, x, 0.01), pathlib.Path(tempfile.mkdtemp()) / "r.png")
    >>> out.read_bytes()[:4] == b"\\x89PNG"
    True
    """
    x = np.asarray(values, dtype=float).reshape(len(times), -1)
    d = x.shape[1]
    names = list(channels) if channels is not None else [f"x{j + 1}" for j in range(d)]
    spline = reduction.spline
    fine = np.linspace(times[0], times[-1], max(2000, 4 * len(times)))
    curve = np.asarray(spline(fine)).reshape(len(fine), -1)
    at_samples = np.asarray(spline(times)).reshape(len(times), -1)
    coef = np.asarray(spline.c).reshape(len(spline.c), -1)
    sites = greville(spline.t, reduction.order)
    fig, axes = plt.subplots(d, 2, figsize=(12, 2.6 * d + 0.6), squeeze=False)
    for j in range(d):
        ax, ax_err = axes[j]
        ax.plot(times, x[:, j], ".", ms=2.5, color="0.55", label="samples")
        ax.plot(fine, curve[:, j], "-", lw=1.2, color="C0", label="curve")
        ax.plot(sites, coef[:, j], "o--", ms=3.5, lw=0.6, color="C3", label="control points")
        ax.set_ylabel(names[j])
        err = at_samples[:, j] - x[:, j]
        tol = float(reduction.tol[j])
        ax_err.axhspan(-tol, tol, color="C2", alpha=0.15, label=f"tolerance ±{tol:g}")
        ax_err.plot(times, err, "-", lw=0.8, color="C0", label="curve - samples")
        ax_err.set_ylim(-1.3 * tol, 1.3 * tol)
        for f in reduction.features:
            label = f"{f.kind}s" if j == 0 and f is next(g for g in reduction.features if g.kind == f.kind) else None
            if f.kind == "pause":
                ax.axvspan(f.start, f.end, color="C1", alpha=0.15, label=label)
            elif f.kind in ("gap", "jump"):
                ax.axvspan(f.start, f.end, facecolor="none", edgecolor="C3", hatch="//", lw=0, label=label)
            else:
                ax.axvline(f.start, color="C4", lw=0.9, ls=":", label=label)
    axes[0, 0].legend(loc="best", fontsize="small")
    axes[0, 1].legend(loc="best", fontsize="small")
    axes[-1, 0].set_xlabel("time (s)")
    axes[-1, 1].set_xlabel("time (s)")
    fig.suptitle(title or (f"{reduction.n_samples} samples -> {reduction.n_coefficients} control points "
                           f"(order {reduction.order})"))
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format=Path(path).suffix.lower().lstrip(".") or "png", dpi=110)
    plt.close(fig)
    return write_atomic(path, buffer.getvalue())
