"""Numbers in text files: what counts as one, and the range a clip file's numbers may
span.

Python's ``float()`` takes more than a file format means by a number: full-width and
other Unicode digits (``１２``), underscores (``1_000``), surrounding whitespace. The
text readers take plain ASCII decimals only (and ``nan``/``inf``, so that their
finiteness checks can name them).

Clip files (BVH, ASF/AMC, C3D) hold lengths in their own units and angles in degrees or
radians: each number must be within :data:`CLIP_RANGE` of zero, and a frame time (BVH;
C3D: one over its point rate) within :data:`FRAME_TIME_RANGE` seconds. Beyond them no
motion is meant, float32 keyframes would no longer resolve a tolerance, and float64
arithmetic on them would overflow (``1e308``). Sample streams (CSV, JSON, TUM, SVC) are checked by the reducer
(:mod:`sketchanim.reducer.conditioning`), which knows each channel's tolerance.
"""

from __future__ import annotations

import re

import numpy as np

#: Largest magnitude of a length or an angle read from a clip file (in its units).
CLIP_RANGE = 1e6
#: Shortest and longest frame time of a clip file, in seconds.
FRAME_TIME_RANGE = (1e-6, 3600.0)

_PLAIN = re.compile(r"[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|nan|inf|infinity)", re.IGNORECASE)


def plain_float(text: str) -> float | None:
    """``text`` (surrounding spaces allowed) as a float if it is a plain ASCII decimal
    number, else ``None``.

    >>> plain_float(" 1e-3"), plain_float("-.5"), plain_float("１２"), plain_float("1_000"), plain_float("x")
    (0.001, -0.5, None, None, None)
    """
    text = text.strip()
    return float(text) if _PLAIN.fullmatch(text) else None


def plain_floats(words: list[str]) -> np.ndarray | None:
    """The words as floats if every one is a plain number, else ``None``.

    >>> plain_floats(["1", "2.5"]).tolist(), plain_floats(["1", "٣"])
    ([1.0, 2.5], None)
    """
    values = [plain_float(w) for w in words]
    return None if None in values else np.array(values, dtype=float)


def out_of_clip_range(values: np.ndarray) -> float | None:
    """The first value beyond :data:`CLIP_RANGE` (or not finite), or ``None``.

    >>> out_of_clip_range(np.array([1.0, -1e308])), out_of_clip_range(np.array([5.0]))
    (-1e+308, None)
    """
    bad = np.flatnonzero(~(np.abs(values) <= CLIP_RANGE))
    return float(values.flat[bad[0]]) if bad.size else None
