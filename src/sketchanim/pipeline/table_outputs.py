"""What a reduced sample table is written as: spline JSON per channel group, one
animated node (.glb through the scene writer, USD sampled at the table's times), and
plots; the outputs checked before any work. The one place the table pipeline calls
the glTF and USD writers."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from sketchanim.atomic import write_atomic
from sketchanim.errors import ArgumentError, InputError
from sketchanim.reducer import Reduction

if TYPE_CHECKING:
    from sketchanim.pipeline.table import TableReduction
    from sketchanim.pipeline.table_options import TableOptions

#: A sample table's USD outputs (an animated Xform, sampled at the table's times).
USD_TABLE = (".usd", ".usda", ".usdc")

#: glTF stores key times as float32: takes whose clock reads past this many seconds
#: start at zero in a .glb (float32 spacing there would be over 0.1 ms).
GLB_CLOCK = 1000.0


@dataclass(frozen=True)
class Written:
    """A file written, and what it holds ("" for a file that says it itself)."""

    path: Path
    note: str = ""


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.resolve() == b.resolve() or (b.exists() and a.samefile(b))
    except OSError:
        return False


def check_outputs(source: Path, output: Path | None, plot: Path | None, order: int, keys: str = "curves") -> None:
    """Outputs a table can be written as, never the input itself; checked before any
    work (an :class:`~sketchanim.errors.ArgumentError` naming ``output``, ``plot``,
    ``order`` or ``keys``: keys other than ``"curves"`` are a .glb's, and only curves
    written exactly are limited to glTF's orders).

    >>> check_outputs(Path("t.csv"), Path("t.json"), None, 4, "compact")
    Traceback (most recent call last):
    sketchanim.errors.ArgumentError: keys: compact files are .glb, not .json
    """
    if output is not None:
        for path in (output, output.with_name(output.stem + ".rotation.json")):
            if _same_file(source, path):
                raise ArgumentError("output", f"{path} is the input; choose another output")
        suffix = output.suffix.lower()
        if suffix not in (".json", ".glb") + USD_TABLE:
            raise ArgumentError("output", f"a sample table is written as .json (the spline), or .glb or "
                                          f".usd/.usda/.usdc (an animated node), not "
                                          f"{suffix or 'a file without an extension'}")
        if keys != "curves" and suffix != ".glb":
            raise ArgumentError("keys", f"{keys} files are .glb, not {suffix}")
        if suffix in USD_TABLE:
            from sketchanim.formats.usd import pxr_modules

            try:
                pxr_modules()
            except InputError as err:
                raise ArgumentError("output", str(err)) from None
        if suffix == ".glb" and order > 4 and keys == "curves":
            raise ArgumentError("order", f"glTF plays orders 2 to 4, got {order} (write .json for higher orders)")
    if plot is not None:
        from matplotlib.backend_bases import FigureCanvasBase

        if _same_file(source, plot) or (output is not None and _same_file(output, plot)):
            raise ArgumentError("plot", f"{plot} is the input or the output; choose another file")
        kinds = FigureCanvasBase.get_supported_filetypes()
        if plot.suffix.lower().lstrip(".") not in kinds:
            raise ArgumentError("plot", f"the extension names the format, one of "
                                        f"{', '.join('.' + k for k in sorted(kinds))}; got {plot.suffix or 'none'}")


def check_node(channels: list[str], parts: list[list[int]], rot: list[int], suffix: str, rot_mode: str) -> None:
    """A .glb (or USD file) holds one animated node: a position of 2 or 3 channels
    and/or an orientation (a quaternion curve in a .glb; USD takes Euler columns and
    curves too, since it stores values at the samples). Other suffixes: no check."""
    if suffix not in (".glb",) + USD_TABLE:
        return
    euler = bool(rot) and (len(rot) != 4 or rot_mode == "euler") and suffix == ".glb"
    if len(parts) > 1 or (parts and len(parts[0]) not in (2, 3)) or euler:
        chans = ", ".join(channels[j] for p in parts for j in p)
        raise ArgumentError("output", f"a {suffix} holds one animated node: a position of 2 or 3 channels (x, y[, z]) "
                                      f"and {'a quaternion' if suffix == '.glb' else 'an orientation'}; this take has "
                                      f"{chans or 'no position channels'}"
                                      + (" and Euler rotation columns or rot_mode=euler" if euler else "")
                                      + " (write .json, or pick the channels with cols=COLUMNS)")


def _group_path(path: Path, channels: list[str], part: list[int], k: int) -> Path:
    """The first group's file is ``path``; the others STEM.<channels>.SUFFIX."""
    if k == 0:
        return path
    return path.with_name(f"{path.stem}.{'+'.join(channels[j] for j in part)}{path.suffix}")


#: What each ``keys`` choice writes, as the report says it.
GLB_KEYS = {"curves": "", "frames": "; LINEAR keys at the sample times",
            "compact": "; LINEAR keys picked from the samples, quantised and compressed (EXT_meshopt_compression)"}


def glb_origin(first: float, last: float) -> float:
    """Where a table's .glb starts its clock: at 0, or at its first sample where the clock
    reads past :data:`GLB_CLOCK`."""
    return first if abs(last) >= GLB_CLOCK else 0.0


def glb_budgets(times: np.ndarray, positions: np.ndarray | None, tol: float, orientations: np.ndarray | None,
                rot_tol_deg: float) -> tuple[float, float]:
    """What a table's .glb reduces its position (within ``tol``, its channels' smallest)
    and its orientation (``rot_tol_deg``) to: the tolerances less what float32 may move
    the samples as the file holds them (:func:`~sketchanim.float32.position_budget`,
    ``rotation_budget``), the bounds the writer checks the curves against, so that no
    curve is reduced again for the file.

    >>> t = np.linspace(0, 4, 100)
    >>> budget, _ = glb_budgets(t, np.c_[np.sin(t), t], 1e-3, None, 0.5)
    >>> bool(0.99e-3 < budget < 1e-3)
    True
    """
    from sketchanim.float32 import position_budget, rotation_budget

    shifted = times - glb_origin(float(times[0]), float(times[-1]))
    return (tol if positions is None else position_budget(shifted, positions, tol,
                                                           subject="for track 'path.position'"),
            rot_tol_deg if orientations is None else rotation_budget(shifted, orientations, rot_tol_deg,
                                                                     subject="for track 'path.orientation'"))


def _write_glb(path: Path, result: TableReduction, rot_tol_deg: float, keys: str = "curves") -> Written:
    """One animated node: the position and orientation curves, exactly or as ``keys``,
    checked against the samples (the table is read whole for a .glb) as float32 plays
    them; scene units as the file's; a clock far from zero moved to start at zero."""
    from sketchanim.export.table_gltf import table_glb, table_tracks

    origin = glb_origin(*result.span)
    assert result.table is not None                     # checked against the samples: the table is read whole
    values = result.table.values
    tracks = table_tracks(result.reductions[0] if result.reductions else None, result.rotation, rot_tol_deg,
                          origin=origin, tol=result.glb_tol, times=result.table.times,
                          positions=values[:, result.parts[0]] if result.parts else None,
                          orientations=values[:, list(result.rotation_columns)] if result.rotation_columns else None)
    write_atomic(path, table_glb(tracks, name=path.stem, keys=keys))
    return Written(path, f"one node, {', '.join(t.path.split('.')[1] for t in tracks)}{GLB_KEYS[keys]}; the file's "
                         f"units written as metres" + (f"; times from the first sample, at {origin:.9g} s: glTF keeps "
                                                       f"float32 times" if origin else ""))


def _write_usd(path: Path, result: TableReduction, rate: float | None) -> Written:
    """One animated Xform, ``/path``: the curves' values at every sample time (USD
    interpolates samples linearly, orientations by slerp), in double precision; time
    codes are seconds times ``rate`` (else the median sampling rate), the clock kept."""
    from scipy.spatial.transform import Rotation

    from sketchanim.anim.tracks import held_values
    from sketchanim.formats.usd import write_usd_path

    assert result.table is not None                     # a USD file takes every sample: the table is read whole
    t = result.table.times
    positions = None
    if result.reductions:
        positions = held_values(result.reductions[0].columns, t, False)
        positions = np.c_[positions, np.zeros(len(t))] if positions.shape[1] == 2 else positions
    orientations = None
    rotation = result.rotation
    if rotation is not None:
        if rotation.report.get("mode") == "euler":
            orientations = Rotation.from_euler(rotation.report["seq"], rotation.spline(t)).as_quat()
        else:
            q = held_values(rotation.columns, t, True)
            orientations = np.roll(q, -1, axis=1) if rotation.report.get("scalar_first") else q
    fps = rate or (float(f"{1 / np.median(np.diff(t)):.6g}") if len(t) > 1 else 1.0)
    write_usd_path(path, t, fps, positions=positions, orientations=orientations)
    held = ", ".join(k for k, v in (("translate", positions), ("orient", orientations)) if v is not None)
    return Written(path, f"one Xform, /path: {len(t)} samples of {held} at the source's times, {fps:g} time codes "
                         f"per second; the file's units written as metres")


def _write_json(path: Path, reduction: Reduction) -> Written:
    write_atomic(path, reduction.to_json())
    return Written(path)


def write_outputs(result: TableReduction, output: Path | None, plot: Path | None,
                  options: TableOptions) -> TableReduction:
    """Write ``result`` as ``output`` (by its suffix) and its plots; ``result`` with
    the files written."""
    written: list[Written] = []
    suffix = output.suffix.lower() if output is not None else ""
    if output is not None and suffix == ".glb":
        written.append(_write_glb(output, result, options.rot_tol_deg, options.keys))
    elif output is not None and suffix in USD_TABLE:
        written.append(_write_usd(output, result, options.rate))
    elif output is not None:
        for k, (part, reduction) in enumerate(zip(result.parts, result.reductions)):
            written.append(_write_json(_group_path(output, result.channels, part, k), reduction))
        if result.rotation is not None:
            written.append(_write_json(output.with_name(output.stem + ".rotation.json"), result.rotation))
    if plot is not None and result.reductions:
        from sketchanim.plot import plot_reduction

        assert result.table is not None                 # a plot draws every sample: the table is read whole
        for k, (part, reduction) in enumerate(zip(result.parts, result.reductions)):
            path = _group_path(plot, result.channels, part, k)
            plot_reduction(result.table.times, result.table.values[:, part], reduction, path, result.names(part),
                           title=result.source)
            written.append(Written(path))
    return replace(result, written=tuple(written))
