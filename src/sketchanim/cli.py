"""The ``sketchanim`` command line."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Annotated, Optional

import numpy as np
import typer
from rich.console import Console
from rich.progress import Progress, TextColumn
from rich.table import Table
from rich.text import Text
from scipy.spatial.transform import Rotation

from sketchanim.mocap.clip_reduction import ReducedClip
from sketchanim.mocap.markers import ReducedMarkers
from sketchanim.motion.skeleton import UNITS_M
from sketchanim.errors import InputError, SampleError
from sketchanim.atomic import write_atomic
from sketchanim.batch import REPORT, Options, Outcome, outcome, plan, previous_report, reduce_file, run, write_report
from sketchanim.export.files import CLIP_OUTPUTS, write_reduced
from sketchanim.formats.clip_files import CLIP_INPUTS
from sketchanim.formats.csvio import SampleTable
from sketchanim.formats.gltf_frames import KEYS
from sketchanim.formats.quirks import DUPLICATES, UNORDERED, merged, ordered
from sketchanim.formats.tables import FORMATS, read_table
from sketchanim.formats.time_units import TIME_UNITS, check_rate
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


def _version(value: bool) -> None:
    if value:
        from importlib.metadata import version

        console.print(f"sketchanim {version('sketchanim')}")
        raise typer.Exit()


@app.callback()
def main(version: Annotated[bool, typer.Option("--version", metavar="", callback=_version, is_eager=True,
                                               help="Print the version and exit.")] = False) -> None:
    """sketchanim command line."""


#: Spline orders the command line accepts (the API takes any >= 2); glTF plays <= 4.
ORDERS = (2, 8)
#: Knots per window of the incremental method.
WINDOWS = (4, 1000)
#: Frame rates of clips written as BVH or USD, Hz.
CLIP_RATES = (1.0, 1000.0)


def _tolerances(text: str) -> list[float]:
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        raise InputError(f"--tol: expected a number or comma-separated numbers, got {text!r}") from None
    bad = [v for v in values if not (np.isfinite(v) and 0 < v <= 1e12)]
    if bad:
        raise InputError(f"--tol: each tolerance must be above 0 and at most 1e12, got {bad[0]:g}")
    return values


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


#: Options for sample tables only, and for clips and folders only (refused elsewhere).
TABLE_ONLY = ("plot", "order", "method", "start", "window", "rot_cols", "rot_mode", "seq", "scalar_first", "pauses",
              "breaks", "min_pause", "time_unit", "time_col", "cols", "groups", "duplicates", "unordered", "gap")
CLIP_ONLY = ("units", "skeleton", "world", "shell", "keys")
FOLDER_ONLY = ("workers", "scheduler")

EXAMPLES = """

Examples:

  sketchanim reduce take.csv --tol 0.01 -o take.json --plot take.png

  sketchanim reduce gt.txt --tol 0.005 -o cam.glb            (TUM: the quaternion is found)

  sketchanim reduce pen.svc --tol 5,5,20 --cols x,y,pressure --groups x,y:pressure

  sketchanim reduce log.csv --tol 0.1 --time-unit ns --unordered sort --duplicates mean

  sketchanim reduce CLIP.bvh -o CLIP.glb --tol 0.5

  sketchanim reduce LIBRARY/ -o OUT/ --format bvh --workers 4
