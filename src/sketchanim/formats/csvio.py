"""Sample tables in text: comma, tab or whitespace separated; first column time, the
others channels; a header is optional (also as a ``#`` comment right above the data).

Tables are read with pandas' C parser in chunks: into arrays allocated once, so a
10-million-row file takes little more memory than its numbers (:func:`read_columns`),
or handed out chunk by chunk with their lines, in a chunk's memory however long the file
(:func:`iter_rows`; ``benchmarks/bench_read.py``). A file the fast path refuses is read again line by line
to say where it is wrong: the file, the line and the column.
"""

from __future__ import annotations

import csv
import math
import os
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from sketchanim.errors import FileFormatError
from sketchanim.formats.numbers import plain_float

#: Delimiters by name: ``None`` is any run of spaces and tabs.
DELIMITERS: dict[str, str | None] = {"comma": ",", "tab": "\t", "whitespace": None}

#: Rows parsed per chunk by the fast reader.
CHUNK_ROWS = 1 << 18


@dataclass(frozen=True)
class SampleTable:
    """Samples read from a file.

    Attributes
    ----------
    times : ndarray, shape (n,)
    values : ndarray, shape (n, d)
    channels : list of str
        Column names (from the header, or ``x1 .. xd``).
    lines : ndarray of int, shape (n,), or int
        Where each sample is, to point at one the reducer rejects: its 1-based file
        line, or (``unit == "record"``) its index in a JSON array. An int ``k`` stands
        for ``k, k + 1, ...`` (a table without blank or comment lines among its rows).
    unit : {"line", "record"}
    orientation : tuple of str
        Channels holding a quaternion, scalar last (x, y, z, w), where the format says
        so (TUM, EuRoC, KITTI); empty otherwise.
    notes : tuple of str
        What the reader recognised or guessed (the format, a unit, an assumed rate).
    """

    times: np.ndarray
    values: np.ndarray
    channels: list[str]
    lines: np.ndarray | int
    unit: str = "line"
    orientation: tuple[str, ...] = ()
    notes: tuple[str, ...] = field(default=())

    def line_numbers(self) -> np.ndarray:
        """Every sample's line (or record) number, as an array.

        >>> SampleTable(np.zeros(3), np.zeros((3, 1)), ["x"], 5).line_numbers().tolist()
        [5, 6, 7]
        """
        if isinstance(self.lines, (int, np.integer)):
            return np.arange(int(self.lines), int(self.lines) + len(self.times))
        return np.asarray(self.lines)

    def where(self, index: int) -> str:
        """Where sample ``index`` is in the file: ``"line 12"`` or ``"record [10]"``.

        >>> SampleTable(np.zeros(1), np.zeros((1, 1)), ["x"], np.array([4])).where(0)
        'line 4'
        """
        lines = self.lines
        number = int(lines) + index if isinstance(lines, (int, np.integer)) else int(lines[index])
        return f"line {number}" if self.unit == "line" else f"record [{number}]"

    def take(self, rows: np.ndarray | slice, columns: Sequence[int] | None = None) -> SampleTable:
        """These rows (and columns, in this order), with their lines.

        >>> t = SampleTable(np.arange(3.0), np.c_[[1.0, 2, 3], [4.0, 5, 6]], ["a", "b"], 2)
        >>> s = t.take(np.array([2, 0]), [1]); s.channels, s.values.tolist(), s.line_numbers().tolist()
        (['b'], [[6.0], [4.0]], [4, 2])
        """
        cols = list(range(len(self.channels))) if columns is None else list(columns)
        names = [self.channels[j] for j in cols]
        return replace(self, times=self.times[rows], values=np.ascontiguousarray(self.values[rows][:, cols]),
                       channels=names, lines=self.line_numbers()[rows],
                       orientation=self.orientation if set(self.orientation) <= set(names) else ())


