"""A message from a page becomes a call on the session.

Each command takes the session, the message (already validated, see
:mod:`sketchanim.studio.protocol`), the sending client's number and whether the server is
ready, and returns the messages to send (see :data:`sketchanim.studio.session.Out`).
Every call runs in the session's one thread, in order.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from sketchanim.studio import protocol as p
from sketchanim.studio.session import Out, Session

Command = Callable[[Session, p.Message, int, bool], list[Out]]


def _ping(s: Session, m: p.Ping, client: int, ready: bool) -> list[Out]:
    return [("self", {"type": "pong", "id": m.id, "server_time": time.time()})]


def _state(s: Session, m: p.StateRequest, client: int, ready: bool) -> list[Out]:
    return [("self", s.state(ready))]


def _set(s: Session, m: p.Set, client: int, ready: bool) -> list[Out]:
    return s.set(m.path, m.value, m.label, m.merge, ready)


def _preview(s: Session, m: p.Preview, client: int, ready: bool) -> list[Out]:
    s.preview(m.path, m.value)
    return [("others", {"type": "preview", "key": m.key, "path": m.path, "value": m.value})]


def _add(s: Session, m: p.ObjectAdd, client: int, ready: bool) -> list[Out]:
    return s.add_object(m.name, m.kind, ready)


def _remove(s: Session, m: p.ObjectRemove, client: int, ready: bool) -> list[Out]:
    return s.remove_object(m.name, ready)


def _rename(s: Session, m: p.ObjectRename, client: int, ready: bool) -> list[Out]:
    return s.rename_object(m.name, m.to, ready)


def _begin(s: Session, m: p.TakeBegin, client: int, ready: bool) -> list[Out]:
    return s.begin_take(client, m.take, m.paths, m.mode, m.blend, m.time, m.speed, m.tol, m.loop, m.gap)


def _samples(s: Session, m: p.TakeSamples, client: int, ready: bool) -> list[Out]:
    return s.samples(client, m.take, np.asarray(m.t, dtype=float), m.values)


def _end(s: Session, m: p.TakeEnd, client: int, ready: bool) -> list[Out]:
    return s.end_take(client, m.take, m.label, ready)


def _cancel(s: Session, m: p.TakeCancel, client: int, ready: bool) -> list[Out]:
    return s.cancel_take(client, m.take)


def _undo(s: Session, m: p.Undo, client: int, ready: bool) -> list[Out]:
    return s.undo(ready)


def _redo(s: Session, m: p.Redo, client: int, ready: bool) -> list[Out]:
    return s.redo(ready)


def _transport(s: Session, m: p.Transport, client: int, ready: bool) -> list[Out]:
    s.transport = {"time": m.time, "playing": m.playing, "speed": m.speed,
                   "loop": None if m.loop is None else list(m.loop)}
    return [("others", {"type": "transport", **s.transport})]


def _export(s: Session, m: p.Export, client: int, ready: bool) -> list[Out]:
    written = s.export(m.file)
    return [("self", {"type": "exported", "file": written.name})]


COMMANDS: dict[str, Command] = {
    "ping": _ping, "state": _state, "set": _set, "preview": _preview, "object.add": _add,
    "object.remove": _remove, "object.rename": _rename, "take.begin": _begin, "take.samples": _samples,
    "take.end": _end, "take.cancel": _cancel, "undo": _undo, "redo": _redo, "transport": _transport,
    "export": _export,
}


def execute(session: Session, message: p.Message, client: int, ready: bool) -> list[Out]:
    """Run ``message`` on ``session`` for ``client``; the messages to send.

    >>> import tempfile, pathlib
    >>> session = Session(pathlib.Path(tempfile.mkdtemp()) / "a.sketchanim")
    >>> execute(session, p.parse('{"type": "set", "path": "lamp.intensity", "value": [2]}'), 0, True)[0]
    ('all', {'type': 'values', 'values': {'lamp.intensity': [2.0]}})
    >>> session.close()
    """
    return COMMANDS[message.type](session, message, client, ready)
