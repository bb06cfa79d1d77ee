"""Atomic file writing: a reader sees the old file or the new one, never half of one.

The data goes to a hidden temporary file beside the output, named for the output and
the writing process (``.NAME.PID.RANDOM.sketchanim-tmp``), which is renamed over the
output once complete. A writer killed midway (SIGKILL, power loss) leaves its temporary
file behind: the next write to the same output removes those whose process is gone.
"""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path

#: Ends the name of every temporary file :func:`write_atomic` makes.
SUFFIX = ".sketchanim-tmp"


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs (on this machine)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def stale_temporaries(target: Path) -> list[Path]:
    """The temporary files of earlier writes to ``target`` whose writer is gone.

    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / f".a.txt.999999999.x{SUFFIX}").write_text("half")
    >>> [p.name for p in stale_temporaries(folder / "a.txt")]
    ['.a.txt.999999999.x.sketchanim-tmp']
    """
    found = []
    prefix = f".{target.name}."
    try:
        names = os.listdir(target.parent)
    except OSError:
        return []
    for name in names:
        if name.startswith(prefix) and name.endswith(SUFFIX):
            pid = name[len(prefix) :].split(".", 1)[0]
            if pid.isascii() and pid.isdigit() and int(pid) != os.getpid() and not _alive(int(pid)):
                found.append(target.parent / name)
    return found


def write_atomic(path: str | os.PathLike[str], data: str | bytes, *, exclusive: bool = False) -> Path:
    """Write ``data`` to ``path`` through a temporary file, fsync and rename; with
    ``exclusive``, an existing ``path`` (a file, a folder, a link) is never replaced:
    ``FileExistsError`` (the temporary file is linked into place, which fails if the
    name is taken; where the filesystem has no links, the name is checked first).

    Parent folders are created, and temporary files that killed writers left beside
    ``path`` are removed. On any error the previous file, if any, is untouched, the
    temporary file is removed, and the ``OSError`` raised names ``path`` (not the
    temporary file).

    >>> import tempfile, pathlib
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "sub" / "a.txt"
    >>> write_atomic(target, "hello").read_text()
    'hello'
    """
    target = Path(path)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    tmp: str | None = None
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        for old in stale_temporaries(target):
            old.unlink(missing_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.{os.getpid()}.", suffix=SUFFIX, dir=target.parent)
        with os.fdopen(fd, "wb") as handle:
            os.fchmod(handle.fileno(), 0o666 & ~current_umask())    # as open() would, not mkstemp's 0600
            handle.write(payload)
            handle.flush()
            os.fsync(handle.fileno())
        (_move_new if exclusive else os.replace)(tmp, target)
        tmp = None
        dir_fd = os.open(target.parent, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)
    except OSError as err:
        raise OSError(err.errno, err.strerror, str(target)) from None
    finally:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)
    return target


def _move_new(tmp: str, target: Path) -> None:
    """Move ``tmp`` to ``target`` unless ``target`` exists (``FileExistsError``)."""
    try:
        os.link(tmp, target, follow_symlinks=False)
    except OSError as err:
        if err.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.ENOSYS):
            raise
        if os.path.lexists(target):             # no hard links here (FAT, some network filesystems)
            raise FileExistsError(errno.EEXIST, os.strerror(errno.EEXIST), str(target)) from None
        os.replace(tmp, target)
    else:
        os.unlink(tmp)


def current_umask() -> int:
    """The process's umask (read by setting and restoring it).

    >>> 0 <= current_umask() <= 0o777
    True
    """
    mask = os.umask(0o022)
    os.umask(mask)
    return mask
