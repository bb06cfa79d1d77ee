"""Tables reduced while they are read (the incremental method on a text table): the
same curves as the table read whole, the tolerance kept at every row, errors that name
the line of a bad row however deep in the file, and real recordings."""

from __future__ import annotations

import gc
import tracemalloc
from functools import partial
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import sketchanim.pipeline.table as table_module
from sketchanim.errors import InputError
from sketchanim.formats.csvio import SampleTable
from sketchanim.formats.tables import TableStream, stream_table
from sketchanim.motion import continuous_quaternions
from sketchanim.pipeline import TableOptions, reduce_table
from sketchanim.pipeline.table import TableReduction
from sketchanim.pipeline import table_stream
from sketchanim.pipeline.table_stream import reduce_streamed


def _write(path: Path, header: str, rows: np.ndarray, fmt: str = "%.9g", delimiter: str = ",") -> Path:
    np.savetxt(path, rows, delimiter=delimiter, header=header, comments="", fmt=fmt)
    return path


def _both(monkeypatch: pytest.MonkeyPatch, path: Path, options: TableOptions, chunk: int, **outputs: Path
          ) -> tuple[TableReduction, TableReduction]:
    """The table reduced while read (in chunks of ``chunk`` rows) and read whole."""
    with monkeypatch.context() as m:
        m.setattr(table_module, "stream_table", partial(stream_table, chunk_rows=chunk))
        streamed = reduce_table(path, options, **outputs)
    with monkeypatch.context() as m:
        m.setattr(table_module, "_streams", lambda *args: False)
        whole = reduce_table(path, options)
    assert streamed.streamed and not whole.streamed
    return streamed, whole


def _same(a: TableReduction, b: TableReduction) -> None:
    """The same curves, features, counts and (to rounding) errors."""
    assert (a.channels, a.notes, a.rows, a.span, a.parts) == (b.channels, b.notes, b.rows, b.span, b.parts)
    assert (a.moved, a.merged_away, a.rotation_columns) == (b.moved, b.merged_away, b.rotation_columns)
    for x, y in zip(a.reductions + ((a.rotation,) if a.rotation else ()),
                    b.reductions + ((b.rotation,) if b.rotation else ()), strict=True):
        np.testing.assert_array_equal(x.columns.t, y.columns.t)
        np.testing.assert_array_equal(x.columns.c, y.columns.c)
        assert x.features == y.features and x.n_samples == y.n_samples and x.metric == y.metric
        assert {k: v for k, v in x.report.items()} == y.report
        np.testing.assert_allclose(x.max_error, y.max_error, rtol=1e-9, atol=1e-15)


def _steps(rng: np.random.Generator, n: int) -> np.ndarray:
    """A noisy path with a few jumps (pen lifts), 3 channels."""
    t = np.arange(n) / 100.0
    x = np.c_[np.sin(t), np.cos(0.7 * t), 0.2 * t] + rng.normal(0, 2e-4, (n, 3))
    for j in rng.integers(5, n - 5, 3):
        x[j:, rng.integers(0, 3)] += rng.choice([-1.0, 1.0])
    return np.c_[t, x]


@pytest.mark.parametrize("chunk", [1, 2, 37, 100_000])
def test_streamed_is_the_table_read_whole(tmp_path, monkeypatch, chunk) -> None:
    rows = _steps(np.random.default_rng(chunk), 1500)
    path = _write(tmp_path / "s.csv", "t,x,y,z", rows)
    a, b = _both(monkeypatch, path, TableOptions(tol=1e-3, method="incremental"), chunk)
    _same(a, b)
    assert [f.kind for f in a.reductions[0].features].count("jump") >= 1