"""


@app.command("reduce", help="""Reduce samples to B-splines: a sample table (CSV, TSV, whitespace-separated, TUM,
Wacom SVC, EuRoC, KITTI poses or JSON: print the report, write the spline as .json or an animated node as .glb
or .usd(a/c), and plot), a motion clip (BVH, AMC: write .glb, .bvh, .usd or .json, by -o's extension; C3D markers: .glb or
.json), or a folder of clips (write them all to -o, with a CSV report). Options marked "Tables:" apply to sample
tables only, "Clips:" to clips and folders, "Folders:" to folders.""" + EXAMPLES)
def reduce_command(
    ctx: typer.Context,
    input: Annotated[Path, typer.Argument(help="Samples: a table (.csv, .tsv, .txt, .svc: time, then one column per "
                                          "channel) or JSON (.json, .jsonl: records with t and channels); a clip "
                                          "(.bvh, .amc, .c3d markers) or a folder of clips.")],
    tol: Annotated[Optional[str], typer.Option("--tol", help="Tolerance: one value, or one per channel "
                                                "(comma-separated), for every column but the rotation's; above 0, "
                                                "at most 1e12. Clips: a distance in the clip's units (default "
                                                "0.5 cm).")] = None,
    output: Annotated[Optional[Path], typer.Option("-o", "--output", help="Tables: the spline as .json (a rotation's "
                                                   "goes beside it, as STEM.rotation.json) or an animated node as "
                                                   ".glb or .usd(a/c). Clips: .glb, .bvh, .usd(a/c) or .json; folders: the output "
                                                   "folder. An existing folder for one input: written into it.")]
    = None,
    order: Annotated[int, typer.Option(help=f"Tables: spline order, {ORDERS[0]} to {ORDERS[1]} (4: cubic; "
                                            f".glb takes 2 to 4).")] = 4,
    method: Annotated[str, typer.Option(help=f"Tables: {' or '.join(METHODS)}.")] = "global",
    start: Annotated[str, typer.Option(help="Tables: starting curve of the global method, paper or lm.")] = "paper",
    window: Annotated[int, typer.Option(help=f"Tables: knots per window of the incremental method, {WINDOWS[0]} "
                                             f"to {WINDOWS[1]}.")] = 20,
    plot: Annotated[Optional[Path], typer.Option(help="Tables: draw components, control points and errors to this "
                                                 "file, in the format its extension names (.png, .pdf, .svg, .jpg, "
                                                 "...).")] = None,
    rot_cols: Annotated[Optional[str], typer.Option("--rot-cols", help="Tables: rotation columns: 4 (a quaternion, "
                                                    "x,y,z,w unless --scalar-first) or 3 (Euler angles in degrees, "
                                                    "--seq). TUM, EuRoC and KITTI quaternions are found.")] = None,
    rot_tol_deg: Annotated[float, typer.Option("--rot-tol-deg", help="Largest rotation error, degrees (above 0, "
                                               "at most 180).")] = 0.5,
    rot_mode: Annotated[str, typer.Option("--rot-mode", help="Tables: rotation curve, quaternion or euler.")]
    = "quaternion",
    seq: Annotated[str, typer.Option(help="Tables: Euler sequence (scipy's: upper case intrinsic, as BVH's ZXY).")]
    = "ZXY",
    scalar_first: Annotated[bool, typer.Option("--scalar-first", metavar="", help="Tables: quaternion columns are w,x,y,z.")]
    = False,
    pauses: Annotated[bool, typer.Option("--pauses/--no-pauses", metavar="", help="Tables: hold exactly still where the take "
                                         "pauses.")] = True,
    breaks: Annotated[bool, typer.Option("--breaks/--no-breaks", metavar="", help="Tables: keep velocity breaks as corners.")]
    = True,
    min_pause: Annotated[float, typer.Option("--min-pause", help="Tables: shortest pause, seconds.")] = 0.5,
    units: Annotated[Optional[str], typer.Option(help=f"Clips: the clip's unit ({', '.join(UNITS_M)}); default: "
                                                 "the file's, else guessed from the figure's height.")] = None,
    skeleton: Annotated[Optional[Path], typer.Option(help="Clips: the ASF skeleton of an AMC (default: found beside "
                                                     "it).")] = None,
    world: Annotated[bool, typer.Option("--world", metavar="", help="Clips: keep every joint, and every point --shell cm from "
                                        "a joint, within --tol in the world (each joint's angle follows from how "
                                        "far it reaches) instead of every rotation within --rot-tol-deg.")] = False,
    shell: Annotated[float, typer.Option(help="Clips, with --world: the shell's distance from each joint, cm.")]
    = 3.0,
    rate: Annotated[Optional[float], typer.Option(help=f"Clips written as BVH or USD (or .glb with "
                                                  f"--keys frames): frames per second, "
                                                  f"{CLIP_RATES[0]:g} to {CLIP_RATES[1]:g} (default: the source's). "
                                                  "Tables: the time column holds frame numbers at this rate (KITTI: "
                                                  "its rate, 10 Hz by default), above 0, at most 1e6.")] = None,
    format: Annotated[Optional[str], typer.Option("--format", help=f"Tables: the layout ({', '.join(FORMATS)}; "
                                                  "default auto, by extension and content). Folders: the output "
                                                  "format (glb, bvh, json, usd; default glb).")] = None,
    workers: Annotated[int, typer.Option(help="Folders: clips reduced at once (processes).")] = 1,
    scheduler: Annotated[Optional[str], typer.Option(help="Folders: reduce on this Dask scheduler "
                                                     "(tcp://host:port) instead of local processes.")] = None,
    time_unit: Annotated[Optional[str], typer.Option("--time-unit", help=f"Tables: the time column's unit "
                                                     f"({', '.join(TIME_UNITS)}); default: seconds, or ns/us/ms since "
                                                     "1970 recognised by magnitude.")] = None,
    time_col: Annotated[Optional[str], typer.Option("--time-col", help="Tables: the time column, by name or number "
                                                    "(default: the first).")] = None,
    cols: Annotated[Optional[str], typer.Option("--cols", help="Tables: the channel columns to read, by name or "
                                                "number, NAME=COLUMN to rename (e.g. x=2,y=3,pressure).")] = None,
    groups: Annotated[Optional[str], typer.Option("--groups", help="Tables: channel groups with their own knot "
                                                  "vector, ':' between groups (e.g. x,y:pressure); channels not "
                                                  "listed form one more group. Written as -o, then "
                                                  "STEM.<channels>.json.")] = None,
    duplicates: Annotated[str, typer.Option(help=f"Tables: two samples at one time with different values: "
                                                 f"{', '.join(DUPLICATES)} (keep the first, or average).")]
    = "error",
    unordered: Annotated[str, typer.Option(help=f"Tables: samples earlier than the one before: "
                                                f"{', '.join(UNORDERED)}.")] = "error",
    gap: Annotated[float, typer.Option(help="Tables: an interval longer than this many median sampling intervals "
                                            "is a gap: each side reduced on its own, bridged straight; jumps and "
                                            "intervals the curve would overshoot are bridged too (0: none of "
                                            "this).")]
    = 5.0,
    keys: Annotated[str, typer.Option("--keys", help="Clips as .glb: 'curves' (exact, few keys: three.js, Babylon, "
                                      "our Blender add-on) or 'frames' (LINEAR keys at every frame or --rate: "
                                      "importers that ignore tangents, such as Blender's own).")] = "curves",
) -> None:
    given = {name for name in ctx.params if ctx.get_parameter_source(name).name not in ("DEFAULT", "DEFAULT_MAP")}
    clip_input = input.is_dir() or input.suffix.lower() in CLIP_INPUTS
    _check_ranges(ctx.params, given)
    if clip_input:
        _refuse(given, TABLE_ONLY + (FOLDER_ONLY if not input.is_dir() else ()) + (
            ("format",) if not input.is_dir() else ()), "clip" if not input.is_dir() else "folder of clips",
                "--tol, --rot-tol-deg, --units, --skeleton, --world, --shell, --rate, --keys" + (
                    ", --format, --workers, --scheduler" if input.is_dir() else ""))
        if rate is not None and not CLIP_RATES[0] <= rate <= CLIP_RATES[1]:
            _fail(f"--rate: clips are written at {CLIP_RATES[0]:g} to {CLIP_RATES[1]:g} frames per second, "
                  f"got {rate:g}")
        clip_options = _clip_options(tol, rot_tol_deg=rot_tol_deg, units=units, rate=rate,
                                     skeleton=skeleton, world=world, shell_cm=shell, keys=keys)
        if input.is_dir():
            _reduce_folder(input, output, format or "glb", clip_options, workers, scheduler)
        else:
            output = _single_output(input, output, ".glb")
            _reduce_clip(input, output, clip_options)
        return
    _refuse(given, CLIP_ONLY + FOLDER_ONLY, "sample table", "every option marked Tables:, and --tol, --rot-tol-deg, "
            "--rate (frame numbers), --format (its layout)")
    _check_rate(rate)
    output = _single_output(input, output, ".json")
    _check_outputs(input, output, plot, order)
    try:
        features = FeatureOptions(pauses=pauses, breaks=breaks, min_pause=min_pause, gap=gap or None)
        table = read_table(input, format=format or "auto", time=time_col,
                           columns=cols.split(",") if cols else None, time_unit=time_unit, rate=rate)
        for note in table.notes:
            console.print(f"{input}: {note}", soft_wrap=True)
        table, moved = ordered(table, unordered, str(input))
        table, merged_away = merged(table, duplicates, str(input))
        rot = (_rotation_columns(table, rot_cols) if rot_cols else
               [table.channels.index(c) for c in table.orientation])
        quaternion_first = scalar_first if rot_cols else False
        rest = [j for j in range(len(table.channels)) if j not in rot]
        if rest and tol is None:
            raise InputError(f"--tol: needed for {', '.join(table.channels[j] for j in rest)}")
        tols = _tolerances(tol) if rest else []
        if len(tols) not in (1, len(rest)):
            raise InputError(f"--tol: needs 1 or {len(rest)} values (one per channel: "
                             f"{', '.join(table.channels[j] for j in rest)}), got {len(tols)}")
        parts = _groups(table, rest, groups)
        if plot is not None and not parts:
            raise InputError(f"--plot: draws the channels reduced with --tol; {input} has only an orientation "
                             f"({', '.join(table.channels[j] for j in rot)})")
        if output is not None and output.suffix.lower() in (".glb",) + USD_TABLE:
            _check_glb(table, parts, rot, output.suffix.lower(), rot_mode)
        reductions = []
        for part in parts:
            part_tol = [tols[0] if len(tols) == 1 else tols[rest.index(j)] for j in part]
            reductions.append(_on_lines(table, input, lambda part=part, part_tol=part_tol: reduce(
                table.times, table.values[:, part], part_tol, order=order, method=method, start=start,
                window=window, features=features)))
        rotation = None
        if rot:
            quaternion_cols = len(rot) == 4
            rotation = _on_lines(table, input, lambda: reduce_rotations(
                table.times,
                table.values[:, rot] if quaternion_cols else _euler_to_quaternions(table.values[:, rot], seq),
                rot_tol_deg, scalar_first=quaternion_first and quaternion_cols, mode=rot_mode, seq=seq,
                method=method, order=order, window=window, features=features))
    except InputError as err:
        _fail(str(err))
    origin = float(table.times[0])
    if origin:
        console.print(f"times below are from the first sample, at {origin:.9g} s (the output keeps the original "
                      f"times)", soft_wrap=True)
    if moved:
        console.print(f"{'sorted' if unordered == 'sort' else 'dropped'} {moved} samples out of time order "
                      f"(--unordered {unordered})")
    if merged_away:
        console.print(f"merged {merged_away} samples at a time already sampled (--duplicates {duplicates})")
    for part, reduction in zip(parts, reductions):
        names = [table.channels[j] for j in part]
        if len(parts) > 1:
            console.print(f"group {', '.join(names)}:")
        console.print(summary_line(reduction, reduction.timings["total"]))
        console.print(summary_table(reduction, names))
        if reduction.report.get("duplicates_dropped"):
            console.print(f"dropped {reduction.report['duplicates_dropped']} exact duplicate samples")
        console.print(features_line(reduction, origin), soft_wrap=True)
    if rotation is not None:
        console.print(f"rotation ({rot_mode}, {', '.join(table.channels[j] for j in rot)}): "
                      f"{summary_line(rotation, rotation.timings['total'])}")
        names = ["rotation"] if rotation.metric == "rotation" else [f"{axis} angle" for axis in seq]
        console.print(summary_table(rotation, [f"{n} (degrees)" for n in names], scale=180 / np.pi))
        console.print(f"rotation {features_line(rotation, origin)}", soft_wrap=True)
    try:
        if output is not None and output.suffix.lower() == ".glb":
            _write_glb(output, table, parts, reductions, rotation, rot_tol_deg)
        elif output is not None and output.suffix.lower() in USD_TABLE:
            _write_usd(output, table, reductions, rotation, rate)
        elif output is not None:
            for k, (part, reduction) in enumerate(zip(parts, reductions)):
                _write(_group_path(output, table, part, k), reduction)
            if rotation is not None:
                _write(output.with_name(output.stem + ".rotation.json"), rotation)
        if plot is not None and reductions:
            from sketchanim.plot import plot_reduction

            for k, (part, reduction) in enumerate(zip(parts, reductions)):
                path = _group_path(plot, table, part, k)
                plot_reduction(table.times, table.values[:, part], reduction, path,
                               [table.channels[j] for j in part], title=str(input))
                console.print(f"wrote {path}")
    except OSError as err:
        _fail(f"{err.filename or output}: cannot write ({err.strerror})")


def _refuse(given: set[str], options: tuple[str, ...], what: str, applies: str) -> None:
    """Refuse options given that do not apply to this input."""
    wrong = [o for o in options if o in given]
    if wrong:
        flags = ", ".join("--" + o.replace("_", "-") for o in wrong)
        _fail(f"{flags}: not for a {what}; for a {what}: {applies}")


def _check_ranges(params: dict, given: set[str]) -> None:
    """Argument ranges, checked before any work."""
    if not ORDERS[0] <= params["order"] <= ORDERS[1]:
        _fail(f"--order: {ORDERS[0]} to {ORDERS[1]} (4: cubic), got {params['order']}")
    if not WINDOWS[0] <= params["window"] <= WINDOWS[1]:
        _fail(f"--window: {WINDOWS[0]} to {WINDOWS[1]} knots, got {params['window']}")
    if params["method"] not in METHODS:
        _fail(f"--method: {' or '.join(METHODS)}, got {params['method']!r}")
    if params["start"] not in ("paper", "lm"):
        _fail(f"--start: paper or lm, got {params['start']!r}")
    if params["rot_mode"] not in ("quaternion", "euler"):
        _fail(f"--rot-mode: quaternion or euler, got {params['rot_mode']!r}")
    if not (np.isfinite(params["rot_tol_deg"]) and 0 < params["rot_tol_deg"] <= 180):
        _fail(f"--rot-tol-deg: above 0 and at most 180 degrees, got {params['rot_tol_deg']:g}")
    if not (np.isfinite(params["min_pause"]) and params["min_pause"] > 0):
        _fail(f"--min-pause: a number of seconds above 0, got {params['min_pause']:g}")
    if not (params["gap"] == 0 or (np.isfinite(params["gap"]) and params["gap"] > 1)):
        _fail(f"--gap: 0 (never) or a number of median intervals above 1, got {params['gap']:g}")
    if params["duplicates"] not in DUPLICATES:
        _fail(f"--duplicates: one of {', '.join(DUPLICATES)}, got {params['duplicates']!r}")
    if params["unordered"] not in UNORDERED:
        _fail(f"--unordered: one of {', '.join(UNORDERED)}, got {params['unordered']!r}")
    if params["time_unit"] is not None and params["time_unit"] not in TIME_UNITS:
        _fail(f"--time-unit: one of {', '.join(TIME_UNITS)}, got {params['time_unit']!r}")
    if params["tol"] is not None:
        try:
            _tolerances(params["tol"])
        except InputError as err:
            _fail(str(err))
    if not 1 <= params["workers"] <= 256:
        _fail(f"--workers: 1 to 256, got {params['workers']}")


def _single_output(input: Path, output: Path | None, suffix: str) -> Path | None:
    """-o naming an existing folder for one input: the input's name in it."""
    if output is not None and output.is_dir():
        return output / (input.stem + suffix)
    return output


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.resolve() == b.resolve() or (b.exists() and a.samefile(b))
    except OSError:
        return False


