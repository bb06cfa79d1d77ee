"""A sample table's reduced path as glTF: one node, ``path``, animated by the position
and orientation curves (scene units as the file's).

Written as scenes' tracks are (:func:`~sketchanim.export.scene_gltf.export_track`): with
``keys="curves"`` the curves exactly; with ``keys="frames"`` the curves as LINEAR keys at
the table's sample times, within the float32 budget of the tolerance at every sample (the
tracks carry the samples as their take). ``keys="compact"`` picks its keys from the
samples themselves, as compact clips do (:func:`sample_keys`), and stores them as the
writer's compact keys (:func:`~sketchanim.formats.gltf_frames.compact_channel`).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import ORIENTATION, POSITION, SCALE
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.errors import ArgumentError
from sketchanim.export.scene_gltf import OBJECT_RADIUS, export_track, take_budget
from sketchanim.formats.gltf import Node, octahedron
from sketchanim.formats.gltf_frames import KEYS
from sketchanim.formats.gltf_tracks import CurvePiece, ExportTrack, tracks_glb
from sketchanim.limits import one_of
from sketchanim.reducer import Reduction

#: The node a table's path animates.
NODE = "path"


def _position(values: np.ndarray) -> np.ndarray:
    """Position values (n, 2 or 3) in glTF's three: a plane's path at z = 0."""
    values = np.asarray(values, dtype=float)
    return np.c_[values, np.zeros(len(values))] if values.shape[1] == 2 else values


def _orientation(values: np.ndarray, scalar_first: bool) -> np.ndarray:
    """Quaternions (n, 4) in glTF's x, y, z, w order."""
    values = np.asarray(values, dtype=float)
    return values[:, [1, 2, 3, 0]] if scalar_first else values


def _take(times: np.ndarray | None, values: np.ndarray | None, origin: float) -> tuple[Take, ...]:
    """The samples as a track's one take (one per time, times less ``origin``); none
    without samples."""
    if times is None or values is None:
        return ()
    t, first = np.unique(np.asarray(times, dtype=float) - origin, return_index=True)
    return (Take(t, values[first]),)


def table_tracks(position: Reduction | None, orientation: Reduction | None, rot_tol_deg: float, *,
                 origin: float = 0.0, tol: float | None = None, times: np.ndarray | None = None,
                 positions: np.ndarray | None = None, orientations: np.ndarray | None = None) -> list[ContinuousTrack]:
    """A table's position curve (2 or 3 channels; a plane's path at z = 0) and
    orientation curve (quaternions, scalar-first ones reordered to glTF's x, y, z, w) as
    tracks of :data:`NODE`, their times less ``origin`` seconds.

    The position's tolerance is ``tol``, by default the smallest of its channels'. Given the samples
    (``times`` (n,), ``positions`` (n, 2 or 3), ``orientations`` (n, 4) in the
    reduction's layout), each track carries its own as its one take: what
    ``keys="frames"`` and ``keys="compact"`` are keyed at and measured against (and the
    curves, written with a take, are kept within the float32 budget of its samples,
    :func:`~sketchanim.export.scene_gltf.written_curve`).

    >>> from sketchanim.reducer import reduce
    >>> t = np.linspace(0, 1, 20)
    >>> [(x.path, x.spline.c.shape[1]) for x in table_tracks(reduce(t, np.c_[t, t], 1e-3), None, 0.5)]
    [('path.position', 3)]
    >>> [x.takes[0].values.shape for x in table_tracks(reduce(t, np.c_[t, t], 1e-3), None, 0.5, times=t,
    ...                                                 positions=np.c_[t, t])]
    [(20, 3)]
    """
    tracks = []
    if position is not None:
        s = position.columns
        take = _take(times, None if positions is None else _position(positions), origin)
        tracks.append(ContinuousTrack(f"{NODE}.position", POSITION, BSpline(s.t - origin, _position(s.c), s.k),
                                      float(np.min(position.tol)) if tol is None else tol, take))
    if orientation is not None:
        s = orientation.columns
        first = bool(orientation.report.get("scalar_first"))
        take = _take(times, None if orientations is None else _orientation(orientations, first), origin)
        tracks.append(ContinuousTrack(f"{NODE}.orientation", ORIENTATION,
                                      BSpline(s.t - origin, _orientation(s.c, first), s.k), rot_tol_deg, take))
    return tracks


