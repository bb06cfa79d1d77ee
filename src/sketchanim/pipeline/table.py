"""One sample table, reduced: read in any layout (:mod:`sketchanim.formats.tables`), its
quirks resolved as the options choose, its channel groups and its rotation each reduced
within tolerance, and (on request) written as spline JSON, an animated node (.glb, USD)
and plots."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sketchanim.errors import ArgumentError, InputError, SampleError
from sketchanim.formats.csvio import SampleTable
from sketchanim.formats.quirks import merged, ordered
from sketchanim.formats.tables import STREAMED, read_table, stream_table, table_format
from sketchanim.motion import reduce_rotations
from sketchanim.pipeline.table_options import TableOptions
from sketchanim.pipeline.table_outputs import USD_TABLE, Written, check_node, check_outputs, glb_budgets, write_outputs
from sketchanim.pipeline.table_stream import euler_quaternions, reduce_streamed
from sketchanim.reducer import Reduction, reduce


@dataclass(frozen=True)
class TableReduction:
    """A reduced table and what was done to it.

    Attributes
    ----------
    source : str
        The table's path.
    table : SampleTable or None
        The samples reduced (in time order, one per time), when the table was read
        whole; None when it was reduced while read (:mod:`.table_stream`).
    channels : list of str
        The table's channels (``parts`` and ``rotation_columns`` index them).
    notes : tuple of str
        What the reader recognised (the format, how the times were read).
    rows : int
        Samples reduced.
    span : (float, float)
        The first and the last sample's time.
    parts : tuple of list of int
        The channel groups, each reduced on its own knots.
    reductions : tuple of Reduction
        One per group.
    rotation : Reduction or None
        The rotation columns' curve.
    rotation_columns : tuple of int
        Its channels.
    moved, merged_away : int
        Samples sorted or dropped out of time order; samples merged at a time already
        sampled.
    written : tuple of Written
        Files written, with what they hold.
    glb_tol : float or None
        For a .glb: the position's tolerance (its channels' smallest), of which its curve
        and the orientation's took float32's budget (``pipeline.table_outputs.glb_budgets``).
    """

    source: str
    table: SampleTable | None
    channels: list[str]
    notes: tuple[str, ...]
    rows: int
    span: tuple[float, float]
    parts: tuple[list[int], ...]
    reductions: tuple[Reduction, ...]
    rotation: Reduction | None
    rotation_columns: tuple[int, ...]
    moved: int
    merged_away: int
    written: tuple[Written, ...] = ()
    glb_tol: float | None = None

    @property
    def streamed(self) -> bool:
        """Whether the table was reduced while read, a chunk of rows at a time."""
        return self.table is None

    def names(self, part: list[int]) -> list[str]:
        """The channel names of a group."""
        return [self.channels[j] for j in part]


def _rotation_columns(channels: list[str], wanted: tuple[str, ...]) -> list[int]:
    missing = [n for n in wanted if n not in channels]
    if missing or len(wanted) not in (3, 4) or len(set(wanted)) != len(wanted):
        raise ArgumentError("rot_cols", f"needs 4 distinct columns (a quaternion) or 3 (Euler angles in degrees) of "
                                        f"{', '.join(channels)}; got {','.join(wanted)!r}"
                                        + (f" ({', '.join(missing)} not in the file)" if missing else ""))
    return [channels.index(n) for n in wanted]


def _groups(channels: list[str], rest: list[int], groups: tuple[tuple[str, ...], ...] | None) -> list[list[int]]:
    """The channel groups (column indices), each reduced with its own knot vector."""
    if not rest:
        return []
    if not groups:
        return [rest]
    names = [channels[j] for j in rest]
    parts: list[list[int]] = []
    for group in groups:
        part = []
        for name in group:
            if name not in names:
                raise ArgumentError("groups", f"{name!r} is not a channel (channels: {', '.join(names)})")
            if any(rest[names.index(name)] in p for p in parts + [part]):
                raise ArgumentError("groups", f"{name!r} is in two groups")
            part.append(rest[names.index(name)])
        parts.append(part)
    left = [j for j in rest if not any(j in p for p in parts)]
    return parts + ([left] if left else [])


def _tolerances(channels: list[str], rest: list[int], tol: tuple[float, ...] | None) -> list[float]:
    """One tolerance per channel of ``rest``."""
    if not rest:
        return []
    names = ", ".join(channels[j] for j in rest)
    if tol is None:
        raise ArgumentError("tol", f"needed for {names}")
    if len(tol) not in (1, len(rest)):
        raise ArgumentError("tol", f"needs 1 or {len(rest)} values (one per channel: {names}), got {len(tol)}")
    return list(tol) * len(rest) if len(tol) == 1 else list(tol)


def _on_lines(table: SampleTable, source: str, run: Callable[[], Reduction]) -> Reduction:
    """``run()``, with a rejected sample named by its file line."""
    try:
        return run()
    except SampleError as err:
        if err.index is None:
            raise
        raise InputError(f"{source}, {table.where(err.index)}: {err}") from None


def _read(source: str | os.PathLike[str], options: TableOptions) -> tuple[SampleTable, int, int]:
    table = read_table(source, format=options.format, time=options.time_col,
                       columns=list(options.cols) if options.cols else None, time_unit=options.time_unit,
                       rate=options.rate)
    table, moved = ordered(table, options.unordered, str(source))
    table, merged_away = merged(table, options.duplicates, str(source))
    return table, moved, merged_away


def _reduce_rotation(table: SampleTable, rot: list[int], options: TableOptions, source: str,
                     tol_deg: float) -> Reduction:
    values = table.values[:, rot]
    quaternion = len(rot) == 4
    return _on_lines(table, source, lambda: reduce_rotations(
        table.times, values if quaternion else euler_quaternions(values, options.seq), tol_deg,
        scalar_first=options.scalar_first and quaternion and options.rot_cols is not None, mode=options.rot_mode,
        seq=options.seq, method=options.method, order=options.order, window=options.window,
        features=options.features))


def reduce_table(source: str | os.PathLike[str], options: TableOptions, *, output: str | os.PathLike[str] | None = None,
                 plot: str | os.PathLike[str] | None = None) -> TableReduction:
    """Read, reduce and (on request) write one sample table.

    Parameters
    ----------
    source
        The table (any layout :func:`~sketchanim.formats.tables.read_table` reads).
    options : TableOptions
        How it is read and reduced.
    output
        ``.json`` (the first group's spline; other groups as ``STEM.<channels>.json``, the
        rotation as ``STEM.rotation.json``), or ``.glb`` / ``.usd(a/c)`` (one animated
        node); an existing folder: ``STEM.json`` in it. Checked before any work.
    plot
        Draw components, control points and errors to this image (one per group).

    Returns
    -------
    TableReduction

    Raises
    ------
    InputError
        A bad file (naming it and the line) or an option that does not fit it (an
        :class:`~sketchanim.errors.ArgumentError` naming the field); nothing is written.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> t = np.linspace(0, 2, 100)
    >>> np.savetxt(p, np.c_[t, np.sin(t)], delimiter=",", header="t,x", comments="")
    >>> result = reduce_table(p, TableOptions(tol=0.01), output=p.with_suffix(".json"))
    >>> result.names(result.parts[0]), [w.path.name for w in result.written]
    (['x'], ['s.json'])
    """
    source = str(source)
    out = None if output is None else Path(output)
    out = out / (Path(source).stem + ".json") if out is not None and out.is_dir() else out
    figure = None if plot is None else Path(plot)
    check_outputs(Path(source), out, figure, options.order, options.keys)
    fmt = table_format(source, options.format, options.time_col, options.cols)
    if _streams(fmt, options, out, figure):
        result = _reduce_streamed(source, fmt, options, out)
        if result is not None:
            return result if out is None else write_outputs(result, out, None, options)
    table, moved, merged_away = _read(source, options)
    channels = table.channels
    rot, rest, tols, parts = _plan(source, channels, list(table.orientation), options, figure)
    if out is not None:
        check_node(channels, parts, rot, out.suffix.lower(), options.rot_mode)
    glb_tol, rot_tol = None, options.rot_tol_deg
    if out is not None and out.suffix.lower() == ".glb":     # reduced to what float32 leaves, as the file is checked
        position = parts[0] if parts else []                   # the node's position: held to its smallest tol
        glb_tol = min((tols[rest.index(j)] for j in position), default=None)
        budget, rot_tol = glb_budgets(table.times, table.values[:, position] if position else None, glb_tol or 0.0,
                                      table.values[:, rot] if rot else None, options.rot_tol_deg)
        tols = [budget if j in position else tol for j, tol in zip(rest, tols)]
    reductions = tuple(_on_lines(table, source, lambda part=part: reduce(
        table.times, table.values[:, part], [tols[rest.index(j)] for j in part], order=options.order,
        method=options.method, start=options.start, window=options.window, features=options.features))
        for part in parts)
    rotation = _reduce_rotation(table, rot, options, source, rot_tol) if rot else None
    result = TableReduction(source, table, channels, table.notes, len(table.times),
                            (float(table.times[0]), float(table.times[-1])), tuple(parts), reductions, rotation,
                            tuple(rot), moved, merged_away, glb_tol=glb_tol)
    return result if out is None and figure is None else write_outputs(result, out, figure, options)


def _plan(source: str, channels: list[str], orientation: list[str], options: TableOptions, figure: Path | None
          ) -> tuple[list[int], list[int], list[float], list[list[int]]]:
    """The rotation's columns, the other channels, their tolerances and their groups."""
    rot = _rotation_columns(channels, options.rot_cols) if options.rot_cols else \
        [channels.index(c) for c in orientation]
    rest = [j for j in range(len(channels)) if j not in rot]
    tols = _tolerances(channels, rest, options.tol)
    parts = _groups(channels, rest, options.groups)
    if figure is not None and not parts:
        raise ArgumentError("plot", f"draws the channels reduced with tol; {source} has only an orientation "
                                    f"({', '.join(channels[j] for j in rot)})")
    return rot, rest, tols, parts