def _check_outputs(input: Path, output: Path | None, plot: Path | None, order: int) -> None:
    """Outputs a table can be written as, never the input itself; checked before any work."""
    if output is not None:
        for path in (output, output.with_name(output.stem + ".rotation.json")):
            if _same_file(input, path):
                _fail(f"-o: {path} is the input; choose another output")
        suffix = output.suffix.lower()
        if suffix not in (".json", ".glb") + USD_TABLE:
            _fail(f"-o: a sample table is written as .json (the spline), or .glb or .usd/.usda/.usdc (an animated "
                  f"node), not {suffix or 'a file without an extension'}")
        if suffix in USD_TABLE:
            from sketchanim.formats.usd import pxr_modules

            try:
                pxr_modules()
            except InputError as err:
                _fail(f"-o: {err}")
        if suffix == ".glb" and order > 4:
            _fail(f"--order: glTF plays orders 2 to 4, got {order} (write .json for higher orders)")
    if plot is not None:
        from matplotlib.backend_bases import FigureCanvasBase

        if _same_file(input, plot) or (output is not None and _same_file(output, plot)):
            _fail(f"--plot: {plot} is the input or the output; choose another file")
        kinds = FigureCanvasBase.get_supported_filetypes()
        if plot.suffix.lower().lstrip(".") not in kinds:
            _fail(f"--plot: the extension names the format, one of {', '.join('.' + k for k in sorted(kinds))}; "
                  f"got {plot.suffix or 'none'}")


