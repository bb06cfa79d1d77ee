"""Reduced motion capture as glTF: skeletal clips (joints as nodes, a skinned bone mesh)
and marker trajectories (one small octahedron per marker, hidden in its gaps), their
tracks written by :func:`~sketchanim.formats.gltf_tracks.tracks_glb`."""

from __future__ import annotations

import numpy as np

from sketchanim.anim.tracks import held_values
from sketchanim.float32 import position_budget
from sketchanim.formats.gltf import Node, Skin, bone_mesh, octahedron
from sketchanim.formats.gltf_frames import allowance, frame_times
from sketchanim.formats.gltf_tracks import CurvePiece, ExportTrack, tracks_glb
from sketchanim.mocap.clip_reduction import ReducedClip
from sketchanim.mocap.markers import ReducedMarkers

#: Size of a marker's octahedron, metres (1 cm, as a marker is).
MARKER_RADIUS_M = 0.01


def clip_export_tracks(clip: ReducedClip, rate: float | None = None) -> list[ExportTrack]:
    """The clip's tracks as the writer takes them, in the clip's order: each curve as
    it is, keyed with ``keys="frames"`` at every source frame (or at ``rate`` per
    second) over the clip's span, dropping keys within what the curve's tolerance leaves
    over its error.

    >>> from sketchanim.motion.skeleton import Clip, Skeleton
    >>> from sketchanim.mocap.clip_reduction import reduce_clip
    >>> s = Skeleton(("hips",), (-1,), np.zeros((1, 3)))
    >>> [t.path for t in clip_export_tracks(reduce_clip(Clip.still(s, np.arange(10) / 30), 0.5, 0.5))]
    ['hips.orientation']
    """
    times = frame_times(clip.start, clip.end, rate or 1.0 / clip.frame_time)
    out = []
    for curve in clip.tracks.values():
        r = curve.reduction
        if curve.is_rotation:
            spare = allowance(float(r.tol[0]), float(r.max_error[0]))
        else:
            budget = float(r.tol[0]) * np.sqrt(3.0)                 # per axis, as reduce_clip asked for it
            spare = allowance(budget, float(r.report.get("max_distance", budget)))
        out.append(ExportTrack(curve.path, (CurvePiece(curve.track.start, curve.track.end, curve.spline, times,
                                                       spare),)))
    return out


def clip_glb(clip: ReducedClip, *, name: str = "clip", keys: str = "curves", rate: float | None = None) -> bytes:
    """A reduced clip as a .glb: one node per joint (rest offsets), a skinned bone mesh,
    and one animation of the clip's tracks (:func:`clip_export_tracks`: exactly, or
    ``keys="frames"``); scaled to metres where the clip's unit is known.

    >>> from sketchanim.motion.skeleton import Clip, Skeleton
    >>> from sketchanim.mocap.clip_reduction import reduce_clip
    >>> s = Skeleton(("hips", "knee"), (-1, 0), np.array([[0.0, 90, 0], [0, -45, 0]]))
    >>> glb = clip_glb(reduce_clip(Clip.still(s, np.arange(10) / 30), 0.5, 0.5))
    >>> glb[:4]
    b'glTF'
    """
    sk = clip.skeleton
    nodes = [Node(n, p, translation=o.tolist()) for n, p, o in zip(sk.names, sk.parents, sk.offsets)]
    tracks = clip_export_tracks(clip, rate)
    rest = sk.rest_positions()
    inverse = np.tile(np.eye(4), (len(sk), 1, 1))
    inverse[:, :3, 3] = -rest
    mesh = bone_mesh(rest, sk.parents)
    if not len(mesh.positions):
        return tracks_glb(nodes, tracks, name=name, keys=keys, unit_m=clip.unit_m)
    nodes.append(Node("bones", mesh=0, skin=0))
    return tracks_glb(nodes, tracks, name=name, keys=keys, meshes=[mesh], skins=[Skin(list(range(len(sk))), inverse)],
                      unit_m=clip.unit_m)


def marker_export_tracks(markers: ReducedMarkers) -> list[ExportTrack]:
    """Every marker's track as the writer takes it: its pieces (keyed with
    ``keys="frames"`` at the piece's frames, dropping keys within what the float32
    budget leaves over the piece's distance), its node shown only on them.

    >>> from sketchanim.mocap.markers import Markers, reduce_markers
    >>> t = np.arange(10) / 100
    >>> reduced = reduce_markers(Markers(("a",), t, np.ones((10, 1, 3))), 0.5)
    >>> [(x.path, len(x.pieces)) for x in marker_export_tracks(reduced)]
    [('a.position', 1)]
    """
    out = []
    shown = (float(markers.times[0]), float(markers.times[-1]), markers.frame_time) if len(markers.times) else None
    for track in markers.tracks.values():
        pieces = []
        for p in track.pieces:
            run = markers.times[(markers.times >= p.start) & (markers.times <= p.end)]
            budget = position_budget(run, held_values(p.spline, run, False), markers.tol,
                                     subject=f"for track {track.path!r}", whose="the markers' times")
            pieces.append(CurvePiece(p.start, p.end, p.spline, run, allowance(budget, p.max_distance)))
        if shown is not None:
            out.append(ExportTrack(track.path, tuple(pieces), shown))
    return out


def markers_glb(markers: ReducedMarkers, *, name: str = "markers", keys: str = "curves") -> bytes:
    """Reduced marker trajectories as a .glb: a node with a small octahedron per
    marker, animated by :func:`marker_export_tracks` (exactly, or ``keys="frames"``);
    scaled to metres where the unit is known.

    >>> from sketchanim.mocap.markers import Markers, reduce_markers
    >>> t = np.arange(10) / 100
    >>> glb = markers_glb(reduce_markers(Markers(("a",), t, np.ones((10, 1, 3))), 0.5))
    >>> glb[:4]
    b'glTF'
    """
    unit = markers.unit_m or 1.0
    nodes = [Node(n, mesh=0) for n in markers.names]
    return tracks_glb(nodes, marker_export_tracks(markers), name=name, keys=keys,
                      meshes=[octahedron("marker", MARKER_RADIUS_M / unit)], unit_m=markers.unit_m)