def sample_keys(track: ContinuousTrack) -> ExportTrack:
    """A track's compact keys, picked from the samples of its take: the samples joined
    by straight lines, keyed at their times within the float32 budget of the track's
    tolerance (:func:`~sketchanim.float32.position_budget` as a distance,
    :func:`~sketchanim.float32.rotation_budget` as an angle), so that what a client
    plays from the decoded keys is within the tolerance of every sample. A track
    without a take: its curve as scenes write it
    (:func:`~sketchanim.export.scene_gltf.export_track`).

    >>> from sketchanim.formats.gltf_frames import compact_channel
    >>> t = np.linspace(0, 1, 11)
    >>> x = np.c_[t, np.minimum(t, 0.5), 0 * t]
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 1, 0]]), 1)
    >>> p = sample_keys(ContinuousTrack("path.position", POSITION, s, 1e-3, (Take(t, x),))).pieces[0]
    >>> compact_channel(0, "translation", p.spline, p.frames, p.allowance).times.tolist()
    [0.0, 0.5, 1.0]
    """
    if not track.takes:
        return export_track(track)
    t, x = track.takes[0].times, track.takes[0].values
    rotation = track.type.is_rotation
    bound = float(np.radians(take_budget(track, t, x))) if rotation else take_budget(track, t, x)
    lines = BSpline(np.r_[t[0], t, t[-1]], x, 1)
    return ExportTrack(track.path, (CurvePiece(float(t[0]), float(t[-1]), lines, t, bound),))


def table_glb(tracks: list[ContinuousTrack], *, name: str = "path", keys: str = "curves") -> bytes:
    """:func:`table_tracks` as a .glb: the node at rest at the origin with a small
    octahedron, one animation ``name`` of its tracks in path order, written as scenes'
    are (:func:`~sketchanim.export.scene_gltf.export_track`; ``keys`` as
    :func:`~sketchanim.formats.gltf_tracks.tracks_glb` takes it), a compact file's keys
    picked from the samples (:func:`sample_keys`).

    Raises
    ------
    ArgumentError
        Naming ``keys`` (not a choice), or ``tol`` (``rot_tol_deg`` for the
        orientation): a tolerance float32 would take more than half of
        (:func:`~sketchanim.export.scene_gltf.take_budget`: a fine tolerance, values far
        from the origin, late times), or a compact key, at the filters' most bits, alone
        misses the tolerance (values far from the origin for a fine one).

    >>> from sketchanim.reducer import reduce
    >>> t = np.linspace(0, 1, 20)
    >>> table_glb(table_tracks(reduce(t, np.c_[t, t, t], 1e-3), None, 0.5))[:4]
    b'glTF'
    >>> x = np.c_[t, t * t, 0 * t]
    >>> glb = table_glb(table_tracks(reduce(t, x, 1e-3), None, 0.5, times=t, positions=x), keys="compact")
    >>> b"EXT_meshopt_compression" in glb
    True
    """
    one_of("keys", keys, KEYS)
    node = Node(NODE, translation=[float(v) for v in POSITION.initial],
                rotation=[float(v) for v in ORIENTATION.initial], scale=[float(v) for v in SCALE.initial], mesh=0)
    written = [_keyed(t, keys) for t in sorted(tracks, key=lambda t: t.path)]
    try:
        return tracks_glb([node], written, name=name, keys=keys, meshes=[octahedron("object", OBJECT_RADIUS)])
    except ArgumentError as err:                 # a compact key alone misses: the filters' most bits are too coarse
        if err.argument != "bound":
            raise
        raise ArgumentError("tol", f"too fine for compact keys of values this far from the origin (the filters' "
                                   f"most bits round them by more; {err})") from None


def _keyed(track: ContinuousTrack, keys: str) -> ExportTrack:
    """The track's keys as ``keys`` asks; a tolerance float32 would take more than half
    of refused naming the table's option: ``tol``, ``rot_tol_deg`` for the orientation."""
    try:
        return sample_keys(track) if keys == "compact" else export_track(track)
    except ArgumentError as err:
        if err.argument != "tolerance":
            raise
        raise ArgumentError("rot_tol_deg" if track.type.is_rotation else "tol",
                            str(err).removeprefix("tolerance: ")) from None
