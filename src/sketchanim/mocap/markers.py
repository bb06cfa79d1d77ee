"""Marker trajectories (motion capture's raw points, as C3D holds them) and their
reduction.

A marker is lost now and then (occluded, out of view): its samples there are NaN. A gap
is never interpolated over: each gap-free run of a marker becomes a curve of its own
(a :class:`MarkerPiece`), within a distance of every sample of the run, and the marker
has no value in between. A run of one frame is a constant that holds at that frame only.
Reduced markers are tracks addressed by path (``"LFHD.position"``), each its pieces.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError, InputError
from sketchanim.float32 import position_budget
from sketchanim.mocap.tracks import FLOAT32, curve_bytes, split_path, track_path
from sketchanim.motion.skeleton import frame_time
from sketchanim.reducer import reduce
from sketchanim.reducer.result import load_versioned

SCHEMA = "sketchanim.markers"
VERSION = 1


@dataclass(frozen=True)
class Markers:
    """Points sampled at times, with gaps.

    Attributes
    ----------
    names : tuple of str
        Marker labels, unique.
    times : ndarray, shape (n,)
        Seconds, increasing.
    positions : ndarray, shape (n, M, 3)
        Positions in the file's units; NaN where a marker was not seen.
    unit_m : float or None
        Metres per unit, where the source says.

    >>> p = np.zeros((5, 1, 3)); p[2] = np.nan
    >>> Markers(("a",), np.arange(5) / 100, p).runs(0)
    [(0, 2), (3, 5)]
    """

    names: tuple[str, ...]
    times: np.ndarray
    positions: np.ndarray
    unit_m: float | None = None

    def __post_init__(self) -> None:
        n, m = len(self.times), len(self.names)
        if np.shape(self.positions) != (n, m, 3):
            raise ArgumentError("positions", f"{n} frames of {m} markers need shape ({n}, {m}, 3), got "
                                             f"{np.shape(self.positions)}")
        if len(set(self.names)) != m:
            raise ArgumentError("names", "marker names must be unique")

    @property
    def frame_time(self) -> float:
        """The median time between frames, seconds."""
        return frame_time(self.times)

    def runs(self, marker: int) -> list[tuple[int, int]]:
        """The gap-free runs of ``marker``: frame ranges ``[first, stop)``."""
        seen = np.all(np.isfinite(self.positions[:, marker]), axis=1).astype(np.int8)
        edges = np.flatnonzero(np.diff(np.r_[0, seen, 0]))
        return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])]


@dataclass(frozen=True)
class MarkerPiece:
    """One gap-free run of a marker as a curve.

    Attributes
    ----------
    start, end : float
        Times of the run's first and last frames: the piece holds on ``[start, end]``.
    frames : int
        Samples in the run.
    spline : BSpline
        Evaluating to (m, 3) positions (a run of one frame: a constant).
    max_distance : float
        Largest distance between the curve and the run's samples.
    """

    start: float
    end: float
    frames: int
    spline: BSpline
    max_distance: float


@dataclass(frozen=True)
class MarkerTrack:
    """A marker's position: ``path`` (``"LFHD.position"``) and its pieces in time
    order (none for a marker never seen)."""

    path: str
    pieces: tuple[MarkerPiece, ...]

    @property
    def marker(self) -> str:
        return split_path(self.path)[0]


@dataclass(frozen=True)
class MarkerReport:
    """One marker's pieces, control points, largest distance to its samples, and the
    frames it was not seen."""

    marker: str
    pieces: int
    control_points: int
    max_distance: float
    gap_frames: int


@dataclass(frozen=True)
class ReducedMarkers:
    """Every marker's track.

    Attributes
    ----------
    tracks : dict of str to MarkerTrack
        By path, ``"marker.position"``, in the source's marker order.
    times : ndarray
        The source's frame times.
    tol : float
        The distance every sample was kept within.
    unit_m : float or None
    """

    tracks: dict[str, MarkerTrack]
    times: np.ndarray
    tol: float
    unit_m: float | None = None

    @property
    def names(self) -> tuple[str, ...]:
        """The markers, in the source's order."""
        return tuple(t.marker for t in self.tracks.values())

    @property
    def frame_time(self) -> float:
        """The median time between the source's frames, seconds."""
        return frame_time(self.times)

    def evaluate(self, times: ArrayLike) -> np.ndarray:
        """Positions (n, M, 3) at ``times``: each marker's piece holding there, NaN in
        its gaps.

        >>> t = np.arange(6) / 100.0
        >>> p = np.repeat(t[:, None, None], 3, axis=2); p[2:4] = np.nan
        >>> r = reduce_markers(Markers(("a",), t, p), 0.001)
        >>> np.isnan(r.evaluate(t)[:, 0, 0]).tolist()
        [False, False, True, True, False, False]
        """
        t = np.asarray(times, dtype=float).reshape(-1)
        out = np.full((len(t), len(self.names), 3), np.nan)
        for m, track in enumerate(self.tracks.values()):
            for p in track.pieces:
                inside = (t >= p.start) & (t <= p.end)
                k = p.spline.k
                out[inside, m] = p.spline(np.clip(t[inside], p.spline.t[k], p.spline.t[-k - 1]))
        return out

    def reports(self) -> list[MarkerReport]:
        """Per marker: pieces, control points, largest distance, frames unseen."""
        return [MarkerReport(t.marker, len(t.pieces), sum(len(p.spline.c) for p in t.pieces),
                             max((p.max_distance for p in t.pieces), default=0.0),
                             len(self.times) - sum(p.frames for p in t.pieces))
                for t in self.tracks.values()]

    def reduced_bytes(self) -> int:
        """Bytes to store every piece (:func:`~sketchanim.mocap.clip_reduction.curve_bytes`)."""
        return sum(curve_bytes(p.spline) for t in self.tracks.values() for p in t.pieces)

    def raw_bytes(self) -> int:
        """Bytes of every marker's x, y, z at every frame as float32."""
        return FLOAT32 * 3 * len(self.times) * len(self.names)

    def compression(self) -> float:
        """Raw bytes over reduced bytes."""
        return self.raw_bytes() / max(self.reduced_bytes(), 1)

    def to_json(self) -> str:
        """Every marker's pieces as JSON (schema ``sketchanim.markers``, version 1)."""
        doc = {
            "schema": SCHEMA, "version": VERSION, "tol": self.tol, "unit_m": self.unit_m,
            "times": self.times.tolist(),
            "markers": {t.marker: [{"start": p.start, "end": p.end, "frames": p.frames, "order": p.spline.k + 1,
                                "knots": np.asarray(p.spline.t).tolist(),
                                "coefficients": np.asarray(p.spline.c).tolist(), "max_distance": p.max_distance}
                               for p in t.pieces] for t in self.tracks.values()},
        }
        return json.dumps(doc, indent=1)

    @classmethod
    def from_json(cls, text: str, *, source: str = "<json>") -> ReducedMarkers:
        """Read what :meth:`to_json` wrote; errors name ``source`` and what is wrong.

        >>> t = np.arange(4) / 100.0
        >>> r = reduce_markers(Markers(("a",), t, np.ones((4, 1, 3))), 0.001)
        >>> ReducedMarkers.from_json(r.to_json()).evaluate(t).tolist() == r.evaluate(t).tolist()
        True
        """
        doc = load_versioned(text, source, SCHEMA, VERSION)
        try:
            tracks = {(path := track_path(str(name), "position")): MarkerTrack(path, tuple(
                MarkerPiece(float(p["start"]), float(p["end"]), int(p["frames"]),
                            BSpline(np.asarray(p["knots"], dtype=float), np.asarray(p["coefficients"], dtype=float)
                                    .reshape(-1, 3), int(p["order"]) - 1), float(p["max_distance"]))
                for p in pieces)) for name, pieces in doc["markers"].items()}
            unit = doc.get("unit_m")
            return cls(tracks, np.asarray(doc["times"], dtype=float), float(doc["tol"]),
                       None if unit is None else float(unit))
        except (KeyError, TypeError, ValueError, AttributeError) as err:
            raise InputError(f"{source}: malformed markers document ({type(err).__name__}: {err})") from None


