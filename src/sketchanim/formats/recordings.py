"""Readers for recording formats met in practice: TUM trajectories, Wacom SVC pen
files and LASA handwriting. Errors name the file and line. (Motion capture clips:
:mod:`sketchanim.formats.bvh`, :mod:`sketchanim.formats.amc`.)
"""

from __future__ import annotations

import os

import numpy as np

from sketchanim.errors import ArgumentError, FileFormatError
from sketchanim.formats.csvio import parse_number, text_lines


def _numbers(path: str | os.PathLike[str], line_no: int, text: str, width: int | None) -> list[float]:
    parts = text.replace(",", " ").split()
    row = [parse_number(p) for p in parts]
    if None in row:
        raise FileFormatError(str(path), f"not a number: {parts[row.index(None)]!r}", line=line_no)
    if width is not None and len(row) != width:
        raise FileFormatError(str(path), f"{len(row)} values, expected {width}", line=line_no)
    if not np.all(np.isfinite(row)):
        raise FileFormatError(str(path), "value is not finite", line=line_no)
    return row  # type: ignore[return-value]


def read_tum(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """TUM RGB-D ground truth: ``timestamp tx ty tz qx qy qz qw`` per line, ``#`` comments.

    Returns ``(times, positions (n, 3), quaternions (n, 4) scalar-last)``; times start at 0.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "gt.txt"
    >>> _ = p.write_text("# t tx ty tz qx qy qz qw\\n10.0 1 2 3 0 0 0 1\\n10.5 1 2 4 0 0 0 1\\n")
    >>> t, pos, q = read_tum(p)
    >>> t.tolist(), pos[1].tolist()
    ([0.0, 0.5], [1.0, 2.0, 4.0])
    """
    rows = [
        _numbers(path, i, line, 8)
        for i, line in enumerate(text_lines(path), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not rows:
        raise FileFormatError(str(path), "has no samples")
    data = np.asarray(rows)
    return data[:, 0] - data[0, 0], data[:, 1:4], data[:, 4:8]


def read_svc(path: str | os.PathLike[str], *, columns: tuple[str, ...], time_scale: float) -> dict[str, np.ndarray]:
    """A Wacom SVC file: a count line, then one sample per line.

    ``columns`` names the columns in file order (one must be ``"t"``); times are
    multiplied by ``time_scale`` (1e-3 for milliseconds) and start at 0.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.svc"
    >>> _ = p.write_text("2\\n5 7 1000 1\\n6 8 1010 1\\n")
    >>> read_svc(p, columns=("y", "x", "t", "down"), time_scale=1e-3)["t"].tolist()
    [0.0, 0.01]
    """
    if "t" not in columns:
        raise ArgumentError("columns", f"must name the time column \"t\", got {columns!r}")
    if not (isinstance(time_scale, (int, float, np.floating)) and 0 < time_scale < float("inf")):
        raise ArgumentError("time_scale", f"must be a positive finite number, got {time_scale!r}")
    lines = text_lines(path)
    if not lines:
        raise FileFormatError(str(path), "is empty")
    count_text = lines[0].strip()
    if not (count_text.isascii() and count_text.isdigit() and len(count_text) <= 12):
        raise FileFormatError(str(path), f"first line should be the sample count, got {lines[0]!r}", line=1)
    count = int(count_text)
    rows = [_numbers(path, i, line, len(columns)) for i, line in enumerate(lines[1:], start=2) if line.strip()]
    if len(rows) != count:
        raise FileFormatError(str(path), f"header says {count} samples, found {len(rows)}")
    data = np.asarray(rows)
    out = {name: data[:, j] for j, name in enumerate(columns)}
    out["t"] = (out["t"] - out["t"][0]) * time_scale
    return out


def read_lasa(path: str | os.PathLike[str]) -> list[tuple[np.ndarray, np.ndarray]]:
    """The demonstrations of one LASA handwriting shape (.mat): ``[(times, positions (n, 2)), ...]``.

    Positions are in millimetres, times in seconds.
    """
    from scipy.io import loadmat

    try:
        mat = loadmat(str(path), squeeze_me=True, struct_as_record=False)
        demos = np.atleast_1d(mat["demos"])
        return [(np.asarray(d.t, dtype=float), np.asarray(d.pos, dtype=float).T) for d in demos]
    except (OSError, KeyError, AttributeError, ValueError) as err:
        raise FileFormatError(str(path), f"not a LASA handwriting file ({err})") from None
