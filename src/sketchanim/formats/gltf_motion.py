"""Reduced motion capture as glTF: skeletal clips (joints as nodes, a skinned bone mesh)
and marker trajectories (one small octahedron per marker, hidden in its gaps)."""

from __future__ import annotations

import numpy as np

from sketchanim.mocap.clip_reduction import ReducedClip, position_budget
from sketchanim.mocap.markers import ReducedMarkers
from sketchanim.anim.tracks import held_values
from sketchanim.errors import ArgumentError
from sketchanim.formats.gltf import Channel, Node, Skin, bone_mesh, glb_bytes, octahedron, sampler_keys
from sketchanim.formats.gltf_frames import KEYS, allowance, frame_channel, frame_times

#: Size of a marker's octahedron, metres (1 cm, as a marker is).
MARKER_RADIUS_M = 0.01


def clip_channels(clip: ReducedClip, keys: str = "curves", rate: float | None = None) -> list[Channel]:
    """The clip's curves as channels (node ``i`` is joint ``i``): exactly (CUBICSPLINE,
    ``keys="curves"``), or as LINEAR keys at every source frame, or at ``rate`` per
    second (``keys="frames"``, :mod:`sketchanim.formats.gltf_frames`), dropping keys within
    what the curve's tolerance leaves over its error.
    """
    if keys == "curves":
        return ([Channel.curve(i, "rotation", r.columns) for i, r in sorted(clip.rotations.items())]
                + [Channel.curve(i, "translation", r.columns) for i, r in sorted(clip.translations.items())])
    if keys != "frames":
        raise ArgumentError("keys", f"one of {', '.join(KEYS)}, got {keys!r}")
    times = frame_times(clip.start, clip.end, rate or 1.0 / clip.frame_time)
    out = [frame_channel(i, "rotation", r.columns, times, allowance(float(r.tol[0]), float(r.max_error[0])))
           for i, r in sorted(clip.rotations.items())]
    for i, r in sorted(clip.translations.items()):
        budget = float(r.tol[0]) * np.sqrt(3.0)                     # per axis, as reduce_clip asked for it
        out.append(frame_channel(i, "translation", r.columns, times,
                                 allowance(budget, float(r.report.get("max_distance", budget)))))
    return out


def clip_glb(clip: ReducedClip, *, name: str = "clip", keys: str = "curves", rate: float | None = None) -> bytes:
    """A reduced clip as a .glb: one node per joint (rest offsets), a skinned bone mesh,
    and one animation whose channels are the clip's curves (:func:`clip_channels`:
    exactly, or ``keys="frames"``); scaled to metres where the clip's unit is known.

    >>> from sketchanim.motion.skeleton import Clip, Skeleton
    >>> from sketchanim.mocap.clip_reduction import reduce_clip
    >>> s = Skeleton(("hips", "knee"), (-1, 0), np.array([[0.0, 90, 0], [0, -45, 0]]))
    >>> glb = clip_glb(reduce_clip(Clip.still(s, np.arange(10) / 30), 0.5, 0.5))
    >>> glb[:4]
    b'glTF'
    """
    sk = clip.skeleton
    nodes = [Node(n, p, translation=o.tolist()) for n, p, o in zip(sk.names, sk.parents, sk.offsets)]
    channels = clip_channels(clip, keys, rate)
    rest = sk.rest_positions()
    inverse = np.tile(np.eye(4), (len(sk), 1, 1))
    inverse[:, :3, 3] = -rest
    mesh = bone_mesh(rest, sk.parents)
    if not len(mesh.positions):
        return glb_bytes(nodes, channels, animation=name, unit_m=clip.unit_m)
    nodes.append(Node("bones", mesh=0, skin=0))
    return glb_bytes(nodes, channels, animation=name, meshes=[mesh], skins=[Skin(list(range(len(sk))), inverse)],
                     unit_m=clip.unit_m)


def marker_channels(markers: ReducedMarkers, marker: int, keys: str = "curves") -> list[Channel]:
    """Marker ``marker``'s (its node's) translation (every piece's CUBICSPLINE keys, one
    sampler; with ``keys="frames"``, LINEAR keys at the piece's frames) and its
    scale (STEP: 1 on its pieces, 0 from half a frame after a piece's last frame until
    the next piece, and before the first): the pieces exactly, nothing shown in a gap.
    A marker never seen gets none. A piece shows from the float32 time at or before its
    first frame, so that a player at that frame's time shows it."""
    pieces = markers.pieces[marker]
    if not pieces:
        return []
    times, values, show_times, shown = [], [], [], []
    if pieces[0].start > markers.times[0]:
        show_times.append(float(markers.times[0]))
        shown.append(0.0)
    for p in pieces:
        if keys == "frames":
            run = markers.times[(markers.times >= p.start) & (markers.times <= p.end)]
            budget = position_budget(run, held_values(p.spline, run, False), markers.tol)
            ch = frame_channel(marker, "translation", p.spline, run, allowance(budget, p.max_distance))
            t, out = ch.times, ch.values
        elif p.spline.k == 0:
            t, out = np.array([p.start]), np.concatenate([np.zeros((1, 1, 3)), p.spline.c[None, :1],
                                                          np.zeros((1, 1, 3))], axis=1)
        else:
            _, t, out = sampler_keys(p.spline)
        times.append(t)
        values.append(out)
        show_times.append(_float32_at_or_before(p.start))
        shown.append(1.0)
        if p.end < markers.times[-1]:
            show_times.append(p.end + markers.frame_time / 2)
            shown.append(0.0)
    if show_times[-1] < markers.times[-1]:          # the clip lasts to the last frame (the key rounds up)
        show_times.append(float(markers.times[-1]))
        shown.append(shown[-1])
    scale = np.repeat(np.array(shown)[:, None], 3, axis=1)
    return [Channel(marker, "translation", "LINEAR" if keys == "frames" else "CUBICSPLINE", np.concatenate(times),
                    np.concatenate(values)),
            Channel(marker, "scale", "STEP", np.array(show_times), scale)]


def markers_glb(markers: ReducedMarkers, *, name: str = "markers", keys: str = "curves") -> bytes:
    """Reduced marker trajectories as a .glb: a node with a small octahedron per
    marker, animated by :func:`marker_channels` (``keys`` as there); scaled to metres
    where the unit is known.

    >>> from sketchanim.mocap.markers import Markers, reduce_markers
    >>> t = np.arange(10) / 100
    >>> glb = markers_glb(reduce_markers(Markers(("a",), t, np.ones((10, 1, 3))), 0.5))
    >>> glb[:4]
    b'glTF'
    """
    unit = markers.unit_m or 1.0
    nodes = [Node(n, mesh=0) for n in markers.names]
    if keys not in KEYS:
        raise ArgumentError("keys", f"one of {', '.join(KEYS)}, got {keys!r}")
    channels = [ch for m in range(len(nodes)) for ch in marker_channels(markers, m, keys)]
    return glb_bytes(nodes, channels, animation=name, meshes=[octahedron("marker", MARKER_RADIUS_M / unit)],
                     unit_m=markers.unit_m)


def _float32_at_or_before(t: float) -> float:
    """The largest float32 not after ``t`` (glTF stores key times as float32).

    >>> _float32_at_or_before(0.1) <= 0.1 < float(np.float32(0.1))
    True
    """
    f = np.float32(t)
    return float(f if float(f) <= t else np.nextafter(f, np.float32(-np.inf)))
