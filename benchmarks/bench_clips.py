"""Whole motion-capture clips: compression, errors and speed at two tolerance pairs and
in the world.

    .venv/bin/python benchmarks/bench_clips.py [--data ../shared/data]

For every BVH clip in ``DATA/bvh`` (and the CMU ASF/AMC clip), reduced with
``reduce_clip`` at 0.5 cm / 0.5 degree and at 0.1 cm / 0.1 degree, and with
``reduce_clip_world`` at 0.5 cm in the world with a 3 cm shell (centimetres through each
clip's unit, guessed from the figure's height):

- compression: bytes of every channel at every frame as float32 (what keeping every
  sample costs, also shown) over the bytes of the curves (distinct knots as float32 and
  a multiplicity byte, control points as float32, a still joint as one value);
- max rotation error (degrees, geodesic, at the frames), max position error of
  translating joints, the largest joint position error in the world (forward
  kinematics, in cm), and the largest error of a point 3 cm from a joint (the world
  mode's promise; the per-joint angle modes do not bound it, so it is measured);
- seconds to read and reduce, and clips per second, in one run on this machine.

Then every C3D file in ``DATA/c3d``: its markers reduced piece by piece (gaps split
them) at 0.5 cm and 0.1 cm, with the same byte counts (raw: x, y, z of every marker at
every frame as float32, gaps included, as C3D stores them).

The .glb written for each clip is checked by nothing here (the tests validate them).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from rich.console import Console
from rich.table import Table

from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.mocap.markers import reduce_markers
from sketchanim.mocap.world_reduction import reduce_clip_world
from sketchanim.pipeline.clip import clip_outcome
from sketchanim.formats.c3d import read_c3d
from sketchanim.formats.clip_files import read_clip

REPO = Path(__file__).resolve().parents[1]
TOLERANCES = ((0.5, 0.5), (0.1, 0.1))
#: The world mode's distance and shell, cm.
WORLD = (0.5, 3.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=REPO.parent / "shared" / "data")
    args = parser.parse_args()
    sources = sorted((args.data / "bvh").glob("*.bvh")) + sorted((args.data / "amc").glob("*.amc"))
    if not sources:
        raise SystemExit(f"no clips under {args.data}")
    console = Console(width=160)
    for tol_cm, tol_deg in [*TOLERANCES, (WORLD[0], None)]:
        title = (f"{tol_cm} cm / {tol_deg} degree" if tol_deg else
                 f"{tol_cm} cm in the world, {WORLD[1]} cm shell (reduce_clip_world)")
        table = Table(title=title)
        for column in ("clip", "frames", "joints", "raw float32 bytes", "curve bytes", "compression",
                       "max rot err (deg)", "max pos err (cm)", "max world err (cm)",
                       f"with {WORLD[1]} cm shell (cm)", "seconds"):
            table.add_column(column, justify="left" if column == "clip" else "right")
        raw_total = reduced_total = frames = 0
        seconds_total = 0.0
        for source in sources:
            start = time.perf_counter()
            clip = read_clip(source)
            unit = clip.guess_unit_m()
            if unit is None:
                table.add_row(source.name, "unit unknown: skipped")
                continue
            shell = WORLD[1] * 0.01 / unit
            reduced = (reduce_clip(clip, tol_cm * 0.01 / unit, tol_deg) if tol_deg else
                       reduce_clip_world(clip, tol_cm * 0.01 / unit, shell))
            seconds = time.perf_counter() - start
            row = clip_outcome(source, Path(), clip, reduced, tol_cm * 0.01 / unit, seconds)
            raw, curves = row.raw_bytes, row.reduced_bytes
            frames += len(clip.times)
            raw_total, reduced_total, seconds_total = raw_total + raw, reduced_total + curves, seconds_total + seconds
            table.add_row(source.name, str(len(clip.times)), str(len(clip.skeleton)), f"{raw:,}", f"{curves:,}",
                          f"{raw / curves:.1f}:1", f"{row.max_rotation_error_deg:.3f}",
                          f"{row.max_position_error * unit * 100:.3f}", f"{row.max_world_error * unit * 100:.2f}",
                          f"{reduced.world_errors(clip, shell).max() * unit * 100:.2f}", f"{seconds:.2f}")
        table.add_row("all", "", "", f"{raw_total:,}", f"{reduced_total:,}",
                      f"{raw_total / max(reduced_total, 1):.1f}:1", "", "", "", "", f"{seconds_total:.2f}")
        console.print(table)
        console.print(f"{len(sources) / seconds_total:.2f} clips/s, {frames / seconds_total:,.0f} frames/s "
                      "(one process)")
    markers_table(sorted((args.data / "c3d").glob("*.c3d")), console)


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
