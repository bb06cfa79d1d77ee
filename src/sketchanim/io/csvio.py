"""Sample tables in CSV: first column time in seconds, the others channels; header optional."""

from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sketchanim.errors import FileFormatError
from sketchanim.io.numbers import plain_float


@dataclass(frozen=True)
class SampleTable:
    """Samples read from a file.

    Attributes
    ----------
    times : ndarray, shape (n,)
    values : ndarray, shape (n, d)
    channels : list of str
        Column names (from the header, or ``x1 .. xd``).
    lines : ndarray of int, shape (n,)
        Where each sample is, to point at one the reducer rejects: its 1-based file
        line, or (``unit == "record"``) its index in a JSON array.
    unit : {"line", "record"}
    """

    times: np.ndarray
    values: np.ndarray
    channels: list[str]
    lines: np.ndarray
    unit: str = "line"

    def where(self, index: int) -> str:
        """Where sample ``index`` is in the file: ``"line 12"`` or ``"record [10]"``.

        >>> SampleTable(np.zeros(1), np.zeros((1, 1)), ["x"], np.array([4])).where(0)
        'line 4'
        """
        number = int(self.lines[index])
        return f"line {number}" if self.unit == "line" else f"record [{number}]"


def text_lines(path: str | os.PathLike[str]) -> list[str]:
    """The lines of a UTF-8 text file; a file that cannot be read, or is not UTF-8,
    raises :class:`FileFormatError` naming it.

    >>> text_lines("/no/such/file")
    Traceback (most recent call last):
    sketchanim.errors.FileFormatError: /no/such/file: cannot read (No such file or directory)
    """
    try:
        return Path(path).read_text(encoding="utf-8", errors="strict").splitlines()
    except OSError as err:
        raise FileFormatError(str(path), f"cannot read ({err.strerror})") from None
    except UnicodeDecodeError:
        raise FileFormatError(str(path), "is not UTF-8 text") from None


def parse_number(text: str) -> float | None:
    """``text`` as a float, or ``None`` if it is not a plain ASCII number
    (:func:`~sketchanim.io.numbers.plain_float`: not ``１２``, not ``1_000``).

    >>> parse_number(" 1e-3"), parse_number("x"), parse_number("1_000")
    (0.001, None, None)
    """
    return plain_float(text)


def read_samples_csv(path: str | os.PathLike[str]) -> SampleTable:
    """Read a CSV of samples; errors name the file, line and column.

    Blank lines and lines starting with ``#`` are skipped. The first row is a header if
    any of its cells is not a number. Time order and finiteness are the reducer's checks
    (they name the sample index); this reader checks shape and that cells are numbers.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.csv"
    >>> _ = p.write_text("t,x,y\\n0,1,2\\n0.5,1.5,2.5\\n")
    >>> table = read_samples_csv(p)
    >>> table.channels, table.values.tolist()
    (['x', 'y'], [[1.0, 2.0], [1.5, 2.5]])
    """
    name = str(path)
    try:
        handle = Path(path).open(newline="", encoding="utf-8")
    except OSError as err:
        raise FileFormatError(name, f"cannot open ({err.strerror})") from None
    rows: list[list[float]] = []
    lines: list[int] = []
    channels: list[str] | None = None
    width = None
    with handle:
        try:
            reader = csv.reader(handle)
            for cells in reader:
                line = reader.line_num
                if not cells or not "".join(cells).strip() or cells[0].lstrip().startswith("#"):
                    continue
                cells = [c.strip() for c in cells]
                parsed = [parse_number(c) for c in cells]
                if width is None:
                    width = len(cells)
                    if width < 2:
                        raise FileFormatError(name, "needs a time column and at least one channel", line=line)
                    if any(v is None for v in parsed):
                        channels = cells[1:]
                        continue
                if len(cells) != width:
                    raise FileFormatError(name, f"{len(cells)} columns, expected {width}", line=line)
                for col, (cell, value) in enumerate(zip(cells, parsed)):
                    if value is None:
                        raise FileFormatError(name, f"column {col + 1} is not a number: {cell!r}", line=line)
                    if not math.isfinite(value):
                        raise FileFormatError(name, f"column {col + 1} is {cell!r}", line=line)
                rows.append(parsed)  # type: ignore[arg-type]
                lines.append(line)
        except UnicodeDecodeError:
            raise FileFormatError(name, "is not UTF-8 text") from None
        except csv.Error as err:
            raise FileFormatError(name, f"bad CSV ({err})") from None
    if not rows:
        raise FileFormatError(name, "has no samples")
    data = np.asarray(rows, dtype=float)
    assert width is not None
    return SampleTable(data[:, 0].copy(), np.ascontiguousarray(data[:, 1:]),
                       channels or [f"x{i}" for i in range(1, width)], np.asarray(lines))

