"""What the command line prints about a reduction: summaries, per-channel and per-joint
tables, a folder's table."""

from __future__ import annotations

from pathlib import Path

from rich.table import Table

from sketchanim.batch import FolderReduction
from sketchanim.export.compact_clip import CompactReport
from sketchanim.mocap.clip_reduction import ReducedClip
from sketchanim.mocap.markers import ReducedMarkers
from sketchanim.motion.skeleton import UNITS_M
from sketchanim.pipeline import ClipOptions, ClipOutcome
from sketchanim.reducer import Reduction


def summary_line(reduction: Reduction, seconds: float) -> str:
    """One line: samples, control points, ratio, order, time."""
    return (f"{reduction.n_samples} samples -> {reduction.n_coefficients} control points "
            f"(ratio {reduction.ratio:.1f}:1, order {reduction.order}, {seconds * 1e3:.1f} ms)")


def features_line(reduction: Reduction, origin: float = 0.0) -> str:
    """The pauses, breaks, gaps and jumps kept, with their times in seconds from ``origin``.

    >>> import numpy as np, sketchanim
    >>> t = np.arange(0, 2, 1 / 120)
    >>> features_line(sketchanim.reduce(t, np.where(t < 1, t, 1.0), 1e-3))
    'features: pause 1.000-1.992 s'
    """
    if not reduction.features:
        return "features: none found"
    return "features: " + ", ".join(f"{f.kind} {f.start - origin:.3f}"
                                    + (f"-{f.end - origin:.3f}" if f.end > f.start else "") + " s"
                                    for f in reduction.features)


def summary_table(reduction: Reduction, channels: list[str], scale: float = 1.0) -> Table:
    """Per channel: tolerance, max error at the samples (both times ``scale``), and their ratio."""
    table = Table()
    table.add_column("channel")
    table.add_column("tolerance", justify="right")
    table.add_column("max error", justify="right")
    table.add_column("max error / tol", justify="right")
    for name, tol, err in zip(channels, reduction.tol, reduction.max_error):
        table.add_row(name, f"{tol * scale:.6g}", f"{err * scale:.6g}", f"{err / tol:.3f}")
    return table


def unit_line(unit_m: float | None, options: ClipOptions) -> str:
    """Which unit the clip's "units" are, and where that came from.

    >>> unit_line(0.01, ClipOptions())
    "units: cm (the file's, or guessed from the figure's height; --units to set it)"
    """
    if options.units:
        return f"units: {options.units} (--units)"
    names = [name for name, m in UNITS_M.items() if m == unit_m]
    if not names:
        return "units: the clip's own (not known; --units to set it)"
    return f"units: {names[0]} (the file's, or guessed from the figure's height; --units to set it)"


def joints_table(reduced: ReducedClip, row: ClipOutcome, options: ClipOptions) -> Table:
    """Per joint of a reduced clip: rotation and position points and their largest errors."""
    promise = (f"every joint and {options.shell_cm:g} cm shell within {row.tol:.4g} units in the world"
               if options.world else f"tolerance {row.tol:.4g} units and {options.rot_tol_deg:g} degrees")
    table = Table(title=f"{Path(row.source).name}: {row.frames} frames, {row.joints} joints, {promise}")
    for column in ("joint", "rotation points", "max rotation error (deg)", "position points", "max position error"):
        table.add_column(column, justify="left" if column == "joint" else "right")
    for j in reduced.joint_reports():
        table.add_row(j.joint, str(j.rotation_points or ""), f"{j.rotation_error_deg:.4f}" if j.rotation_points else "",
                      str(j.position_points or ""), f"{j.position_error:.4g}" if j.position_points else "")
    return table


def compact_table(report: CompactReport, row: ClipOutcome) -> Table:
    """A compact clip's file: how the world tolerance was split and spent."""
    table = Table(title=f"{Path(row.source).name}: {row.frames} frames, {row.joints} joints, every joint and "
                        f"{report.shell:.4g} units shell within {report.tol:.4g} units in the world, as played")
    table.add_column("compact .glb", justify="left")
    table.add_column("", justify="right")
    bits = ", ".join(f"{what} {'-'.join(map(str, sorted(set(b))))}" for what, b in
                     (("rotations", report.rotation_bits), ("translations", report.translation_bits)) if b)
    for label, value in (("quantisation's share of each joint's bound", f"{report.quantisation_share:.0%}"),
                         ("bits", bits or "none"),
                         ("largest world error of the decoded values alone", f"{report.quantisation_error:.4g}"),
                         ("largest world error as played", f"{report.max_world_error:.4g}"),
                         ("kept under the tolerance for float32", f"{report.float32_margin:.3g}"),
                         ("largest rotation error (deg)", f"{report.max_rotation_error_deg:.4f}"),
                         ("joint frames held on the ground / their bound / their largest world error",
                          f"{report.planted:,} / {report.planted_bound:.4g} / {report.planted_error:.4g}"),
                         ("their sliding, source / as played (units/s)",
                          " / ".join(f"{v:.4g}" for v in report.sliding) or "none held"),
                         ("tracks written / as their node's value", f"{report.tracks - report.constant_tracks} / "
                                                                   f"{report.constant_tracks}"),
                         ("keys (of frames x tracks)",
                          f"{report.keys:,} ({report.keys / max(report.frames * report.tracks, 1):.1%})"),
                         ("key times", "one array" if report.sharing == "skeleton" else "per track"),
                         ("bytes", f"{report.bytes:,}")):
        table.add_row(label, value)
    return table


def markers_table(reduced: ReducedMarkers, row: ClipOutcome) -> Table:
    """Per marker of reduced C3D markers: pieces, frames unseen, points and largest distance."""
    table = Table(title=f"{Path(row.source).name}: {row.frames} frames, {row.joints} markers, tolerance "
                        f"{row.tol:.4g} units")
    for column in ("marker", "pieces", "frames unseen", "control points", "max distance"):
        table.add_column(column, justify="left" if column == "marker" else "right")
    for m in reduced.reports():
        table.add_row(m.marker, str(m.pieces), str(m.gap_frames), str(m.control_points),
                      f"{m.max_distance:.4g}" if m.pieces else "")
    return table


def folder_table(result: FolderReduction) -> Table:
    """A row per clip of a folder: status, frames, points, ratio and errors."""
    table = Table(title=f"{len(result.outcomes)} clips from {result.folder}")
    for column in ("clip", "status", "frames", "points", "ratio", "rot err°", "pos err", "world err", "s"):
        table.add_column(column, justify="left" if column in ("clip", "status") else "right")
    for o in result.outcomes:
        table.add_row(str(Path(o.source).relative_to(result.folder)), o.status,
                      *((str(o.frames), str(o.control_points), f"{o.compression:.1f}:1",
                         f"{o.max_rotation_error_deg:.3f}", f"{o.max_position_error:.3g}", f"{o.max_world_error:.3g}",
                         f"{o.seconds:.2f}") if o.frames else ("",) * 7))
    return table
