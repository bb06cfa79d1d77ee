"""Errors raised on bad input, shared by every layer.

Each names what is wrong and where: the argument, the sample index, the channel, or the
file and line. All are :class:`ValueError` subclasses, so callers that only know numpy's
conventions still catch them. :func:`load_json` is how every layer reads untrusted
JSON: bounded, so that hostile nesting or numbers end as one of these errors.
"""

from __future__ import annotations

import json
import re

import numpy as np


class InputError(ValueError):
    """Bad input: the message says what is wrong and where.

    Examples
    --------
    >>> try:
    ...     raise SampleError("time is NaN", index=3, field="time")
    ... except InputError as err:
    ...     print(err, err.index, err.field)
    sample 3, time: time is NaN 3 time
    """


class ArgumentError(InputError):
    """A bad argument (tolerance, order, method...), named in ``argument``."""

    def __init__(self, argument: str, message: str) -> None:
        self.argument = argument
        super().__init__(f"{argument}: {message}")


class SampleError(InputError):
    """A bad sample, at position ``index`` of the caller's input, in ``field``."""

    def __init__(self, message: str, *, index: int | None = None, field: str | None = None) -> None:
        self.index = index
        self.field = field
        where = []
        if index is not None:
            where.append(f"sample {index}")
        if field is not None:
            where.append(field)
        super().__init__(f"{', '.join(where)}: {message}" if where else message)


class FileFormatError(InputError):
    """A malformed file, at ``path`` and (where known) 1-based ``line``."""

    def __init__(self, path: str, message: str, *, line: int | None = None) -> None:
        self.path = path
        self.line = line
        where = f"{path}, line {line}" if line is not None else path
        super().__init__(f"{where}: {message}")


class StorageError(InputError):
    """A write the disk or the folder refused (full, unwritable, read-only, gone): what
    could not be written, and why. Nothing that was kept before is lost."""


class ToleranceUnreachableError(InputError):
    """Not even the interpolating spline meets the tolerance (it is below rounding)."""


#: Deepest nesting of arrays and objects a JSON reader accepts.
MAX_JSON_DEPTH = 64
#: Most digits an integer in JSON may have (beyond 308 it is no float64).
MAX_JSON_DIGITS = 300


def _json_depth(text: str) -> int:
    """The deepest nesting of ``[`` and ``{`` in JSON ``text`` (strings skipped), found
    without recursion."""
    if text.count("[") + text.count("{") <= MAX_JSON_DEPTH:
        return 0
    bare = re.sub(r'"[^"\\]*(?:\\.[^"\\]*)*"', "", text).encode("utf-8", "replace")
    chars = np.frombuffer(bare, dtype=np.uint8)
    at = np.flatnonzero((chars == 91) | (chars == 123) | (chars == 93) | (chars == 125))
    steps = np.where((chars[at] == 91) | (chars[at] == 123), 1, -1).astype(np.int32)
    return int(np.cumsum(steps).max(initial=0))


def _json_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_JSON_DIGITS:
        raise InputError(f"an integer of {len(text.lstrip('-'))} digits (at most {MAX_JSON_DIGITS})")
    return int(text)


def load_json(text: str | bytes, source: str, *, line: int | None = None) -> object:
    """``json.loads`` for untrusted text, bounded: nesting deeper than
    :data:`MAX_JSON_DEPTH` and integers longer than :data:`MAX_JSON_DIGITS` digits raise
    :class:`FileFormatError` naming ``source`` (and ``line``); text that is not JSON
    raises ``json.JSONDecodeError``, as ``json.loads`` does. Non-finite numbers (``NaN``,
    ``1e400``) come through for the reader to refuse by field.

    >>> load_json('{"t": [1, 2.5]}', "f.json")
    {'t': [1, 2.5]}
    >>> load_json("[" * 100 + "]" * 100, "f.json")
    Traceback (most recent call last):
    sketchanim.errors.FileFormatError: f.json: nested 100 deep (at most 64)
    """
    if isinstance(text, bytes):
        text = text.decode("utf-8")
    depth = _json_depth(text)
    if depth > MAX_JSON_DEPTH:
        raise FileFormatError(source, f"nested {depth} deep (at most {MAX_JSON_DEPTH})", line=line)
    try:
        return json.loads(text, parse_int=_json_int)
    except InputError as err:
        raise FileFormatError(source, str(err), line=line) from None
