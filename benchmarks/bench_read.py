"""Reading and reducing large sample tables: peak memory and time of the table reader
(pandas' C parser in chunks into arrays allocated once) against numpy's ``loadtxt``, of
streaming the same file chunk by chunk into the incremental reducer, and of
``reduce_table`` end to end (what ``sketchanim reduce TABLE --method incremental -o
OUT.json`` runs) at several row counts.

End to end, per row count: the table read whole then reduced (the path a table takes
when something needs every sample at once), reduced while read (the path the
incremental method takes on a text table), and, with ``--baseline-src``, the whole
``reduce_table`` of another source tree (an older commit's ``src``, e.g. from ``git
archive COMMIT src | tar -x -C DIR``). Row counts above ``--file-max`` are not written
to disk: generated blocks of the same take, as many rows a block as the reader's chunks,
are fed to :func:`sketchanim.pipeline.table_stream.reduce_streamed`, which measures
everything but the text parsing (the reader's own row, above, gives the parsing's
cost).

Each measurement runs in its own process, so its peak resident memory (``ru_maxrss``)
is its own; "above start" subtracts the process's memory after its imports and a
warm-up reduction (numba's cached kernels loaded).
Run ``.venv/bin/python benchmarks/bench_read.py [--rows 10000000] [--stream-rows N]
[--e2e-rows 1000000,10000000,100000000] [--baseline-src DIR]``; figures are one run on
this machine: quote them with the ratios from the same run.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

REPO = Path(__file__).resolve().parents[1]
CACHE = Path(os.environ.get("SKETCHANIM_BENCH_CACHE", REPO / ".cache" / "bench_read"))
#: Rows per generated block (the take of :func:`take_blocks`): the reader's chunk
#: (``sketchanim.formats.csvio.CHUNK_ROWS``), so that generated rows are reduced in the
#: blocks a file's rows are (the take is the same whatever the block).
BLOCK = 1 << 18


def take_blocks(rows: int):
    """The benchmark's take, ``rows`` samples at 1 kHz (t, x, y, z: a smooth path with
    noise of 1e-4), a block of :data:`BLOCK` rows at a time, as the CSV holds them
    (rounded as it writes them)."""
    rng = np.random.default_rng(0)
    for a in range(0, rows, BLOCK):
        t = np.arange(a, min(a + BLOCK, rows)) / 1000.0
        x = np.c_[np.sin(0.3 * t), np.cos(0.2 * t), 0.01 * t] + rng.normal(0, 1e-4, (len(t), 3))
        yield np.round(t, 3), np.round(x, 6)


def table_file(rows: int) -> Path:
    """A CSV of the take (:func:`take_blocks`), made once."""
    path = CACHE / f"take_{rows}.csv"
    if path.exists():
        return path
    CACHE.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    with tmp.open("w") as out:
        out.write("t,x,y,z\n")
        for t, x in take_blocks(rows):
            np.savetxt(out, np.c_[t, x], fmt="%.3f,%.6f,%.6f,%.6f")
    tmp.replace(path)
    return path


def measure(kind: str, path: Path) -> dict:
    """Run one measurement in a fresh process; its time, peak memory and row count."""
    code = f"""
import json, resource, time, numpy as np
from sketchanim.formats.csvio import read_samples_csv, iter_columns, sniff
from sketchanim.reducer import StreamReducer
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
clock = time.perf_counter()
path = {str(path)!r}
if {kind!r} == "reader":
    table = read_samples_csv(path); rows = len(table.times)
elif {kind!r} == "loadtxt":
    data = np.loadtxt(path, delimiter=",", skiprows=1); rows = len(data)
else:
    stream = StreamReducer(3, 1e-3); rows = 0
    for block in iter_columns(path, sniff(path), [0, 1, 2, 3]):
        stream.extend(block[:, 0], block[:, 1:]); rows += len(block)
    stream.close()
seconds = time.perf_counter() - clock
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({{"rows": rows, "seconds": seconds, "peak_mb": peak / 1024, "above_mb": (peak - base) / 1024}}))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


#: Tolerance of the end-to-end reductions (10 times the take's noise).
TOL = 1e-3

E2E = """
import json, resource, sys, time, tempfile, pathlib, numpy as np
from sketchanim.pipeline import TableOptions, reduce_table
kind, path, rows, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
options = TableOptions(tol={tol}, method="incremental")
warm = pathlib.Path(tempfile.mkdtemp()) / "warm.csv"
t = np.linspace(0, 4, 2000)
np.savetxt(warm, np.c_[t, np.sin(t), np.cos(t), t], delimiter=",", header="t,x,y,z", comments="")
reduce_table(warm, options)
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
clock = time.perf_counter()
if kind == "whole":
    import sketchanim.pipeline.table as table
    table._streams = lambda *args: False
if kind == "generated":
    from sketchanim.formats.csvio import SampleTable
    from sketchanim.formats.tables import TableStream
    from sketchanim.pipeline.table_stream import reduce_streamed
    sys.path.insert(0, {bench!r})
    from bench_read import take_blocks
    blocks = (SampleTable(t, x, ["x", "y", "z"], 2 + i * {block}) for i, (t, x) in enumerate(take_blocks(rows)))
    done = reduce_streamed(TableStream(["x", "y", "z"], (), ("generated",), blocks), options, "generated",
                           [[0, 1, 2]], [np.full(3, {tol})], [])
    reduction, n = done.reductions[0], done.rows
else:
    result = reduce_table(path, options, output=out)
    reduction, n = result.reductions[0], len(result.table.times) if result.table is not None else result.rows
seconds = time.perf_counter() - clock
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({{"rows": n, "seconds": seconds, "peak_mb": peak / 1024, "above_mb": (peak - base) / 1024,
                  "coefficients": reduction.n_coefficients, "max_error": float(reduction.max_error.max())}}))
""".format(tol=TOL, bench=str(Path(__file__).resolve().parent), block=BLOCK)


