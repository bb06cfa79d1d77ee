"""What each message from a page does: a call on the session for its ``type``.

A handler takes the session, the message (already validated, see
:mod:`sketchanim.studio.protocol`) and the sending client's number, and returns the
messages to send (:data:`~sketchanim.studio.protocol.Out`). Every call runs in the
session's one thread, in order. The undoable operations are the commands the editor
runs (:mod:`sketchanim.anim.commands`); this only maps messages to them.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from sketchanim.errors import InputError, StorageError

from sketchanim.studio import protocol as p
from sketchanim.studio.session import Session

Handler = Callable[[Session, p.Message, int], list[p.Out]]

HANDLERS: dict[str, Handler] = {
    "ping": lambda s, m, client: [("self", p.wire(p.Pong(id=m.id, server_time=time.time())))],
    "state": lambda s, m, client: [("self", s.state())],
    "set": lambda s, m, client: s.set(m.path, m.value, m.label, m.merge),
    "preview": lambda s, m, client: s.preview(m, client),
    "object.add": lambda s, m, client: s.add_object(m.name, m.kind),
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
    "export": lambda s, m, client: [("self", p.wire(p.Exported(file=s.export(m.file).name)))],
}


def error_code(message: p.Message, err: InputError, session: Session) -> p.ErrorCode:
    """The code of the error reply when ``message`` was refused with ``err``.

    >>> import tempfile, pathlib
    >>> session = Session(pathlib.Path(tempfile.mkdtemp()) / "a.sketchanim")
    >>> error_code(p.parse('{"type": "undo"}'), StorageError("the disk is full"), session)
    'failed'
    >>> session.close()
    """
    if isinstance(err, StorageError):
        return "failed"
    if message.type == "take.begin" and session.take is not None:
        return "busy"
    return "refused"


def handle(session: Session, message: p.Message, client: int) -> list[p.Out]:
    """Run ``message`` on ``session`` for ``client``; the messages to send.

    >>> import tempfile, pathlib
    >>> session = Session(pathlib.Path(tempfile.mkdtemp()) / "a.sketchanim")
    >>> handle(session, p.parse('{"type": "set", "path": "lamp.intensity", "value": [2]}'), 0)[0]
    ('all', {'type': 'values', 'values': {'lamp.intensity': [2.0]}})
    >>> session.close()
    """
    return HANDLERS[message.type](session, message, client)
