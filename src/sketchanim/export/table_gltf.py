"""A sample table's reduced path as glTF: one node, ``path``, animated by the position
and orientation curves (scene units as the file's)."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import ORIENTATION, POSITION, SCALE
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.export.scene_gltf import OBJECT_RADIUS, export_track
from sketchanim.formats.gltf import Node, octahedron
from sketchanim.formats.gltf_tracks import tracks_glb
from sketchanim.reducer import Reduction

#: The node a table's path animates.
NODE = "path"


def table_tracks(position: Reduction | None, orientation: Reduction | None, rot_tol_deg: float, *,
                 origin: float = 0.0) -> list[ContinuousTrack]:
    """A table's position curve (2 or 3 channels; a plane's path at z = 0) and
    orientation curve (quaternions, scalar-first ones reordered to glTF's x, y, z, w) as
    tracks of :data:`NODE`, their times less ``origin`` seconds.

    >>> from sketchanim.reducer import reduce
    >>> t = np.linspace(0, 1, 20)
    >>> [(x.path, x.spline.c.shape[1]) for x in table_tracks(reduce(t, np.c_[t, t], 1e-3), None, 0.5)]
    [('path.position', 3)]
    """
    tracks = []
    if position is not None:
        s = position.columns
        c = np.asarray(s.c)
        if c.shape[1] == 2:
            c = np.c_[c, np.zeros(len(c))]
        tracks.append(ContinuousTrack(f"{NODE}.position", POSITION, BSpline(s.t - origin, c, s.k),
                                      float(np.max(position.tol))))
    if orientation is not None:
        s = orientation.columns
        c = np.asarray(s.c)[:, [1, 2, 3, 0]] if orientation.report.get("scalar_first") else s.c
        tracks.append(ContinuousTrack(f"{NODE}.orientation", ORIENTATION, BSpline(s.t - origin, c, s.k),
                                      rot_tol_deg))
    return tracks


def table_glb(tracks: list[ContinuousTrack], *, name: str = "path") -> bytes:
    """:func:`table_tracks` as a .glb: the node at rest at the origin with a small
    octahedron, one animation ``name`` of its curves in path order (written as scenes'
    are, :func:`~sketchanim.export.scene_gltf.export_track`).

    >>> from sketchanim.reducer import reduce
    >>> t = np.linspace(0, 1, 20)
    >>> table_glb(table_tracks(reduce(t, np.c_[t, t, t], 1e-3), None, 0.5))[:4]
    b'glTF'
    """
    node = Node(NODE, translation=[float(v) for v in POSITION.initial],
                rotation=[float(v) for v in ORIENTATION.initial], scale=[float(v) for v in SCALE.initial], mesh=0)
    return tracks_glb([node], [export_track(t) for t in sorted(tracks, key=lambda t: t.path)], name=name,
                      meshes=[octahedron("object", OBJECT_RADIUS)])
