"""The project's sounds: audio files imported into the project's folder and referred to
by the project (name, path, checksum, duration, offset on the timeline).

An import is checked before anything changes: the name as exports are named
(:func:`~.exports.checked_name`, with the audio suffixes), the size against a cap (read
in chunks: never more than the cap in memory), and the bytes decoded by libsndfile
(``soundfile``: WAV, FLAC, OGG/Vorbis/Opus, MP3, AIFF) for the duration; refused,
nothing is written. Stored atomically in ``<project stem>.sounds/NAME`` beside the
project, with its SHA-256. On loading, each file is checked again: ``ok``, ``missing``
(gone, or its path leaves the project's folder) or ``changed`` (its checksum differs),
reported and never a crash.

Sounds are a project setting, like the take tolerances and the frame rate, not History
steps: the file an import brought stays on disk whatever is undone, and undo stays with
what the animator made (a beat track baked from a sound is one History step:
:mod:`.beats`).
"""

from __future__ import annotations

import hashlib
import io
from collections.abc import AsyncIterator
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

import soundfile

from sketchanim.atomic import write_atomic
from sketchanim.errors import ArgumentError, FileFormatError, InputError, StorageError
from sketchanim.project.document import SoundDoc, SoundStatus
from sketchanim.studio.exports import checked_name

#: What a sound's file may be called (libsndfile decodes these).
SUFFIXES = (".wav", ".flac", ".ogg", ".oga", ".opus", ".mp3", ".aif", ".aiff")
#: The largest sound file an import takes, in bytes (10 minutes of 48 kHz 24-bit stereo
#: WAV is 173 MB).
MAX_SOUND_BYTES = 200 * 2**20
#: Bytes read at a time when a file is hashed.
CHUNK = 2**20


class SoundTooLarge(InputError):
    """An import over the size cap (HTTP 413)."""


class NotAudio(FileFormatError):
    """Bytes libsndfile cannot decode as audio (HTTP 415)."""


class SoundExists(ArgumentError):
    """A sound of that name is in the project already (HTTP 409)."""


class NoSuchSound(ArgumentError):
    """No sound of that name in the project (HTTP 404)."""


def sounds_folder(project: Path) -> Path:
    """Where the sounds of ``project`` are stored: ``<stem>.sounds`` beside it.

    >>> sounds_folder(Path("/shows/pilot.sketchanim")).as_posix()
    '/shows/pilot.sounds'
    """
    return project.with_name(project.stem + ".sounds")


def sound_name(name: str, project: Path) -> str:
    """``name`` if a sound may be called so: a bare file name (the rules of exports) with
    an audio suffix (:data:`SUFFIXES`); :class:`~sketchanim.errors.ArgumentError` naming it.

    >>> sound_name("take one.wav", Path("show.sketchanim"))
    'take one.wav'
    >>> sound_name("../x.wav", Path("show.sketchanim"))
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: file: '../x.wav': a file name in the sounds folder, not a path
    """
    return checked_name(name, project, SUFFIXES, "sounds")


async def read_capped(chunks: AsyncIterator[bytes], name: str, limit: int = MAX_SOUND_BYTES) -> bytes:
    """The bytes of an upload, read chunk by chunk; :class:`SoundTooLarge` naming ``name``
    as soon as they pass ``limit`` (what came is dropped: never more than ``limit`` kept).

    >>> import asyncio
    >>> async def body():
    ...     yield b"abc"; yield b"def"
    >>> asyncio.run(read_capped(body(), "a.wav", 6))
    b'abcdef'
    >>> asyncio.run(read_capped(body(), "a.wav", 5))
    Traceback (most recent call last):
    ...
    sketchanim.studio.sounds.SoundTooLarge: 'a.wav': over 5 bytes, the largest sound the studio imports
    """
    parts: list[bytes] = []
    size = 0
    async for chunk in chunks:
        size += len(chunk)
        if size > limit:
            parts.clear()
            raise SoundTooLarge(too_large(name, limit))
        parts.append(chunk)
    return b"".join(parts)