def _groups(table: SampleTable, rest: list[int], groups: str | None) -> list[list[int]]:
    """The channel groups (column indices), each reduced with its own knot vector."""
    if not rest:
        return []
    if not groups:
        return [rest]
    names = [table.channels[j] for j in rest]
    parts: list[list[int]] = []
    for text in groups.split(":"):
        part = []
        for name in (n.strip() for n in text.split(",")):
            if name not in names:
                raise InputError(f"--groups: {name!r} is not a channel (channels: {', '.join(names)})")
            if any(rest[names.index(name)] in p for p in parts + [part]):
                raise InputError(f"--groups: {name!r} is in two groups")
            part.append(rest[names.index(name)])
        parts.append(part)
    left = [j for j in rest if not any(j in p for p in parts)]
    return parts + ([left] if left else [])


def _group_path(path: Path, table: SampleTable, part: list[int], k: int) -> Path:
    """The first group's file is ``path``; the others STEM.<channels>.SUFFIX."""
    if k == 0:
        return path
    return path.with_name(f"{path.stem}.{'+'.join(table.channels[j] for j in part)}{path.suffix}")


def _check_glb(table: SampleTable, parts: list[list[int]], rot: list[int], suffix: str = ".glb",
               rot_mode: str = "quaternion") -> None:
    """A .glb (or USD file) holds one animated node: a position of 2 or 3 channels
    and/or an orientation (a quaternion curve in a .glb; USD takes Euler columns and
    curves too, since it stores values at the samples)."""
    euler = bool(rot) and (len(rot) != 4 or rot_mode == "euler") and suffix == ".glb"
    if len(parts) > 1 or (parts and len(parts[0]) not in (2, 3)) or euler:
        chans = ", ".join(table.channels[j] for p in parts for j in p)
        raise InputError(f"-o: a {suffix} holds one animated node: a position of 2 or 3 channels (x, y[, z]) and "
                         f"{'a quaternion' if suffix == '.glb' else 'an orientation'}; this take has "
                         f"{chans or 'no position channels'}" + (" and Euler rotation columns or --rot-mode euler" if euler else "")
                         + " (write .json, or pick the channels with --cols)")


