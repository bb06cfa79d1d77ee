"""The one glTF animation writer: nodes, and tracks addressed by path
(``"Hips.orientation"``, ``"LFHD.position"``, ``"cam.position"``), each a channel of its
node (found by name) per attribute. Scenes, mocap clips, markers and sample tables are
all written through :func:`tracks_glb` (their preparation is in :mod:`sketchanim.export`).

A track is written exactly (``keys="curves"``: a CUBICSPLINE or LINEAR sampler per
curve, :func:`~sketchanim.formats.gltf.sampler_keys`) or as LINEAR keys at frames
(``keys="frames"``, :mod:`sketchanim.formats.gltf_frames`), or as the fewest LINEAR keys
at frames, quantised and compressed (``keys="compact"``,
:mod:`sketchanim.formats.gltf_compact`). A track whose node is shown
only where it has a curve (a marker lost now and then) has several pieces in one
sampler, and a STEP scale channel that hides its node where no piece holds.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pygltflib as gl
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError
from sketchanim.formats.gltf import Channel, Mesh, Node, Skin, glb_bytes, sampler_keys
from sketchanim.formats.gltf_compact import CompactChannel, compact_glb
from sketchanim.formats.gltf_frames import KEYS, compact_channel, frame_channel

#: Attributes written as glTF channels, and their glTF paths.
GLTF_PATHS = {"position": "translation", "orientation": "rotation", "scale": "scale"}


@dataclass(frozen=True)
class CurvePiece:
    """A curve to write, holding on ``[start, end]``.

    Attributes
    ----------
    start, end : float
        Seconds.
    spline : BSpline
        Evaluating to (n, d) values (order 1: a constant held at ``start``).
    frames : ndarray, shape (m,)
        The times of its keys with ``keys="frames"``.
    allowance : float
        What dropping frame keys may add to its error (a distance, or radians).
    """

    start: float
    end: float
    spline: BSpline
    frames: np.ndarray
    allowance: float


@dataclass(frozen=True)
class ExportTrack:
    """An attribute's curve to write, addressed by path.

    Attributes
    ----------
    path : str
        ``"node.attribute"``: a node's name, and ``position``, ``orientation`` or ``scale``.
    pieces : tuple of CurvePiece
        In time order; one, unless ``shown`` is given.
    shown : tuple of float, optional
        ``(first, last, frame_time)`` of the source, for a node shown only on its pieces:
        hidden before the first, from half a frame after a piece's end until the next,
        and from the float32 time at or before a piece's start shown again.
    """

    path: str
    pieces: tuple[CurvePiece, ...]
    shown: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        if self.path.rpartition(".")[2] not in GLTF_PATHS:
            raise ArgumentError("path", f"{self.path!r}: glTF animates {', '.join(GLTF_PATHS)} only")
        if self.shown is None and len(self.pieces) != 1:
            raise ArgumentError("pieces", f"{self.path}: a track shown throughout needs one piece, "
                                          f"got {len(self.pieces)}")

    @property
    def node(self) -> str:
        """The node's name."""
        return self.path.rpartition(".")[0]