def text_lines(path: str | os.PathLike[str]) -> list[str]:
    """The lines of a UTF-8 text file (a byte-order mark dropped); a file that cannot
    be read, or is not UTF-8, raises :class:`FileFormatError` naming it.

    >>> text_lines("/no/such/file")
    Traceback (most recent call last):
    sketchanim.errors.FileFormatError: /no/such/file: cannot read (No such file or directory)
    """
    try:
        return Path(path).read_text(encoding="utf-8-sig", errors="strict").splitlines()
    except OSError as err:
        raise FileFormatError(str(path), f"cannot read ({err.strerror})") from None
    except UnicodeDecodeError:
        raise FileFormatError(str(path), "is not UTF-8 text") from None


def parse_number(text: str) -> float | None:
    """``text`` as a float, or ``None`` if it is not a plain ASCII number
    (:func:`~sketchanim.formats.numbers.plain_float`: not ``１２``, not ``1_000``).

    >>> parse_number(" 1e-3"), parse_number("x"), parse_number("1_000")
    (0.001, None, None)
    """
    return plain_float(text)


@dataclass(frozen=True)
class Layout:
    """How a table is laid out, from its first lines (:func:`sniff`).

    Attributes
    ----------
    delimiter : str or None
        ``","``, ``"\\t"``, or ``None`` for runs of whitespace.
    header : list of str or None
        Column names, if the file names them.
    first : int
        1-based line of the first row of numbers.
    width : int
        Cells in that row.
    head : list of str
        The file's first lines (up to the first rows of numbers), for format detection.
    """

    delimiter: str | None
    header: list[str] | None
    first: int
    width: int
    head: list[str]


def split_cells(line: str, delimiter: str | None) -> list[str]:
    """The cells of one line, stripped.

    >>> split_cells(" 1\\t 2  3 ", None), split_cells("a, b", ",")
    (['1', '2', '3'], ['a', 'b'])
    """
    if delimiter is None:
        return line.split()
    return [c.strip() for c in next(csv.reader([line], delimiter=delimiter), [])]


def _skipped(line: str) -> bool:
    return not line.strip() or line.lstrip().startswith("#")


def head_lines(path: str | os.PathLike[str], limit: int = 64) -> list[str]:
    """The file's first lines, up to its ``limit``-th line that is neither blank nor a
    ``#`` comment (a byte-order mark dropped); errors name the file.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.txt"
    >>> _ = p.write_bytes(b"\\xef\\xbb\\xbf# c\\n1 2\\n3 4\\n")
    >>> head_lines(p, 1)
    ['# c', '1 2']
    """
    name = str(path)
    out: list[str] = []
    try:
        with Path(path).open(encoding="utf-8-sig", errors="strict", newline="") as handle:
            rows = 0
            for line in handle:
                out.append(line.rstrip("\r\n"))
                rows += not _skipped(line)
                if rows >= limit or len(out) > 100_000:
                    break
    except OSError as err:
        raise FileFormatError(name, f"cannot read ({err.strerror})") from None
    except UnicodeDecodeError:
        raise FileFormatError(name, "is not UTF-8 text") from None
    return out


def sniff(path: str | os.PathLike[str], delimiter: str | None | bool = True) -> Layout:
    """The delimiter (unless given; ``True`` detects it: a comma, else a tab, else
    whitespace), the header and the first row of numbers of a table.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.txt"
    >>> _ = p.write_text("# t x y\\n0 1 2\\n1 2 3\\n")
    >>> layout = sniff(p); layout.delimiter, layout.header, layout.first
    (None, ['t', 'x', 'y'], 2)
    """
    name = str(path)
    head = head_lines(path)
    rows = [(i, line) for i, line in enumerate(head, 1) if not _skipped(line)]
    if not rows:
        raise FileFormatError(name, "has no samples")
    if delimiter is True:
        probe = rows[min(1, len(rows) - 1)][1]
        delimiter = "," if "," in probe else "\t" if "\t" in probe.strip() else None
    header = None
    first, line = rows[0]
    cells = split_cells(line, delimiter)
    if any(parse_number(c) is None for c in cells):
        if len(rows) == 1:
            raise FileFormatError(name, "has no samples")
        header = cells
        first, line = rows[1]
        cells = split_cells(line, delimiter)
    elif first > 1 and head[first - 2].lstrip().startswith("#"):
        named = split_cells(head[first - 2].lstrip()[1:], delimiter)
        if len(named) == len(cells) and any(parse_number(c) is None for c in named):
            header = named
    if header is not None and len(header) != len(cells):
        raise FileFormatError(name, f"the header names {len(header)} columns, line {first} has {len(cells)} "
                                    f"(format=LAYOUT names the layout)", line=rows[0][0])
    if len(cells) < 2:
        what = "a comma, a tab or spaces" if delimiter is None else repr(delimiter)
        raise FileFormatError(name, f"needs a time column and at least one channel, separated by {what}; "
                                    f"line {first} has one cell (format=LAYOUT names the layout)", line=first)
    return Layout(delimiter, header, first, len(cells), head[:first])


