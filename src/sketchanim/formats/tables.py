"""Sample tables of any layout the command line reduces, recognised by content or
named: comma, tab or whitespace separated text, the trajectory formats met in practice
(TUM, Wacom SVC, EuRoC ground truth, KITTI poses) and JSON sample streams; times in
seconds (:mod:`.time_units`), a format's orientation columns marked as a quaternion.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from itertools import chain
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.errors import ArgumentError, FileFormatError, InputError
from sketchanim.formats.csvio import CHUNK_ROWS, DELIMITERS, Layout, SampleTable, csv_columns, head_lines, \
    iter_rows, parse_number, read_columns, resolve_column, sniff, split_cells
from sketchanim.formats.jsonio import JSON_SAMPLES, read_samples_json
from sketchanim.formats.time_units import to_seconds
from sketchanim.limits import LIMITS

#: Input formats ``format`` names; ``auto`` recognises them by extension and content.
FORMATS = ("auto", "csv", "tsv", "whitespace", "tum", "svc", "euroc", "kitti", "json")

#: Formats read in chunks by :func:`stream_table` (the others are read whole).
STREAMED = ("csv", "tsv", "whitespace", "tum", "euroc")

#: Column names of a Wacom SVC file (SVC2004's order; time in milliseconds).
SVC_COLUMNS = ("x", "y", "t", "button", "azimuth", "altitude", "pressure")

#: KITTI poses carry no times: the rate assumed without ``rate`` (its cameras' 10 Hz).
KITTI_RATE = 10.0

_TUM = ("t", "tx", "ty", "tz", "qx", "qy", "qz", "qw")
_QUATERNION = ("qx", "qy", "qz", "qw")


def _numeric_rows(layout: Layout, path: str | os.PathLike[str], limit: int = 8) -> np.ndarray | None:
    """The first rows of numbers (as far as :func:`sniff` read), or None if ragged."""
    rows = []
    for line in head_lines(path, limit)[layout.first - 1 :]:
        cells = split_cells(line, layout.delimiter)
        if not cells or line.lstrip().startswith("#"):
            continue
        numbers = [parse_number(c) for c in cells]
        if None in numbers or len(numbers) != layout.width:
            return None
        rows.append(numbers)
    return np.asarray(rows, dtype=float) if rows else None


def _unit_norm(q: np.ndarray) -> bool:
    return bool(np.all(np.abs(np.linalg.norm(q, axis=1) - 1) < 1e-2))


def _is_svc(path: str | os.PathLike[str]) -> bool:
    """Whether the file starts with a lone sample count, then rows of 3 or more values."""
    head = [line for line in head_lines(path, 3) if line.strip()]
    return len(head) >= 2 and head[0].strip().isdigit() and len(head[1].split()) >= 3


def recognise(path: str | os.PathLike[str]) -> str:
    """The format of a table, from its extension and first lines: one of
    :data:`FORMATS` but ``auto``.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "gt.txt"
    >>> _ = p.write_text("# timestamp tx ty tz qx qy qz qw\\n1.0 1 2 3 0 0 0 1\\n1.1 1 2 3 0 0 0 1\\n")
    >>> recognise(p)
    'tum'
    """
    if Path(path).suffix.lower() in JSON_SAMPLES:
        return "json"
    if Path(path).suffix.lower() == ".svc" or _is_svc(path):
        return "svc"
    layout = sniff(path)
    names = [n.split(" [")[0].strip() for n in layout.header or []]
    if {"p_RS_R_x", "q_RS_w"} <= set(names):
        return "euroc"
    rows = _numeric_rows(layout, path)
    if layout.delimiter is None and rows is not None:
        if layout.width == 8 and _unit_norm(rows[:, 4:8]) and layout.header in (None, list(_TUM)) \
                or layout.header == ["timestamp", *_TUM[1:]]:
            return "tum"
        if layout.width == 12 and layout.header is None:
            m = rows[:, :12].reshape(-1, 3, 4)[:, :, :3]
            if np.allclose(m @ m.transpose(0, 2, 1), np.eye(3), atol=1e-3):
                return "kitti"
    return {",": "csv", "\t": "tsv", None: "whitespace"}[layout.delimiter]


@dataclass(frozen=True)
class Columns:
    """Where a text table's samples are: its layout, the columns read (0-based: the
    time, then the channels), the channels' names, those holding a quaternion, and
    what the reader recognised."""

    layout: Layout
    usecols: list[int]
    channels: list[str]
    orientation: tuple[str, ...]
    label: str


def _tum(path: str | os.PathLike[str]) -> Columns:
    layout = sniff(path, None)
    if layout.width != 8:
        raise FileFormatError(str(path), f"a TUM trajectory has 8 columns (timestamp tx ty tz qx qy qz qw), this "
                                         f"one {layout.width}", line=layout.first)
    return Columns(layout, list(range(8)), list(_TUM[1:]), _QUATERNION, "TUM trajectory")


def _euroc(path: str | os.PathLike[str], columns: Sequence[str] | None) -> Columns:
    if columns is not None:
        layout, usecols, channels = csv_columns(path, delimiter=",", columns=columns)
        return Columns(layout, usecols, channels, (), "EuRoC ground truth")
    layout = sniff(path, ",")
    names = [n.split(" [")[0].strip().lstrip("#") for n in layout.header or []]
    wanted = ["p_RS_R_x", "p_RS_R_y", "p_RS_R_z", "q_RS_x", "q_RS_y", "q_RS_z", "q_RS_w"]
    rest = [n for n in names[1:] if n not in wanted]
    return Columns(layout, [0] + [names.index(n) for n in wanted], wanted, tuple(wanted[3:]),
                   "EuRoC ground truth" + (f"; left out {', '.join(rest)} (cols=COLUMNS to read them)" if rest else ""))


def text_columns(path: str | os.PathLike[str], fmt: str, time: str | None = None,
                 columns: Sequence[str] | None = None) -> Columns:
    """Where the samples of a table of format ``fmt`` (one of :data:`STREAMED`) are.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x,y\\n0,1,2\\n")
    >>> c = text_columns(p, "csv"); c.usecols, c.channels, c.label
    ([0, 1, 2], ['x', 'y'], 'comma-separated table')
    """
    if fmt == "tum":
        return _tum(path)
    if fmt == "euroc":
        return _euroc(path, columns)
    delimiter = {"csv": DELIMITERS["comma"], "tsv": DELIMITERS["tab"], "whitespace": None}[fmt]
    layout, usecols, channels = csv_columns(path, delimiter=delimiter, time=time, columns=columns)
    label = {"csv": "comma-separated table", "tsv": "tab-separated table", "whitespace": "whitespace-separated table"}
    return Columns(layout, usecols, channels, (), label[fmt])


def _kitti(path: str | os.PathLike[str], rate: float | None) -> tuple[SampleTable, str]:
    layout = sniff(path, None)
    if layout.width != 12:
        raise FileFormatError(str(path), f"KITTI poses are 12 numbers a line (a 3x4 matrix), this one "
                                         f"{layout.width}", line=layout.first)
    _, values, lines = read_columns(path, layout, [0] + list(range(12)))
    pose = values.reshape(-1, 3, 4)
    try:
        quats = Rotation.from_matrix(pose[:, :, :3]).as_quat()
    except ValueError as err:
        raise FileFormatError(str(path), f"a pose is not a rotation and translation ({err})") from None
    hz = KITTI_RATE if rate is None else float(LIMITS["rate"].check(rate))
    table = SampleTable(np.arange(len(pose)) / hz, np.c_[pose[:, :, 3], quats], ["tx", "ty", "tz", *_QUATERNION],
                        lines, orientation=_QUATERNION, notes=("KITTI poses",))
    note = f"times from the line number at {hz:g} Hz" + (" (KITTI's camera rate; rate=HZ to change)" if rate is None
                                                          else "")
    return table, note


def _svc(path: str | os.PathLike[str], columns: Sequence[str] | None) -> tuple[SampleTable, str | None]:

    head = head_lines(path, 2)
    first = next(i for i, line in enumerate(head, 1) if line.strip())
    count = int(head[first - 1].strip())
    width = len(head[first].split())
    names = list(SVC_COLUMNS[:width]) + [f"c{i}" for i in range(len(SVC_COLUMNS) + 1, width + 1)]
    layout = Layout(None, names, first + 1, width, head[:first])
    if "t" not in names:
        raise FileFormatError(str(path), f"an SVC file has x, y and the time in its first 3 columns, this one "
                                         f"{width}", line=first + 1)
    t_col = names.index("t")
    picked = [(n, j) for j, n in enumerate(names) if j != t_col] if columns is None else [
        (spec.rpartition("=")[0] or names[j], j) for spec in columns
        for j in [_column(path, spec.rpartition("=")[2], names)]]
    times, values, lines = read_columns(path, layout, [t_col] + [j for _, j in picked])
    if len(times) != count:
        raise FileFormatError(str(path), f"the first line says {count} samples, the file holds {len(times)}",
                              line=first)
    unit = "ms" if np.all(times == np.round(times)) else None
    table = SampleTable(times, values, [n for n, _ in picked], lines, notes=("Wacom SVC (x, y, t, button, azimuth, "
                                                                             "altitude, pressure)",))
    return table, unit


def _column(path: str | os.PathLike[str], spec: str, names: Sequence[str]) -> int:

    try:
        return resolve_column(spec, names)
    except ValueError as err:
        raise FileFormatError(str(path), f"cols: {err}") from None


def table_format(path: str | os.PathLike[str], format: str = "auto", time: str | None = None,
                 columns: Sequence[str] | None = None) -> str:
    """The format of a table (``format``, or the one :func:`recognise` finds), checked
    against the options that only some formats take.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x\\n0,1\\n1,2\\n")
    >>> table_format(p)
    'csv'
    """
    if format not in FORMATS:
        raise ArgumentError("format", f"one of {', '.join(FORMATS)} for samples, got {format!r}")
    fmt = recognise(path) if format == "auto" else format
    if columns is not None and fmt in ("tum", "kitti", "json"):
        raise ArgumentError("cols", f"{path} is {fmt}, whose channels are fixed; cols= applies to csv, tsv, "
                                   f"whitespace, svc and euroc tables")
    if time is not None and fmt not in ("csv", "tsv", "whitespace"):
        raise ArgumentError("time_col", f"{path} is {fmt}, whose time column is fixed; time_col= applies to "
                                       f"csv, tsv and whitespace tables")
    return fmt


def read_table(path: str | os.PathLike[str], *, format: str = "auto", time: str | None = None,
               columns: Sequence[str] | None = None, time_unit: str | None = None,
               rate: float | None = None) -> SampleTable:
    """Samples of a table in any of :data:`FORMATS`, times in seconds; the table's
    ``notes`` say the format and how its times were read.

    Parameters
    ----------
    format : str
        One of :data:`FORMATS`; ``auto`` recognises it (:func:`recognise`).
    time, columns
        The time column and the channel columns (see
        :func:`sketchanim.formats.csvio.read_samples_csv`); text tables and SVC files.
    time_unit, rate
        How to read the time column (see :func:`sketchanim.formats.time_units.to_seconds`);
        for KITTI poses, ``rate`` is the frame rate.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.tsv"
    >>> _ = p.write_text("t\\tx\\n1700000000000\\t1\\n1700000000010\\t2\\n")
    >>> table = read_table(p)
    >>> table.channels, round(float(table.times[1] - table.times[0]), 6), table.notes
    (['x'], 0.01, ('tab-separated table', 'time column read as milliseconds since 1970 (from its magnitude; time_unit=UNIT to change)'))
    """
    fmt = table_format(path, format, time, columns)
    if fmt == "kitti":
        table, note = _kitti(path, rate)
        return replace(table, notes=table.notes + (note,))
    if fmt == "json":
        table = read_samples_json(path)
        label = "JSON sample stream"
    elif fmt == "svc":
        table, unit = _svc(path, columns)
        label = table.notes[0]
        if unit is not None and time_unit is None and rate is None:
            time_unit = unit
            label += "; whole-number times read as ms (SVC's unit)"
    else:
        where = text_columns(path, fmt, time, columns)
        times, values, lines = read_columns(path, where.layout, where.usecols)
        table = SampleTable(times, values, where.channels, lines, orientation=where.orientation)
        label = where.label
    try:
        times, note = to_seconds(table.times, unit=time_unit, rate=rate)
    except InputError as err:
        raise FileFormatError(str(path), str(err)) from None
    return replace(table, times=times, notes=(label, note))


@dataclass(frozen=True)
class TableStream:
    """A table read in chunks (:func:`stream_table`).

    Attributes
    ----------
    channels : list of str
    orientation : tuple of str
        Channels holding a quaternion, as :attr:`SampleTable.orientation`.
    notes : tuple of str
        The format and how the times are read, as :func:`read_table` says them.
    blocks : iterator of SampleTable
        The rows in order, a chunk at a time, times in seconds, each with its lines.
    """

    channels: list[str]
    orientation: tuple[str, ...]
    notes: tuple[str, ...]
    blocks: Iterator[SampleTable]


def _seconds(path: str, times: np.ndarray, origin: float, unit: str | None, rate: float | None) -> tuple[np.ndarray, str]:
    """A chunk's times in seconds as :func:`to_seconds` reads the whole column (``origin``,
    the column's first time, leads the chunk: wall-clock times are converted from it)."""
    try:
        seconds, note = to_seconds(np.r_[origin, times], unit=unit, rate=rate)
    except InputError as err:
        raise FileFormatError(path, str(err)) from None
    return seconds[1:], note


