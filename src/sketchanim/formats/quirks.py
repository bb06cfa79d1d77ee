"""Real-data quirks in sample tables, resolved only as the user chooses: samples out of
time order and two samples at one time with different values. The default is an error
that names the line and says which choice goes on."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from sketchanim.errors import ArgumentError, FileFormatError
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


def ordered(table: SampleTable, how: str, name: str, *, whole: bool = True) -> tuple[SampleTable, int]:
    """The table in time order, and how many samples were dropped or moved.

    ``how``: ``"error"`` raises :class:`FileFormatError` at the first sample earlier
    than the one before; ``"drop"`` drops every sample earlier than one before it;
    ``"sort"`` sorts by time (stable). ``whole``: the table is the whole file (else
    the rows read so far, as :class:`Resolver` passes them: errors count those).

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
                                  f"of order{'' if whole else ' in the rows around it'} (unordered=drop or sort goes on)")
    if how == "drop":
        keep = np.ones(len(t), dtype=bool)
        keep[back] = False
        return table.take(keep), int(back.size)
    order = np.argsort(t, kind="stable")
    return table.take(order), int(back.size)


def merged(table: SampleTable, how: str, name: str, *, whole: bool = True) -> tuple[SampleTable, int]:
    """The table with one sample per time where samples at one time differ (times in
    order), and how many samples were merged away. Exact duplicates (same values) are
    left to the reducer, which drops and counts them.

    ``how``: ``"error"`` raises :class:`FileFormatError` at the first time with two
    different values; ``"first"`` keeps the first sample at such a time; ``"mean"``
    averages them. ``whole`` as for :func:`ordered`.

    >>> t = SampleTable(np.array([0.0, 1, 1, 2, 2]), np.c_[[0.0, 1, 3, 2, 2]], ["x"], 1)
    >>> [(merged(t, how, "f")[0].values[:, 0].tolist(), merged(t, how, "f")[1]) for how in ("first", "mean")]
    [([0.0, 1.0, 2.0, 2.0], 1), ([0.0, 2.0, 2.0, 2.0], 1)]
    """
    t, x = table.times, table.values
    same = np.flatnonzero(t[1:] == t[:-1]) + 1
    differ = same[np.any(x[same] != x[same - 1], axis=1)]
    if not differ.size:
        return table, 0
    if how == "error":
        i = int(differ[0])
        raise _at(table, name, i, f"same time {t[i]:g} as the sample before, different values; {differ.size} such "
                                  f"samples{'' if whole else ' in the rows around it'} (duplicates=first or mean "
                                  f"goes on)")
    starts = np.r_[0, np.flatnonzero(t[1:] != t[:-1]) + 1]
    sizes = np.diff(np.r_[starts, len(t)])
    mixed = np.zeros(len(starts), dtype=bool)
    mixed[np.searchsorted(starts, differ, side="right") - 1] = True
    keep = ~np.repeat(mixed, sizes)
    keep[starts] = True
    result = table.take(keep)
    if how == "mean":
        values = result.values
        at = np.searchsorted(np.flatnonzero(keep), starts[mixed])
        values[at] = np.add.reduceat(x, starts, axis=0)[mixed] / sizes[mixed, None]
    return result, len(t) - len(result.times)


def _joined(a: SampleTable, b: SampleTable) -> SampleTable:
    """The rows of ``a``, then those of ``b``."""
    return replace(b, times=np.r_[a.times, b.times], values=np.r_[a.values, b.values],
                   lines=np.r_[a.line_numbers(), b.line_numbers()])


class Resolver:
    """:func:`ordered` and :func:`merged` over a table read in chunks, as they resolve
    the whole table: the samples at the last time of a chunk wait for the next chunk,
    where more may come at that time.

    >>> r = Resolver("drop", "mean", "f")
    >>> a = r.push(SampleTable(np.array([0.0, 1, 1]), np.c_[[0.0, 1, 3]], ["x"], 1))
    >>> b = r.push(SampleTable(np.array([1.0, 0.5, 2]), np.c_[[5.0, 9, 2]], ["x"], 4))
    >>> c = r.flush()
    >>> [s.values[:, 0].tolist() for s in (a, b, c)], r.moved, r.merged_away
    ([[0.0], [3.0], [2.0]], 1, 2)
    """

    def __init__(self, unordered: str, duplicates: str, name: str) -> None:
        if unordered == "sort":
            raise ArgumentError("unordered", "sort needs the whole table; a table read in chunks takes error or drop")
        self.unordered, self.duplicates, self.name = unordered, duplicates, name
        self.moved = 0
        self.merged_away = 0
        self._carry: SampleTable | None = None

    def push(self, block: SampleTable) -> SampleTable:
        """The samples of ``block`` (and of the chunks before) that are resolved now."""
        table = block if self._carry is None else _joined(self._carry, block)
        table, moved = ordered(table, self.unordered, self.name, whole=False)
        self.moved += moved
        last = int(np.searchsorted(table.times, table.times[-1], side="left"))
        self._carry = table.take(slice(last, None))
        ready, merged_away = merged(table.take(slice(0, last)), self.duplicates, self.name, whole=False)
        self.merged_away += merged_away
        return ready

    def flush(self) -> SampleTable | None:
        """The samples still waiting, at the end of the table."""
        if self._carry is None:
            return None
        ready, merged_away = merged(self._carry, self.duplicates, self.name, whole=False)
        self.merged_away += merged_away
        self._carry = None
        return ready