def test_quirks_groups_and_outputs_streamed_as_read_whole(tmp_path, monkeypatch) -> None:
    rows = _steps(np.random.default_rng(5), 1200)
    rows = np.insert(rows, 300, rows[299], axis=0)                   # an exact duplicate
    twin = rows[600].copy()
    twin[1] += 0.5
    rows = np.insert(rows, 601, twin, axis=0)                        # one time, two values
    late = rows[900].copy()
    late[0] -= 0.5
    rows = np.insert(rows, 901, late, axis=0)                        # time going back
    path = _write(tmp_path / "q.csv", "t,x,y,z", rows)
    options = TableOptions(tol=(1e-3, 1e-3, 5e-3), method="incremental", groups="x,y:z", unordered="drop",
                           duplicates="mean")
    a, b = _both(monkeypatch, path, options, 64, output=tmp_path / "q.json")
    _same(a, b)
    assert (a.moved, a.merged_away, a.reductions[0].report["duplicates_dropped"]) == (1, 1, 1)
    assert [w.path.name for w in a.written] == ["q.json", "q.z.json"]


@pytest.mark.parametrize("mode", ["quaternion", "euler"])
def test_a_trajectory_with_its_orientation_streamed_as_read_whole(tmp_path, monkeypatch, mode) -> None:
    rng = np.random.default_rng(2)
    n = 1500
    t = 1.7e9 + np.arange(n) / 200.0                                 # a wall clock, in seconds
    q = continuous_quaternions(np.c_[0.3 * np.sin(t / 3), 0.1 * np.cos(t), 0.2 * np.sin(t / 2), np.ones(n)])
    q *= np.where(rng.random(n) < 0.3, -1.0, 1.0)[:, None]            # signs as trackers write them
    rows = np.c_[t, np.sin(t / 4), np.cos(t / 5), 0.01 * t % 1, q]
    path = _write(tmp_path / "gt.txt", "# timestamp tx ty tz qx qy qz qw", rows, fmt="%.9f", delimiter=" ")
    options = TableOptions(tol=1e-3, method="incremental", rot_mode=mode, rot_tol_deg=0.2)
    a, b = _both(monkeypatch, path, options, 50, output=tmp_path / "gt.json")
    _same(a, b)
    assert a.notes[0] == "TUM trajectory" and a.rotation is not None


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 400), chunk=st.integers(1, 120),
       jumps=st.integers(0, 4), tol=st.sampled_from([1e-4, 1e-3, 1e-2]))
def test_property_streamed_keeps_every_row_and_equals_the_whole(tmp_path_factory, seed, n, chunk, jumps, tol) -> None:
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.001, 0.02, n))
    x = np.cumsum(rng.normal(0, 3 * tol, (n, 2)), axis=0)
    for j in rng.integers(0, n, jumps):
        x[j:] += rng.normal(0, 50 * tol, 2)
    path = _write(tmp_path_factory.mktemp("p") / "p.csv", "t,x,y", np.c_[t, x], fmt="%.17g")
    with pytest.MonkeyPatch.context() as monkeypatch:
        a, b = _both(monkeypatch, path, TableOptions(tol=tol, method="incremental"), chunk)
    _same(a, b)
    r = a.reductions[0]
    err = np.abs(r.columns(t) - x).max(axis=0)
    assert np.all(err <= tol * (1 + 1e-9)), err / tol
    assert a.rows == n and a.span == (t[0], t[-1])


def _big(path: Path, n: int, comments: tuple[int, ...] = ()) -> list[str]:
    """A table of ``n`` rows (as text lines, header first), comment lines before rows ``comments``."""
    t = np.arange(n) / 1000.0
    body = np.char.add(np.char.add(np.char.mod("%.3f", t), ","), np.char.mod("%.6f", np.sin(t)))
    lines = ["t,x"] + body.tolist()
    for k, row in enumerate(sorted(comments)):
        lines.insert(1 + row + k, "# a note")
    return lines


@pytest.mark.parametrize(("bad", "field"), [("0.5,oops", "column 2 is not a number: 'oops'"),
                                              ("0.1,1.0", "time goes backwards")])
def test_a_bad_row_deep_in_a_big_file_is_named_by_its_line(tmp_path, bad, field) -> None:
    n, at = 300_000, 270_000
    lines = _big(tmp_path, n, comments=(10, 150_000))
    lines[at] = bad                                                  # line at + 1 of the file
    path = tmp_path / "big.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as caught:
        reduce_table(path, TableOptions(tol=1e-3, method="incremental"))
    message = str(caught.value)
    assert f"line {at + 1}" in message and field in message and str(path) in message


