"""Real-data quirks in sample tables, resolved only as the user chooses: samples out of
time order and two samples at one time with different values. The default is an error
that names the line and says which choice goes on."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from sketchanim.errors import FileFormatError
from sketchanim.formats.csvio import SampleTable

#: Choices for samples out of order: stop, drop the ones that go back, or sort them.
UNORDERED = ("error", "drop", "sort")

#: Choices for two samples at one time: stop, keep the first, or average them.
DUPLICATES = ("error", "first", "mean")


def _at(table: SampleTable, name: str, index: int, message: str) -> FileFormatError:
    """An error at sample ``index``: its line, or its record."""
    if table.unit == "line":
        return FileFormatError(name, message, line=int(table.line_numbers()[index]))
    return FileFormatError(name, f"{table.where(index)}: {message}")


def ordered(table: SampleTable, how: str, name: str) -> tuple[SampleTable, int]:
    """The table in time order, and how many samples were dropped or moved.

    ``how``: ``"error"`` raises :class:`FileFormatError` at the first sample earlier
    than the one before; ``"drop"`` drops every sample earlier than one before it;
    ``"sort"`` sorts by time (stable).

    >>> t = SampleTable(np.array([0.0, 2, 1, 3]), np.c_[[0.0, 2, 1, 3]], ["x"], 1)
    >>> [(ordered(t, how, "f")[0].times.tolist(), ordered(t, how, "f")[1]) for how in ("drop", "sort")]
    [([0.0, 2.0, 3.0], 1), ([0.0, 1.0, 2.0, 3.0], 1)]
    """
    t = table.times
    back = np.flatnonzero(t[1:] < np.maximum.accumulate(t)[:-1]) + 1
    if not back.size:
        return table, 0
    if how == "error":
        i = int(back[0])
        raise _at(table, name, i, f"time goes backwards ({t[i]:g} after {t[i - 1]:g}); {back.size} samples are out "
                                  f"of order (unordered=drop or sort goes on)")
    if how == "drop":
        keep = np.ones(len(t), dtype=bool)
        keep[back] = False
        return table.take(keep), int(back.size)
    order = np.argsort(t, kind="stable")
    return table.take(order), int(back.size)


def merged(table: SampleTable, how: str, name: str) -> tuple[SampleTable, int]:
    """The table with one sample per time (times in order), and how many samples were
    merged away. Exact duplicates (same values) are left to the reducer, which drops
    and counts them.

    ``how``: ``"error"`` raises :class:`FileFormatError` at the first time with two
    different values; ``"first"`` keeps the first sample at each time; ``"mean"``
    averages the samples at each time.

    >>> t = SampleTable(np.array([0.0, 1, 1, 2]), np.c_[[0.0, 1, 3, 2]], ["x"], 1)
    >>> [(merged(t, how, "f")[0].values[:, 0].tolist(), merged(t, how, "f")[1]) for how in ("first", "mean")]
    [([0.0, 1.0, 2.0], 1), ([0.0, 2.0, 2.0], 1)]
    """
    t, x = table.times, table.values
    same = np.flatnonzero(t[1:] == t[:-1]) + 1
    differ = same[np.any(x[same] != x[same - 1], axis=1)]
    if not differ.size:
        return table, 0
    if how == "error":
        i = int(differ[0])
        raise _at(table, name, i, f"same time {t[i]:g} as the sample before, different values; {differ.size} such "
                                  f"samples (duplicates=first or mean goes on)")
    starts = np.r_[0, np.flatnonzero(t[1:] != t[:-1]) + 1]
    first = table.take(starts)
    if how == "first":
        return first, len(t) - len(starts)
    counts = np.diff(np.r_[starts, len(t)])
    means = np.add.reduceat(x, starts, axis=0) / counts[:, None]
    return replace(first, values=means), len(t) - len(starts)
