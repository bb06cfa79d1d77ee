"""The project's SQLite database: its tables, how it is opened, and what a damaged
one raises while read.

Tables (every save is one transaction):

* ``meta``: the format name and version, and how checksums are made;
* ``documents``: the scene and the tracks as a versioned JSON document
  (:mod:`.document`);
* ``takes``: every track's raw takes, samples as little-endian float64 blobs;
* ``journal``: the samples of the take being recorded (:mod:`.journal`);
* ``checksums``: a digest of the document and of every take (:mod:`.checksums`).
"""

from __future__ import annotations

import json
import os
import sqlite3
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from urllib.parse import quote

import numpy as np

from sketchanim.errors import FileFormatError

FORMAT = "sketchanim-project"
FORMAT_VERSION = 1
#: Most samples in one take (a hostile file cannot make a reader allocate more).
MAX_TAKE_SAMPLES = 50_000_000

CREATE_TABLES = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS documents (name TEXT PRIMARY KEY, body TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS takes (id INTEGER PRIMARY KEY, mode TEXT NOT NULL, blend REAL NOT NULL,
    dim INTEGER NOT NULL, n INTEGER NOT NULL, times BLOB NOT NULL, vals BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS journal (seq INTEGER PRIMARY KEY, started REAL NOT NULL, path TEXT NOT NULL,
    n INTEGER NOT NULL, times BLOB NOT NULL, vals NOT NULL);
CREATE TABLE IF NOT EXISTS checksums (name TEXT PRIMARY KEY, digest TEXT NOT NULL);
"""
#: The columns of each table, as CREATE_TABLES makes them (a file with others is not ours).
COLUMNS = {"meta": ("key", "value"), "documents": ("name", "body"),
           "takes": ("id", "mode", "blend", "dim", "n", "times", "vals"),
           "journal": ("seq", "started", "path", "n", "times", "vals"), "checksums": ("name", "digest")}


def connect(path: Path, read_only: bool = False, *, wal: bool = True) -> sqlite3.Connection:
    """A connection to the project database at ``path`` (autocommit: transactions are
    begun explicitly), in write-ahead-log mode with ``wal``; read-only opens write nothing.

    >>> import tempfile
    >>> db = connect(Path(tempfile.mkdtemp()) / "p.sketchanim")
    >>> db.execute("PRAGMA journal_mode").fetchone()[0]
    'wal'
    >>> db.close()
    """
    if read_only:
        # immutable: no lock, no -shm, nothing written (read-only media); a left-over
        # write-ahead log needs a normal read-only open to be read
        wal = Path(f"{path}-wal")
        flag = "mode=ro" if wal.exists() and wal.stat().st_size else "immutable=1"
        uri = f"file:{quote(str(path.resolve()))}?{flag}"
        return sqlite3.connect(uri, uri=True, timeout=10, check_same_thread=False, isolation_level=None)
    db = sqlite3.connect(path, timeout=10, check_same_thread=False, isolation_level=None)
    if wal:
        use_wal(db)
    return db


def use_wal(db: sqlite3.Connection) -> None:
    """Write-ahead logging (a project's mode: readers never wait for the journal)."""
    db.execute("PRAGMA journal_mode=WAL")
    db.execute("PRAGMA synchronous=NORMAL")


def writable(path: Path) -> bool:
    """Whether a project at ``path`` can be written: the file and its folder."""
    folder = path.parent if str(path.parent) else Path(".")
    return os.access(folder, os.W_OK) and (not path.exists() or os.access(path, os.W_OK))


@contextmanager
def reading(source: str, what: str) -> Iterator[None]:
    """Turn what a damaged database raises while read into a :class:`FileFormatError`."""
    try:
        yield
    except (sqlite3.DatabaseError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise FileFormatError(source, f"{what} ({type(err).__name__}: {err})") from None


def floats(blob: object, count: int, where: str, source: str) -> np.ndarray:
    """The ``count`` finite little-endian float64 values in ``blob``; a
    :class:`FileFormatError` naming ``where`` in the file ``source`` otherwise.

    >>> floats(np.arange(2.0).tobytes(), 2, "take 0", "p.sketchanim").tolist()
    [0.0, 1.0]
    """
    if not isinstance(blob, bytes) or len(blob) != 8 * count:
        raise FileFormatError(source, f"{where}: expected {count} float64 values")
    x = np.frombuffer(blob, dtype="<f8").astype(float)
    if not np.all(np.isfinite(x)):
        raise FileFormatError(source, f"{where}: holds a non-finite number")
    return x


