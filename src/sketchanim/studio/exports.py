"""Where a studio export may be written, and writing it.

A page names an export by a bare file name; it goes into the studio's exports folder
(the project's, unless the studio was started with ``--exports DIR``). :func:`target`
checks the name as the file system would take it and refuses the project's own files;
:func:`write` writes atomically and never replaces a file unless asked to, a folder
never. Every refusal is an :class:`~sketchanim.errors.InputError` naming the file:
:class:`ExportExists` (the name is taken), :class:`ExportFailed` (the system could not
write it, with its reason), :class:`~sketchanim.errors.ArgumentError` (not a name an
export may have).
"""

from __future__ import annotations

import os
import unicodedata
from pathlib import Path

from sketchanim.atomic import SUFFIX, write_atomic
from sketchanim.errors import ArgumentError, StorageError

#: What an export may be: a glTF scene or the project as JSON.
SUFFIXES = (".glb", ".json")
#: Longest name a file system takes (bytes, as the system encodes it)...
NAME_MAX = 255
#: ...less what the temporary file written first adds to it
#: (``.NAME.PID.RANDOM.sketchanim-tmp``, a pid of up to 7 digits, 8 random characters).
MAX_NAME_BYTES = NAME_MAX - len(f"..1234567.abcdefgh.{SUFFIX}")
#: Ends of the names beside a project that are its own (SQLite's logs, the studio's lock
#: and take notes, anything else ``<project>.``...).
OWN_ENDINGS = ("-wal", "-shm", "-journal", ".")


class ExportExists(ArgumentError):
    """The export's name is taken: a file (replaced only when asked to) or a folder."""


class ExportFailed(StorageError):
    """The system could not write the export (its reason in the message)."""


def _key(name: str) -> str:
    """``name`` as a case-insensitive, normalising file system compares it."""
    return unicodedata.normalize("NFC", name).casefold()


def _refuse(name: str, why: str) -> ArgumentError:
    return ArgumentError("file", f"{name!r}: {why}")


def _exists(name: str) -> ExportExists:
    return ExportExists("file", f"{name!r} exists in the exports folder (export again with overwrite to replace it)")


def _own(name: str, project: Path) -> bool:
    """Whether ``name`` is one of the project's files, or a companion of any project
    (``*.sketchanim.*``), in the project's folder."""
    key, own = _key(name), _key(project.name)
    return key == own or any(key.startswith(own + end) for end in OWN_ENDINGS) or ".sketchanim." in key


def checked_name(name: str, project: Path, suffixes: tuple[str, ...] = SUFFIXES, what: str = "exports") -> str:
    """``name`` if it is a bare file name (:func:`check_name`) ending in one of
    ``suffixes``, and none of the files of ``project``; :class:`~sketchanim.errors.ArgumentError` naming
    it otherwise (``what``: what such files are, for the message). The rules of
    :func:`target`; the studio's sounds (:mod:`.sounds`) are named by them too.

    >>> checked_name("beat.wav", Path("show.sketchanim"), (".wav",), "sounds")
    'beat.wav'
    >>> checked_name("beat.txt", Path("show.sketchanim"), (".wav",), "sounds")
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: file: 'beat.txt': sounds are .wav
    """
    check_name(name, f"the {what} folder")
    if Path(name).suffix.lower() not in suffixes:
        raise _refuse(name, f"{what} are {' or '.join(suffixes)}")
    if _own(name, project):
        raise _refuse(name, "one of the project's own files")
    return name


def target(folder: Path, name: str, project: Path, overwrite: bool = False) -> Path:
    """Where the export ``name`` goes in ``folder`` (the exports folder of the studio of
    ``project``): ``folder / name``, if ``name`` is a bare file name (no separator, no
    control character, not hidden, at most :data:`MAX_NAME_BYTES` bytes) ending in
    ``.glb`` or ``.json``, none of the project's own files (:func:`checked_name`), and
    not taken (a folder is never replaced, a file only with ``overwrite``).

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> target(folder, "shot.glb", folder / "show.sketchanim") == folder / "shot.glb"
    True
    >>> target(folder, "show.sketchanim.take.json", folder / "show.sketchanim")
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: file: 'show.sketchanim.take.json': one of the project's own files
    >>> target(folder, "../x.glb", folder / "show.sketchanim")
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: file: '../x.glb': a file name in the exports folder, not a path
    """
    checked_name(name, project)
    path = folder / name
    if path.is_dir():
        raise ExportExists("file", f"{name!r} is a folder in the exports folder; it is never replaced")
    if not overwrite and os.path.lexists(path):
        raise _exists(name)
    return path


def check_name(name: str, folder: str) -> str:
    """``name``, if it is a bare file name for ``folder`` (words naming it): not empty,
    no separator, no control character, not hidden, at most :data:`MAX_NAME_BYTES`
    bytes; else an :class:`ArgumentError` saying which.

    >>> check_name("shot.glb", "the exports folder")
    'shot.glb'
    >>> check_name("a/b.sketchanim", "the project's folder")
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: file: 'a/b.sketchanim': a file name in the project's folder, not a path
    """
    if not name:
        raise _refuse(name, "needs a file name")
    if any(unicodedata.category(c) in ("Cc", "Cs") for c in name):
        raise _refuse(name, "a file name holds no control characters (NUL, newline...) or lone surrogates")
    if any(sep and sep in name for sep in ("/", "\\", os.sep, os.altsep)):
        raise _refuse(name, f"a file name in {folder}, not a path")
    if name in (".", "..") or name.startswith("."):
        raise _refuse(name, "a file name that is not hidden (it starts with '.')")
    size = len(os.fsencode(name))
    if size > MAX_NAME_BYTES:
        raise _refuse(name[:40] + "...", f"{size} bytes long; a name has at most {MAX_NAME_BYTES}")
    return name


def write(path: Path, data: bytes, overwrite: bool = False) -> Path:
    """Write ``data`` at ``path`` (found by :func:`target`) atomically: an existing file
    is replaced only with ``overwrite`` (:class:`ExportExists`); what the system refuses
    (no space, no permission, read-only...) raises :class:`ExportFailed` naming the file
    and the reason, and leaves nothing behind (a replaced file stays as it was).

    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "a.json"
    >>> write(path, b"{}").read_bytes()
    b'{}'
    >>> write(path, b"[]")
    Traceback (most recent call last):
    ...
    sketchanim.studio.exports.ExportExists: file: 'a.json' exists in the exports folder (export again with overwrite to replace it)
    """
    try:
        return write_atomic(path, data, exclusive=not overwrite)
    except FileExistsError:
        raise _exists(path.name) from None
    except OSError as err:
        raise failed(path, err) from None


def failed(path: Path, err: OSError) -> ExportFailed:
    """The export to ``path`` could not be made: the system's reason, ``err``.

    >>> import errno
    >>> failed(Path("a.glb"), OSError(errno.ENOSPC, "No space left on device"))
    ExportFailed("file: 'a.glb': cannot be written (No space left on device)")
    """
    return ExportFailed(f"file: {path.name!r}: cannot be written ({err.strerror or err})")
