"""Project files from the page: save as (a copy of the model as the pages see it, in the
studio's files folder: the project's, unless started with ``--files DIR``), open (a
project in the files folder, or one of the recent list), and the recent list as the page
shows it.

A copy is written as a whole new project in a temporary folder, then put in place
atomically under its name, never over a file or folder that has it: a failure leaves
nothing behind and the open project as it was. Every refusal is an
:class:`~sketchanim.errors.InputError` naming the file.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Mapping
from pathlib import Path

from pydantic import BaseModel

from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import Track
from sketchanim.atomic import write_atomic
from sketchanim.errors import ArgumentError
from sketchanim.project.document import ToleranceDoc
from sketchanim.project.recent import Recent
from sketchanim.project.store import Project
from sketchanim.studio.exports import ExportExists, check_name, failed

#: What a project file's name ends in.
PROJECT_SUFFIX = ".sketchanim"
#: The names a page may give (as the OpenAPI spec says; anything else is checked and
#: refused with its reason).
NAME_PATTERN = r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,100}\.sketchanim$"
#: Most projects of the files folder listed.
MAX_LISTED = 500


class ProjectMissing(ArgumentError):
    """The project to open is not there (moved, deleted, never made)."""


class ProjectFile(BaseModel):
    """A project the page may open: its path, its name, whether it is there."""

    path: str
    name: str
    exists: bool
    #: when it was last opened (seconds since the epoch), if it is in the recent list
    opened: float | None = None


class ProjectFiles(BaseModel):
    """``GET /api/recent``'s answer: the open project, the files folder, the projects
    opened lately (newest first) and those in the files folder (by name, at most
    :data:`MAX_LISTED`)."""

    current: str
    folder: str
    recent: list[ProjectFile]
    files: list[ProjectFile]


def copy_target(folder: Path, name: str) -> Path:
    """Where ``save as name`` writes: ``folder / name`` for a bare file name ending in
    ``.sketchanim`` that no file or folder there has.

    >>> folder = Path(tempfile.mkdtemp())
    >>> copy_target(folder, "take2.sketchanim") == folder / "take2.sketchanim"
    True
    >>> copy_target(folder, "take2.glb")
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: file: 'take2.glb': a project's name ends in .sketchanim
    """
    check_name(name, "the project's folder")
    if Path(name).suffix.lower() != PROJECT_SUFFIX:
        raise ArgumentError("file", f"{name!r}: a project's name ends in {PROJECT_SUFFIX}")
    path = folder / name
    if os.path.lexists(path):
        raise ExportExists("file", f"{name!r} exists in {folder}; save as another name")
    return path


def write_copy(target: Path, scene: Scene, tracks: Mapping[str, Track], tolerances: dict[str, ToleranceDoc],
               fps: float) -> Path:
    """Write the model as a new project at ``target`` (found by :func:`copy_target`),
    atomically and never over a file (:class:`~.exports.ExportExists`); what the
    system refuses raises :class:`~.exports.ExportFailed` naming the file, leaving
    nothing behind.

    >>> folder = Path(tempfile.mkdtemp())
    >>> scene = Scene(); _ = scene.add("box")
    >>> with Project(write_copy(folder / "b.sketchanim", scene, {}, {}, 24.0), create=False) as copy:
    ...     list(copy.load()[0].objects), copy.fps()
    (['box'], 24.0)
    """
    try:
        with tempfile.TemporaryDirectory() as tmp:
            scratch = Path(tmp) / target.name
            with Project(scratch) as copy:
                copy.save(scene, dict(tracks), tolerances, fps)
            return write_atomic(target, scratch.read_bytes(), exclusive=True)
    except FileExistsError:
        raise ExportExists("file", f"{target.name!r} exists in {target.parent}; save as another name") from None
    except OSError as err:
        raise failed(target, err) from None


def openable(path: str, folder: Path, recent: list[Recent]) -> Path:
    """The project ``path`` names, if the page may open it: a bare name of a project in
    the files ``folder``, or a path of the recent list; it must exist.

    >>> folder = Path(tempfile.mkdtemp())
    >>> openable("/etc/passwd", folder, [])
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: path: '/etc/passwd': neither a project in the files folder nor a recent one
    """
    known = {r.path for r in recent}
    if path in known:
        target = Path(path)
    elif os.sep not in path and "/" not in path:
        target = folder / check_name(path, "the files folder")
    else:
        raise ArgumentError("path", f"{path!r}: neither a project in the files folder nor a recent one")
    if target.suffix.lower() != PROJECT_SUFFIX:
        raise ArgumentError("path", f"{path!r}: a project's name ends in {PROJECT_SUFFIX}")
    if not target.is_file():
        raise ProjectMissing("path", f"{str(target)!r}: no such project file (moved or deleted?)")
    return target.resolve()


def listing(current: Path, folder: Path, recent: list[Recent]) -> ProjectFiles:
    """What ``GET /api/recent`` answers (a files folder that cannot be read lists none).

    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / "show.sketchanim").write_bytes(b""); _ = (folder / "notes.txt").write_bytes(b"")
    >>> answer = listing(folder / "show.sketchanim", folder, [Recent("/a/gone.sketchanim", 5.0)])
    >>> [(f.name, f.exists) for f in answer.recent], [f.name for f in answer.files]
    ([('gone.sketchanim', False)], ['show.sketchanim'])
    """
    try:
        found = sorted(f for f in folder.iterdir() if f.suffix.lower() == PROJECT_SUFFIX and f.is_file())
    except OSError:
        found = []
    return ProjectFiles(current=str(current), folder=str(folder), recent=[
        ProjectFile(path=r.path, name=Path(r.path).name, exists=Path(r.path).is_file(), opened=r.opened)
        for r in recent], files=[ProjectFile(path=str(f), name=f.name, exists=True) for f in found[:MAX_LISTED]])
