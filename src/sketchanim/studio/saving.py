"""Whether the project is on disk: the studio's save status, and where the model goes when
the project's own folder cannot take it.

A save that fails (the disk is full, the folder cannot be written or is gone, the
database is locked) loses nothing: the model keeps what was not saved and the studio
tries again every :data:`RETRY` seconds. :class:`SaveStatus` turns the outcome of each
try into what the pages are told (a ``saved`` message and a notice, when the status
changes, not at every failed retry) and what the log says. If the studio stops while
saves fail, :func:`rescue` writes the model as a new project where it can.
"""

from __future__ import annotations

import contextlib
import errno
import logging
import os
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path

from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import Track
from sketchanim.errors import InputError
from sketchanim.project.document import SoundDoc, ToleranceDoc
from sketchanim.project.store import Project
from sketchanim.studio import protocol as p

#: Seconds between tries to save while saving fails.
RETRY = 2.0

log = logging.getLogger("sketchanim.studio")


def write_fault(err: BaseException) -> str:
    """What went wrong with a write, in a few words (the OS's own for an ``OSError``).

    >>> write_fault(OSError(errno.ENOSPC, "No space left on device", "/p/show.sketchanim"))
    'No space left on device (/p/show.sketchanim)'
    """
    if isinstance(err, OSError) and err.strerror:
        return f"{err.strerror} ({err.filename})" if err.filename else err.strerror
    return str(err)


class SaveStatus:
    """The outcome of the saves so far, as the pages see it (:class:`~.protocol.Saved`).

    What the pages are to be told of a change waits in it until :meth:`news` takes it
    (whoever answers next: a save's caller, or the studio's next tick).

    >>> status = SaveStatus("show.sketchanim")
    >>> status.failed(OSError(errno.ENOSPC, "No space left on device"), now=5.0)
    >>> [m["type"] for _, m in status.news()]
    ['saved', 'notice']
    >>> status.failed(OSError(errno.ENOSPC, "No space left on device"), now=7.0)
    >>> status.news(), status.due(8.0)
    ([], False)
    >>> status.succeeded()
    >>> [m["type"] for _, m in status.news()], status.info().ok
    (['saved', 'notice'], True)
    """

    def __init__(self, project: str) -> None:
        self.project = project
        self.error: str | None = None
        self.since: float | None = None            # epoch seconds of the first failure
        self.tried = -float("inf")                 # monotonic time of the last failed try
        self._news: list[p.Out] = []               # messages of a change not yet taken

    @property
    def ok(self) -> bool:
        return self.error is None

    def info(self) -> p.Saved:
        """The status as ``state`` and ``saved`` carry it."""
        return p.Saved(ok=self.ok, error=self.error, since=self.since)

    def due(self, now: float) -> bool:
        """Whether a failed save should be tried again at monotonic time ``now``."""
        return now - self.tried >= RETRY

    def news(self) -> list[p.Out]:
        """The messages for the pages of what changed since the last call (taken)."""
        news, self._news = self._news, []
        return news

    def failed(self, err: BaseException, now: float | None = None) -> None:
        """A save failed with ``err`` at monotonic time ``now``: news for the pages if
        it is (the first failure, or another reason)."""
        self.tried = time.monotonic() if now is None else now
        text = f"cannot save {self.project}: {write_fault(err)}"
        if text == self.error:
            return
        first = self.error is None
        self.error = text
        if first:
            self.since = time.time()
        log.error("%s; kept in memory, trying again every %g s", text, RETRY)
        self._news += [("all", p.wire(self.info())),
                ("all", p.wire(p.Notice(level="error", source="disk",
                                        text=f"{text}. Nothing is lost: the studio keeps it and saves it as "
                                             f"soon as it can (trying every {RETRY:g} s).")))]

    def succeeded(self) -> None:
        """A save went through: news for the pages if saves were failing."""
        if self.ok:
            return
        log.warning("saved %s again", self.project)
        self.error, self.since, self.tried = None, None, -float("inf")
        self._news += [("all", p.wire(self.info())),
                ("all", p.wire(p.Notice(level="info", source="disk", text=f"saved {self.project} again")))]


def rescue(project: Path, scene: Scene, tracks: Mapping[str, Track], tolerances: dict[str, ToleranceDoc],
           sounds: list[SoundDoc] | None = None) -> Path:
    """Write the model (its sounds' references too) as a new project named for ``project``
    and the time, in the first of its folder, the user's cache and the temporary folder
    that takes it; the path written, or the ``OSError`` of the last place tried.

    >>> folder = Path(tempfile.mkdtemp())
    >>> scene = Scene(); _ = scene.add("box")
    >>> rescue(folder / "show.sketchanim", scene, {}, {}).name.startswith("show.rescued-")
    True
    """
    stamp = time.strftime("%Y%m%d-%H%M%S")
    name = f"{project.stem}.rescued-{stamp}-{os.getpid()}.sketchanim"
    places = [project.parent, Path.home() / ".cache" / "sketchanim", Path(tempfile.gettempdir())]
    last: BaseException = OSError(errno.ENOSPC, "nowhere to write")
    for folder in places:
        target = folder / name
        try:
            folder.mkdir(parents=True, exist_ok=True)
            with Project(target) as copy:
                copy.save(scene, dict(tracks), tolerances, sounds=sounds)
            return target
        except (OSError, InputError) as err:
            last = err
            for left in (target, target.with_name(target.name + "-wal"), target.with_name(target.name + "-shm")):
                with contextlib.suppress(OSError):
                    left.unlink(missing_ok=True)
    raise last if isinstance(last, OSError) else OSError(errno.EIO, str(last))