def measure_e2e(kind: str, rows: int, src: Path) -> dict:
    """One end-to-end reduction in a fresh process with ``src`` first on its path."""
    path = "" if kind == "generated" else str(table_file(rows))
    out = CACHE / f"out_{kind}_{rows}.json"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(src), os.environ.get("PYTHONPATH", "")]))
    run = subprocess.run([sys.executable, "-c", E2E, kind, path, str(rows), str(out)], capture_output=True,
                         text=True, env=env)
    if run.returncode:
        raise SystemExit(f"{kind} at {rows} rows failed:\n{run.stderr}")
    return json.loads(run.stdout.strip().splitlines()[-1])


def end_to_end(rows: list[int], file_max: int, whole_max: int, baseline: Path | None, baseline_max: int) -> None:
    """The end-to-end table: seconds and peak memory per path and row count."""
    src = REPO / "src"
    table = Table(title=f"reduce_table end to end, method incremental, tol {TOL:g} (t, x, y, z at 1 kHz)")
    for column in ("rows", "path", "seconds", "rows/s", "peak MB", "above start MB", "control points",
                   "max error / tol", "time vs read whole", "time vs baseline"):
        table.add_column(column, justify="left" if column == "path" else "right")
    for n in rows:
        runs = []
        if n <= file_max:
            if baseline is not None and n <= baseline_max:
                runs.append(("baseline: its reduce_table", "baseline", baseline))
            if n <= whole_max:
                runs.append(("read whole, then reduced", "whole", src))
            runs.append(("reduced while read", "streamed", src))
        else:
            runs.append(("generated blocks, reduced (no parsing)", "generated", src))
        results = {}
        for label, kind, where in runs:
            r = results[kind] = measure_e2e("streamed" if kind == "baseline" else kind, n, where)
            whole = results.get("whole")
            base = results.get("baseline")
            table.add_row(f"{n:,}", label, f"{r['seconds']:.1f}", f"{r['rows'] / r['seconds']:,.0f}",
                          f"{r['peak_mb']:.0f}", f"{r['above_mb']:.0f}", f"{r['coefficients']:,}",
                          f"{r['max_error'] / TOL:.3f}",
                          f"{whole['seconds'] / r['seconds']:.2f}x" if whole and kind != "whole" else "",
                          f"{base['seconds'] / r['seconds']:.2f}x" if base and kind != "baseline" else "")
    Console(width=160).print(table)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--rows", type=int, default=10_000_000)
    parser.add_argument("--stream-rows", type=int, default=None, help="rows streamed into the reducer (default: --rows)")
    parser.add_argument("--no-loadtxt", action="store_true", help="skip numpy's loadtxt (slow on 10M rows)")
    parser.add_argument("--no-read", action="store_true", help="only the end-to-end table")
    parser.add_argument("--e2e-rows", default="1000000,10000000",
                        help="row counts of the end-to-end table, comma-separated (e.g. 1000000,10000000,100000000)")
    parser.add_argument("--file-max", type=int, default=10_000_000,
                        help="larger row counts are generated blocks, not a CSV written to disk")
    parser.add_argument("--whole-max", type=int, default=10_000_000, help="largest table read whole")
    parser.add_argument("--baseline-src", type=Path, default=None,
                        help="another tree's src folder whose reduce_table is measured too")
    parser.add_argument("--baseline-max", type=int, default=10_000_000, help="largest table the baseline reduces")
    args = parser.parse_args()
    if not args.no_read:
        read_tables(args)
    end_to_end([int(r) for r in args.e2e_rows.split(",") if r], args.file_max, args.whole_max, args.baseline_src,
               args.baseline_max)


def read_tables(args: argparse.Namespace) -> None:
    """The reader's table: reader, loadtxt and the bare stream on one file."""
    path = table_file(args.rows)
    runs = [("table reader (pandas, chunked)", "reader", path)]
    if not args.no_loadtxt:
        runs.append(("numpy loadtxt (whole file)", "loadtxt", path))
    runs.append(("streamed into StreamReducer", "stream", table_file(args.stream_rows or args.rows)))
    table = Table(title=f"reading {path.name} ({path.stat().st_size / 2**20:.0f} MiB): t, x, y, z")
    for column in ("what", "rows", "seconds", "rows/s", "peak MB", "above start MB", "bytes/row above start"):
        table.add_column(column, justify="left" if column == "what" else "right")
    results = {}
    for label, kind, file in runs:
        r = results[kind] = measure(kind, file)
        table.add_row(label, f"{r['rows']:,}", f"{r['seconds']:.1f}", f"{r['rows'] / r['seconds']:,.0f}",
                      f"{r['peak_mb']:.0f}", f"{r['above_mb']:.0f}", f"{r['above_mb'] * 2**20 / r['rows']:.0f}")
    Console(width=140).print(table)
    if "loadtxt" in results:
        print(f"loadtxt / reader: time {results['loadtxt']['seconds'] / results['reader']['seconds']:.2f}, memory above "
              f"start {results['loadtxt']['above_mb'] / max(results['reader']['above_mb'], 1):.2f}; the reader's "
              f"numbers alone are {results['reader']['rows'] * 4 * 8 / 2**20:.0f} MB")


if __name__ == "__main__":
    main()