def track_channels(node: int, track: ExportTrack, keys: str = "curves") -> list[Channel | CompactChannel]:
    """The channels of ``track`` on node ``node``: exactly, or with ``keys="frames"``
    LINEAR keys at each piece's frames (``"compact"``: as
    :func:`~sketchanim.formats.gltf_frames.compact_channel` stores them); a track with
    ``shown`` also gets its scale.

    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> piece = CurvePiece(0.0, 1.0, s, np.linspace(0, 1, 5), 1e-6)
    >>> [(c.path, c.interpolation, len(c.times)) for c in track_channels(0, ExportTrack("a.position", (piece,)))]
    [('translation', 'LINEAR', 2)]
    >>> [(c.path, c.interpolation, c.times.tolist()) for c in track_channels(
    ...     0, ExportTrack("a.position", (piece,), shown=(-1.0, 2.0, 0.5)), "frames")]
    [('translation', 'LINEAR', [0.0, 1.0]), ('scale', 'STEP', [-1.0, 0.0, 1.25, 2.0])]
    """
    if keys not in KEYS:
        raise ArgumentError("keys", f"one of {', '.join(KEYS)}, got {keys!r}")
    path = GLTF_PATHS[track.path.rpartition(".")[2]]
    keyed = {"frames": frame_channel, "compact": compact_channel}.get(keys)
    if track.shown is None:
        p = track.pieces[0]
        if keyed is not None:
            return [keyed(node, path, p.spline, p.frames, p.allowance)]
        return [Channel.curve(node, path, p.spline)]
    if not track.pieces:
        return []
    first, last, step = track.shown
    times, values, show_times, shown, bits = [], [], [], [], []
    if track.pieces[0].start > first:
        show_times.append(first)
        shown.append(0.0)
    for p in track.pieces:
        if keyed is not None:
            ch = keyed(node, path, p.spline, p.frames, p.allowance)
            t, out = ch.times, ch.values
            if isinstance(ch, CompactChannel):
                bits.append(ch.bits)
        elif p.spline.k == 0:                    # a constant: one key, flat
            c = np.asarray(p.spline.c)[None, :1]
            t, out = np.array([p.start]), np.concatenate([np.zeros_like(c), c, np.zeros_like(c)], axis=1)
        else:
            _, t, out = sampler_keys(p.spline)
        times.append(t)
        values.append(out)
        show_times.append(_float32_at_or_before(p.start))
        shown.append(1.0)
        if p.end < last:
            show_times.append(p.end + step / 2)
            shown.append(0.0)
    if show_times[-1] < last:                    # the clip lasts to the last frame (the key rounds up)
        show_times.append(last)
        shown.append(shown[-1])
    scale = np.repeat(np.array(shown)[:, None], 3, axis=1)
    if keys == "compact":                        # 0 and 1 are exact
        return [CompactChannel(node, path, np.concatenate(times), np.concatenate(values), max(bits)),
                CompactChannel(node, "scale", np.array(show_times), scale, 8, "STEP")]
    return [Channel(node, path, "LINEAR" if keys == "frames" else "CUBICSPLINE", np.concatenate(times),
                    np.concatenate(values)),
            Channel(node, "scale", "STEP", np.array(show_times), scale)]


def tracks_glb(nodes: Sequence[Node], tracks: Sequence[ExportTrack], *, name: str = "take", keys: str = "curves",
               meshes: Sequence[Mesh] = (), skins: Sequence[Skin] = (), cameras: Sequence[gl.Camera] = (),
               lights: Sequence[dict] = (), unit_m: float | None = None) -> bytes:
    """A .glb of ``nodes`` (and the ``meshes``, ``skins``, ``cameras`` and ``lights``
    they refer to: :func:`~sketchanim.formats.gltf.glb_bytes`), with one animation,
    ``name``, of ``tracks`` in their order (:func:`track_channels`; a track's node is
    the first node of its name).

    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> track = ExportTrack("box.position", (CurvePiece(0.0, 1.0, s, np.array([0.0, 1.0]), 0.0),))
    >>> doc = gl.GLTF2.load_from_bytes(tracks_glb([Node("box")], [track]))
    >>> doc.animations[0].channels[0].target.path
    'translation'
    """
    if keys not in KEYS:
        raise ArgumentError("keys", f"one of {', '.join(KEYS)}, got {keys!r}")
    index: dict[str, int] = {}
    for i, node in enumerate(nodes):
        index.setdefault(node.name, i)
    missing = [t.path for t in tracks if t.node not in index]
    if missing:
        raise ArgumentError("tracks", f"no node for {', '.join(missing)}")
    channels = [ch for t in tracks for ch in track_channels(index[t.node], t, keys)]
    if keys == "compact":
        return compact_glb(nodes, channels, animation=name, meshes=meshes, skins=skins, cameras=cameras,
                           lights=lights, unit_m=unit_m)
    return glb_bytes(nodes, channels, animation=name, meshes=meshes, skins=skins, cameras=cameras, lights=lights,
                     unit_m=unit_m)


def _float32_at_or_before(t: float) -> float:
    """The largest float32 not after ``t`` (glTF stores key times as float32).

    >>> _float32_at_or_before(0.1) <= 0.1 < float(np.float32(0.1))
    True
    """
    f = np.float32(t)
    return float(f if float(f) <= t else np.nextafter(f, np.float32(-np.inf)))
