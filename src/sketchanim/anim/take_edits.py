"""Editing a track's takes as layers: rename, mute, solo, delete, reorder, and keep one
pass of a loop recording. Each edit is a function from takes to takes (a track's are a
tuple, never changed in place); the track's curve is composed again from the result
(:func:`.layers.recomposed`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from sketchanim.anim.tracks import Take
from sketchanim.errors import ArgumentError

#: What :func:`edited_takes` can do to a take.
TAKE_OPS = ("rename", "mute", "unmute", "solo", "delete", "move", "keep")


def edited_takes(takes: Sequence[Take], index: int, op: str, name: str | None = None,
                 to: int | None = None) -> tuple[Take, ...]:
    """``takes`` after ``op`` on take ``index``: ``rename`` it ``name`` ("" clears it),
    ``mute`` / ``unmute`` it, ``solo`` it (it alone plays), ``delete`` it, ``move`` it
    to index ``to``, or ``keep`` its pass of a loop recording (that pass's takes play,
    the other passes' are muted). Leaving only muted takes is refused: a track plays at
    least one (deleting its last take leaves none: the track goes).

    >>> import numpy as np
    >>> t = np.linspace(0, 1, 5)
    >>> takes = (Take(t, np.c_[t]), Take(t, np.c_[t], "additive", name="wobble"))
    >>> [x.name for x in edited_takes(takes, 1, "move", to=0)], [x.muted for x in edited_takes(takes, 1, "solo")]
    (['wobble', ''], [True, False])
    """
    takes = tuple(takes)
    if not 0 <= index < len(takes):
        raise ArgumentError("take", f"take {index} of {len(takes)}")
    take = takes[index]
    if op == "rename":
        name = (name or "").strip()
        if len(name) > 64 or not name.isprintable():
            raise ArgumentError("name", f"a take's name is up to 64 printable characters, got {name[:80]!r}")
        out = _put(takes, index, replace(take, name=name))
    elif op in ("mute", "unmute"):
        out = _put(takes, index, replace(take, muted=op == "mute"))
    elif op == "solo":
        out = tuple(replace(t, muted=i != index) for i, t in enumerate(takes))
    elif op == "delete":
        out = takes[:index] + takes[index + 1:]
        if not out:
            return out                                     # the track goes with its last take
    elif op == "move":
        if to is None or not 0 <= to < len(takes):
            raise ArgumentError("to", f"a take moves to an index in 0..{len(takes) - 1}, got {to!r}")
        rest = takes[:index] + takes[index + 1:]
        out = rest[:to] + (take,) + rest[to:]
    elif op == "keep":
        if take.loop is None:
            raise ArgumentError("take", f"take {index} is not a pass of a loop recording")
        out = tuple(replace(t, muted=t.loop_pass != take.loop_pass) if t.loop == take.loop else t for t in takes)
    else:
        raise ArgumentError("op", f"must be one of {', '.join(TAKE_OPS)}, got {op!r}")
    if all(t.muted for t in out):
        raise ArgumentError("take", "a track plays at least one take: unmute another first, or delete the take")
    return out


def _put(takes: tuple[Take, ...], index: int, take: Take) -> tuple[Take, ...]:
    return takes[:index] + (take,) + takes[index + 1:]
