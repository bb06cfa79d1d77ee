"""The journal: the samples of the take being recorded, committed batch by batch to
the project's ``journal`` table while the recorder runs, so that a crash loses at most
the last batch; a take still in the journal when the project is opened is read back by
:func:`journaled_take` (see :mod:`.recovery`).
"""

from __future__ import annotations

import json
import sqlite3
import threading
import time
from pathlib import Path

import numpy as np

from sketchanim.errors import FileFormatError, load_json
from sketchanim.project.database import MAX_TAKE_SAMPLES, connect, floats, reading


class Journal:
    """Commits the batches of samples the recorder hands it to the project's ``journal``
    table, one transaction per call (its own connection; called from the recorder's
    journal thread). Numbers go in as float64 blobs, discrete values as JSON."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.started = time.time()
        self._db: sqlite3.Connection | None = None
        self._lock = threading.Lock()

    def __call__(self, batches: list[tuple[str, np.ndarray, object]]) -> None:
        """Commit ``batches`` (path, times, values) as one transaction."""
        rows = [(self.started, path, len(times), np.asarray(times, "<f8").tobytes(),
                 np.asarray(values, "<f8").tobytes() if isinstance(values, np.ndarray) else json.dumps(list(values)))
                for path, times, values in batches]
        with self._lock:
            if self._db is None:
                self._db = connect(self.path)
            with self._db:
                self._db.execute("BEGIN")
                self._db.executemany("INSERT INTO journal (started, path, n, times, vals) VALUES (?, ?, ?, ?, ?)",
                                     rows)

    def close(self) -> None:
        """Close the journal's connection (the rows stay until the project is saved)."""
        with self._lock:
            if self._db is not None:
                self._db.close()
                self._db = None


def journaled_take(db: sqlite3.Connection, source: str) -> dict[str, tuple[np.ndarray, list | np.ndarray]]:
    """The samples of the last take in the ``journal`` table of the project database
    ``db`` (the file ``source``): path -> (times, values), or empty;
    :class:`FileFormatError` naming a damaged batch."""
    out: dict[str, tuple[list, list]] = {}
    with reading(source, "unreadable journal"):
        rows = db.execute("SELECT seq, path, n, times, vals FROM journal "
                               "WHERE started = (SELECT max(started) FROM journal) ORDER BY seq").fetchall()
        for seq, path, n, times, vals in rows:
            if not isinstance(n, int) or not 0 < n <= MAX_TAKE_SAMPLES:
                raise FileFormatError(source, f"journal batch {seq}: bad size {n!r}")
            ts, xs = out.setdefault(path, ([], []))
            where = f"journal batch {seq}"
            ts.append(floats(times, n, where, source))
            if isinstance(vals, bytes):
                dim = len(vals) // (8 * n)
                xs.append(floats(vals, n * max(dim, 1), where, source).reshape(n, -1))
            else:
                values = load_json(vals, source)
                if not isinstance(values, list) or len(values) != n:
                    raise FileFormatError(source, f"{where}: expected a list of {n} values")
                xs.append(values)
    for p, (ts, xs) in out.items():
        kinds = {x.shape[1] if isinstance(x, np.ndarray) else "json" for x in xs}
        if len(kinds) > 1:
            raise FileFormatError(source, f"journal: the batches of {p!r} disagree on their values ({kinds})")
    return {p: (np.concatenate(ts), np.vstack(xs) if isinstance(xs[0], np.ndarray) else sum(xs, []))
            for p, (ts, xs) in out.items()}
