"""One studio per project: an exclusive lock on the file ``<project>.lock`` beside it."""

from __future__ import annotations

import os
from pathlib import Path
from typing import IO

from sketchanim.errors import ArgumentError


class ProjectLock:
    """An exclusive lock on the project ``path``, held while open (the system lets go
    of it when the process ends, however it ends); :class:`ArgumentError` if another
    studio holds it. Nothing is locked where locks are not available (``handle`` None).

    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "p.sketchanim"
    >>> lock = ProjectLock(path)
    >>> ProjectLock(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: project: ...p.sketchanim is open in another studio (one server per project)
    >>> lock.release()
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        path = Path(path)
        self.handle: IO | None = None
        try:
            import fcntl
        except ImportError:                             # not a POSIX system
            return
        handle = open(path.with_name(path.name + ".lock"), "a+")
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            raise ArgumentError("project", f"{path} is open in another studio (one server per project)") from None
        self.handle = handle

    def release(self) -> None:
        """Let another studio open the project (the lock file goes)."""
        if self.handle is not None:
            Path(self.handle.name).unlink(missing_ok=True)
            self.handle.close()
            self.handle = None
