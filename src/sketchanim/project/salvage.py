"""Salvage a damaged project into a new one: what :meth:`.store.Project.salvage` keeps
(the scene and its tracks if the document is sound, every undamaged take), written as a
new project, and the undamaged takes of no track beside it as JSON
(``OUT.orphan-takes.json``: a project holds only the takes of its tracks). The damaged
project is opened read-only and never written.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from sketchanim.anim.tracks import Take
from sketchanim.atomic import SUFFIX, current_umask, write_atomic
from sketchanim.errors import ArgumentError, FileFormatError, InputError
from sketchanim.project.store import Project, Salvaged

#: The ``format`` of an orphan takes file.
ORPHANS_FORMAT = "sketchanim-orphan-takes"


@dataclass
class SalvageReport:
    """What :func:`salvage_project` wrote.

    Attributes
    ----------
    out : Path
        The new project.
    orphans : Path or None
        The takes of no track, as JSON (None: there were none).
    kept : list of str
        What was kept, one line each.
    left_out : list of str
        What was left out, and why.
    """

    out: Path
    orphans: Path | None
    kept: list[str] = field(default_factory=list)
    left_out: list[str] = field(default_factory=list)


def default_output(project: str | os.PathLike[str]) -> Path:
    """Where a salvaged ``project`` goes unless told: ``<stem>.salvaged.sketchanim``
    beside it.

    >>> default_output("shots/show.sketchanim").as_posix()
    'shots/show.salvaged.sketchanim'
    """
    project = Path(project)
    return project.with_name(f"{project.stem}.salvaged.sketchanim")


def orphans_path(out: str | os.PathLike[str]) -> Path:
    """Where the takes of no track of the salvaged project ``out`` go.

    >>> orphans_path("show.salvaged.sketchanim").name
    'show.salvaged.sketchanim.orphan-takes.json'
    """
    out = Path(out)
    return out.with_name(out.name + ".orphan-takes.json")


def _key(take: Take) -> tuple[str, float, bytes]:
    digest = hashlib.blake2b(take.times.tobytes(), digest_size=16)
    digest.update(take.values.tobytes())
    return take.mode, float(take.blend), digest.digest()


def orphan_takes(kept: Salvaged) -> dict[int, Take]:
    """The takes ``kept`` holds that none of its tracks holds, by id."""
    used = {_key(t) for track in kept.tracks.values() for t in getattr(track, "takes", ())}
    return {i: t for i, t in kept.takes.items() if _key(t) not in used}


def orphans_document(project: Path, takes: dict[int, Take]) -> str:
    """The JSON of ``takes`` of no track from ``project``: each take's id in the damaged
    project, mode, blend, smoothing, times and values.

    >>> import numpy as np
    >>> doc = json.loads(orphans_document(Path("p.sketchanim"), {3: Take(np.r_[0.0, 1.0], np.c_[[1.0, 2.0]])}))
    >>> doc["format"], doc["takes"][0]["id"], doc["takes"][0]["values"]
    ('sketchanim-orphan-takes', 3, [[1.0], [2.0]])
    """
    return json.dumps({"format": ORPHANS_FORMAT, "version": 1, "project": str(project),
                       "takes": [{"id": i, "mode": t.mode, "blend": t.blend, "smoothing": t.smoothing,
                                  "times": t.times.tolist(), "values": t.values.tolist()}
                                 for i, t in takes.items()]}, indent=1)


def _write_project(out: Path, kept: Salvaged, tolerances: dict) -> None:
    """The new project at ``out``, made beside it and moved into place in one step (a
    project that was there before goes with its logs)."""
    fd, name = tempfile.mkstemp(prefix=f".{out.name}.{os.getpid()}.", suffix=SUFFIX, dir=out.parent)
    os.fchmod(fd, 0o666 & ~current_umask())                 # as a new project's, not mkstemp's 0600
    os.close(fd)
    tmp = Path(name)
    try:
        with Project(tmp) as project:
            project.save(kept.scene, kept.tracks, tolerances)
        os.replace(tmp, out)
    finally:
        for left in (tmp, Path(f"{tmp}-wal"), Path(f"{tmp}-shm")):
            left.unlink(missing_ok=True)
    for log in ("-wal", "-shm", "-journal"):               # an earlier project's, which would be read into this one
        Path(f"{out}{log}").unlink(missing_ok=True)


def salvage_project(project: str | os.PathLike[str], out: str | os.PathLike[str] | None = None, *,
                    force: bool = False) -> SalvageReport:
    """Salvage the damaged ``project`` into the new project ``out`` (default
    :func:`default_output`), its takes of no track into :func:`orphans_path` beside it.
    ``out`` (or its orphans file) is replaced only with ``force``. A project of which
    nothing can be read, or not a project, raises :class:`FileFormatError`.

    >>> import sqlite3, tempfile
    >>> from sketchanim.anim.scene import Scene
    >>> path = Path(tempfile.mkdtemp()) / "show.sketchanim"
    >>> scene = Scene(); _ = scene.add("box")
    >>> with Project(path) as p:
    ...     p.save(scene, {})
    >>> with sqlite3.connect(path) as db:
    ...     _ = db.execute("UPDATE checksums SET digest = 'x' WHERE name = 'document'")
    >>> salvage_project(path)
    Traceback (most recent call last):
    ...
    sketchanim.errors.FileFormatError: ...show.sketchanim: nothing could be read: the document (its checksum does not match)
    """
    source = Path(project)
    out = default_output(source) if out is None else Path(out)
    orphans_file = orphans_path(out)
    if out.resolve() == source.resolve():
        raise ArgumentError("output", f"{out} is the damaged project itself")
    if not force:
        for taken in (out, orphans_file):
            if os.path.lexists(taken):
                raise ArgumentError("force", f"{taken} exists and is not replaced without it")
    with Project(source, create=False, read_only=True) as opened:
        kept = opened.salvage()
        left_out = list(kept.damaged)
        tolerances = {}
        if kept.scene.objects:
            try:
                tolerances = opened.tolerances(kept.scene)
            except InputError as err:
                left_out.append(f"the take tolerances ({err})")
    orphans = orphan_takes(kept)
    if not kept.scene.objects and not kept.takes:
        raise FileFormatError(str(source), "nothing could be read: " + "; ".join(left_out or ["an empty project"]))
    _write_project(out, kept, tolerances)
    if orphans:
        write_atomic(orphans_file, orphans_document(source, orphans))
    else:
        orphans_file.unlink(missing_ok=True)               # an earlier salvage's, replaced with force
    report = SalvageReport(out, orphans_file if orphans else None, left_out=left_out)
    if kept.scene.objects:
        report.kept.append(f"the scene: {len(kept.scene.objects)} objects ({', '.join(kept.scene.objects)})")
    for path, track in kept.tracks.items():
        report.kept.append(f"{path}: a track, takes kept: {len(getattr(track, 'takes', ()))}")
    if orphans:
        report.kept.append(f"takes of no track: ids {', '.join(map(str, orphans))}, in {orphans_file}")
    return report
