"""Editing a track's takes as layers: rename, mute, solo, delete, reorder, keep one
pass of a loop recording, and move or stretch one in time. Each edit is a function from takes to takes (a track's are a
tuple, never changed in place); the track's curve is composed again from the result
(:func:`.layers.recomposed`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from sketchanim.anim.tracks import Take
from sketchanim.errors import ArgumentError

#: What :func:`edited_takes` can do to a take.
TAKE_OPS = ("rename", "mute", "unmute", "solo", "delete", "move", "keep", "shift", "scale")


def retimed_take(take: Take, factor: float = 1.0, pivot: float = 0.0, shift: float = 0.0) -> Take:
    """``take`` with each sample time ``t`` at ``pivot + factor * (t - pivot) + shift``
    (``factor`` > 0); its seconds of blend and smoothing stretched by ``factor`` with it,
    so that the take plays as before, in the new time.

    >>> take = Take(np.array([1.0, 2.0, 3.0]), np.zeros((3, 1)), blend=0.1)
    >>> moved = retimed_take(take, 2.0, pivot=1.0, shift=0.5)
    >>> moved.times.tolist(), moved.blend
    ([1.5, 3.5, 5.5], 0.2)
    """
    for field, x in (("factor", factor), ("pivot", pivot), ("shift", shift)):
        if not np.isfinite(x):
            raise ArgumentError(field, f"must be finite, got {x!r}")
    if not factor > 0:
        raise ArgumentError("factor", f"a time scale must be > 0, got {factor!r}")
    times = pivot + factor * (np.asarray(take.times, dtype=float) - pivot) + shift
    return replace(take, times=times, blend=take.blend * factor, smoothing=take.smoothing * factor)


def edited_takes(takes: Sequence[Take], index: int, op: str, name: str | None = None,
                 to: int | None = None, by: float | None = None, factor: float | None = None,
                 pivot: float | None = None) -> tuple[Take, ...]:
    """``takes`` after ``op`` on take ``index``: ``rename`` it ``name`` ("" clears it),
    ``mute`` / ``unmute`` it, ``solo`` it (it alone plays), ``delete`` it, ``move`` it
    to index ``to``, ``keep`` its pass of a loop recording (that pass's takes play,
    the other passes' are muted), ``shift`` it later by ``by`` seconds, or ``scale`` its
    times by ``factor`` about ``pivot`` (its start if None; :func:`retimed_take`).
    Leaving only muted takes is refused: a track plays at least one (deleting its last
    take leaves none: the track goes).

    >>> import numpy as np
    >>> t = np.linspace(0, 1, 5)
    >>> takes = (Take(t, np.c_[t]), Take(t, np.c_[t], "additive", name="wobble"))
    >>> [x.name for x in edited_takes(takes, 1, "move", to=0)], [x.muted for x in edited_takes(takes, 1, "solo")]
    (['wobble', ''], [True, False])
    >>> edited_takes(takes, 1, "scale", factor=2.0)[1].times.tolist()
    [0.0, 0.5, 1.0, 1.5, 2.0]
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
    elif op == "shift":
        if by is None:
            raise ArgumentError("by", "a take shifts by a number of seconds, got none")
        out = _put(takes, index, retimed_take(take, shift=by))
    elif op == "scale":
        if factor is None:
            raise ArgumentError("factor", "a take scales by a factor > 0, got none")
        out = _put(takes, index, retimed_take(take, factor, take.start if pivot is None else pivot))
    else:
        raise ArgumentError("op", f"must be one of {', '.join(TAKE_OPS)}, got {op!r}")
    if all(t.muted for t in out):
        raise ArgumentError("take", "a track plays at least one take: unmute another first, or delete the take")
    return out


def _put(takes: tuple[Take, ...], index: int, take: Take) -> tuple[Take, ...]:
    return takes[:index] + (take,) + takes[index + 1:]
