"""Readers for recording formats met in practice: TUM trajectories, Wacom SVC pen
files and the motion section of BVH files. Errors name the file and line.

These read samples for reduction; full skeleton import (offsets, hierarchy, rotations
as quaternions) belongs with the animation model.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sketchanim.errors import FileFormatError
from sketchanim.io.csvio import parse_number


def _lines(path: str | os.PathLike[str]) -> list[str]:
    try:
        return Path(path).read_text(encoding="utf-8", errors="strict").splitlines()
    except OSError as err:
        raise FileFormatError(str(path), f"cannot read ({err.strerror})") from None
    except UnicodeDecodeError:
        raise FileFormatError(str(path), "is not UTF-8 text") from None


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
        for i, line in enumerate(_lines(path), start=1)
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
    lines = _lines(path)
    if not lines:
        raise FileFormatError(str(path), "is empty")
    try:
        count = int(lines[0].strip())
    except ValueError:
        raise FileFormatError(str(path), f"first line should be the sample count, got {lines[0]!r}", line=1) from None
    rows = [_numbers(path, i, line, len(columns)) for i, line in enumerate(lines[1:], start=2) if line.strip()]
    if len(rows) != count:
        raise FileFormatError(str(path), f"header says {count} samples, found {len(rows)}")
    data = np.asarray(rows)
    out = {name: data[:, j] for j, name in enumerate(columns)}
    out["t"] = (out["t"] - out["t"][0]) * time_scale
    return out


@dataclass(frozen=True)
class BvhMotion:
    """The MOTION section of a BVH file with the channel names from its HIERARCHY.

    Attributes
    ----------
    channels : list of (joint, channel)
        e.g. ``("Hips", "Xposition")``, in column order.
    frame_time : float
        Seconds per frame.
    frames : ndarray, shape (n_frames, n_channels)
    """

    channels: list[tuple[str, str]]
    frame_time: float
    frames: np.ndarray

    @property
    def times(self) -> np.ndarray:
        """Frame times in seconds, from 0."""
        return np.arange(len(self.frames)) * self.frame_time

    def columns(self, joint: str, names: tuple[str, ...]) -> np.ndarray:
        """The columns of ``joint`` named ``names`` (e.g. the three positions)."""
        index = {c: i for i, c in enumerate(self.channels)}
        missing = [n for n in names if (joint, n) not in index]
        if missing:
            raise KeyError(f"joint {joint!r} has no channel {missing[0]!r}")
        return self.frames[:, [index[(joint, n)] for n in names]]


def read_bvh_motion(path: str | os.PathLike[str]) -> BvhMotion:
    """Read channel names and frames of a BVH file; a truncated MOTION section is an error.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "m.bvh"
    >>> _ = p.write_text("HIERARCHY\\nROOT Hips\\n{\\n OFFSET 0 0 0\\n CHANNELS 3 Xposition Yposition Zposition\\n"
    ...                  " End Site\\n {\\n  OFFSET 0 1 0\\n }\\n}\\nMOTION\\nFrames: 2\\nFrame Time: 0.5\\n0 1 2\\n3 4 5\\n")
    >>> m = read_bvh_motion(p)
    >>> m.channels[0], m.times.tolist(), m.columns("Hips", ("Zposition",)).ravel().tolist()
    (('Hips', 'Xposition'), [0.0, 0.5], [2.0, 5.0])
    """
    lines = _lines(path)
    channels: list[tuple[str, str]] = []
    joint: str | None = None
    motion_at = None
    for i, line in enumerate(lines, start=1):
        words = line.split()
        if not words:
            continue
        if words[0] in ("ROOT", "JOINT") and len(words) >= 2:
            joint = words[1]
        elif words[0] == "CHANNELS":
            if joint is None or len(words) < 2 or not words[1].isdigit() or len(words) != 2 + int(words[1]):
                raise FileFormatError(str(path), "malformed CHANNELS line", line=i)
            channels += [(joint, name) for name in words[2:]]
        elif words[0] == "MOTION":
            motion_at = i
            break
    if motion_at is None:
        raise FileFormatError(str(path), "no MOTION section")
    header = lines[motion_at : motion_at + 2]
    try:
        n_frames = int(header[0].split(":")[1])
        frame_time = float(header[1].split(":")[1])
    except (IndexError, ValueError):
        raise FileFormatError(str(path), "expected 'Frames: N' and 'Frame Time: T'", line=motion_at + 1) from None
    if not frame_time > 0:
        raise FileFormatError(str(path), f"frame time must be > 0, got {frame_time}", line=motion_at + 2)
    first = motion_at + 3
    rows = [_numbers(path, i, line, len(channels))
            for i, line in enumerate(lines[first - 1 :], start=first) if line.strip()]
    if len(rows) != n_frames:
        raise FileFormatError(str(path), f"MOTION says {n_frames} frames but has {len(rows)} (truncated?)")
    return BvhMotion(channels, frame_time, np.asarray(rows).reshape(n_frames, len(channels)))


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
