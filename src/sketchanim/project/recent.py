"""The projects opened lately: ``recent.json`` in the user's state folder
(``$XDG_STATE_HOME/sketchanim``, by default ``~/.local/state/sketchanim``, through
platformdirs), newest first, at most :data:`MAX_RECENT`, written atomically.

The list is a convenience: a damaged or unreadable file reads as an empty list (and is
written anew at the next open), and a failure to write it is the caller's to log, never
a reason not to open a project.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import platformdirs

from sketchanim.atomic import write_atomic

#: Projects the list keeps.
MAX_RECENT = 20


@dataclass(frozen=True)
class Recent:
    """A project opened lately: its resolved path and when (seconds since the epoch)."""

    path: str
    opened: float


def recent_file() -> Path:
    """Where the list is kept (``$XDG_STATE_HOME/sketchanim/recent.json``).

    >>> recent_file().name
    'recent.json'
    """
    return platformdirs.user_state_path("sketchanim") / "recent.json"


def recent(file: Path | None = None) -> list[Recent]:
    """The projects opened lately, newest first (``file``: the list's file,
    :func:`recent_file` by default); an empty list if it is missing or damaged.

    >>> import tempfile
    >>> file = Path(tempfile.mkdtemp()) / "recent.json"
    >>> recent(file)
    []
    >>> _ = file.write_text("{not json")
    >>> recent(file)
    []
    """
    file = recent_file() if file is None else file
    try:
        entries = json.loads(file.read_text(encoding="utf-8"))["projects"]
        return [Recent(str(e["path"]), float(e["opened"])) for e in entries][:MAX_RECENT]
    except (OSError, ValueError, KeyError, TypeError):
        return []


def remember(project: str | os.PathLike[str], file: Path | None = None, now: float | None = None) -> list[Recent]:
    """Put ``project`` (resolved) first in the list and write it atomically; the list.
    Raises the :class:`OSError` of a list that cannot be written.

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = remember(folder / "a.sketchanim", folder / "recent.json", 1.0)
    >>> _ = remember(folder / "b.sketchanim", folder / "recent.json", 2.0)
    >>> [Path(r.path).name for r in remember(folder / "a.sketchanim", folder / "recent.json", 3.0)]
    ['a.sketchanim', 'b.sketchanim']
    """
    file = recent_file() if file is None else file
    path = str(Path(project).resolve())
    entries = [Recent(path, time.time() if now is None else now)]
    entries += [r for r in recent(file) if r.path != path][:MAX_RECENT - 1]
    write_atomic(file, json.dumps({"projects": [asdict(r) for r in entries]}, indent=1))
    return entries
