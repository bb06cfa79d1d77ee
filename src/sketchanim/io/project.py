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

Every save is one transaction. Loading rejects what is not a project of ours, sizes
beyond the bounds below, and values that do not fit their types, with a
:class:`~sketchanim.errors.FileFormatError` naming the file and what is wrong. Nothing
is unpickled; JSON and float blobs only.
"""

from __future__ import annotations

import json
import os
import sqlite3
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import DISCRETE, AttributeType
from sketchanim.anim.scene import KINDS, Scene
from sketchanim.anim.tracks import MODES, ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.errors import FileFormatError, InputError
from sketchanim.io.atomic import write_atomic

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
"""


def _connect(path: Path) -> sqlite3.Connection:
    db = sqlite3.connect(path, timeout=10, check_same_thread=False, isolation_level=None)
    db.execute("PRAGMA journal_mode=WAL")
    db.execute("PRAGMA synchronous=NORMAL")
    return db


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

    def __init__(self, path: str | os.PathLike[str], *, create: bool = True) -> None:
        self.path = Path(path)
        if not self.path.exists() and not create:
            raise FileFormatError(str(self.path), "no such project file")
        if self.path.exists():
            with open(self.path, "rb") as handle:
                head = handle.read(16)
            if head and head != b"SQLite format 3\x00":
                raise FileFormatError(str(self.path), "not a project file (not an SQLite database)")
        with _reading(str(self.path), "not a readable project database"):
            self.db = _connect(self.path)
            tables = {r[0] for r in self.db.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
            if tables and "meta" not in tables:
                self.db.close()
                raise FileFormatError(str(self.path), "an SQLite database, but not a project file (no meta table)")
            self.db.executescript(SCHEMA)
            meta = dict(self.db.execute("SELECT key, value FROM meta").fetchall())
        if not meta:
            with self.db:
                self.db.execute("BEGIN")
                self.db.executemany("INSERT INTO meta VALUES (?, ?)", [("format", FORMAT), ("version", str(VERSION))])
        elif meta.get("format") != FORMAT or meta.get("version") != str(VERSION):
            raise FileFormatError(str(self.path), f"not a {FORMAT} version {VERSION} file (meta says {meta})")

    def __enter__(self) -> Project:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.db.close()

    # -- documents --------------------------------------------------------------------------

    def save(self, scene: Scene, tracks: dict[str, Track]) -> None:
        """Store the scene and the tracks (with their takes) in one transaction; the
        journal of a take now stored is cleared with it."""
        doc, takes = to_document(scene, tracks)
        body = doc.model_dump_json()
        with self.db:
            self.db.execute("BEGIN IMMEDIATE")
            self.db.execute("DELETE FROM takes")
            self.db.executemany("INSERT INTO takes VALUES (?, ?, ?, ?, ?, ?, ?)", [
                (i, t.mode, t.blend, t.values.shape[1], len(t.times), np.asarray(t.times, "<f8").tobytes(),
                 np.asarray(t.values, "<f8").tobytes()) for i, t in enumerate(takes)])
            self.db.execute("INSERT OR REPLACE INTO documents VALUES ('project', ?)", (body,))
            self.db.execute("DELETE FROM journal")

    def load(self) -> tuple[Scene, dict[str, Track]]:
        """The scene and tracks last saved (an empty scene in a new project)."""
        source = str(self.path)
        with _reading(source, "unreadable"):
            row = self.db.execute("SELECT body FROM documents WHERE name = 'project'").fetchone()
            if row is None:
                return Scene(), {}
            rows = self.db.execute("SELECT id, mode, blend, dim, n, times, vals FROM takes ORDER BY id").fetchall()
        if not isinstance(row[0], str) or len(row[0]) > MAX_DOCUMENT_BYTES:
            raise FileFormatError(source, "the project document is not text of a bounded size")
        takes = {}
        for i, mode, blend, dim, n, times, vals in rows:
            where = f"take {i}"
            if not (isinstance(n, int) and isinstance(dim, int) and 2 <= n <= MAX_TAKE_SAMPLES and 1 <= dim <= 64):
                raise FileFormatError(source, f"{where}: bad size {n} x {dim}")
            if mode not in MODES or not isinstance(blend, float):
                raise FileFormatError(source, f"{where}: bad mode {mode!r} or blend {blend!r}")
            try:
                takes[i] = Take(_floats(times, n, where, source), _floats(vals, n * dim, where, source).reshape(n, dim),
                                mode, blend)
            except InputError as err:
                raise FileFormatError(source, f"{where}: {err}") from None
        return from_document(load_document(row[0], source), takes, source)

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
        text = Path(path).read_text(encoding="utf-8")
        if len(text) > MAX_DOCUMENT_BYTES:
            raise FileFormatError(source, "larger than the bound on a project document")
        try:
            body = json.loads(text)
            raw = body.pop("takes")
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
                    values = json.loads(vals)
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
