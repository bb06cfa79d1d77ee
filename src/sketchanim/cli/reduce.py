"""``sketchanim reduce``: a sample table, a clip or a folder of clips, each handed to its
library function (:func:`~sketchanim.pipeline.reduce_table`,
:func:`~sketchanim.pipeline.reduce_clip_file`, :func:`~sketchanim.batch.reduce_folder`)
with its options object; what they return is printed."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import typer
from rich.progress import Progress, TextColumn
from rich.text import Text

from sketchanim.batch import FolderOptions, reduce_folder
from sketchanim.cli.flags import console, stderr, fail, fail_to_write, in_flags
from sketchanim.cli.reduce_flags import clip_options, folder_options, input_kind, refuse_others, table_options, \
    with_parameters
from sketchanim.cli.report import compact_table, features_line, folder_table, joints_table, markers_table, summary_line, \
    summary_table, unit_line
from sketchanim.errors import InputError
from sketchanim.export.compact_clip import CompactClip
from sketchanim.mocap.markers import ReducedMarkers
from sketchanim.pipeline import ClipOptions, TableOptions, TableReduction, reduce_clip_file, reduce_table

REDUCE_EXAMPLES = """

Examples:

  sketchanim reduce take.csv --tol 0.01 -o take.json --plot take.png

  sketchanim reduce gt.txt --tol 0.005 -o cam.glb            (TUM: the quaternion is found)

  sketchanim reduce pen.svc --tol 5,5,20 --cols x,y,pressure --groups x,y:pressure

  sketchanim reduce log.csv --tol 0.1 --time-unit ns --unordered sort --duplicates mean

  sketchanim reduce CLIP.bvh -o CLIP.glb --tol 0.5

  sketchanim reduce LIBRARY/ -o OUT/ --format bvh --workers 4
"""

REDUCE_HELP = """Reduce samples to B-splines: a sample table (CSV, TSV, whitespace-separated, TUM,
Wacom SVC, EuRoC, KITTI poses or JSON: print the report, write the spline as .json or an animated node as .glb
or .usd(a/c), and plot), a motion clip (BVH, AMC: write .glb, .bvh, .usd or .json, by -o's extension; C3D markers: .glb or
.json), or a folder of clips (write them all to -o, with a CSV report). Options marked "Tables:" apply to sample
tables only, "Clips:" to clips and folders, "Folders:" to folders.""" + REDUCE_EXAMPLES


@with_parameters
def reduce_command(ctx: typer.Context, input: Path, **values: Any) -> None:
    """Refuse flags that do not apply to the input's kind, build its options and reduce."""
    given = {name for name in values if ctx.get_parameter_source(name).name not in ("DEFAULT", "DEFAULT_MAP")}
    kind = input_kind(input)
    refuse_others(kind, given)
    try:
        if kind == "sample table":
            _table(input, values["output"], values["plot"], table_options(values))
        elif kind == "clip":
            _clip(input, values["output"], clip_options(values))
        else:
            _folder(input, values["output"], folder_options(values))
    except InputError as err:
        fail(str(err))
    except OSError as err:
        fail_to_write(err, values["output"])


def _table(source: Path, output: Path | None, plot: Path | None, options: TableOptions) -> None:
    result = reduce_table(source, options, output=output, plot=plot)
    for note in result.notes:
        console.print(f"{source}: {note}", soft_wrap=True)
    origin = result.span[0]
    if origin:
        console.print(f"times below are from the first sample, at {origin:.9g} s (the output keeps the original "
                      f"times)", soft_wrap=True)
    if result.moved:
        console.print(f"{'sorted' if options.unordered == 'sort' else 'dropped'} {result.moved} samples out of time "
                      f"order (--unordered {options.unordered})")
    if result.merged_away:
        console.print(f"merged {result.merged_away} samples at a time already sampled (--duplicates "
                      f"{options.duplicates})")
    _print_groups(result, origin)
    if result.rotation is not None:
        _print_rotation(result, options, origin)
    for written in result.written:
        console.print(f"wrote {written.path}" + (f" ({written.note})" if written.note else ""), soft_wrap=True)


def _print_groups(result: TableReduction, origin: float) -> None:
    for part, reduction in zip(result.parts, result.reductions):
        names = result.names(part)
        if len(result.parts) > 1:
            console.print(f"group {', '.join(names)}:")
        console.print(summary_line(reduction, reduction.timings["total"]))
        console.print(summary_table(reduction, names))
        if reduction.report.get("duplicates_dropped"):
            console.print(f"dropped {reduction.report['duplicates_dropped']} exact duplicate samples")
        console.print(features_line(reduction, origin), soft_wrap=True)


def _print_rotation(result: TableReduction, options: TableOptions, origin: float) -> None:
    rotation = result.rotation
    assert rotation is not None
    columns = ", ".join(result.channels[j] for j in result.rotation_columns)
    console.print(f"rotation ({options.rot_mode}, {columns}): {summary_line(rotation, rotation.timings['total'])}")
    names = ["rotation"] if rotation.metric == "rotation" else [f"{axis} angle" for axis in options.seq]
    console.print(summary_table(rotation, [f"{n} (degrees)" for n in names], scale=180 / np.pi))
    console.print(f"rotation {features_line(rotation, origin)}", soft_wrap=True)


def _clip(source: Path, output: Path | None, options: ClipOptions) -> None:
    if output is not None and output.is_dir():
        output = output / (source.stem + ".glb")
    result = reduce_clip_file(source, options, output)
    row, reduced = result.outcome, result.reduced
    markers = isinstance(reduced, ReducedMarkers)
    console.print(markers_table(reduced, row) if isinstance(reduced, ReducedMarkers) else compact_table(
        reduced.report, row) if isinstance(reduced, CompactClip) else joints_table(reduced, row, options))
    what = "of the file" if isinstance(reduced, CompactClip) else "of curves"
    console.print(f"compression {row.compression:.1f}:1 ({row.reduced_bytes:,} bytes {what} vs {row.raw_bytes:,} "
                  f"bytes of float32 channels); largest {'marker' if markers else 'joint'} position error in the "
                  f"world {row.max_world_error:.4g} units; {row.seconds:.2f} s")
    console.print(unit_line(result.clip.unit_m, options), soft_wrap=True)
    if output is not None:
        console.print(f"wrote {output}")


def _folder(folder: Path, output: Path | None, options: FolderOptions) -> None:
    with Progress(*Progress.get_default_columns(), TextColumn("{task.fields[last]}"), console=console,
                  transient=True) as progress:
        task = progress.add_task("reducing", total=None, last="")
        result = reduce_folder(folder, output, options, on_planned=lambda n: progress.update(task, total=n),
                               on_done=lambda o: progress.update(task, advance=1, last=Path(o.source).name))
    console.print(folder_table(result))
    for o in result.outcomes:
        if o.status == "failed":
            stderr.print(Text.assemble(("failed: ", "red"), in_flags(o.message)), soft_wrap=True)
    total, failed, skipped = len(result.outcomes), result.count("failed"), result.count("skipped")
    console.print(f"wrote {result.report}; {total - failed} of {total} clips done"
                  + (f", {skipped} of them from an earlier run" if skipped else ""))
    if failed:
        stderr.print(f"{failed} of {total} clips failed (see {result.report})")
        raise typer.Exit(1)
