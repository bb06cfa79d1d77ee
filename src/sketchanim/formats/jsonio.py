"""Sample streams in JSON: JSON Lines (one record per line), an array of records, or
columns.

A record is an object with the time in seconds under ``t`` or ``time`` and one field per
channel: a number, or an array of numbers (``"pos": [x, y, z]`` gives channels
``pos[0]``, ``pos[1]``, ``pos[2]``). Every record has the same fields. A columns document
is an object of arrays: ``{"t": [...], "x": [...], "pos": [[x, y, z], ...]}``.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from sketchanim.errors import FileFormatError, load_json
from sketchanim.formats.csvio import SampleTable, text_lines

#: Names the time may go by.
TIME_KEYS = ("t", "time")

#: Extensions read as JSON Lines.
JSON_LINES = (".jsonl", ".ndjson")

#: Extensions read as JSON sample streams.
JSON_SAMPLES = (".json", *JSON_LINES)


def _flat(value: object, field: str) -> list[float]:
    """A field's numbers, or the reason it has none (ValueError)."""
    items = value if isinstance(value, list) else [value]
    if not items:
        raise ValueError(f"field {field!r} is an empty array")
    out = []
    for item in items:
        if isinstance(item, bool) or not isinstance(item, (int, float)):
            raise ValueError(f"field {field!r} is not a number or array of numbers: {json.dumps(value)[:40]}")
        if not math.isfinite(item):
            raise ValueError(f"field {field!r} is {item}")
        out.append(float(item))
    return out


def _error(name: str, unit: str, number: int, message: str) -> FileFormatError:
    """An error at a line of the file, or at a record of its array."""
    if unit == "line":
        return FileFormatError(name, message, line=number)
    return FileFormatError(name, f"record [{number}]: {message}")


def _layout(record: dict) -> tuple[str, list[str], list[int]]:
    """The time key, the channel fields in order, and each field's width (ValueError
    saying what is missing)."""
    times = [k for k in TIME_KEYS if k in record]
    if len(times) != 1:
        raise ValueError(f"needs the time in seconds under one of {', '.join(TIME_KEYS)}")
    fields = [k for k in record if k != times[0]]
    if not fields:
        raise ValueError("has no channel besides the time")
    return times[0], fields, [len(_flat(record[k], k)) for k in fields]


def _channels(fields: list[str], widths: list[int]) -> list[str]:
    return [f if w == 1 else f"{f}[{i}]" for f, w in zip(fields, widths) for i in range(w)]


def _records(records: list[tuple[object, int]], unit: str, name: str) -> SampleTable:
    """A table of ``records`` (each with its line, or its index in the array: ``unit``)."""
    if not records:
        raise FileFormatError(name, "has no samples")
    rows, numbers = [], []
    layout = None
    for record, number in records:
        try:
            if not isinstance(record, dict):
                raise ValueError("is not an object")
            layout = layout or _layout(record)
            time_key, fields, widths = layout
            if set(record) != {time_key, *fields}:
                missing = sorted({time_key, *fields} - set(record))
                extra = sorted(set(record) - {time_key, *fields})
                raise ValueError("; ".join(([f"lacks {', '.join(map(repr, missing))}"] if missing else [])
                                           + ([f"has {', '.join(map(repr, extra))}, the first record not"]
                                              if extra else [])))
            row = _flat(record[time_key], time_key)
            for f, w in zip(fields, widths):
                values = _flat(record[f], f)
                if len(values) != w:
                    raise ValueError(f"field {f!r} has {len(values)} numbers, the first record {w}")
                row += values
        except ValueError as err:
            raise _error(name, unit, number, str(err)) from None
        rows.append(row)
        numbers.append(number)
    assert layout is not None
    data = np.asarray(rows, dtype=float)
    return SampleTable(data[:, 0].copy(), np.ascontiguousarray(data[:, 1:]), _channels(*layout[1:]),
                       np.asarray(numbers), unit)


def _columns(doc: dict, name: str) -> SampleTable:
    """A table of a columns document."""
    lengths = {k: len(v) if isinstance(v, list) else -1 for k, v in doc.items()}
    if any(n < 0 for n in lengths.values()):
        bad = next(k for k, n in lengths.items() if n < 0)
        raise FileFormatError(name, f"field {bad!r} is not an array (a columns document holds one array per field)")
    if len(set(lengths.values())) > 1:
        raise FileFormatError(name, "fields have different lengths: " + ", ".join(
            f"{k} {n}" for k, n in lengths.items()))
    records = [({k: v[i] for k, v in doc.items()}, i) for i in range(next(iter(lengths.values()), 0))]
    return _records(records, "record", name)


def read_samples_json(path: str | os.PathLike[str]) -> SampleTable:
    """Samples from JSON Lines (.jsonl, .ndjson: numbered by line) or a JSON document
    (an array of records or an object of columns: numbered by record index); errors
    name the file, the line or record, and the field.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.jsonl"
    >>> _ = p.write_text('{"t": 0, "pos": [1, 2]}\\n{"t": 0.5, "pos": [1.5, 2.5]}\\n')
    >>> table = read_samples_json(p)
    >>> table.channels, table.values.tolist(), table.lines.tolist()
    (['pos[0]', 'pos[1]'], [[1.0, 2.0], [1.5, 2.5]], [1, 2])
    """
    name = str(path)
    lines = text_lines(path)
    if Path(path).suffix.lower() in JSON_LINES:
        records = []
        for number, line in enumerate(lines, 1):
            if line.strip():
                try:
                    records.append((load_json(line, name, line=number), number))
                except json.JSONDecodeError as err:
                    raise FileFormatError(name, f"not JSON ({err.msg}, column {err.colno})", line=number) from None
        return _records(records, "line", name)
    try:
        doc = load_json("\n".join(lines), name)
    except json.JSONDecodeError as err:
        raise FileFormatError(name, f"not JSON ({err.msg}, column {err.colno})", line=err.lineno) from None
    if isinstance(doc, list) and (not doc or isinstance(doc[0], dict)):
        return _records(list(zip(doc, range(len(doc)))), "record", name)
    if isinstance(doc, dict) and any(k in doc for k in TIME_KEYS):
        return _columns(doc, name)
    what = (f"an object with fields {', '.join(map(repr, list(doc)[:6]))}" + (", ..." if len(doc) > 6 else "")
            if isinstance(doc, dict) else f"an array of {type(doc[0]).__name__}" if isinstance(doc, list)
            else f"a {type(doc).__name__}")
    raise FileFormatError(name, f"is not a sample stream: expected an array of records or an object of columns, "
                                f"with the time in seconds under {' or '.join(map(repr, TIME_KEYS))} (or JSON Lines, "
                                f"one record a line, as .jsonl); this is {what}")