def too_large(name: str, limit: int) -> str:
    """The refusal of a sound over ``limit`` bytes.

    >>> too_large("a.wav", 200 * 2**20)
    "'a.wav': over 209715200 bytes, the largest sound the studio imports"
    """
    return f"{name!r}: over {limit} bytes, the largest sound the studio imports"


@dataclass(frozen=True)
class Decoded:
    """What libsndfile read of a sound: its duration (s), sample rate (Hz), channels."""

    duration: float
    rate: int
    channels: int


def decoded(data: bytes, name: str) -> Decoded:
    """Check that ``data`` is audio libsndfile decodes (its header, and its first
    frames); :class:`NotAudio` naming ``name`` and what libsndfile said otherwise.

    >>> import numpy as np
    >>> buffer = io.BytesIO(); soundfile.write(buffer, np.zeros(8000), 8000, format="WAV")
    >>> decoded(buffer.getvalue(), "a.wav")
    Decoded(duration=1.0, rate=8000, channels=1)
    >>> decoded(b"not audio", "a.wav")
    Traceback (most recent call last):
    ...
    sketchanim.studio.sounds.NotAudio: a.wav: not audio the studio can decode (Format not recognised.)
    """
    try:
        with soundfile.SoundFile(io.BytesIO(data)) as sound:
            frames, rate, channels = sound.frames, sound.samplerate, sound.channels
            sound.read(min(frames, 4096))
    except (soundfile.LibsndfileError, RuntimeError, ValueError, TypeError) as err:
        text = str(err).split(": ", 1)[-1] if isinstance(err, soundfile.LibsndfileError) else str(err)
        raise NotAudio(name, f"not audio the studio can decode ({text.strip() or type(err).__name__})") from None
    if frames <= 0 or rate <= 0:
        raise NotAudio(name, f"holds no audio ({frames} frames at {rate} Hz)")
    return Decoded(frames / rate, rate, channels)


def digest(path: Path) -> str:
    """The SHA-256 of the file at ``path``, read in chunks.

    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "a"; _ = path.write_bytes(b"abc")
    >>> digest(path)[:16]
    'ba7816bf8f01cfea'
    """
    h = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(CHUNK):
            h.update(block)
    return h.hexdigest()


def located(sound: SoundDoc, project: Path) -> Path | None:
    """The file of ``sound`` (its path relative to the folder of ``project``), or None
    if the path leaves that folder (a document's path is not trusted).

    >>> doc = SoundDoc(name="a.wav", path="show.sounds/a.wav", sha256="0" * 64, duration=1)
    >>> located(doc, Path("/p/show.sketchanim")).as_posix(), located(doc.model_copy(update={"path": "../x.wav"}), Path("/p/s.sketchanim"))
    ('/p/show.sounds/a.wav', None)
    """
    relative = PurePosixPath(sound.path)
    if relative.is_absolute() or ".." in relative.parts:
        return None
    return project.parent.joinpath(*relative.parts)


def status(sound: SoundDoc, project: Path) -> SoundStatus:
    """Whether the file of ``sound`` is as imported: ``ok``, ``missing`` (gone, not a
    file, unreadable, or outside the project's folder), ``changed`` (another checksum).

    >>> import tempfile
    >>> project = Path(tempfile.mkdtemp()) / "s.sketchanim"
    >>> doc = SoundDoc(name="a.wav", path="s.sounds/a.wav", sha256="0" * 64, duration=1)
    >>> status(doc, project)
    'missing'
    """
    path = located(sound, project)
    try:
        if path is None or not path.is_file():
            return "missing"
        return "ok" if digest(path) == sound.sha256 else "changed"
    except OSError:
        return "missing"