def reduce_markers(markers: Markers, tol: float, *, method: str = "global") -> ReducedMarkers:
    """Reduce every gap-free run of every marker to a cubic curve within ``tol`` (a
    distance in the markers' units: ``tol / sqrt(3)`` per axis) of each of its samples,
    float32's share left out (:func:`~sketchanim.float32.position_budget`).

    Raises
    ------
    ArgumentError
        Naming ``tol``: not a positive distance, or one float32 would take more than
        half of for a marker's run (named with its frames).

    Examples
    --------
    >>> t = np.arange(200) / 100.0
    >>> p = np.stack([np.cos(t), np.sin(t), t], axis=1)[:, None].repeat(2, axis=1)
    >>> p[50:60, 1] = np.nan                          # marker 1 lost for 10 frames
    >>> r = reduce_markers(Markers(("a", "b"), t, p), 0.001)
    >>> [(x.pieces, x.gap_frames, x.max_distance <= 0.001) for x in r.reports()]
    [(1, 0, True), (2, 10, True)]
    """
    if not np.isfinite(tol) or tol <= 0:
        raise ArgumentError("tol", f"must be a positive distance, got {tol!r}")
    step = markers.frame_time or 1.0
    out = {}
    for m, name in enumerate(markers.names):
        pieces = []
        for a, b in markers.runs(m):
            t, x = markers.times[a:b], markers.positions[a:b, m]
            if b - a == 1:
                pieces.append(MarkerPiece(float(t[0]), float(t[0]), 1, BSpline(np.r_[t[0], t[0] + step], x, 0), 0.0))
                continue
            budget = position_budget(t, x, tol, subject=f"for marker {name!r}, frames {a}..{b - 1},",
                                     whose="the markers' times")
            try:
                r = reduce(t, x, budget / np.sqrt(3.0), method=method)
            except InputError as err:
                raise InputError(f"marker {name!r}, frames {a}..{b - 1}: {err}") from None
            distance = float(np.linalg.norm(r.spline(t) - x, axis=1).max())
            pieces.append(MarkerPiece(float(t[0]), float(t[-1]), b - a, r.columns, distance))
        path = track_path(name, "position")
        out[path] = MarkerTrack(path, tuple(pieces))
    return ReducedMarkers(out, np.asarray(markers.times, dtype=float), float(tol), markers.unit_m)