def _count_lines(path: str | os.PathLike[str]) -> int:
    """Lines in the file (a last line without a newline counts)."""
    count, last = 0, b"\n"
    with Path(path).open("rb") as handle:
        while block := handle.read(1 << 22):
            count += block.count(b"\n")
            last = block[-1:]
    return count + (last != b"\n")


def _located(path: str | os.PathLike[str], layout: Layout, usecols: Sequence[int]) -> FileFormatError | None:
    """The first bad cell or row of the table, read line by line; ``None`` if all are good."""
    name = str(path)
    with Path(path).open(encoding="utf-8-sig", errors="strict", newline="") as handle:
        for number, line in enumerate(handle, 1):
            if number < layout.first or _skipped(line):
                continue
            cells = split_cells(line.rstrip("\r\n"), layout.delimiter)
            if len(cells) != layout.width:
                return FileFormatError(name, f"{len(cells)} columns, expected {layout.width}", line=number)
            for col in usecols:
                value = parse_number(cells[col])
                if value is None:
                    return FileFormatError(name, f"column {col + 1} is not a number: {cells[col]!r} (cols=COLUMNS "
                                                 f"picks the columns to read)", line=number)
                if not math.isfinite(value):
                    return FileFormatError(name, f"column {col + 1} is {cells[col]!r}", line=number)
    return None


def iter_columns(path: str | os.PathLike[str], layout: Layout, usecols: Sequence[int],
                 chunk_rows: int = CHUNK_ROWS) -> Iterator[np.ndarray]:
    """The table's columns ``usecols`` (0-based, in this order) in chunks of rows,
    float64 arrays of shape (m, len(usecols)), parsed by pandas' C reader; errors name
    the file, line and column.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x,y\\n0,1,2\\n1,2,3\\n")
    >>> [c.tolist() for c in iter_columns(p, sniff(p), [0, 2])]
    [[[0.0, 2.0], [1.0, 3.0]]]
    """
    import pandas as pd

    name = str(path)
    cols = list(usecols)
    # every column, unless some are left out: then pandas does not count the cells
    every = sorted(cols) == list(range(layout.width))
    try:
        reader = pd.read_csv(path, sep=layout.delimiter if layout.delimiter is not None else r"\s+", header=None,
                             skiprows=layout.first - 1, comment="#", skip_blank_lines=True, usecols=None if every else cols,
                             dtype=np.float64, engine="c", encoding="utf-8-sig", encoding_errors="strict",
                             chunksize=chunk_rows)
        with reader:
            for chunk in reader:
                block = chunk[cols].to_numpy(dtype=np.float64)
                if not np.isfinite(block).all():
                    raise ValueError("not finite")
                yield block
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError) as err:
        if isinstance(err, UnicodeDecodeError):
            raise FileFormatError(name, "is not UTF-8 text") from None
        located = _located(path, layout, cols)
        if located is None:
            raise FileFormatError(name, f"cannot be read as a table ({err})") from None
        raise located from None


