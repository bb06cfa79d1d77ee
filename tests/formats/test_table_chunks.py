"""Tables read a chunk of rows at a time: the same samples, times, lines and quirks as
the table read whole."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from sketchanim.errors import FileFormatError
from sketchanim.formats.csvio import SampleTable, iter_rows, read_columns, sniff
from sketchanim.formats.quirks import Resolver, merged, ordered
from sketchanim.formats.tables import read_table, stream_table


def _chunked(table: SampleTable, cuts: list[int], unordered: str, duplicates: str
             ) -> tuple[SampleTable, int, int]:
    resolver = Resolver(unordered, duplicates, "f")
    edges = [0] + sorted(set(c % len(table.times) for c in cuts) - {0}) + [len(table.times)]
    out = [resolver.push(table.take(slice(a, b))) for a, b in zip(edges[:-1], edges[1:])] + [resolver.flush()]
    got = SampleTable(np.concatenate([o.times for o in out]), np.concatenate([o.values for o in out]), ["x"],
                      np.concatenate([o.line_numbers() for o in out]))
    return got, resolver.moved, resolver.merged_away


@given(times=st.lists(st.integers(0, 12), min_size=1, max_size=60), cuts=st.lists(st.integers(0, 59), max_size=6),
       values=st.lists(st.integers(0, 2), min_size=60, max_size=60),
       unordered=st.sampled_from(["error", "drop"]), duplicates=st.sampled_from(["error", "first", "mean"]))
def test_property_quirks_in_chunks_resolve_as_the_whole(times, cuts, values, unordered, duplicates) -> None:
    t = np.asarray(times, dtype=float)
    table = SampleTable(t, np.c_[values[: len(t)]].astype(float), ["x"], 3)
    try:
        whole, moved = ordered(table, unordered, "f")
        whole, merged_away = merged(whole, duplicates, "f")
    except FileFormatError as err:
        lines = {err.line}
        if duplicates == "error":            # read as it streams, a repeated time before a step back is met first
            try:
                merged(table, duplicates, "f")
            except FileFormatError as first:
                lines.add(first.line)
        with pytest.raises(FileFormatError) as caught:
            _chunked(table, cuts, unordered, duplicates)
        assert caught.value.line in lines, (caught.value.line, lines)
        return
    got, got_moved, got_merged = _chunked(table, cuts, unordered, duplicates)
    np.testing.assert_array_equal(got.times, whole.times)
    np.testing.assert_array_equal(got.values, whole.values)
    np.testing.assert_array_equal(got.line_numbers(), whole.line_numbers())
    assert (got_moved, got_merged) == (moved, merged_away)


@pytest.mark.parametrize("chunk", [1, 3, 1000])
def test_rows_in_chunks_are_the_rows_read_whole_with_their_lines(tmp_path, chunk) -> None:
    path = tmp_path / "s.txt"
    path.write_text("# t x y\n0 1 2\n\n1 2 3\n# note\n  \n2 3 4\n3 4 5\n# end\n")
    layout = sniff(path)
    t, x, lines = read_columns(path, layout, [0, 1, 2])
    parts = list(iter_rows(path, layout, [0, 1, 2], chunk_rows=chunk))
    np.testing.assert_array_equal(np.concatenate([p[0] for p in parts]), t)
    np.testing.assert_array_equal(np.concatenate([p[1] for p in parts]), x)
    got = np.concatenate([np.atleast_1d(p[2]) if not isinstance(p[2], int) else p[2] + np.arange(len(p[0]))
                          for p in parts])
    assert got.tolist() == lines.tolist() == [2, 4, 7, 8]


def test_stream_table_reads_times_as_read_table_does(tmp_path) -> None:
    path = tmp_path / "clock.csv"
    t = 1_700_000_000_000 + np.arange(1000) * 7
    np.savetxt(path, np.c_[t, np.sin(t / 1e4)], delimiter=",", header="t,x", comments="", fmt="%d,%.6f")
    whole = read_table(path)
    stream = stream_table(path, "csv", chunk_rows=64)
    blocks = list(stream.blocks)
    np.testing.assert_array_equal(np.concatenate([b.times for b in blocks]), whole.times)
    assert stream.notes == whole.notes


def test_a_time_column_that_changes_unit_midway_is_named_by_its_line(tmp_path) -> None:
    path = tmp_path / "mixed.csv"
    path.write_text("t,x\n" + "".join(f"{i * 0.01:.2f},{i}\n" for i in range(100))
                    + "".join(f"{1_700_000_000_000 + i},{i}\n" for i in range(100)))
    stream = stream_table(path, "csv", chunk_rows=100)
    with pytest.raises(FileFormatError) as caught:
        list(stream.blocks)
    assert caught.value.line == 102 and "time column" in str(caught.value)
