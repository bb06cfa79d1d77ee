"""One studio per project: an exclusive lock on the file ``<project>.lock`` beside it,
or, where nothing can be created beside it (read-only media, a folder the user cannot
write), on a file in the user's temporary folder named for the project's resolved path."""

from __future__ import annotations

import errno
import hashlib
import os
import tempfile
from pathlib import Path
from typing import IO

from sketchanim.errors import ArgumentError

#: What opening the lock file beside a project raises when it cannot be created there.
UNWRITABLE = (errno.EROFS, errno.EACCES, errno.EPERM)


def fallback_path(project: str | os.PathLike[str]) -> Path:
    """The lock file of ``project`` when none can be made beside it: in
    :func:`tempfile.gettempdir`, named for the user and the project's resolved path.

    >>> fallback_path("a/show.sketchanim") == fallback_path(Path("a/../a/show.sketchanim"))
    True
    """
    digest = hashlib.sha256(os.fsencode(Path(project).resolve())).hexdigest()[:24]
    return Path(tempfile.gettempdir()) / f"sketchanim-{os.getuid()}-{digest}.lock"


def _open(path: Path, create: bool = True) -> IO:
    """The lock file at ``path``, opened to write (made if missing), or to read only
    (``create`` False: one that exists but cannot be written); a link is not followed."""
    flags = (os.O_RDWR | os.O_CREAT) if create else os.O_RDONLY
    return os.fdopen(os.open(path, flags | os.O_NOFOLLOW, 0o644), "r+" if create else "r")


class ProjectLock:
    """An exclusive lock on the project ``path``, held while open (the system lets go
    of it when the process ends, however it ends); :class:`ArgumentError` if another
    studio holds it. The lock file is ``<project>.lock`` beside the project, or
    :func:`fallback_path` where that cannot be created (``path`` says which). Nothing
    is locked where locks are not available (``handle`` None).

    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "p.sketchanim"
    >>> lock = ProjectLock(path)
    >>> lock.path.name
    'p.sketchanim.lock'
    >>> ProjectLock(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: project: ...p.sketchanim is open in another studio (one server per project)
    >>> lock.release()
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        path = Path(path)
        self.handle: IO | None = None
        #: The lock file.
        self.path = path.with_name(path.name + ".lock")
        try:
            import fcntl
        except ImportError:                             # not a POSIX system
            return
        try:
            handle = _open(self.path)
        except OSError as err:
            if err.errno not in UNWRITABLE:
                raise
            if self.path.exists():                      # left there, or another user's: it still locks
                handle = _open(self.path, create=False)
            else:
                self.path = fallback_path(path)
                handle = _open(self.path)
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            raise ArgumentError("project", f"{path} is open in another studio (one server per project)") from None
        self.handle = handle

    def release(self) -> None:
        """Let another studio open the project (the lock file goes, where it can)."""
        if self.handle is not None:
            try:
                self.path.unlink(missing_ok=True)
            except OSError:                             # read-only media: the file stays, unlocked
                pass
            self.handle.close()
            self.handle = None