class SoundShelf:
    """The sounds of one project, by name, in import order; each with its status.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> project = Path(tempfile.mkdtemp()) / "show.sketchanim"
    >>> buffer = io.BytesIO(); soundfile.write(buffer, np.zeros(4410), 44100, format="WAV")
    >>> shelf = SoundShelf(project, [])
    >>> doc = shelf.put(shelf.stored("click.wav", buffer.getvalue()))
    >>> doc.path, doc.duration, doc.status, shelf.set_offset("click.wav", 1.5).offset
    ('show.sounds/click.wav', 0.1, 'ok', 1.5)
    >>> shelf.stored("click.wav", buffer.getvalue())
    Traceback (most recent call last):
    ...
    sketchanim.studio.sounds.SoundExists: file: 'click.wav' is a sound of the project already (remove it first, or import with overwrite)
    """

    def __init__(self, project: Path, sounds: list[SoundDoc], limit: int = MAX_SOUND_BYTES) -> None:
        self.project = project
        #: The largest file an import takes, in bytes.
        self.limit = limit
        #: The sounds by name, each with the status its file has now.
        self.sounds: dict[str, SoundDoc] = {s.name: s.model_copy(update={"status": status(s, project)})
                                            for s in sounds}

    def docs(self) -> list[SoundDoc]:
        """The sounds as the project document lists them."""
        return list(self.sounds.values())

    def get(self, name: str) -> SoundDoc:
        """The sound ``name``; :class:`NoSuchSound` if the project has none so called."""
        if name not in self.sounds:
            raise NoSuchSound("name", f"no sound {name!r} in the project")
        return self.sounds[name]

    def path(self, name: str) -> Path:
        """The file of sound ``name``; :class:`NoSuchSound` if there is none or it is missing."""
        sound = self.get(name)
        path = located(sound, self.project)
        if path is None or not path.is_file():
            raise NoSuchSound("name", f"{name!r}: its file {sound.path!r} is missing from the project's folder")
        return path

    def stored(self, name: str, data: bytes, overwrite: bool = False) -> SoundDoc:
        """Store ``data`` as the file of sound ``name``: checked (name, size, decoded)
        before anything is written, then written atomically into the sounds folder;
        refused (:class:`SoundExists`) if the project has a sound of that name, unless
        ``overwrite`` (its offset is kept then). The sound, for :meth:`put` (this
        changes no list: it may run beside the model's thread)."""
        sound_name(name, self.project)
        if len(data) > self.limit:
            raise SoundTooLarge(too_large(name, self.limit))
        if name in self.sounds and not overwrite:
            raise SoundExists("file", f"{name!r} is a sound of the project already (remove it first, or import "
                                      "with overwrite)")
        info = decoded(data, name)
        folder = sounds_folder(self.project)
        try:
            write_atomic(folder / name, data)
        except OSError as err:
            raise StorageError(f"file: {name!r}: cannot be written into {folder.name} "
                               f"({err.strerror or err})") from None
        before = self.sounds.get(name)
        return SoundDoc(name=name, path=f"{folder.name}/{name}", sha256=hashlib.sha256(data).hexdigest(),
                        duration=info.duration, offset=0.0 if before is None else before.offset)

    def put(self, sound: SoundDoc) -> SoundDoc:
        """List ``sound`` (one :meth:`stored` made) among the project's, replacing one of its name."""
        self.sounds[sound.name] = sound
        return sound

    def set_offset(self, name: str, offset: float) -> SoundDoc:
        """Start sound ``name`` at ``offset`` seconds on the timeline (finite)."""
        if not isinstance(offset, (int, float)) or not float("-inf") < offset < float("inf"):
            raise ArgumentError("offset", f"{name!r}: an offset is a finite number of seconds, got {offset!r}")
        self.sounds[name] = self.get(name).model_copy(update={"offset": float(offset)})
        return self.sounds[name]

    def remove(self, name: str) -> None:
        """Drop sound ``name`` from the project (its file stays in the sounds folder:
        nothing the animator brought is deleted)."""
        self.get(name)
        del self.sounds[name]



def http_status(err: Exception) -> int:
    """The HTTP status of an import or a download refused with ``err``: 404 no such
    sound, 409 its name is taken, 413 too large, 415 not audio, 507 the disk refused
    it, 400 a bad name.

    >>> http_status(SoundTooLarge("x")), http_status(NotAudio("a.wav", "not audio")), http_status(ArgumentError("file", "x"))
    (413, 415, 400)
    """
    for kind, code in ((NoSuchSound, 404), (SoundExists, 409), (SoundTooLarge, 413), (NotAudio, 415),
                       (StorageError, 507)):
        if isinstance(err, kind):
            return code
    return 400
