"""The ``reduce`` command's flags, declared once as a table (field, type, default,
help), and the options objects built from the ones given: which flags apply to which
input kind comes from the options objects' fields, never from a list kept by hand.

The command's signature is made from the table (``__signature__``, which typer reads
as it reads any function's), so the command itself takes ``**given``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import fields
from pathlib import Path
from typing import Annotated, Any, Optional

import typer

from sketchanim.batch import FolderOptions, reduce_folder
from sketchanim.cli.flags import FLAGS, fail
from sketchanim.export.files import CLIP_OUTPUTS
from sketchanim.formats.clip_files import CLIP_INPUTS
from sketchanim.formats.quirks import DUPLICATES, UNORDERED
from sketchanim.formats.tables import FORMATS
from sketchanim.formats.time_units import TIME_UNITS
from sketchanim.limits import LIMITS
from sketchanim.motion.skeleton import UNITS_M
from sketchanim.pipeline import ClipOptions, TableOptions, reduce_clip_file, reduce_table
from sketchanim.reducer import METHODS


def _option(field: str, kind: type, default: Any, help: str, *decls: str, **extra: Any) -> inspect.Parameter:
    info = typer.Option(*(decls or (FLAGS[field],)), help=help, **extra)
    return inspect.Parameter(field, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=Annotated[kind, info])


def _range(name: str) -> str:
    return LIMITS[name].describe()


#: Every flag of ``reduce``, in --help's order.
REDUCE_PARAMETERS = [
    inspect.Parameter("ctx", inspect.Parameter.POSITIONAL_OR_KEYWORD, annotation=typer.Context),
    inspect.Parameter("input", inspect.Parameter.POSITIONAL_OR_KEYWORD, annotation=Annotated[Path, typer.Argument(
        help="Samples: a table (.csv, .tsv, .txt, .svc: time, then one column per channel) or JSON (.json, .jsonl: "
             "records with t and channels); a clip (.bvh, .amc, .c3d markers) or a folder of clips.")]),
    _option("tol", Optional[str], None, f"Tolerance: one value, or one per channel (comma-separated), for every "
            f"column but the rotation's; {_range('tol')}. Clips: a distance in the clip's units (default 0.5 cm)."),
    _option("output", Optional[Path], None, "Tables: the spline as .json (a rotation's goes beside it, as "
            "STEM.rotation.json) or an animated node as .glb or .usd(a/c). Clips: .glb, .bvh, .usd(a/c) or .json; "
            "folders: the output folder. An existing folder for one input: written into it.", "-o", "--output"),
    _option("order", Optional[int], None, f"Spline order: tables {_range('order')}, 4 (cubic) unless given; "
            f"skeletal clips 2 (straight pieces, glTF's LINEAR keys) unless given, 3 or 4 (.glb takes 2 to 4)."),
    _option("method", str, "global", f"Tables: {' or '.join(METHODS)}."),
    _option("start", str, "paper", "Tables: starting curve of the global method, paper or lm."),
    _option("window", int, 20, f"Tables: knots per window of the incremental method, {_range('window')}."),
    _option("plot", Optional[Path], None, "Tables: draw components, control points and errors to this file, in "
            "the format its extension names (.png, .pdf, .svg, .jpg, ...)."),
    _option("rot_cols", Optional[str], None, "Tables: rotation columns: 4 (a quaternion, x,y,z,w unless "
            "--scalar-first) or 3 (Euler angles in degrees, --seq). TUM, EuRoC and KITTI quaternions are found."),
    _option("rot_tol_deg", float, 0.5, f"Largest rotation error ({_range('rot_tol_deg')})."),
    _option("rot_mode", str, "quaternion", "Tables: rotation curve, quaternion or euler."),
    _option("seq", str, "ZXY", "Tables: Euler sequence (scipy's: upper case intrinsic, as BVH's ZXY)."),
    _option("scalar_first", bool, False, "Tables: quaternion columns are w,x,y,z.", "--scalar-first", metavar=""),
    _option("pauses", bool, True, "Tables: hold exactly still where the take pauses.", "--pauses/--no-pauses",
            metavar=""),
    _option("breaks", bool, True, "Tables: keep velocity breaks as corners.", "--breaks/--no-breaks", metavar=""),
    _option("min_pause", float, 0.5, f"Tables: shortest pause ({_range('min_pause')})."),
    _option("units", Optional[str], None, f"Clips: the clip's unit ({', '.join(UNITS_M)}); default: the file's, "
            "else guessed from the figure's height."),
    _option("skeleton", Optional[Path], None, "Clips: the ASF skeleton of an AMC (default: found beside it)."),
    _option("world", bool, False, "Clips: keep every joint, and every point --shell cm from a joint, within --tol "
            "in the world (each joint's angle follows from how far it reaches) instead of every rotation within "
            "--rot-tol-deg.", metavar=""),
    _option("contacts", bool, True, "Skeletal clips: hold the end joints the source plants on the ground (feet) "
            "within a tighter bound there, so that they slide at most 1 cm/s more than the source's; "
            "--no-contacts bounds them as every other joint, for a smaller file.", "--contacts/--no-contacts",
            metavar=""),
    _option("shell_cm", float, 3.0, f"Clips, with --world: the shell's distance from each joint, "
            f"{_range('shell_cm')}."),
    _option("rate", Optional[float], None, f"Clips written as BVH or USD (or .glb with --keys frames): "
            f"{_range('clip_rate')} (default: the source's). Tables: the time column holds frame numbers at "
            f"this rate (KITTI: its rate, 10 Hz by default), {_range('rate')}."),
    _option("format", Optional[str], None, f"Tables: the layout ({', '.join(FORMATS)}; default auto, by extension "
            f"and content). Folders: the output format ({', '.join(s[1:] for s in CLIP_OUTPUTS)}; default glb)."),
    _option("workers", int, 1, f"Folders: clips reduced at once (processes), {_range('workers')}."),
    _option("scheduler", Optional[str], None, "Folders: reduce on this Dask scheduler (tcp://host:port) instead "
            "of local processes."),
    _option("time_unit", Optional[str], None, f"Tables: the time column's unit ({', '.join(TIME_UNITS)}); "
            "default: seconds, or ns/us/ms since 1970 recognised by magnitude."),
    _option("time_col", Optional[str], None, "Tables: the time column, by name or number (default: the first)."),
    _option("cols", Optional[str], None, "Tables: the channel columns to read, by name or number, NAME=COLUMN to "
            "rename (e.g. x=2,y=3,pressure)."),
    _option("groups", Optional[str], None, "Tables: channel groups with their own knot vector, ':' between groups "
            "(e.g. x,y:pressure); channels not listed form one more group. Written as -o, then "
            "STEM.<channels>.json."),
    _option("duplicates", str, "error", f"Tables: two samples at one time with different values: "
            f"{', '.join(DUPLICATES)} (keep the first, or average)."),
    _option("unordered", str, "error", f"Tables: samples earlier than the one before: {', '.join(UNORDERED)}."),
    _option("gap", float, 0.0, "Tables: also bridge every interval longer than this many median sampling "
            "intervals (0: only jumps and intervals the curve would swing across, always bridged; "
            f"{_range('gap')})."),
    _option("keys", str, "curves", "Clips and tables as .glb: 'curves' (exact, few keys: three.js, Babylon, our "
            "Blender add-on), 'frames' (LINEAR keys at every frame or --rate, a table's at its samples: importers "
            "that ignore tangents, such as Blender's own) or 'compact' (the smallest file, quantised and "
            "meshopt-compressed, that plays every joint and every point --shell cm from one within --tol in the "
            "world, a table's every sample within --tol and --rot-tol-deg: three.js with its meshopt decoder, our "
            "Blender add-on)."),
]


def with_parameters(command: Callable[..., None]) -> Callable[..., None]:
    """``command`` with the signature of :data:`REDUCE_PARAMETERS`, for typer to read."""
    command.__signature__ = inspect.Signature(REDUCE_PARAMETERS)  # type: ignore[attr-defined]
    return command


def _arguments(function: Callable[..., object]) -> set[str]:
    """The keyword arguments a pipeline function takes besides its source and options."""
    return set(inspect.signature(function).parameters) - {"source", "folder", "options", "on_planned", "on_done"}


#: Each input kind: its name, and the fields that apply to it (its options object's
#: and its pipeline function's).
INPUT_KINDS = {
    "sample table": {f.name for f in fields(TableOptions)} | _arguments(reduce_table),
    "clip": {f.name for f in fields(ClipOptions)} | _arguments(reduce_clip_file),
    "folder of clips": ({f.name for f in fields(FolderOptions)} - {"clip"}) | {f.name for f in fields(ClipOptions)}
    | _arguments(reduce_folder),
}


def input_kind(source: Path) -> str:
    """Which input kind ``source`` is (a key of :data:`INPUT_KINDS`)."""
    if source.is_dir():
        return "folder of clips"
    return "clip" if source.suffix.lower() in CLIP_INPUTS else "sample table"


def refuse_others(kind: str, given: set[str]) -> None:
    """Refuse flags given that do not apply to this input kind."""
    wrong = [FLAGS[name] for name in FLAGS if name in given and name not in INPUT_KINDS[kind]]
    if wrong:
        applies = ", ".join(FLAGS[name] for name in FLAGS if name in INPUT_KINDS[kind])
        fail(f"{', '.join(wrong)}: not for a {kind}; for a {kind}: {applies}")


def _tolerances(text: str | None) -> tuple[float, ...] | None:
    if text is None:
        return None
    try:
        return tuple(float(part) for part in text.split(","))
    except ValueError:
        fail(f"--tol: expected a number or comma-separated numbers, got {text!r}")


def _distance(text: str | None) -> float | None:
    try:
        return None if text is None else float(text)
    except ValueError:
        fail(f"--tol: clips take one distance in the clip's units, got {text!r}")


#: Flags whose default (None) means "the options' own default", which differs by input kind.
KIND_DEFAULTS = ("order",)


def _fields(options: type, given: dict[str, Any]) -> dict[str, Any]:
    """The flags' values for the fields of ``options``, leaving out a flag of
    :data:`KIND_DEFAULTS` not given, so that ``options`` takes its own default."""
    return {f.name: given[f.name] for f in fields(options)
            if f.name in given and not (f.name in KIND_DEFAULTS and given[f.name] is None)}


def table_options(given: dict[str, Any]) -> TableOptions:
    """The table's options from the flags' values (every flag, given or default)."""
    return TableOptions(**{**_fields(TableOptions, given), "tol": _tolerances(given["tol"]),
                           "format": given["format"] or "auto"})


def clip_options(given: dict[str, Any]) -> ClipOptions:
    """The clip's options from the flags' values."""
    return ClipOptions(**{**_fields(ClipOptions, given), "tol": _distance(given["tol"]),
                          "skeleton": None if given["skeleton"] is None else str(given["skeleton"])})


def folder_options(given: dict[str, Any]) -> FolderOptions:
    """A folder's options from the flags' values."""
    return FolderOptions(clip_options(given), format=given["format"] or "glb", workers=given["workers"],
                         scheduler=given["scheduler"])
