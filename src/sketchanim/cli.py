"""The ``sketchanim`` command line."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Optional

import numpy as np
import typer
from rich.console import Console
from rich.progress import Progress, TextColumn
from rich.table import Table
from rich.text import Text
from scipy.spatial.transform import Rotation

from sketchanim.anim.clip_reduction import ReducedClip
from sketchanim.anim.markers import ReducedMarkers
from sketchanim.anim.skeleton import UNITS_M
from sketchanim.errors import InputError, SampleError
from sketchanim.io.atomic import write_atomic
from sketchanim.io.batch import REPORT, Options, Outcome, outcome, plan, previous_report, reduce_file, run, write_report
from sketchanim.io.clip_files import CLIP_INPUTS, CLIP_OUTPUTS, write_reduced
from sketchanim.io.csvio import SampleTable, read_samples_csv
from sketchanim.io.jsonio import JSON_SAMPLES, read_samples_json
from sketchanim.motion import reduce_rotations
from sketchanim.reducer import METHODS, FeatureOptions, Reduction, reduce

app = typer.Typer(
    help="Sketch 3D animations: reduce performed motion to compact B-splines within tolerance.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
console = Console()
errors = Console(stderr=True)


@app.callback()
def main() -> None:
    """sketchanim command line."""


def _tolerances(text: str) -> list[float]:
    try:
        return [float(part) for part in text.split(",")]
    except ValueError:
        raise InputError(f"--tol: expected a number or comma-separated numbers, got {text!r}") from None


def summary_line(reduction: Reduction, seconds: float) -> str:
    """One line: samples, control points, ratio, order, time."""
    return (f"{reduction.n_samples} samples -> {reduction.n_coefficients} control points "
            f"(ratio {reduction.ratio:.1f}:1, order {reduction.order}, {seconds * 1e3:.1f} ms)")


def features_line(reduction: Reduction) -> str:
    """The pauses and breaks kept, with their times in seconds.

    >>> import numpy as np, sketchanim
    >>> t = np.arange(0, 2, 1 / 120)
    >>> features_line(sketchanim.reduce(t, np.where(t < 1, t, 1.0), 1e-3))
    'features: pause 1.000-1.992 s'
    """
    if not reduction.features:
        return "features: none found"
    return "features: " + ", ".join(f"{f.kind} {f.start:.3f}" + (f"-{f.end:.3f}" if f.end > f.start else "") + " s"
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


def _rotation_columns(table: SampleTable, names: str) -> list[int]:
    wanted = [n.strip() for n in names.split(",")]
    missing = [n for n in wanted if n not in table.channels]
    if missing or len(wanted) not in (3, 4) or len(set(wanted)) != len(wanted):
        raise InputError(f"--rot-cols: needs 4 distinct columns (a quaternion) or 3 (Euler angles in degrees) of "
                         f"{', '.join(table.channels)}; got {names!r}"
                         + (f" ({', '.join(missing)} not in the file)" if missing else ""))
    return [table.channels.index(n) for n in wanted]


def _euler_to_quaternions(degrees: np.ndarray, seq: str) -> np.ndarray:
    """Scalar-last quaternions of Euler angles given in degrees, in ``seq`` order."""
    if not np.all(np.isfinite(degrees)):
        row = int(np.flatnonzero(~np.isfinite(degrees).all(axis=1))[0])
        raise SampleError("Euler angle is not finite", index=row, field="--rot-cols")
    try:
        return Rotation.from_euler(seq, degrees, degrees=True).as_quat()
    except ValueError as err:
        raise InputError(f"--seq: {seq!r} is not an Euler sequence ({err})") from None


def _on_lines(table: SampleTable, input: Path, run: Callable[[], Reduction]) -> Reduction:
    """``run()``, with a rejected sample named by its file line."""
    try:
        return run()
    except SampleError as err:
        if err.index is None:
            raise
        raise InputError(f"{input}, {table.where(err.index)}: {err}") from None


def _write(path: Path, reduction: Reduction) -> None:
    write_atomic(path, reduction.to_json())
    console.print(f"wrote {path}")


@app.command("reduce")
def reduce_command(
    input: Annotated[Path, typer.Argument(help="Samples: CSV (time in seconds, then one column per channel) or "
                                          "JSON (.json, .jsonl: records with t and channels); a clip (.bvh, .amc, "
                                          ".c3d markers) or a folder of clips.")],
    tol: Annotated[Optional[str], typer.Option("--tol", help="Tolerance: one value, or one per channel "
                                                "(comma-separated), for every column but the rotation's. Clips: "
                                                "a distance in the clip's units (default 0.5 cm).")] = None,
    output: Annotated[Optional[Path], typer.Option("-o", "--output", help="Write the spline JSON here (a rotation's "
                                                   "goes beside it, as STEM.rotation.json). Clips: .glb, .bvh, "
                                                   ".usd(a/c) or .json; folders: the output folder.")] = None,
    order: Annotated[int, typer.Option(help="Spline order (4: cubic).")] = 4,
    method: Annotated[str, typer.Option(help=f"One of: {', '.join(METHODS)}.")] = "global",
    start: Annotated[str, typer.Option(help="Starting curve: paper or lm.")] = "paper",
    window: Annotated[int, typer.Option(help="Knots per window of the incremental method.")] = 20,
    plot: Annotated[Optional[Path], typer.Option(help="Draw components, control points and errors to this PNG "
                                                 "(the columns reduced with --tol).")] = None,
    rot_cols: Annotated[Optional[str], typer.Option("--rot-cols", help="Rotation columns: 4 (a quaternion, x,y,z,w "
                                                    "unless --scalar-first) or 3 (Euler angles in degrees, --seq).")]
    = None,
    rot_tol_deg: Annotated[float, typer.Option("--rot-tol-deg", help="Largest rotation error, degrees.")] = 0.5,
    rot_mode: Annotated[str, typer.Option("--rot-mode", help="Rotation curve: quaternion or euler.")] = "quaternion",
    seq: Annotated[str, typer.Option(help="Euler sequence (scipy's: upper case intrinsic, as BVH's ZXY).")] = "ZXY",
    scalar_first: Annotated[bool, typer.Option("--scalar-first", help="Quaternion columns are w,x,y,z.")] = False,
    pauses: Annotated[bool, typer.Option("--pauses/--no-pauses", help="Hold exactly still where the take pauses.")]
    = True,
    breaks: Annotated[bool, typer.Option("--breaks/--no-breaks", help="Keep velocity breaks as corners.")] = True,
    min_pause: Annotated[float, typer.Option("--min-pause", help="Shortest pause, seconds.")] = 0.5,
    units: Annotated[Optional[str], typer.Option(help=f"Clips: the clip's unit ({', '.join(UNITS_M)}); default: "
                                                 "the file's, else guessed from the figure's height.")] = None,
    skeleton: Annotated[Optional[Path], typer.Option(help="AMC clips: the ASF skeleton (default: found beside it).")]
    = None,
    world: Annotated[bool, typer.Option("--world", help="Clips: keep every joint, and every point --shell cm from "
                                        "a joint, within --tol in the world (each joint's angle follows from how "
                                        "far it reaches) instead of every rotation within --rot-tol-deg.")] = False,
    shell: Annotated[float, typer.Option(help="With --world: the shell's distance from each joint, cm.")] = 3.0,
    rate: Annotated[Optional[float], typer.Option(help="Clips written as BVH or USD: frames per second "
                                                  "(default: the source's).")] = None,
    format: Annotated[str, typer.Option("--format", help="Folders: the output format (glb, bvh, json, usd).")]
    = "glb",
    workers: Annotated[int, typer.Option(help="Folders: clips reduced at once (processes).")] = 1,
    scheduler: Annotated[Optional[str], typer.Option(help="Folders: reduce on this Dask scheduler "
                                                     "(tcp://host:port) instead of local processes.")] = None,
) -> None:
    """Reduce samples to B-splines: a CSV or JSON sample stream (print the report, write
    JSON and plot), a motion clip (BVH, AMC: write .glb, .bvh, .usd or .json, by -o's
    extension; C3D markers: .glb or .json), or a folder of clips (write them all to -o,
    with a CSV report)."""
    if input.is_dir() or input.suffix.lower() in CLIP_INPUTS:
        clip_options = _clip_options(tol, rot_tol_deg=rot_tol_deg, units=units, rate=rate,
                                     skeleton=skeleton, world=world, shell_cm=shell)
        if input.is_dir():
            _reduce_folder(input, output, format, clip_options, workers, scheduler)
        else:
            _reduce_clip(input, output, clip_options)
        return
    try:
        features = FeatureOptions(pauses=pauses, breaks=breaks, min_pause=min_pause)
        table = read_samples_json(input) if input.suffix.lower() in JSON_SAMPLES else read_samples_csv(input)
        rot = _rotation_columns(table, rot_cols) if rot_cols else []
        rest = [j for j in range(len(table.channels)) if j not in rot]
        if rest and tol is None:
            raise InputError(f"--tol: needed for {', '.join(table.channels[j] for j in rest)}")
        reduction = rotation = None
        if rest:
            reduction = _on_lines(table, input, lambda: reduce(
                table.times, table.values[:, rest], _tolerances(tol), order=order, method=method, start=start,
                window=window, features=features))
        if rot:
            quaternion_cols = len(rot) == 4
            rotation = _on_lines(table, input, lambda: reduce_rotations(
                table.times,
                table.values[:, rot] if quaternion_cols else _euler_to_quaternions(table.values[:, rot], seq),
                rot_tol_deg, scalar_first=scalar_first and quaternion_cols, mode=rot_mode, seq=seq, method=method,
                order=order, window=window, features=features))
    except InputError as err:
        _fail(str(err))
    if reduction is not None:
        console.print(summary_line(reduction, reduction.timings["total"]))
        console.print(summary_table(reduction, [table.channels[j] for j in rest]))
        if reduction.report.get("duplicates_dropped"):
            console.print(f"dropped {reduction.report['duplicates_dropped']} exact duplicate samples")
        console.print(features_line(reduction))
    if rotation is not None:
        console.print(f"rotation ({rot_mode}): {summary_line(rotation, rotation.timings['total'])}")
        names = ["rotation"] if rotation.metric == "rotation" else [f"{axis} angle" for axis in seq]
        console.print(summary_table(rotation, [f"{n} (degrees)" for n in names], scale=180 / np.pi))
        console.print(f"rotation {features_line(rotation)}")
    try:
        if output is not None and reduction is not None:
            _write(output, reduction)
        if output is not None and rotation is not None:
            _write(output.with_name(output.stem + ".rotation.json"), rotation)
        if plot is not None and reduction is not None:
            from sketchanim.plot import plot_reduction

            plot_reduction(table.times, table.values[:, rest], reduction, plot, [table.channels[j] for j in rest],
                           title=str(input))
            console.print(f"wrote {plot}")
    except OSError as err:
        _fail(f"{err.filename or output}: cannot write ({err.strerror})")


def _clip_options(tol: str | None, *, rot_tol_deg: float, units: str | None, rate: float | None,
                  skeleton: Path | None, world: bool, shell_cm: float) -> Options:
    try:
        distance = None if tol is None else float(tol)
    except ValueError:
        _fail(f"--tol: clips take one distance in the clip's units, got {tol!r}")
    if units is not None and units not in UNITS_M:
        _fail(f"--units: one of {', '.join(UNITS_M)}, got {units!r}")
    if not (np.isfinite(shell_cm) and shell_cm >= 0):
        _fail(f"--shell: a distance in cm, 0 or more, got {shell_cm!r}")
    return Options(tol=distance, rot_tol_deg=rot_tol_deg, units=units, rate=rate,
                   skeleton=None if skeleton is None else str(skeleton), world=world, shell_cm=shell_cm)


def _reduce_clip(input: Path, output: Path | None, options: Options) -> None:
    start = time.perf_counter()
    try:
        clip, reduced, tol = reduce_file(input, options)
        if output is not None:
            write_reduced(output, reduced, rate=options.rate)
    except InputError as err:
        _fail(str(err))
    except OSError as err:
        _fail(f"{err.filename or output}: cannot write ({err.strerror})")
    row = outcome(input, output or Path(), clip, reduced, tol, time.perf_counter() - start)
    console.print(_markers_table(reduced, row) if isinstance(reduced, ReducedMarkers) else _joints_table(
        reduced, row, options))
    console.print(f"compression {row.compression:.1f}:1 ({row.reduced_bytes:,} bytes of curves vs {row.raw_bytes:,} "
                  f"bytes of float32 channels); largest {'marker' if isinstance(reduced, ReducedMarkers) else 'joint'} "
                  f"position error in the world {row.max_world_error:.4g} units; {row.seconds:.2f} s")
    if output is not None:
        console.print(f"wrote {output}")


def _joints_table(reduced: ReducedClip, row: Outcome, options: Options) -> Table:
    promise = (f"every joint and {options.shell_cm:g} cm shell within {row.tol:.4g} units in the world"
               if options.world else f"tolerance {row.tol:.4g} units and {options.rot_tol_deg:g} degrees")
    table = Table(title=f"{Path(row.source).name}: {row.frames} frames, {row.joints} joints, {promise}")
    for column in ("joint", "rotation points", "max rotation error (deg)", "position points", "max position error"):
        table.add_column(column, justify="left" if column == "joint" else "right")
    for j in reduced.joint_reports():
        table.add_row(j.joint, str(j.rotation_points or ""), f"{j.rotation_error_deg:.4f}" if j.rotation_points else "",
                      str(j.position_points or ""), f"{j.position_error:.4g}" if j.position_points else "")
    return table


def _markers_table(reduced: ReducedMarkers, row: Outcome) -> Table:
    table = Table(title=f"{Path(row.source).name}: {row.frames} frames, {row.joints} markers, tolerance "
                        f"{row.tol:.4g} units")
    for column in ("marker", "pieces", "frames unseen", "control points", "max distance"):
        table.add_column(column, justify="left" if column == "marker" else "right")
    for m in reduced.reports():
        table.add_row(m.marker, str(m.pieces), str(m.gap_frames), str(m.control_points),
                      f"{m.max_distance:.4g}" if m.pieces else "")
    return table


def _reduce_folder(folder: Path, output: Path | None, fmt: str, options: Options, workers: int,
                   scheduler: str | None) -> None:
    if output is None:
        _fail("-o: a folder of clips needs an output folder")
    suffix = "." + fmt.lower().lstrip(".")
    if suffix not in CLIP_OUTPUTS:
        _fail(f"--format: one of {', '.join(s[1:] for s in CLIP_OUTPUTS)}, got {fmt!r}")
    jobs = plan(folder, output, suffix)
    if not jobs:
        _fail(f"{folder}: no clips ({', '.join(CLIP_INPUTS)}) in it")
    with Progress(*Progress.get_default_columns(), TextColumn("{task.fields[last]}"), console=console,
                  transient=True) as progress:
        task = progress.add_task("reducing", total=len(jobs), last="")
        outcomes = run(jobs, options, workers=workers, scheduler=scheduler, previous=previous_report(output),
                       on_done=lambda o: progress.update(task, advance=1, last=Path(o.source).name))
    report = write_report(output / REPORT, outcomes)
    table = Table(title=f"{len(jobs)} clips from {folder}")
    for column in ("clip", "status", "frames", "points", "ratio", "rot err°", "pos err", "world err", "s"):
        table.add_column(column, justify="left" if column in ("clip", "status") else "right")
    for o in outcomes:
        table.add_row(str(Path(o.source).relative_to(folder)), o.status,
                      *((str(o.frames), str(o.control_points), f"{o.compression:.1f}:1",
                         f"{o.max_rotation_error_deg:.3f}", f"{o.max_position_error:.3g}", f"{o.max_world_error:.3g}",
                         f"{o.seconds:.2f}") if o.frames else ("",) * 7))
    console.print(table)
    for o in outcomes:
        if o.status == "failed":
            errors.print(Text.assemble(("failed: ", "red"), o.message), soft_wrap=True)
    failed = sum(o.status == "failed" for o in outcomes)
    console.print(f"wrote {report}; {len(jobs) - failed} of {len(jobs)} clips done"
                  + (f", {sum(o.status == 'skipped' for o in outcomes)} of them from an earlier run" if any(
                      o.status == "skipped" for o in outcomes) else ""))
    if failed:
        errors.print(f"{failed} of {len(jobs)} clips failed (see {report})")
        raise typer.Exit(1)


@app.command("export")
def export_command(
    project: Annotated[Path, typer.Argument(help="A project file (.sketchanim).")],
    output: Annotated[Path, typer.Option("-o", "--output", help="The scene as glTF (.glb), or the whole project as "
                                         "JSON (.json).")],
) -> None:
    """Export a project: its scene as glTF (objects, cameras, lights, and their
    position, orientation and scale tracks), or everything as JSON."""
    from sketchanim.io.gltf_scene import scene_glb
    from sketchanim.io.project import Project

    suffix = output.suffix.lower()
    if suffix not in (".glb", ".json"):
        _fail(f"-o: a project exports to .glb or .json, not {suffix or 'a file without an extension'}")
    try:
        with Project(project, create=False) as opened:
            if suffix == ".json":
                opened.export_json(output)
                left_out: list[str] = []
            else:
                scene, tracks = opened.load()
                glb, left_out = scene_glb(scene, tracks, name=output.stem)
                write_atomic(output, glb)
    except InputError as err:
        _fail(str(err))
    except OSError as err:
        _fail(f"{err.filename or output}: cannot write ({err.strerror})")
    console.print(f"wrote {output}")
    if left_out:
        errors.print(f"not in the glTF (core glTF animates only position, orientation and scale): "
                     f"{', '.join(left_out)}", soft_wrap=True)


@app.command("paper")
def paper_command(
    output: Annotated[Path, typer.Option("-o", "--output", help="Folder for the PNG plots.")] = Path("out/paper"),
    data: Annotated[Path, typer.Option(help="Recordings folder; its camera path runs beside the synthetic takes.")]
    = Path("../shared/data"),
) -> None:
    """Re-run the paper's section 2.2 experiments; print tables 8 and 10 and write the figures."""
    from sketchanim.paper import run

    try:
        tables = run(output, data if data.is_dir() else None)
    except OSError as err:
        _fail(f"{err.filename or output}: cannot write ({err.strerror})")
    for name, rows in tables.items():
        table = Table(title=name if name != "spiral" else "spiral, window 10, tol (0.1, 0.1): figures 1 and 2")
        for column in rows[0]:
            table.add_column(column, justify="right")
        for row in rows:
            table.add_row(*(f"{v:.1f}" if isinstance(v, float) else str(v) for v in row.values()))
        console.print(table)
    console.print(f"wrote the figures to {output}/")


@app.command("studio")
def studio_command(
    project: Annotated[Path, typer.Argument(help="The project file (created with a default scene if missing).")]
    = Path("studio.sketchanim"),
    host: Annotated[str, typer.Option(help="Address to serve on (127.0.0.1: this machine only).")] = "127.0.0.1",
    port: Annotated[int, typer.Option(help="Port to serve on.")] = 8000,
    browser: Annotated[bool, typer.Option("--browser/--no-browser", help="Open the page in a browser.")] = True,
) -> None:
    """Start the studio: perform, record, play back and layer animation in the browser."""
    from sketchanim.studio.serve import serve

    try:
        serve(project, host, port, browser, console.print)
    except InputError as err:
        _fail(str(err))
    except OSError as err:
        _fail(f"{err.filename or f'{host}:{port}'}: {err.strerror or err}")


def _fail(message: str) -> None:
    errors.print(Text.assemble(("error: ", "red"), message), soft_wrap=True)
    raise typer.Exit(2)
