"""The timeline's clipboard on the wire: a copied range of a track (a
:class:`~sketchanim.anim.retime.Piece`) as the page keeps it, and back.

The page keeps the clipboard (``track.piece`` brings it, ``track.paste`` sends it back):
a copy survives undo, redo and a restart of the server, and pastes into another project
open in the same page; the server checks a piece it gets back as any message: its
curve's knots and coefficients, its values against its attribute's type.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.retime import Piece
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack
from sketchanim.errors import ArgumentError
from sketchanim.studio import protocol as p
from sketchanim.studio.outbound import track_info


def piece_message(path: str, clip: Piece) -> p.TrackPiece:
    """The ``track.piece`` answering a copy of ``path``.

    >>> from sketchanim.anim.attributes import BOOL
    >>> p.wire(piece_message("a.on", Piece(DiscreteTrack("a.on", BOOL, [0.5], [True]), 1.0)))["piece"]["times"]
    [0.5]
    """
    return p.TrackPiece(path=path, piece=track_info(clip.track), length=clip.length)


def piece_from(info: p.CurveInfo | p.StepsInfo, length: float, kind: AttributeType) -> Piece:
    """The :class:`Piece` a ``track.paste`` carries, its attribute of type ``kind``;
    :class:`ArgumentError` naming the field that is wrong.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> info = p.CurveInfo(path="a.x", dim=1, order=2, rotation=False, tol=0.01, knots=[0, 0, 1, 1],
    ...                    coef=[[0], [2]], start=0, end=1, takes=[])
    >>> float(piece_from(info, 1.0, FLOAT).track.evaluate([0.5])[0, 0])
    1.0
    >>> piece_from(info.model_copy(update={"knots": [0, 1]}), 1.0, FLOAT)
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: piece.knots: a.x: 2 knots for 2 coefficients of order 2 (needs 4, clamped, increasing)
    """
    if isinstance(info, p.StepsInfo):
        if kind.continuous:
            raise ArgumentError("piece", f"{info.path}: steps cannot go on a {kind.name} attribute")
        return Piece(DiscreteTrack(info.path, kind, info.times, info.values), length)
    try:
        coef = np.asarray(info.coef, dtype=float)
    except ValueError:
        raise ArgumentError("piece.coef", f"{info.path}: rows of coefficients of different lengths") from None
    knots, k = np.asarray(info.knots, dtype=float), info.order - 1
    n = len(coef)
    if not (1 <= k <= 7 and coef.ndim == 2 and n > k and len(knots) == n + k + 1 and np.all(np.isfinite(knots))
            and np.all(np.diff(knots) >= 0) and np.all(knots[: k + 1] == knots[0])
            and np.all(knots[-k - 1:] == knots[-1]) and knots[-1] > knots[0]):
        raise ArgumentError("piece.knots", f"{info.path}: {len(knots)} knots for {n} coefficients of order "
                                           f"{info.order} (needs {n + k + 1}, clamped, increasing)")
    if not np.all(np.isfinite(coef)):
        raise ArgumentError("piece.coef", f"{info.path}: coefficients must be finite")
    return Piece(ContinuousTrack(info.path, kind, BSpline(knots, coef, k), info.tol), length)