#: glTF stores key times as float32: takes whose clock reads past this many seconds
#: start at zero in a .glb (float32 spacing there would be over 0.1 ms).
GLB_CLOCK = 1000.0


def _write_glb(path: Path, table: SampleTable, parts: list[list[int]], reductions: list[Reduction],
               rotation: Reduction | None, rot_tol_deg: float) -> None:
    """One animated node: the position and orientation curves, exactly (scene units as
    the file's; a clock far from zero moved to start at zero)."""
    from sketchanim.export.table_gltf import table_glb, table_tracks

    origin = float(table.times[0]) if abs(float(table.times[-1])) >= GLB_CLOCK else 0.0
    tracks = table_tracks(reductions[0] if reductions else None, rotation, rot_tol_deg, origin=origin)
    glb = table_glb(tracks, name=path.stem)
    write_atomic(path, glb)
    console.print(f"wrote {path} (one node, {', '.join(t.path.split('.')[1] for t in tracks)}; the file's units "
                  f"written as metres" + (f"; times from the first sample, at {origin:.9g} s: glTF keeps float32 "
                                         f"times" if origin else "") + ")", soft_wrap=True)


#: A sample table's USD outputs (an animated Xform, sampled at the table's times).
USD_TABLE = (".usd", ".usda", ".usdc")


