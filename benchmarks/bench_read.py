"""Reading large sample tables: peak memory and time of the table reader (pandas' C
parser in chunks into arrays allocated once) against numpy's ``loadtxt``, and of
streaming the same file chunk by chunk into the incremental reducer.

Each measurement runs in its own process, so its peak resident memory (``ru_maxrss``)
is its own; "above start" subtracts the process's memory after its imports.
Run ``.venv/bin/python benchmarks/bench_read.py [--rows 10000000] [--stream-rows N]``;
figures are one run on this machine: quote them with the ratios from the same run.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

CACHE = Path(__file__).resolve().parents[1] / ".cache" / "bench_read"


def table_file(rows: int) -> Path:
    """A CSV of ``rows`` samples at 1 kHz: t, x, y, z (a smooth path with noise), made once."""
    path = CACHE / f"take_{rows}.csv"
    if path.exists():
        return path
    CACHE.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(0)
    tmp = path.with_suffix(".tmp")
    with tmp.open("w") as out:
        out.write("t,x,y,z\n")
        for a in range(0, rows, 1_000_000):
            t = np.arange(a, min(a + 1_000_000, rows)) / 1000.0
            x = np.c_[np.sin(0.3 * t), np.cos(0.2 * t), 0.01 * t] + rng.normal(0, 1e-4, (len(t), 3))
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--rows", type=int, default=10_000_000)
    parser.add_argument("--stream-rows", type=int, default=None, help="rows streamed into the reducer (default: --rows)")
    parser.add_argument("--no-loadtxt", action="store_true", help="skip numpy's loadtxt (slow on 10M rows)")
    args = parser.parse_args()
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