def stream_table(path: str | os.PathLike[str], fmt: str, *, time: str | None = None,
                 columns: Sequence[str] | None = None, time_unit: str | None = None, rate: float | None = None,
                 chunk_rows: int = CHUNK_ROWS) -> TableStream:
    """A table of format ``fmt`` (one of :data:`STREAMED`) read a chunk of rows at a
    time, as :func:`read_table` reads it whole: the same samples, times and lines, in
    the memory of a chunk however long the file. The first chunk is read at once (a
    bad start is an error here); the unit of the time column is the one the first
    chunk shows, and a later chunk that reads otherwise is an error naming its line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x\\n0,1\\n0.5,2\\n1,3\\n")
    >>> s = stream_table(p, "csv", chunk_rows=2)
    >>> s.channels, [b.times.tolist() for b in s.blocks]
    (['x'], [[0.0, 0.5], [1.0]])
    """
    name = str(path)
    if fmt not in STREAMED:
        raise ArgumentError("format", f"{fmt} tables are read whole; streamed: {', '.join(STREAMED)}")
    where = text_columns(path, fmt, time, columns)
    rows = iter_rows(path, where.layout, where.usecols, chunk_rows)
    first = next(rows, None)
    if first is None:
        raise FileFormatError(name, "has no samples")
    origin = float(first[0][0])
    _, note = _seconds(name, first[0], origin, time_unit, rate)

    def blocks() -> Iterator[SampleTable]:
        for times, values, lines in chain([first], rows):
            seconds, said = _seconds(name, times, origin, time_unit, rate)
            if said != note:
                line = lines if isinstance(lines, int) else int(lines[0])
                raise FileFormatError(name, f"the time column reads otherwise from here on ({said}; before: "
                                            f"{note}); time_unit=UNIT says how to read it", line=line)
            yield SampleTable(seconds, values, where.channels, lines, orientation=where.orientation)

    return TableStream(where.channels, where.orientation, (where.label, note), blocks())