#: A blank or ``#`` comment line right after a newline (what :func:`skipped_lines` looks for first).
_SKIPPED = re.compile(rb"\n[ \t\r\f\v]*[#\n]")


def skipped_lines(path: str | os.PathLike[str], first: int) -> np.ndarray:
    """The 1-based numbers of the blank and ``#`` comment lines after line ``first``
    (the first row of numbers), sorted: one quick scan of the bytes, and a line by
    line pass only if it finds one.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x\\n0,1\\n\\n# c\\n1,2\\n")
    >>> skipped_lines(p, 2).tolist()
    [3, 4]
    """
    with Path(path).open("rb") as handle:
        tail, ahead = b"", first                           # newlines before the newline ending line ``first``
        while block := handle.read(1 << 22):
            while ahead > 1 and block:                     # the lines up to ``first`` are not looked at
                cut = block.find(b"\n")
                block = b"" if cut < 0 else block[cut + 1 :]
                ahead -= cut >= 0
            if ahead == 1 and (cut := block.find(b"\n")) >= 0:
                block, ahead = block[cut:], 0
            if not ahead and _SKIPPED.search(tail + block):
                break
            tail = block[block.rfind(b"\n") :] if b"\n" in block else tail + block
        else:
            return np.zeros(0, dtype=np.int64)
    with Path(path).open(encoding="utf-8-sig", errors="strict", newline="") as handle:
        return np.array([n for n, line in enumerate(handle, 1) if n > first and _skipped(line)], dtype=np.int64)


def row_lines(rows: np.ndarray, first: int, skipped: np.ndarray) -> np.ndarray:
    """The 1-based file lines of the rows of numbers ``rows`` (0-based), the first on
    line ``first``, given the :func:`skipped_lines` among them.

    >>> row_lines(np.arange(4), 2, np.array([4, 5])).tolist()
    [2, 3, 6, 7]
    """
    before = skipped - first - np.arange(len(skipped))       # rows of numbers before each skipped line
    return first + rows + np.searchsorted(before, rows, side="right")


def iter_rows(path: str | os.PathLike[str], layout: Layout, usecols: Sequence[int],
              chunk_rows: int = CHUNK_ROWS) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray | int]]:
    """The table's rows in chunks, as :func:`read_columns` returns them whole: the
    first of ``usecols`` as times (m,), the others as values (m, d), and the rows'
    lines (an int for consecutive lines; see :attr:`SampleTable.lines`). Memory is a
    chunk's, however long the file.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x\\n0,1\\n\\n1,2\\n2,3\\n")
    >>> [(t.tolist(), lines.tolist()) for t, _, lines in iter_rows(p, sniff(p), [0, 1], chunk_rows=2)]
    [([0.0, 1.0], [2, 4]), ([2.0], [5])]
    """
    skipped = skipped_lines(path, layout.first)
    n = 0
    for block in iter_columns(path, layout, usecols, chunk_rows):
        rows = np.arange(n, n + len(block))
        lines: np.ndarray | int = row_lines(rows, layout.first, skipped) if skipped.size else layout.first + n
        yield block[:, 0], block[:, 1:], lines
        n += len(block)


def read_columns(path: str | os.PathLike[str], layout: Layout, usecols: Sequence[int]) -> tuple[
        np.ndarray, np.ndarray, np.ndarray | int]:
    """All rows of columns ``usecols``: the first as times (n,), the others as values
    (n, d), filled chunk by chunk into arrays allocated once (from the file's line
    count), and the rows' lines (see :attr:`SampleTable.lines`).

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x\\n0,1\\n\\n1,2\\n")
    >>> t, x, lines = read_columns(p, sniff(p), [0, 1]); t.tolist(), x.tolist(), lines.tolist()
    ([0.0, 1.0], [[1.0], [2.0]], [2, 4])
    """
    total = _count_lines(path)
    capacity = max(total - layout.first + 1, 1)
    times, values = np.empty(capacity), np.empty((capacity, len(usecols) - 1))
    n = 0
    for block in iter_columns(path, layout, usecols):
        if n + len(block) > len(times):                  # rows spanning lines (quoted newlines)
            times = np.r_[times[:n], np.empty(n + len(block))]
            values = np.r_[values[:n], np.empty((n + len(block), values.shape[1]))]
        times[n : n + len(block)] = block[:, 0]
        values[n : n + len(block)] = block[:, 1:]
        n += len(block)
    if not n:
        raise FileFormatError(str(path), "has no samples")
    lines: np.ndarray | int = layout.first
    if total - layout.first + 1 != n:                    # blank or comment lines among the rows
        skipped = skipped_lines(path, layout.first)
        if total - layout.first + 1 - len(skipped) == n:
            lines = row_lines(np.arange(n), layout.first, skipped)
    return times[:n], values[:n], lines