def _streams(fmt: str, options: TableOptions, out: Path | None, figure: Path | None) -> bool:
    """Whether the table is reduced while read: the incremental method on a text table,
    unless something needs every sample at once (sorting, the median interval of
    ``gap``, a USD file, a plot, or a .glb, whose curves or keys are checked against every
    sample as float32 plays them)."""
    suffix = "" if out is None else out.suffix.lower()
    whole = suffix in USD_TABLE or suffix == ".glb"
    return (options.method == "incremental" and fmt in STREAMED and options.unordered != "sort" and not options.gap
            and figure is None and not whole)


def _reduce_streamed(source: str, fmt: str, options: TableOptions, out: Path | None) -> TableReduction | None:
    """The table reduced while read (:mod:`.table_stream`); None where a curve misses
    its tolerance after rounding (then the table is read whole, as
    :func:`sketchanim.reduce` keeps the interpolant there)."""
    stream = stream_table(source, fmt, time=options.time_col, columns=list(options.cols) if options.cols else None,
                          time_unit=options.time_unit, rate=options.rate)
    channels = stream.channels
    rot, rest, tols, parts = _plan(source, channels, list(stream.orientation), options, None)
    if out is not None:
        check_node(channels, parts, rot, out.suffix.lower(), options.rot_mode)
    done = reduce_streamed(stream, options, source, parts,
                           [np.array([tols[rest.index(j)] for j in part]) for part in parts], rot)
    if not done.within:
        return None
    return TableReduction(source, None, channels, stream.notes, done.rows, done.span, tuple(parts), done.reductions,
                          done.rotation, tuple(rot), done.moved, done.merged_away)