def _write_usd(path: Path, table: SampleTable, reductions: list[Reduction], rotation: Reduction | None,
               rate: float | None) -> None:
    """One animated Xform, ``/path``: the curves' values at every sample time (USD
    interpolates samples linearly, orientations by slerp), in double precision; time
    codes are seconds times ``rate`` (else the median sampling rate), the clock kept."""
    from scipy.spatial.transform import Rotation

    from sketchanim.anim.tracks import held_values
    from sketchanim.formats.usd import write_usd_path

    t = table.times
    positions = None
    if reductions:
        positions = held_values(reductions[0].columns, t, False)
        positions = np.c_[positions, np.zeros(len(t))] if positions.shape[1] == 2 else positions
    orientations = None
    if rotation is not None:
        if rotation.report.get("mode") == "euler":
            orientations = Rotation.from_euler(rotation.report["seq"], rotation.spline(t)).as_quat()
        else:
            q = held_values(rotation.columns, t, True)
            orientations = np.roll(q, -1, axis=1) if rotation.report.get("scalar_first") else q
    fps = rate or (float(f"{1 / np.median(np.diff(t)):.6g}") if len(t) > 1 else 1.0)
    write_usd_path(path, t, fps, positions=positions, orientations=orientations)
    console.print(f"wrote {path} (one Xform, /path: {len(t)} samples of "
                  f"{', '.join(k for k, v in (('translate', positions), ('orient', orientations)) if v is not None)}"
                  f" at the source's times, {fps:g} time codes per second; the file's units written as metres)",
                  soft_wrap=True)


