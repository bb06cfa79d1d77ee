"""Project files: one SQLite database (WAL) per project.

Tables:

* ``meta``: the format name and version;
* ``documents``: the scene and the tracks as versioned JSON documents, validated with
  pydantic when loaded (:class:`ProjectDoc`);
* ``takes``: every track's raw takes, samples as little-endian float64 blobs;
* ``journal``: the samples of the take being recorded, committed batch by batch by
  :class:`Journal` while the recorder runs, so that a crash loses at most the last
  batch; a take still in the journal when a project is opened is offered back by
  :meth:`Project.recovered`.

* ``checksums``: a digest (BLAKE2b) of the document and of every take, written in the
  save's transaction and checked on load, so that a damaged page is refused by name
  (:meth:`Project.salvage` keeps what is undamaged). A project saved before checksums
  (no ``checksums`` key in ``meta``) loads unchecked and gets them on its next save.

Every save is one transaction. Loading rejects what is not a project of ours, sizes
beyond the bounds below, values that do not fit their types, and damage, with a
:class:`~sketchanim.errors.FileFormatError` naming the file and what is wrong. Nothing
is unpickled; JSON and float blobs only. A project that cannot be written (read-only
media, or a read-only file) is opened read-only: it loads and exports, and a save says
why it cannot.
"""

from __future__ import annotations

import hashlib
import json
import os
import sqlite3
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import quote
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import DISCRETE, AttributeType
from sketchanim.anim.scene import KINDS, Scene
from sketchanim.anim.tracks import MODES, ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.errors import FileFormatError, InputError, load_json
from sketchanim.atomic import write_atomic

FORMAT = "sketchanim-project"
VERSION = 1
#: Bounds on what a file may hold (a hostile file cannot make a reader allocate more).
MAX_DOCUMENT_BYTES = 256 * 2**20
MAX_ITEMS = 10_000_000
MAX_TAKE_SAMPLES = 50_000_000
TYPE_NAMES = ("position", "orientation", "scale", "color", "intensity", "fov", "float", "vector") + DISCRETE

Number = Annotated[float, Field(allow_inf_nan=False)]
Name = Annotated[str, Field(min_length=1, max_length=64)]
Items = Field(max_length=MAX_ITEMS)


class _Doc(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=False)


class TypeDoc(_Doc):
    name: Literal[TYPE_NAMES]  # type: ignore[valid-type]
    dim: int = Field(ge=0, le=64)
    tol: Number = Field(ge=0)
    unit: str = Field(max_length=64)
    default: list[Number | bool | str | None] = Field(max_length=64)
    choices: list[Name] = Field(default_factory=list, max_length=1024)


class AttributeDoc(_Doc):
    name: Name
    type: TypeDoc
    value: list[Number] | bool | str | None


class ObjectDoc(_Doc):
    name: Name
    kind: Literal[tuple(KINDS)]  # type: ignore[valid-type]
    attributes: list[AttributeDoc] = Field(max_length=4096)


class CurveDoc(_Doc):
    path: str = Field(max_length=200)
    tol: Number = Field(gt=0)
    order: int = Field(ge=1, le=32)
    knots: list[Number] = Items
    coef: list[list[Number]] = Items
    takes: list[int] = Field(default_factory=list, max_length=100_000)


class StepsDoc(_Doc):
    path: str = Field(max_length=200)
    times: list[Number] = Items
    values: list[bool | str | None] = Items


class ProjectDoc(_Doc):
    """The scene and its tracks (a take's samples live in the ``takes`` table and are
    referenced by id)."""

    format: Literal["sketchanim-project"] = FORMAT
    version: Literal[1] = VERSION
    objects: list[ObjectDoc] = Field(max_length=100_000)
    curves: list[CurveDoc] = Field(max_length=100_000)
    steps: list[StepsDoc] = Field(max_length=100_000)


SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS documents (name TEXT PRIMARY KEY, body TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS takes (id INTEGER PRIMARY KEY, mode TEXT NOT NULL, blend REAL NOT NULL,
    dim INTEGER NOT NULL, n INTEGER NOT NULL, times BLOB NOT NULL, vals BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS journal (seq INTEGER PRIMARY KEY, started REAL NOT NULL, path TEXT NOT NULL,
    n INTEGER NOT NULL, times BLOB NOT NULL, vals NOT NULL);
CREATE TABLE IF NOT EXISTS checksums (name TEXT PRIMARY KEY, digest TEXT NOT NULL);
"""
#: The columns of each table, as SCHEMA makes them (a file with others is not ours).
COLUMNS = {"meta": ("key", "value"), "documents": ("name", "body"),
           "takes": ("id", "mode", "blend", "dim", "n", "times", "vals"),
           "journal": ("seq", "started", "path", "n", "times", "vals"), "checksums": ("name", "digest")}
#: The ``meta`` value saying the project carries checksums, and how they are made.
CHECKSUMS = "blake2b-128"


def _connect(path: Path, read_only: bool = False, *, wal: bool = True) -> sqlite3.Connection:
    if read_only:
        # immutable: no lock, no -shm, nothing written (read-only media); a left-over
        # write-ahead log needs a normal read-only open to be read
        wal = Path(f"{path}-wal")
        flag = "mode=ro" if wal.exists() and wal.stat().st_size else "immutable=1"
        uri = f"file:{quote(str(path.resolve()))}?{flag}"
        return sqlite3.connect(uri, uri=True, timeout=10, check_same_thread=False, isolation_level=None)
    db = sqlite3.connect(path, timeout=10, check_same_thread=False, isolation_level=None)
    if wal:
        _wal(db)
    return db


def _wal(db: sqlite3.Connection) -> None:
    """Write-ahead logging (a project's mode: readers never wait for the journal)."""
    db.execute("PRAGMA journal_mode=WAL")
    db.execute("PRAGMA synchronous=NORMAL")


def _writable(path: Path) -> bool:
    """Whether a project at ``path`` can be written: the file and its folder."""
    folder = path.parent if str(path.parent) else Path(".")
    return os.access(folder, os.W_OK) and (not path.exists() or os.access(path, os.W_OK))


def document_digest(body: str) -> str:
    """The checksum of a project document's text.

    >>> len(document_digest("{}"))
    32
    """
    return hashlib.blake2b(body.encode("utf-8"), digest_size=16).hexdigest()


def take_digest(i: object, mode: object, blend: object, dim: object, n: object, times: object, vals: object) -> str:
    """The checksum of one row of the ``takes`` table (every column).

    >>> take_digest(0, "replace", 0.1, 1, 2, b"a", b"b") == take_digest(0, "replace", 0.1, 1, 2, b"a", b"c")
    False
    """
    h = hashlib.blake2b(digest_size=16)
    h.update(repr((i, mode, blend, dim, n)).encode("utf-8"))
    for blob in (times, vals):
        data = blob if isinstance(blob, bytes) else repr(blob).encode("utf-8")
        h.update(len(data).to_bytes(8, "little"))
        h.update(data)
    return h.hexdigest()


@dataclass
class Salvaged:
    """What :meth:`Project.salvage` kept of a damaged project.

    Attributes
    ----------
    scene : Scene
        The scene (empty if its document is damaged).
    tracks : dict
        Its tracks, each with its undamaged takes (none if the document is damaged).
    takes : dict
        Every undamaged take by its id, those of no track included.
    damaged : list of str
        What was left out, and why.
    """

    scene: Scene
    tracks: dict[str, Track]
    takes: dict[int, Take]
    damaged: list[str] = field(default_factory=list)


@contextmanager
def _reading(source: str, what: str) -> Iterator[None]:
    """Turn what a damaged database raises while read into a :class:`FileFormatError`."""
    try:
        yield
    except (sqlite3.DatabaseError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise FileFormatError(source, f"{what} ({type(err).__name__}: {err})") from None


def _floats(blob: object, count: int, where: str, source: str) -> np.ndarray:
    if not isinstance(blob, bytes) or len(blob) != 8 * count:
        raise FileFormatError(source, f"{where}: expected {count} float64 values")
    x = np.frombuffer(blob, dtype="<f8").astype(float)
    if not np.all(np.isfinite(x)):
        raise FileFormatError(source, f"{where}: holds a non-finite number")
    return x


class Project:
    """A project file: create or open it, save and load the scene and its tracks.

    Examples
    --------
    >>> import tempfile
    >>> from sketchanim.anim.attributes import POSITION
    >>> path = Path(tempfile.mkdtemp()) / "demo.sketchanim"
    >>> scene = Scene(); _ = scene.add("box")
    >>> t = np.linspace(0, 1, 5)
    >>> curve = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> take = Take(t, np.c_[t, 2 * t, 3 * t])
    >>> with Project(path) as project:
    ...     project.save(scene, {"box.position": ContinuousTrack("box.position", POSITION, curve, 0.005, (take,))})
    >>> with Project(path) as project:
    ...     scene2, tracks = project.load()
    >>> tracks["box.position"].evaluate([0.5]).tolist(), tracks["box.position"].takes[0].times.tolist() == t.tolist()
    ([[0.5, 1.0, 1.5]], True)
    """

    def __init__(self, path: str | os.PathLike[str], *, create: bool = True, read_only: bool | None = None) -> None:
        self.path = Path(path)
        source = str(self.path)
        exists = self.path.exists()
        if not exists and not create:
            raise FileFormatError(source, "no such project file")
        if exists:
            with _reading(source, "cannot read"), open(self.path, "rb") as handle:
                head = handle.read(16)
            if head != b"SQLite format 3\x00" and (head or not create):
                raise FileFormatError(source, "not a project file (" + (
                    "an empty file" if not head else "not an SQLite database") + ")")
        #: Opened read-only (asked for, or the file or its folder cannot be written).
        self.read_only = (not _writable(self.path)) if read_only is None else bool(read_only)
        if self.read_only and not exists:
            raise FileFormatError(source, "no such project file (and it cannot be created read-only)")
        with _reading(source, "not a readable project database"):
            # WAL only once the file is known to be ours: switching rewrites its header
            self.db = _connect(self.path, self.read_only, wal=False)
            try:
                meta, sums = self._check(source, create and not self.read_only)
            except FileFormatError:
                self.db.close()
                raise
            if not self.read_only:
                _wal(self.db)
        if not meta:
            with self.db:
                self.db.execute("BEGIN")
                self.db.executemany("INSERT INTO meta VALUES (?, ?)", [("format", FORMAT), ("version", str(VERSION)),
                                                                       ("checksums", CHECKSUMS)])
        #: Whether the file carries checksums (an older project does not until saved;
        #: checksum rows are checked whatever meta says).
        self.checksummed = not meta or "checksums" in meta or sums > 0

    def _check(self, source: str, create: bool) -> tuple[dict[str, str], int]:
        """The ``meta`` table of a project whose tables are ours (made if ``create``
        and the database is new), and how many checksums it holds;
        :class:`FileFormatError` otherwise."""
        tables = {r[0] for r in self.db.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        if not tables and not create:
            raise FileFormatError(source, "not a project file (an empty database)")
        if tables and "meta" not in tables:
            raise FileFormatError(source, "an SQLite database, but not a project file (no meta table)")
        for name in tables & set(COLUMNS):
            columns = tuple(r[1] for r in self.db.execute(f"PRAGMA table_info({name})"))
            if columns != COLUMNS[name]:
                raise FileFormatError(source, f"table {name} has columns {', '.join(columns)}, "
                                              f"a project's has {', '.join(COLUMNS[name])}")
        missing = set(COLUMNS) - tables - {"checksums"}
        if tables and missing:
            raise FileFormatError(source, f"not a project file (no {', '.join(sorted(missing))} table)")
        meta = dict(self.db.execute("SELECT key, value FROM meta").fetchall()) if tables else {}
        if meta and (meta.get("format") != FORMAT or meta.get("version") != str(VERSION)):
            raise FileFormatError(source, f"not a {FORMAT} version {VERSION} file (meta says {meta})")
        if set(meta) - {"format", "version", "checksums"} or meta.get("checksums", CHECKSUMS) != CHECKSUMS:
            raise FileFormatError(source, f"damaged: meta says {meta}")
        if not self.read_only:
            self.db.executescript(SCHEMA)
            tables |= set(COLUMNS)
        sums = self.db.execute("SELECT count(*) FROM checksums").fetchone()[0] if "checksums" in tables else 0
        return meta, sums

    def __enter__(self) -> Project:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.db.close()

    # -- documents --------------------------------------------------------------------------

    def save(self, scene: Scene, tracks: dict[str, Track]) -> None:
        """Store the scene and the tracks (with their takes) in one transaction; the
        journal of a take now stored is cleared with it; the checksums with them (an
        older project gets them here). A project opened read-only, or whose tables
        cannot be written, raises :class:`FileFormatError` and is left as it was."""
        source = str(self.path)
        if self.read_only:
            raise FileFormatError(source, "opened read-only: cannot save (export it, or save to a writable copy)")
        doc, takes = to_document(scene, tracks)
        body = doc.model_dump_json()
        rows = [(i, t.mode, float(t.blend), t.values.shape[1], len(t.times), np.asarray(t.times, "<f8").tobytes(),
                 np.asarray(t.values, "<f8").tobytes()) for i, t in enumerate(takes)]
        sums = [("document", document_digest(body))] + [(f"take {r[0]}", take_digest(*r)) for r in rows]
        with _reading(source, "cannot save"), self.db:
            self.db.execute("BEGIN IMMEDIATE")
            self.db.execute("DELETE FROM takes")
            self.db.executemany("INSERT INTO takes VALUES (?, ?, ?, ?, ?, ?, ?)", rows)
            self.db.execute("INSERT OR REPLACE INTO documents VALUES ('project', ?)", (body,))
            self.db.execute("DELETE FROM journal")
            self.db.execute("DELETE FROM checksums")
            self.db.executemany("INSERT INTO checksums VALUES (?, ?)", sums)
            self.db.execute("INSERT OR REPLACE INTO meta VALUES ('checksums', ?)", (CHECKSUMS,))
        self.checksummed = True

    def load(self) -> tuple[Scene, dict[str, Track]]:
        """The scene and tracks last saved (an empty scene in a new project).

        Raises :class:`FileFormatError` naming what is damaged or malformed (the
        document, a take); :meth:`salvage` keeps the rest."""
        source = str(self.path)
        body, takes, damaged = self._read()
        if damaged:
            raise FileFormatError(source, f"damaged: {'; '.join(damaged)} (Project.salvage() keeps the rest)")
        if body is None:
            return Scene(), {}
        return from_document(load_document(body, source), takes, source)

    def salvage(self) -> Salvaged:
        """Everything undamaged in the project: the scene and its tracks if the document
        is sound (each track with its undamaged takes), every undamaged take, and what
        was left out. Damage in the database's own structure still raises
        :class:`FileFormatError` (nothing can be read past it)."""
        source = str(self.path)
        body, takes, damaged = self._read()
        scene, tracks = Scene(), {}
        if body is not None and not any(d.startswith("the document") for d in damaged):
            try:
                doc = load_document(body, source)
                for curve in doc.curves:
                    lost = [i for i in curve.takes if i not in takes]
                    if lost:
                        damaged.append(f"{curve.path}: left without takes {lost}")
                        curve.takes = [i for i in curve.takes if i in takes]
                scene, tracks = from_document(doc, takes, source)
            except FileFormatError as err:
                damaged.append(f"the document: {err}")
        return Salvaged(scene, tracks, takes, damaged)

    def _read(self) -> tuple[str | None, dict[int, Take], list[str]]:
        """The document's text (None in a new project), the takes that are sound, and
        what is damaged (checksums that do not match, malformed takes)."""
        source = str(self.path)
        with _reading(source, "unreadable"):
            row = self.db.execute("SELECT body FROM documents WHERE name = 'project'").fetchone()
            rows = self.db.execute("SELECT id, mode, blend, dim, n, times, vals FROM takes ORDER BY id").fetchall()
            sums = dict(self.db.execute("SELECT name, digest FROM checksums").fetchall()) if self.checksummed else None
        damaged: list[str] = []
        body = None if row is None else row[0]
        if sums is not None and (body is not None or "document" in sums):
            if body is None or not isinstance(body, str) or sums.get("document") != document_digest(body):
                damaged.append("the document (its checksum does not match)")
        if body is not None and (not isinstance(body, str) or len(body) > MAX_DOCUMENT_BYTES):
            damaged.append("the document (not text of a bounded size)")
        takes = {}
        for r in rows:
            i, mode, blend, dim, n, times, vals = r
            where = f"take {i}"
            try:
                if sums is not None and sums.get(where) != take_digest(*r):
                    raise FileFormatError(source, "its checksum does not match")
                if not (isinstance(n, int) and isinstance(dim, int) and 2 <= n <= MAX_TAKE_SAMPLES and 1 <= dim <= 64):
                    raise FileFormatError(source, f"bad size {n} x {dim}")
                if mode not in MODES or not isinstance(blend, float):
                    raise FileFormatError(source, f"bad mode {mode!r} or blend {blend!r}")
                takes[i] = Take(_floats(times, n, where, source), _floats(vals, n * dim, where, source).reshape(n, dim),
                                mode, blend)
            except InputError as err:
                damaged.append(f"{where} ({str(err).removeprefix(source + ': ').removeprefix(where + ': ')})")
        if sums is not None:
            present = {f"take {r[0]}" for r in rows}
            damaged += [f"{name} (missing)" for name in sorted(sums) if name.startswith("take ") and name not in present]
        return body, takes, damaged

    # -- exchange ---------------------------------------------------------------------------

    def export_json(self, path: str | os.PathLike[str]) -> Path:
        """Write the project, takes included, as one JSON file (atomically)."""
        scene, tracks = self.load()
        doc, takes = to_document(scene, tracks)
        body = json.loads(doc.model_dump_json())
        body["takes"] = [{"mode": t.mode, "blend": t.blend, "times": t.times.tolist(), "values": t.values.tolist()}
                         for t in takes]
        return write_atomic(path, json.dumps(body, indent=1))

    def import_json(self, path: str | os.PathLike[str]) -> None:
        """Replace the project's contents by a JSON file written by :meth:`export_json`."""
        source = str(path)
        try:
            text = Path(path).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as err:
            raise FileFormatError(source, f"cannot read ({getattr(err, 'strerror', None) or err})") from None
        if len(text) > MAX_DOCUMENT_BYTES:
            raise FileFormatError(source, "larger than the bound on a project document")
        try:
            body = load_json(text, source)
            raw = body.pop("takes")  # type: ignore[union-attr]
            takes = {i: Take(np.asarray(t["times"], dtype=float), np.asarray(t["values"], dtype=float),
                             t["mode"], float(t["blend"])) for i, t in enumerate(raw)}
        except (json.JSONDecodeError, AttributeError, KeyError, TypeError, ValueError) as err:
            raise FileFormatError(source, f"not a project export ({type(err).__name__}: {err})") from None
        scene, tracks = from_document(load_document(json.dumps(body), source), takes, source)
        self.save(scene, tracks)

    # -- the journal -------------------------------------------------------------------------

    def journal(self) -> Journal:
        """A journal for a recorder (see :class:`Journal`)."""
        return Journal(self.path)

    def recovered(self) -> dict[str, tuple[np.ndarray, list | np.ndarray]]:
        """Samples of the last take that was being recorded when the program stopped
        without saving: path -> (times, values), or empty. Saving clears them."""
        out: dict[str, tuple[list, list]] = {}
        source = str(self.path)
        with _reading(source, "unreadable journal"):
            rows = self.db.execute("SELECT seq, path, n, times, vals FROM journal "
                                   "WHERE started = (SELECT max(started) FROM journal) ORDER BY seq").fetchall()
            for seq, path, n, times, vals in rows:
                if not isinstance(n, int) or not 0 < n <= MAX_TAKE_SAMPLES:
                    raise FileFormatError(source, f"journal batch {seq}: bad size {n!r}")
                ts, xs = out.setdefault(path, ([], []))
                where = f"journal batch {seq}"
                ts.append(_floats(times, n, where, source))
                if isinstance(vals, bytes):
                    dim = len(vals) // (8 * n)
                    xs.append(_floats(vals, n * max(dim, 1), where, source).reshape(n, -1))
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
        rows = [(self.started, path, len(times), np.asarray(times, "<f8").tobytes(),
                 np.asarray(values, "<f8").tobytes() if isinstance(values, np.ndarray) else json.dumps(list(values)))
                for path, times, values in batches]
        with self._lock:
            if self._db is None:
                self._db = _connect(self.path)
            with self._db:
                self._db.execute("BEGIN")
                self._db.executemany("INSERT INTO journal (started, path, n, times, vals) VALUES (?, ?, ?, ?, ?)",
                                     rows)

    def close(self) -> None:
        with self._lock:
            if self._db is not None:
                self._db.close()
                self._db = None


def load_document(text: str, source: str) -> ProjectDoc:
    """Validate a project document; :class:`FileFormatError` naming the first bad field."""
    try:
        return ProjectDoc.model_validate_json(text)
    except ValidationError as err:
        first = err.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        raise FileFormatError(source, f"{where}: {first['msg']} ({err.error_count()} problems)") from None


def to_document(scene: Scene, tracks: dict[str, Track]) -> tuple[ProjectDoc, list[Take]]:
    """The document of a scene and its tracks, and the takes it refers to by index."""
    takes: list[Take] = []
    index: dict[int, int] = {}
    objects = [ObjectDoc(name=o.name, kind=o.kind, attributes=[
        AttributeDoc(name=n, type=TypeDoc(name=a.type.name, dim=a.type.dim, tol=a.type.tol, unit=a.type.unit,
                                          default=list(a.type.default), choices=list(a.type.choices)),
                     value=a.value.tolist() if isinstance(a.value, np.ndarray) else a.value)
        for n, a in o.attributes.items()]) for o in scene.objects.values()]
    curves, steps = [], []
    for track in tracks.values():
        if isinstance(track, DiscreteTrack):
            steps.append(StepsDoc(path=track.path, times=track.times, values=track.values))
            continue
        ids = []
        for take in track.takes:
            ids.append(index.setdefault(id(take), len(takes)))
            if ids[-1] == len(takes):
                takes.append(take)
        curves.append(CurveDoc(path=track.path, tol=track.tol, order=track.spline.k + 1,
                               knots=np.asarray(track.spline.t).tolist(), coef=np.asarray(track.spline.c).tolist(),
                               takes=ids))
    return ProjectDoc(objects=objects, curves=curves, steps=steps), takes


def from_document(doc: ProjectDoc, takes: dict[int, Take], source: str) -> tuple[Scene, dict[str, Track]]:
    """The scene and tracks of a validated document; :class:`FileFormatError` naming
    what does not fit (a value of the wrong type, a track for no attribute...)."""
    scene = Scene()
    tracks: dict[str, Track] = {}
    try:
        for o in doc.objects:
            obj = scene.add(o.name, o.kind)
            for a in o.attributes:
                kind = AttributeType(a.type.name, a.type.dim, a.type.tol, a.type.unit, tuple(a.type.default),
                                     tuple(a.type.choices))
                if a.name in obj.attributes and obj.attributes[a.name].type != kind:
                    raise FileFormatError(source, f"{o.name}.{a.name}: not the {o.kind}'s standard type")
                if a.name not in obj.attributes:
                    if kind.continuous and (kind.dim < 1 or kind.tol <= 0):
                        raise FileFormatError(source, f"{o.name}.{a.name}: a continuous type needs dim >= 1, tol > 0")
                    obj.add(a.name, kind)
                scene.set(f"{o.name}.{a.name}", a.value)
        for c in doc.curves:
            kind = scene.type(c.path)
            missing = [i for i in c.takes if i not in takes]
            if missing:
                raise FileFormatError(source, f"{c.path}: refers to missing takes {missing[:5]}")
            n = len(c.knots) - c.order
            if n < 1 or len(c.coef) != n or np.any(np.diff(c.knots) < 0):
                raise FileFormatError(source, f"{c.path}: {len(c.knots)} sorted knots for order {c.order} need "
                                              f"{max(n, 1)} coefficients, got {len(c.coef)}")
            coef = np.array(c.coef, dtype=float) if all(len(r) == kind.dim for r in c.coef) else None
            if coef is None:
                raise FileFormatError(source, f"{c.path}: coefficients need {kind.dim} numbers each")
            spline = BSpline(np.array(c.knots), coef, c.order - 1)
            tracks[c.path] = ContinuousTrack(c.path, kind, spline, c.tol, tuple(takes[i] for i in c.takes))
        for s in doc.steps:
            tracks[s.path] = DiscreteTrack(s.path, scene.type(s.path), list(s.times), list(s.values))
    except FileFormatError:
        raise
    except InputError as err:
        raise FileFormatError(source, str(err)) from None
    return scene, tracks
