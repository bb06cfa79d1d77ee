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
from scipy.spatial.transform import Rotation

from sketchanim.errors import ArgumentError, InputError, SampleError
from sketchanim.formats.csvio import SampleTable
from sketchanim.formats.quirks import merged, ordered
from sketchanim.formats.tables import read_table
from sketchanim.motion import reduce_rotations
from sketchanim.pipeline.table_options import TableOptions
from sketchanim.pipeline.table_outputs import Written, check_node, check_outputs, write_outputs
from sketchanim.reducer import Reduction, reduce


@dataclass(frozen=True)
class TableReduction:
    """A reduced table and what was done to it.

    Attributes
    ----------
    source : str
        The table's path.
    table : SampleTable
        The samples reduced (in time order, one per time).
    parts : tuple of list of int
        The channel groups (columns of ``table``), each reduced on its own knots.
    reductions : tuple of Reduction
        One per group.
    rotation : Reduction or None
        The rotation columns' curve.
    rotation_columns : tuple of int
        Its columns of ``table``.
    moved, merged_away : int
        Samples sorted or dropped out of time order; samples merged at a time already
        sampled.
    written : tuple of Written
        Files written, with what they hold.
    """

    source: str
    table: SampleTable
    parts: tuple[list[int], ...]
    reductions: tuple[Reduction, ...]
    rotation: Reduction | None
    rotation_columns: tuple[int, ...]
    moved: int
    merged_away: int
    written: tuple[Written, ...] = ()

    def names(self, part: list[int]) -> list[str]:
        """The channel names of a group."""
        return [self.table.channels[j] for j in part]


def _rotation_columns(table: SampleTable, wanted: tuple[str, ...]) -> list[int]:
    missing = [n for n in wanted if n not in table.channels]
    if missing or len(wanted) not in (3, 4) or len(set(wanted)) != len(wanted):
        raise ArgumentError("rot_cols", f"needs 4 distinct columns (a quaternion) or 3 (Euler angles in degrees) of "
                                        f"{', '.join(table.channels)}; got {','.join(wanted)!r}"
                                        + (f" ({', '.join(missing)} not in the file)" if missing else ""))
    return [table.channels.index(n) for n in wanted]


def _euler_to_quaternions(degrees: np.ndarray, seq: str) -> np.ndarray:
    """Scalar-last quaternions of Euler angles given in degrees, in ``seq`` order."""
    if not np.all(np.isfinite(degrees)):
        row = int(np.flatnonzero(~np.isfinite(degrees).all(axis=1))[0])
        raise SampleError("Euler angle is not finite", index=row, field="rot_cols")
    try:
        return Rotation.from_euler(seq, degrees, degrees=True).as_quat()
    except ValueError as err:
        raise ArgumentError("seq", f"{seq!r} is not an Euler sequence ({err})") from None


def _groups(table: SampleTable, rest: list[int], groups: tuple[tuple[str, ...], ...] | None) -> list[list[int]]:
    """The channel groups (column indices), each reduced with its own knot vector."""
    if not rest:
        return []
    if not groups:
        return [rest]
    names = [table.channels[j] for j in rest]
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


def _tolerances(table: SampleTable, rest: list[int], tol: tuple[float, ...] | None) -> list[float]:
    """One tolerance per channel of ``rest``."""
    if not rest:
        return []
    names = ", ".join(table.channels[j] for j in rest)
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


def _reduce_rotation(table: SampleTable, rot: list[int], options: TableOptions, source: str) -> Reduction:
    values = table.values[:, rot]
    quaternion = len(rot) == 4
    return _on_lines(table, source, lambda: reduce_rotations(
        table.times, values if quaternion else _euler_to_quaternions(values, options.seq), options.rot_tol_deg,
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
    check_outputs(Path(source), out, figure, options.order)
    table, moved, merged_away = _read(source, options)
    rot = (_rotation_columns(table, options.rot_cols) if options.rot_cols else
           [table.channels.index(c) for c in table.orientation])
    rest = [j for j in range(len(table.channels)) if j not in rot]
    tols = _tolerances(table, rest, options.tol)
    parts = _groups(table, rest, options.groups)
    if figure is not None and not parts:
        raise ArgumentError("plot", f"draws the channels reduced with tol; {source} has only an orientation "
                                    f"({', '.join(table.channels[j] for j in rot)})")
    if out is not None:
        check_node(table, parts, rot, out.suffix.lower(), options.rot_mode)
    reductions = tuple(_on_lines(table, source, lambda part=part: reduce(
        table.times, table.values[:, part], [tols[rest.index(j)] for j in part], order=options.order,
        method=options.method, start=options.start, window=options.window, features=options.features))
        for part in parts)
    rotation = _reduce_rotation(table, rot, options, source) if rot else None
    result = TableReduction(source, table, tuple(parts), reductions, rotation, tuple(rot), moved, merged_away)
    return result if out is None and figure is None else write_outputs(result, out, figure, options)