def resolve_column(spec: str, names: Sequence[str]) -> int:
    """A column given by name or by 1-based number, as a 0-based index.

    >>> resolve_column("y", ["t", "x", "y"]), resolve_column("2", ["t", "x", "y"])
    (2, 1)
    """
    spec = spec.strip()
    if spec in names:
        return list(names).index(spec)
    if spec.isdigit() and 1 <= int(spec) <= len(names):
        return int(spec) - 1
    raise ValueError(f"{spec!r} is not a column (columns: {', '.join(names)}; or 1 to {len(names)})")


def read_samples_csv(path: str | os.PathLike[str], *, delimiter: str | None | bool = True, time: str | None = None,
                     columns: Sequence[str] | None = None) -> SampleTable:
    """Read a table of samples; errors name the file, line and column.

    Blank lines and lines starting with ``#`` are skipped. The first row is a header if
    any of its cells is not a number (or the comment line just above the first row
    names every column). Time order and finiteness are the reducer's checks (they name
    the sample index); this reader checks shape and that cells are numbers.

    Parameters
    ----------
    delimiter : str, None or True
        ``","``, ``"\\t"``, ``None`` (whitespace) or ``True`` (detect).
    time : str, optional
        The time column, by name or 1-based number (default: the first).
    columns : sequence of str, optional
        The channel columns to read, each ``COLUMN`` or ``NAME=COLUMN`` (renamed); by
        default every column but the time.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x,y\\n0,1,2\\n0.5,1.5,2.5\\n")
    >>> table = read_samples_csv(p)
    >>> table.channels, table.values.tolist()
    (['x', 'y'], [[1.0, 2.0], [1.5, 2.5]])
    >>> read_samples_csv(p, columns=["height=y"]).channels
    ['height']
    """
    layout, usecols, channels = csv_columns(path, delimiter=delimiter, time=time, columns=columns)
    times, values, lines = read_columns(path, layout, usecols)
    return SampleTable(times, values, channels, lines)


def csv_columns(path: str | os.PathLike[str], *, delimiter: str | None | bool = True, time: str | None = None,
                columns: Sequence[str] | None = None) -> tuple[Layout, list[int], list[str]]:
    """How :func:`read_samples_csv` reads a table: its layout, the columns (0-based:
    the time, then the channels) and the channel names.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x,y\\n0,1,2\\n")
    >>> csv_columns(p, columns=["h=y"])[1:]
    ([0, 2], ['h'])
    """
    layout = sniff(path, delimiter)
    names = layout.header or ["t"] + [f"x{i}" for i in range(1, layout.width)]
    try:
        t_col = 0 if time is None else resolve_column(time, names)
        if columns is None:
            picked = [(names[j], j) for j in range(layout.width) if j != t_col]
        else:
            picked = []
            for spec in columns:
                label, _, col = spec.rpartition("=")
                j = resolve_column(col, names)
                picked.append((label.strip() or names[j], j))
    except ValueError as err:
        raise FileFormatError(str(path), f"cols: {err}") from None
    if not picked:
        raise FileFormatError(str(path), "cols: no channel picked")
    return layout, [t_col] + [j for _, j in picked], [label for label, _ in picked]
