"""The model as the pages see it: the protocol's server-to-page models built from the
scene, its tracks and the history (sent as :func:`~.protocol.wire` makes them)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.history import History
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import DiscreteTrack, Track
from sketchanim.reducer.stream import Piece
from sketchanim.studio import protocol as p


def plain(value: object) -> object:
    """A scene value as JSON holds it (an array as a list)."""
    return value.tolist() if isinstance(value, np.ndarray) else value


def type_info(kind: AttributeType) -> p.TypeInfo:
    """An attribute type as the page sees it.

    >>> from sketchanim.anim.attributes import FOV
    >>> p.wire(type_info(FOV))
    {'name': 'fov', 'dim': 1, 'tol': 0.1, 'unit': 'degrees', 'default': [50.0], 'choices': [], 'continuous': True}
    """
    return p.TypeInfo(name=kind.name, dim=kind.dim, tol=kind.tol, unit=kind.unit, default=list(kind.default),
                      choices=list(kind.choices), continuous=kind.continuous)


def track_info(track: Track) -> p.CurveInfo | p.StepsInfo:
    """A track as the page needs it to evaluate it as the player does (see
    docs/studio-protocol.md for the rule).

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import INTENSITY
    >>> from sketchanim.anim.tracks import ContinuousTrack
    >>> line = BSpline(np.r_[[0.0] * 2, [2.0] * 2], np.c_[[1.0, 3.0]], 1)
    >>> m = p.wire(track_info(ContinuousTrack("lamp.intensity", INTENSITY, line, 0.01)))
    >>> m["order"], m["knots"], m["coef"], m["rotation"], m["start"], m["end"], m["bounds"]
    (2, [0.0, 0.0, 2.0, 2.0], [[1.0], [3.0]], False, 0.0, 2.0, [0.0, None])
    """
    if isinstance(track, DiscreteTrack):
        return p.StepsInfo(path=track.path, times=list(track.times), values=list(track.values))
    s = track.spline
    return p.CurveInfo(path=track.path, dim=track.type.dim, order=s.k + 1, rotation=track.type.is_rotation,
                       tol=track.tol, knots=np.asarray(s.t).tolist(), coef=np.asarray(s.c).tolist(),
                       start=track.start, end=track.end,
                       takes=[p.TakeSpan(start=t.start, end=t.end, mode=t.mode, n=len(t.times),
                                         smoothing=t.smoothing, name=t.name, muted=t.muted, loop=t.loop,
                                         loop_pass=t.loop_pass) for t in track.takes],
                       bounds=None if track.type.bounds is None else
                       [float(b) if np.isfinite(b) else None for b in track.type.bounds], edited=track.edited)


def objects_info(scene: Scene) -> list[p.ObjectInfo]:
    """Every object of ``scene``, its attributes with their types and values."""
    return [p.ObjectInfo(name=o.name, kind=o.kind,
                         attributes=[p.AttributeInfo(name=n, type=type_info(a.type), value=plain(a.value))
                                     for n, a in o.attributes.items()]) for o in scene.objects.values()]


def history_info(history: History) -> p.HistoryInfo:
    """The history's labels and whether undo and redo are possible."""
    undo, redo = history.labels
    return p.HistoryInfo(undo=undo, redo=redo, can_undo=bool(undo), can_redo=bool(redo))


def tracks_info(tracks: Mapping[str, Track | None], span: tuple[float, float]) -> p.Tracks:
    """The tracks that changed (None: removed) and the player's span after."""
    return p.Tracks(changed=[track_info(t) for t in tracks.values() if t is not None],
                    removed=[path for path, t in tracks.items() if t is None], span=span)


def piece_info(take: str, path: str, piece: Piece, rotation: bool) -> p.TakePiece:
    """A finished piece of a running take's curve."""
    return p.TakePiece(take=take, path=path, order=piece.order, rotation=rotation, knots=piece.knots.tolist(),
                       coef=piece.coef.tolist())


def layout(scene: Scene, paths: Iterable[str]) -> list[tuple[str, int, int]]:
    """Where each path's columns are in a row of a take's samples: (path, start, stop).

    >>> from sketchanim.studio.defaults import default_scene
    >>> layout(default_scene(), ["box.position", "lamp.intensity"])
    [('box.position', 0, 3), ('lamp.intensity', 3, 4)]
    """
    at, out = 0, []
    for path in paths:
        dim = scene.type(path).dim
        out.append((path, at, at + dim))
        at += dim
    return out
