"""What each message from a page does: a call on the session for its ``type``.

A handler takes the session, the message (already validated, see
:mod:`sketchanim.studio.protocol`) and the sending client's number, and returns the
messages to send (:data:`~sketchanim.studio.protocol.Out`). Every call runs in the
session's one thread, in order. The undoable operations are the commands the editor
runs (:mod:`sketchanim.anim.commands`); this only maps messages to them.

A read-only project refuses the messages that edit (:data:`EDITS`) before they run;
:func:`error_code` gives the code of the error reply for what a handler raised.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from sketchanim.errors import InputError, StorageError
from sketchanim.studio import protocol as p
from sketchanim.studio.exports import ExportExists
from sketchanim.studio.session import Session

Handler = Callable[[Session, p.Message, int], list[p.Out]]

HANDLERS: dict[str, Handler] = {
    "ping": lambda s, m, client: [("self", p.wire(p.Pong(id=m.id, server_time=time.time())))],
    "state": lambda s, m, client: [("self", s.state())],
    "set": lambda s, m, client: s.set(m.path, m.value, m.label, m.merge),
    "preview": lambda s, m, client: s.preview(m, client),
    "object.add": lambda s, m, client: s.add_object(m.name, m.kind, None if m.position is None else list(m.position)),
    "object.duplicate": lambda s, m, client: s.duplicate_object(m.name, m.to),
    "object.remove": lambda s, m, client: s.remove_object(m.name),
    "object.rename": lambda s, m, client: s.rename_object(m.name, m.to),
    "take.begin": lambda s, m, client: s.begin_take(client, m.take, m.paths, m.mode, m.blend, m.time, m.speed,
                                                    m.tol, m.loop, m.gap, m.smoothing),
    "take.samples": lambda s, m, client: s.samples(client, m.take, np.asarray(m.t, dtype=float), m.values),
    "take.end": lambda s, m, client: s.end_take(client, m.take, m.label),
    "take.cancel": lambda s, m, client: s.cancel_take(client, m.take),
    "undo": lambda s, m, client: s.undo(),
    "redo": lambda s, m, client: s.redo(),
    "transport": lambda s, m, client: s.set_transport(m),
    "tolerance.set": lambda s, m, client: s.set_tolerance(m.path, m.amount, m.unit),
    "export": lambda s, m, client: [("self", p.wire(p.Exported(file=s.export(m.file, m.overwrite).name)))],
    "curve.points": lambda s, m, client: s.move_points(m.edits, m.label),
    "curve.key": lambda s, m, client: s.move_key(m.path, m.time, m.value, m.slope, m.label),
    "curve.knots": lambda s, m, client: s.edit_knots(m.path, m.insert, m.remove),
    "track.key": lambda s, m, client: s.key(m.path, m.time, m.value),
    "track.reduce": lambda s, m, client: s.reduce(m.paths, m.tol, m.preview),
    "track.samples": lambda s, m, client: s.kept_samples(m.path)(),
    "take.edit": lambda s, m, client: s.edit_take(m.path, m.take, m.op, m.name, m.to, m.by, m.factor, m.pivot),
    "settings": lambda s, m, client: s.set_settings(m.fps),
    "track.retime": lambda s, m, client: s.retime(m.paths, m.factor, m.pivot, m.shift),
    "track.cut": lambda s, m, client: s.cut(m.paths, m.t0, m.t1),
    "track.copy": lambda s, m, client: s.copy(m.path, m.t0, m.t1),
    "track.paste": lambda s, m, client: s.paste(m.path, m.at, m.piece, m.length),
    # sounds (studio/sounds.py, studio/beats.py); the app finds beats beside the model's thread
    "sound.set": lambda s, m, client: s.set_sound(m.name, m.offset),
    "sound.remove": lambda s, m, client: s.remove_sound(m.name),
    "sound.beats": lambda s, m, client: s.beats_found(s.beat_finding(m.name, m.path)()),
}

#: The messages that change the project (refused on a read-only one; a ``track.reduce``
#: preview changes nothing and is not refused).
EDITS = frozenset({"set", "preview", "object.add", "object.duplicate", "object.remove", "object.rename", "take.begin",
                   "take.samples", "take.end", "take.cancel", "undo", "redo", "tolerance.set", "curve.points",
                   "curve.key", "curve.knots", "track.key", "track.reduce", "take.edit", "settings",
                   "track.retime", "track.cut", "track.paste", "sound.set", "sound.remove", "sound.beats"})


def check_writable(session: Session, message: p.Message) -> None:
    """Raise :class:`ReadOnlyProject` if ``message`` would change (:data:`EDITS`, but a
    preview) a project open read-only."""
    if session.read_only and message.type in EDITS and not getattr(message, "preview", False):
        raise ReadOnlyProject(f"{message.type}: {session.path.name} is open read-only (started with --read-only, or "
                              "its file or folder cannot be written), so edits are refused; playback and export "
                              "still work (export to a writable folder: start the studio with --exports DIR)")


class ReadOnlyProject(InputError):
    """An edit sent to a project open read-only."""


def error_code(message: p.Message, err: InputError, session: Session) -> p.ErrorCode:
    """The code of the error reply when ``message`` was refused with ``err``:
    ``read_only`` (an edit on a read-only project), ``exists`` (an export's name is
    taken), ``failed`` (the disk or the folder refused a write), ``busy`` (a take is
    already being recorded), else ``refused``.

    >>> import tempfile, pathlib
    >>> session = Session(pathlib.Path(tempfile.mkdtemp()) / "a.sketchanim")
    >>> error_code(p.parse('{"type": "undo"}'), StorageError("the disk is full"), session)
    'failed'
    >>> error_code(p.parse('{"type": "export", "file": "a.glb"}'), ExportExists("file", "'a.glb' exists"), session)
    'exists'
    >>> session.close()
    """
    if isinstance(err, ReadOnlyProject):
        return "read_only"
    if isinstance(err, ExportExists):
        return "exists"
    if isinstance(err, StorageError):
        return "failed"
    if message.type == "take.begin" and session.take is not None:
        return "busy"
    return "refused"


def handle(session: Session, message: p.Message, client: int) -> list[p.Out]:
    """Run ``message`` on ``session`` for ``client``; the messages to send. An edit
    on a read-only project raises :class:`ReadOnlyProject` (:func:`check_writable`).

    >>> import tempfile, pathlib
    >>> session = Session(pathlib.Path(tempfile.mkdtemp()) / "a.sketchanim")
    >>> handle(session, p.parse('{"type": "set", "path": "lamp.intensity", "value": [2]}'), 0)[0]
    ('all', {'type': 'values', 'values': {'lamp.intensity': [2.0]}})
    >>> session.close()
    """
    check_writable(session, message)
    return HANDLERS[message.type](session, message, client)