def test_a_refused_sample_deep_in_the_stream_is_named_by_its_line(tmp_path) -> None:
    lines = _big(tmp_path, 100_000, comments=(5,))
    lines[90_001] = "89.999,1e300"                                   # row 89999, beyond any curve's reach
    path = tmp_path / "far.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as caught:
        reduce_table(path, TableOptions(tol=1e-3, method="incremental"))
    assert f"{path}, line 90002:" in str(caught.value)


def test_streamed_tables_say_so_and_whole_ones_are_kept(tmp_path) -> None:
    path = _write(tmp_path / "s.csv", "t,x", np.c_[np.linspace(0, 1, 50), np.linspace(0, 1, 50) ** 2])
    assert reduce_table(path, TableOptions(tol=1e-3, method="incremental")).table is None
    for options, plot in ((TableOptions(tol=1e-3), None), (TableOptions(tol=1e-3, method="incremental"),
                                                           tmp_path / "s.png"),
                          (TableOptions(tol=1e-3, method="incremental", unordered="sort"), None)):
        result = reduce_table(path, options, plot=plot)
        assert result.table is not None and result.rows == 50


def test_real_trajectory_streamed_as_read_whole(data_dir, monkeypatch) -> None:
    path = data_dir / "camera" / "freiburg1_xyz-groundtruth.txt"
    if not path.exists():
        pytest.skip(f"{path} not found")
    a, b = _both(monkeypatch, path, TableOptions(tol=5e-3, method="incremental", rot_tol_deg=0.5), 211)
    _same(a, b)
    assert a.rows > 1000 and np.all(a.reductions[0].max_error <= 5e-3)


def _take_block(rows: int) -> SampleTable:
    """bench_read's take (t, x, y, z at 1 kHz, a smooth path with noise of 1e-4) as one block."""
    t = np.arange(rows) / 1000.0
    x = np.c_[np.sin(0.3 * t), np.cos(0.2 * t), 0.01 * t] + np.random.default_rng(0).normal(0, 1e-4, (rows, 3))
    return SampleTable(np.round(t, 3), np.round(x, 6), ["x", "y", "z"], 2)


def _traced_peak(block: SampleTable) -> int:
    """Peak of the Python allocations (numpy's included) while ``block`` is reduced
    through :func:`reduce_streamed`, above what was allocated before (the block itself)."""
    options = TableOptions(tol=1e-3, method="incremental")
    gc.collect()
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        done = reduce_streamed(TableStream(["x", "y", "z"], (), ("generated",), iter([block])), options, "generated",
                               [[0, 1, 2]], [np.full(3, 1e-3)], [])
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    assert done.rows == len(block.times) and done.within
    return peak


def test_streamed_memory_is_flat_in_the_rows_whatever_the_blocks(monkeypatch) -> None:
    """A source that yields big blocks (bench_read's generated rows, 1M a block) is
    reduced a reader's chunk (``CHUNK_ROWS``) at a time: the peak of what the reduction
    allocates stays that of a chunk and of the curve, flat from N to 4N rows given as one
    block. (Before, every pass over a block allocated in proportion to its rows, and the
    feature detector's store kept twice the largest block: 22 MB more from 20,000 to
    80,000 rows; now 20 kB.) The bound is on traced allocations, not on resident memory,
    so it is the same on a loaded machine; the curve's own growth over the 60,000 rows is
    about 12 kB, and a chunk's work is the same for both sizes."""
    monkeypatch.setattr(table_stream, "CHUNK_ROWS", 4096, raising=False)   # the reader's chunk, small
    _traced_peak(_take_block(5_000))                              # kernels loaded, caches warm
    small, large = (_traced_peak(_take_block(n)) for n in (20_000, 80_000))
    assert large - small < 1_000_000, (small, large)
