"""Project files: one SQLite database (WAL) per project (:mod:`.database` lists its
tables), the scene and its tracks in a versioned document (:mod:`.document`), their
takes as float blobs, every one checksummed (:mod:`.checksums`), and the take being
recorded in a journal (:mod:`.journal`, brought back by :mod:`.recovery`).

Every save is one transaction. Loading rejects what is not a project of ours, sizes
beyond the bounds, values that do not fit their types, and damage, with a
:class:`~sketchanim.errors.FileFormatError` naming the file and what is wrong. Nothing
is unpickled; JSON and float blobs only. A project that cannot be written (read-only
media, or a read-only file) is opened read-only: it loads and exports, and a save says
why it cannot.
"""

from __future__ import annotations

import json
import os
import shlex
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import MODES, ContinuousTrack, Take, Track
from sketchanim.atomic import write_atomic
from sketchanim.errors import FileFormatError, InputError, load_json
from sketchanim.project.checksums import CHECKSUMS, document_digest, take_digest
from sketchanim.project.database import (COLUMNS, CREATE_TABLES, FORMAT, FORMAT_VERSION, MAX_TAKE_SAMPLES, connect,
                                         floats, reading, use_wal, writable)
from sketchanim.project.document import (DEFAULT_FPS, MAX_DOCUMENT_BYTES, SoundDoc, ToleranceDoc, document_tolerances,
                                         from_document, load_document, to_document)