def _clip_options(tol: str | None, *, rot_tol_deg: float, units: str | None, rate: float | None,
                  skeleton: Path | None, world: bool, shell_cm: float, keys: str = "curves") -> Options:
    try:
        distance = None if tol is None else float(tol)
    except ValueError:
        _fail(f"--tol: clips take one distance in the clip's units, got {tol!r}")
    if units is not None and units not in UNITS_M:
        _fail(f"--units: one of {', '.join(UNITS_M)}, got {units!r}")
    if not (np.isfinite(shell_cm) and shell_cm >= 0):
        _fail(f"--shell: a distance in cm, 0 or more, got {shell_cm!r}")
    _check_keys(keys, rate)
    try:
        return Options(tol=distance, rot_tol_deg=rot_tol_deg, units=units, rate=rate,
                       skeleton=None if skeleton is None else str(skeleton), world=world, shell_cm=shell_cm, keys=keys)
    except InputError as err:
        _fail(f"--{err}")
        raise                       # _fail has exited


def _check_keys(keys: str, rate: float | None) -> None:
    if keys not in KEYS:
        _fail(f"--keys: one of {', '.join(KEYS)}, got {keys!r}")
    _check_rate(rate)


def _check_rate(rate: float | None) -> None:
    """A table's frame numbers, or keys per second: above 0, at most 1e6 Hz."""
    if rate is not None:
        try:
            check_rate(rate)
        except InputError as err:
            _fail(str(err))


def _reduce_clip(input: Path, output: Path | None, options: Options) -> None:
    start = time.perf_counter()
    try:
        clip, reduced, tol = reduce_file(input, options)
        if output is not None:
            write_reduced(output, reduced, rate=options.rate, keys=options.keys)
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
    console.print(_unit_line(clip.unit_m, options), soft_wrap=True)
    if output is not None:
        console.print(f"wrote {output}")


def _unit_line(unit_m: float | None, options: Options) -> str:
    """Which unit the clip's "units" are, and where that came from.

    >>> _unit_line(0.01, Options())
    "units: cm (the file's, or guessed from the figure's height; --units to set it)"
    """
    if options.units:
        return f"units: {options.units} (--units)"
    names = [name for name, m in UNITS_M.items() if m == unit_m]
    if not names:
        return "units: the clip's own (not known; --units to set it)"
    return f"units: {names[0]} (the file's, or guessed from the figure's height; --units to set it)"


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
        try:
            outcomes = run(jobs, options, workers=workers, scheduler=scheduler, previous=previous_report(output),
                           on_done=lambda o: progress.update(task, advance=1, last=Path(o.source).name))
        except InputError as err:
            progress.stop()
            _fail(str(err))
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
    keys: Annotated[str, typer.Option("--keys", help="glTF: 'curves' (exact) or 'frames' (LINEAR keys at the "
                                      "takes' samples or --rate, for importers that ignore tangents).")] = "curves",
    rate: Annotated[Optional[float], typer.Option(help="With --keys frames: keys per second.")] = None,
) -> None:
    """Export a project: its scene as glTF (objects, cameras, lights, and their
    position, orientation and scale tracks), or everything as JSON.

    Examples: sketchanim export show.sketchanim -o show.glb; sketchanim export show.sketchanim -o show.json"""
    from sketchanim.export.scene_gltf import scene_glb
    from sketchanim.project.store import Project

    suffix = output.suffix.lower()
    _check_keys(keys, rate)
    if suffix not in (".glb", ".json"):
        _fail(f"-o: a project exports to .glb or .json, not {suffix or 'a file without an extension'}")
    try:
        with Project(project, create=False) as opened:
            if suffix == ".json":
                opened.export_json(output)
                left_out: list[str] = []
            else:
                scene, tracks = opened.load()
                glb, left_out = scene_glb(scene, tracks, name=output.stem, keys=keys, rate=rate)
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
    """Re-run the paper's section 2.2 experiments; print tables 8 and 10 and write the figures.

    Example: sketchanim paper -o out/paper --data ../shared/data"""
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
