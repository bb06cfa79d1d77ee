"""Whole motion-capture clips: speed, compression, errors and planted feet's sliding, the
reduction as it was (the global method, no contacts) beside today's default, in one run.

    .venv/bin/python benchmarks/bench_clips.py [--data ../shared/data]

For every BVH clip in ``DATA/bvh`` (and the CMU ASF/AMC clip), reduced with
``reduce_clip`` at 0.5 cm / 0.5 degree and at 0.1 cm / 0.1 degree, and with
``reduce_clip_world`` at 0.5 cm in the world with a 3 cm shell (centimetres through each
clip's unit, guessed from the figure's height), four ways:

- *before*: ``method="global"``, cubic curves (``order=4``) and no contacts held
  (``contacts`` all False), as the clips were reduced before the incremental default,
  straight pieces and contacts;
- *no contacts*: today's default method, no contacts held (what holding them costs);
- *cubic*: today's default with cubic curves (``order=4``), what straight pieces save;
- *after*: today's default (the incremental method, straight pieces, planted end joints held within
  ``CONTACT_SHARE`` of the tolerance: :mod:`sketchanim.mocap.contacts`).

Columns: seconds to read and reduce (and the speed-up), bytes of the curves (distinct
knots as float32 and a multiplicity byte, control points as float32, a still joint as one
value) and raw float32 frames over them; max rotation error (degrees, at the frames), the
largest joint position error in the world (forward kinematics, cm) and with a 3 cm shell
(the world mode's promise); the largest world error of a planted joint on its planted
frames (cm); and sliding: the median speed (cm/s) of the planted joints while planted,
sampled at 60 Hz, in the source and in each reduction (:func:`~sketchanim.mocap.contacts.sliding`).

Then every C3D file in ``DATA/c3d``: its markers reduced piece by piece (gaps split
them) at 0.5 cm and 0.1 cm, with the same byte counts (raw: x, y, z of every marker at
every frame as float32, gaps included, as C3D stores them).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from sketchanim.formats.c3d import read_c3d
from sketchanim.formats.clip_files import read_clip
from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.mocap.contacts import planted, sliding
from sketchanim.mocap.markers import reduce_markers
from sketchanim.mocap.world_reduction import reduce_clip_world
from sketchanim.pipeline.clip import clip_outcome

REPO = Path(__file__).resolve().parents[1]
TOLERANCES = ((0.5, 0.5), (0.1, 0.1))
#: The world mode's distance and shell, cm.
WORLD = (0.5, 3.0)
#: The ways compared: (label, keyword arguments of the reduction, whether contacts are held).
WAYS = (("before", {"method": "global", "order": 4}, False), ("no contacts", {}, False), ("cubic", {"order": 4}, True),
        ("after", {}, True))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=REPO.parent / "shared" / "data")
    args = parser.parse_args()
    sources = sorted((args.data / "bvh").glob("*.bvh")) + sorted((args.data / "amc").glob("*.amc"))
    if not sources:
        raise SystemExit(f"no clips under {args.data}")
    console = Console(width=200)
    warm = read_clip(sources[0])                                  # compile the kernels outside the clock
    reduce_clip(warm, 1.0, 0.5)
    for tol_cm, tol_deg in [*TOLERANCES, (WORLD[0], None)]:
        clips_table(sources, tol_cm, tol_deg, console)
    markers_table(sorted((args.data / "c3d").glob("*.c3d")), console)


def clips_table(sources: list[Path], tol_cm: float, tol_deg: float | None, console: Console) -> None:
    """One table: every clip reduced each of :data:`WAYS`."""
    title = (f"{tol_cm} cm / {tol_deg} degree (reduce_clip)" if tol_deg else
             f"{tol_cm} cm in the world, {WORLD[1]} cm shell (reduce_clip_world)")
    table = Table(title=title)
    for column in ("clip", "way", "frames", "seconds", "speed-up", "curve bytes", "bytes ratio", "compression",
                   "max rot err (deg)", "max world err (cm)", f"with {WORLD[1]} cm shell (cm)",
                   "planted err (cm)", "sliding src (cm/s)", "sliding (cm/s)"):
        table.add_column(column, justify="left" if column in ("clip", "way") else "right")
    totals = {label: [0.0, 0] for label, _, _ in WAYS}
    frames = 0
    for source in sources:
        clip = read_clip(source)
        unit = clip.guess_unit_m()
        if unit is None:
            table.add_row(source.name, "unit unknown: skipped")
            continue
        frames += len(clip.times)
        tol, shell = tol_cm * 0.01 / unit, WORLD[1] * 0.01 / unit
        held = planted(clip)
        none = np.zeros_like(held)
        source_slide = sliding(clip, contacts=held) * unit * 100
        first = None
        for label, kwargs, contacts in WAYS:
            start = time.perf_counter()
            clip = read_clip(source)
            args = {**kwargs, "contacts": None if contacts else none}
            reduced = (reduce_clip(clip, tol, tol_deg, **args) if tol_deg else
                       reduce_clip_world(clip, tol, shell, **args))
            seconds = time.perf_counter() - start
            row = clip_outcome(source, Path(), clip, reduced, tol, seconds)
            first = first or (seconds, row.reduced_bytes)
            totals[label][0] += seconds
            totals[label][1] += row.reduced_bytes
            errors = reduced.world_errors(clip)
            table.add_row(source.name if label == WAYS[0][0] else "", label, str(len(clip.times)), f"{seconds:.2f}",
                          f"{first[0] / seconds:.1f}x", f"{row.reduced_bytes:,}",
                          f"{row.reduced_bytes / first[1]:.2f}", f"{row.raw_bytes / row.reduced_bytes:.1f}:1",
                          f"{row.max_rotation_error_deg:.3f}", f"{errors.max() * unit * 100:.2f}",
                          f"{reduced.world_errors(clip, shell).max() * unit * 100:.2f}",
                          f"{errors[held].max(initial=0.0) * unit * 100:.3f}", f"{source_slide:.2f}",
                          f"{sliding(clip, reduced.sample, contacts=held) * unit * 100:.2f}")
    base_s, base_b = totals[WAYS[0][0]]
    for label, (seconds, curves) in totals.items():
        table.add_row("all", label, f"{frames:,}", f"{seconds:.2f}", f"{base_s / seconds:.1f}x", f"{curves:,}",
                      f"{curves / base_b:.2f}", "", "", "", "", "", "",
                      f"{len(sources) / seconds:.2f} clips/s")
    console.print(table)


def markers_table(sources: list[Path], console: Console) -> None:
    """C3D markers at each distance of :data:`TOLERANCES`."""
    if not sources:
        return
    table = Table(title="C3D markers (gaps split each marker into pieces)")
    for column in ("file", "tol (cm)", "frames", "markers", "frames unseen", "pieces", "raw float32 bytes",
                   "curve bytes", "compression", "max distance (cm)", "seconds"):
        table.add_column(column, justify="left" if column == "file" else "right")
    for source in sources:
        for tol_cm, _ in TOLERANCES:
            start = time.perf_counter()
            markers = read_c3d(source)
            unit = markers.unit_m
            if unit is None:
                table.add_row(source.name, "unit unknown: skipped")
                break
            reduced = reduce_markers(markers, tol_cm * 0.01 / unit)
            seconds = time.perf_counter() - start
            rows = reduced.reports()
            table.add_row(source.name, f"{tol_cm}", str(len(markers.times)), str(len(rows)),
                          f"{sum(r.gap_frames for r in rows):,}", str(sum(r.pieces for r in rows)),
                          f"{reduced.raw_bytes():,}", f"{reduced.reduced_bytes():,}", f"{reduced.compression():.1f}:1",
                          f"{max(r.max_distance for r in rows) * unit * 100:.3f}", f"{seconds:.2f}")
    console.print(table)


if __name__ == "__main__":
    main()