from sketchanim.project.journal import Journal, journaled_take


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
            with reading(source, "cannot read"), open(self.path, "rb") as handle:
                head = handle.read(16)
            if head != b"SQLite format 3\x00" and (head or not create):
                raise FileFormatError(source, "not a project file (" + (
                    "an empty file" if not head else "not an SQLite database") + ")")
        #: Opened read-only (asked for, or the file or its folder cannot be written).
        self.read_only = (not writable(self.path)) if read_only is None else bool(read_only)
        if self.read_only and not exists:
            raise FileFormatError(source, "no such project file (and it cannot be created read-only)")
        with reading(source, "not a readable project database"):
            # WAL only once the file is known to be ours: switching rewrites its header
            self.db = connect(self.path, self.read_only, wal=False)
            try:
                meta, sums = self._check(source, create and not self.read_only)
            except FileFormatError:
                self.db.close()
                raise
            if not self.read_only:
                use_wal(self.db)
        if not meta:
            with self.db:
                self.db.execute("BEGIN")
                self.db.executemany("INSERT INTO meta VALUES (?, ?)", [("format", FORMAT),
                                                                       ("version", str(FORMAT_VERSION)),
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
        if meta and (meta.get("format") != FORMAT or meta.get("version") != str(FORMAT_VERSION)):
            raise FileFormatError(source, f"not a {FORMAT} version {FORMAT_VERSION} file (meta says {meta})")
        if set(meta) - {"format", "version", "checksums"} or meta.get("checksums", CHECKSUMS) != CHECKSUMS:
            raise FileFormatError(source, f"damaged: meta says {meta}")
        if not self.read_only:
            self.db.executescript(CREATE_TABLES)
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

    def save(self, scene: Scene, tracks: dict[str, Track], tolerances: dict[str, ToleranceDoc] | None = None,
             fps: float = DEFAULT_FPS, sounds: list[SoundDoc] | None = None) -> None:
        """Store the scene, the tracks (with their takes), the take tolerances (those
        of attributes the scene holds), the frame rate and the sounds (references to
        their files) in one transaction; the
        journal of a take now stored is cleared with it; the checksums with them (an
        older project gets them here). A project opened read-only, or whose tables
        cannot be written, raises :class:`FileFormatError` and is left as it was."""
        source = str(self.path)
        if self.read_only:
            raise FileFormatError(source, "opened read-only: cannot save (export it, or save to a writable copy)")
        doc, takes = to_document(scene, tracks, tolerances, fps, sounds)
        body = doc.model_dump_json()
        rows = [(i, t.mode, float(t.blend), t.values.shape[1], len(t.times), np.asarray(t.times, "<f8").tobytes(),
                 np.asarray(t.values, "<f8").tobytes()) for i, t in enumerate(takes)]
        sums = [("document", document_digest(body))] + [(f"take {r[0]}", take_digest(*r)) for r in rows]
        with reading(source, "cannot save"), self.db:
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
        document, a take) and the command that keeps the rest (``sketchanim salvage``,
        which calls :meth:`salvage`)."""
        source = str(self.path)
        body, takes, damaged = self._read()
        if damaged:
            raise FileFormatError(source, f"damaged: {'; '.join(damaged)}; run `sketchanim salvage "
                                          f"{shlex.quote(source)}` to keep the rest (Project.salvage())")
        if body is None:
            return Scene(), {}
        return from_document(load_document(body, source), takes, source)

    def tolerances(self, scene: Scene) -> dict[str, ToleranceDoc]:
        """The take tolerances last saved, by path (none in a new project), checked
        against ``scene`` (what :meth:`load` gave, which checked the document's
        checksum): :class:`FileFormatError` naming one for an attribute the scene does
        not have.

        >>> import tempfile
        >>> path = Path(tempfile.mkdtemp()) / "tol.sketchanim"
        >>> scene = Scene(); _ = scene.add("box")
        >>> with Project(path) as project:
        ...     project.save(scene, {}, {"box.position": ToleranceDoc(amount=0.01, unit="units")})
        >>> with Project(path) as project:
        ...     project.tolerances(project.load()[0])
        {'box.position': ToleranceDoc(amount=0.01, unit='units')}
        """
        source = str(self.path)
        with reading(source, "unreadable"):
            row = self.db.execute("SELECT body FROM documents WHERE name = 'project'").fetchone()
        return {} if row is None else document_tolerances(load_document(row[0], source), scene, source)

    def fps(self) -> float:
        """The frame rate last saved (:data:`~.document.DEFAULT_FPS` in a new project or one
        from before frame rates)."""
        source = str(self.path)
        with reading(source, "unreadable"):
            row = self.db.execute("SELECT body FROM documents WHERE name = 'project'").fetchone()
        return DEFAULT_FPS if row is None else load_document(row[0], source).fps

    def sounds(self) -> list[SoundDoc]:
        """The sounds last saved, as the document recorded them (none in a new project
        or one from before sounds; their files are checked by the studio,
        :func:`sketchanim.studio.sounds.checked`)."""
        source = str(self.path)
        with reading(source, "unreadable"):
            row = self.db.execute("SELECT body FROM documents WHERE name = 'project'").fetchone()
        return [] if row is None else load_document(row[0], source).sounds

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
        with reading(source, "unreadable"):
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
                takes[i] = Take(floats(times, n, where, source), floats(vals, n * dim, where, source).reshape(n, dim),
                                mode, blend)
            except InputError as err:
                damaged.append(f"{where} ({str(err).removeprefix(source + ': ').removeprefix(where + ': ')})")
        if sums is not None:
            present = {f"take {r[0]}" for r in rows}
            damaged += [f"{name} (missing)" for name in sorted(sums) if name.startswith("take ") and name not in present]
        return body, takes, damaged

    # -- exchange ---------------------------------------------------------------------------

    def export_json(self, path: str | os.PathLike[str]) -> Path:
        """Write the project as saved, takes included, as one JSON file (atomically;
        :func:`export_text`)."""
        scene, tracks = self.load()
        return write_atomic(path, export_text(scene, tracks, self.tolerances(scene), self.fps(), self.sounds()))

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
        doc = load_document(json.dumps(body), source)
        scene, tracks = from_document(doc, takes, source)
        self.save(scene, tracks, document_tolerances(doc, scene, source), doc.fps, doc.sounds)

    # -- the journal -------------------------------------------------------------------------

    def clear_journal(self) -> None:
        """Drop the journal's rows (a take that was cancelled: nothing to recover)."""
        with reading(str(self.path), "cannot clear the journal"), self.db:
            self.db.execute("BEGIN IMMEDIATE")
            self.db.execute("DELETE FROM journal")

    def journal(self) -> Journal:
        """A journal for a recorder (see :class:`Journal`)."""
        return Journal(self.path)

    def recovered(self) -> dict[str, tuple[np.ndarray, list | np.ndarray]]:
        """Samples of the last take that was being recorded when the program stopped
        without saving: path -> (times, values), or empty. Saving clears them."""
        return journaled_take(self.db, str(self.path))


def export_text(scene: Scene, tracks: dict[str, Track], tolerances: dict[str, ToleranceDoc] | None = None,
                fps: float = DEFAULT_FPS, sounds: list[SoundDoc] | None = None) -> str:
    """The project export's JSON (what :meth:`Project.export_json` writes and
    :meth:`Project.import_json` reads): the document, with every take's samples.

    >>> scene = Scene(); _ = scene.add("box")
    >>> body = json.loads(export_text(scene, {}))
    >>> [o["name"] for o in body["objects"]], body["takes"]
    (['box'], [])
    """
    doc, takes = to_document(scene, tracks, tolerances, fps, sounds)
    body = json.loads(doc.model_dump_json())
    body["takes"] = [{"mode": t.mode, "blend": t.blend, "times": t.times.tolist(), "values": t.values.tolist()}
                     for t in takes]
    return json.dumps(body, indent=1)
