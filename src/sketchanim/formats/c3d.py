"""C3D marker trajectories, read with the ``c3d`` package (pure Python).

We read with ``c3d`` rather than ezc3d: on damaged parameter sections ezc3d can crash the
process (a segmentation fault, seen on bit-flipped copies of a real file), which would
take a whole batch down; ``c3d`` raises, and every failure becomes a
:class:`FileFormatError` naming the file.

A marker's sample is a gap where its residual is negative (the C3D convention for "not
seen") or a coordinate is not finite. Analog channels are not read.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import c3d
import numpy as np

from sketchanim.mocap.markers import Markers
from sketchanim.motion.skeleton import UNITS_M
from sketchanim.errors import FileFormatError
from sketchanim.formats.numbers import CLIP_RANGE, FRAME_TIME_RANGE


def marker_names(labels: list[str]) -> tuple[str, ...]:
    """Unique names from C3D point labels: blanks stripped, an empty label named by its
    position, a repeated one numbered.

    >>> marker_names(["LASI  ", "", "LASI"])
    ('LASI', 'marker2', 'LASI_2')
    """
    names: list[str] = []
    for i, label in enumerate(labels):
        base = str(label).strip() or f"marker{i + 1}"
        name, k = base, 1
        while name in names:
            k += 1
            name = f"{base}_{k}"
        names.append(name)
    return tuple(names)


def read_c3d(path: str | os.PathLike[str]) -> Markers:
    """The marker trajectories of a C3D file, NaN in their gaps, at the file's point rate
    (the first frame's time is ``(first_frame - 1) / rate``).

    A file that cannot be parsed, has no markers, or holds fewer frames than its header
    says (truncated) raises :class:`FileFormatError` naming it.

    >>> read_c3d("/no/such.c3d")
    Traceback (most recent call last):
    sketchanim.errors.FileFormatError: /no/such.c3d: cannot read (No such file or directory)
    """
    name = str(path)
    try:
        handle = Path(path).open("rb")
    except OSError as err:
        raise FileFormatError(name, f"cannot read ({err.strerror})") from None
    with handle, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            reader = c3d.Reader(handle)
            rate, count, first = float(reader.point_rate), int(reader.frame_count), int(reader.first_frame)
            labels = list(reader.point_labels)
            units = reader.get("POINT:UNITS")
            unit = units.string_value.strip().lower() if units is not None else ""
            frames = [points[:, :4].astype(float) for _, points, _ in reader.read_frames()]
        except Exception as err:  # noqa: BLE001 - the reader raises anything on a damaged file
            raise FileFormatError(name, f"not a readable C3D file ({type(err).__name__}: {err})") from None
    low, high = FRAME_TIME_RANGE
    if not 1 / high <= rate <= 1 / low:
        raise FileFormatError(name, f"point rate is {rate!r} frames per second ({1 / high:.3g} to {1 / low:g} read)")
    if not labels or not frames or frames[0].shape[0] == 0:
        raise FileFormatError(name, "has no marker trajectories")
    if len(frames) < count:
        raise FileFormatError(name, f"truncated: the header says {count} frames, the file holds {len(frames)}")
    data = np.stack(frames)
    positions = data[:, :, :3]
    positions[(data[:, :, 3] < 0) | ~np.all(np.isfinite(positions), axis=2)] = np.nan
    names = marker_names(labels)
    if len(names) != positions.shape[1]:
        raise FileFormatError(name, f"{len(names)} labels for {positions.shape[1]} markers")
    far = np.argwhere(np.abs(positions) > CLIP_RANGE)
    if len(far):
        f, m, axis = far[0]
        raise FileFormatError(name, f"marker {names[m]!r}, frame {f}: coordinate {'xyz'[axis]} is "
                                    f"{float(positions[f, m, axis]):.6g}, beyond the range of +/-{CLIP_RANGE:g}")
    times = (first - 1 + np.arange(len(frames))) / rate
    return Markers(names, times, positions, UNITS_M.get(unit))
