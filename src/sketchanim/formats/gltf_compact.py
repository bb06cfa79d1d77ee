"""Compact glTF animation: LINEAR keys stored as a client decodes them from
``EXT_meshopt_compression`` with the filters meant for animation.

Rotations are normalised shorts through meshopt's quaternion filter (the three
smallest components of a unit quaternion at ``bits`` bits each); translations and
scales are floats through its exponential filter (a ``bits`` bit mantissa per value, an
exponent shared per vector). Key times are float32, each distinct array written once.
Every kind of data is one buffer view, compressed by meshopt's vertex codec (lossless:
only the filters round). :func:`held` gives exactly what a client holds after decoding,
so the keys can be chosen, and their error measured, on the values the file gives;
:func:`roundings`, the other values a filter can store near each, for a caller that picks
among them.

Compressed data is the .glb's binary chunk; the buffer views name a fallback buffer
without data, as the extension has it, and the file requires the extension.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import meshopt
import numpy as np
import pygltflib as gl

from sketchanim.errors import ArgumentError
from sketchanim.formats.gltf import Mesh, Node, Skin, document, finished, key_times, last_key_free

MESHOPT = "EXT_meshopt_compression"

#: meshopt's vertex codec, its version 1 (meshoptimizer 0.23 and later decode it, three.js's
#: decoder among them) at its hardest level.
CODEC_VERSION, CODEC_LEVEL = 1, 3

#: Of a channel's bound, what the filters' rounding may take (it sets their bits).
QUANTISATION_SHARE = 0.2

#: Bits a filter takes: the quaternion filter 4 to 16 per component, the exponential
#: filter's mantissa 2 to 24.
BITS = {"rotation": (4, 16), "translation": (2, 24), "scale": (2, 24)}

_ROWS = {"rotation": 8}                  # bytes a key takes in its view (others: 4 per component)


@dataclass(frozen=True)
class CompactChannel:
    """A LINEAR (or STEP) channel to store compactly: node index, glTF path, key
    times (m,), the values (m, d) it should hold, and the filter's bits: one number for
    every key, or one per key (m,) (both filters keep what decoding needs in each key)."""

    node: int
    path: str
    times: np.ndarray
    values: np.ndarray
    bits: int | np.ndarray
    interpolation: str = "LINEAR"

    def __post_init__(self) -> None:
        low, high = BITS[self.path]
        bits = np.asarray(self.bits)
        if bits.size and not (low <= bits.min() and bits.max() <= high):
            raise ArgumentError("bits", f"{self.path} takes {low} to {high} bits, got {bits.min()} to {bits.max()}")


def bits_for(path: str, allowed: float | np.ndarray, scale: float) -> int | np.ndarray:
    """The fewest bits whose rounding stays within ``allowed`` (a number, or an array of
    them: then the bits of each): an angle (radians) for rotations, each of three
    components rounded to a step of ``1 / sqrt(2) / (2^(bits-1) - 1)`` (doubled for the
    angle, with the shorts' rounding); else a distance, for values up to ``scale`` in
    size. The most bits if none do.

    >>> bits_for("rotation", np.radians(0.05), 1.0), bits_for("translation", 1e-4, 1.0)
    (13, 16)
    >>> bits_for("rotation", np.radians([0.05, 1.0, 1e-9]), 1.0).tolist()
    [13, 8, 16]
    """
    low, high = BITS[path]
    bits = np.arange(low, high + 1)
    if path == "rotation":
        error = 1.5 * np.sqrt(3) / np.sqrt(2) / (2.0 ** (bits - 1) - 1)
    else:
        error = max(scale, 1e-300) * 2.0 ** (2 - bits)
    fewest = bits[np.minimum(np.searchsorted(-error, -np.asarray(allowed, dtype=float)), len(bits) - 1)]
    return int(fewest) if fewest.ndim == 0 else fewest


def _encoded(values: np.ndarray, path: str, bits: int | np.ndarray) -> np.ndarray:
    """Rows of bytes the filter makes of ``values`` (m, d) at ``bits`` (one, or one per row)."""
    each = np.broadcast_to(np.asarray(bits, dtype=int), (len(values),))
    kinds = np.unique(each)
    if len(kinds) <= 1:
        return _filtered(values, path, int(kinds[0]) if len(kinds) else BITS[path][1])
    parts = [_filtered(np.asarray(values)[each == b], path, int(b)) for b in kinds]
    rows = np.empty((len(values), parts[0].shape[1]), dtype=parts[0].dtype)
    for b, part in zip(kinds, parts):
        rows[each == b] = part
    return rows


def _filtered(values: np.ndarray, path: str, bits: int) -> np.ndarray:
    """Rows of bytes the filter makes of ``values`` (m, d) at ``bits``."""
    if path == "rotation":
        q = np.asarray(values, dtype=float).reshape(-1, 4)
        return meshopt.encode_filter_quat(q / np.linalg.norm(q, axis=1, keepdims=True), 8, bits)
    return meshopt.encode_filter_exp(np.ascontiguousarray(values, dtype=np.float32), bits, "SharedVector")


def held(values: np.ndarray, path: str, bits: int | np.ndarray) -> np.ndarray:
    """What a client holds after decoding ``values`` (m, d) stored for ``path`` at
    ``bits`` bits (one number, or one per row): the filter's rounding, then (rotations)
    normalised shorts as floats.

    >>> q = np.array([[0.0, 0.0, np.sin(0.3), np.cos(0.3)]])
    >>> bool(np.abs(held(q, "rotation", 12) - q).max() < 1e-3)
    True
    >>> held(np.array([[1.0, 0.5, -3.0]]), "translation", 10).tolist()
    [[1.0, 0.5, -3.0]]
    >>> two = np.repeat(q, 2, axis=0)
    >>> coarse, fine = np.abs(held(two, "rotation", np.array([5, 14])) - two).max(axis=1)
    >>> bool(fine < coarse)
    True
    """
    return _decoded(_encoded(values, path, bits), path)


def _decoded(rows: np.ndarray, path: str) -> np.ndarray:
    """What a client holds of the filter's rows of bytes (m, size) for ``path``, through
    meshopt's codec and the filter's decoding: (m, d) float32 (rotations: normalised
    shorts as floats)."""
    filter = "QUATERNION" if path == "rotation" else "EXPONENTIAL"
    raw = meshopt.decode_gltf_buffer(meshopt.encode_gltf_buffer(rows, "ATTRIBUTES"), len(rows), rows.shape[1],
                                     "ATTRIBUTES", filter)
    if path == "rotation":
        return (np.frombuffer(raw.tobytes(), np.int16).reshape(-1, 4) * np.float32(1 / 32767)).astype(np.float32)
    return np.frombuffer(raw.tobytes(), np.float32).reshape(len(rows), -1).copy()


def roundings(values: np.ndarray, path: str, bits: int | np.ndarray, steps: Sequence[int] = (-1, 0, 1)
              ) -> np.ndarray:
    """What a client decodes of the keys a filter can store near each of ``values`` (m,
    d) at ``bits`` (one, or one per row): each stored component (a rotation's three
    smallest, a vector's mantissas) the ``steps`` from the filter's own rounding, in
    every combination, (K, m, d) for K = ``len(steps) ** 3`` (the filter's own rounding,
    all steps 0, first). A combination that would not store as itself (its decoded
    value filtered again gives other bits) is NaN: every other one, given to
    :class:`CompactChannel` as its values, is written as that combination.

    >>> q = np.array([[0.0, 0.0, np.sin(0.3), np.cos(0.3)]])
    >>> near = roundings(q, "rotation", 10)
    >>> near.shape, bool(np.array_equal(near[0], held(q, "rotation", 10)))
    ((27, 1, 4), True)
    >>> ok = near[~np.isnan(near[:, 0, 0]), 0]
    >>> bool(np.array_equal(held(ok, "rotation", 10), ok))                  # each written as itself
    True
    """
    values = np.asarray(values, dtype=float)
    m, d = values.shape
    each = np.broadcast_to(np.asarray(bits, dtype=int), (m,))
    combos = np.array(np.meshgrid(*[steps] * 3, indexing="ij")).reshape(3, -1).T        # (K, 3)
    combos = combos[np.argsort(np.abs(combos).sum(axis=1), kind="stable")]            # no step first
    rows = _encoded(values, path, each)
    if path == "rotation":
        shorts = rows.view(np.int16).reshape(m, 4).astype(np.int64)
        top = ((1 << (each - 1)) - 1)[:, None]                                         # the shorts' range
        stored = np.repeat(shorts[None], len(combos), axis=0)
        stored[..., :3] = np.clip(shorts[None, :, :3] + combos[:, None, :], -top, top)
        raw = np.ascontiguousarray(stored.astype(np.int16)).view(np.uint8).reshape(-1, 8)
    else:
        words = rows.view(np.int32).reshape(m, d).astype(np.int64)
        mantissa = ((words & 0xFFFFFF) ^ 0x800000) - 0x800000                          # 24-bit, signed
        stored = (words >> 24 << 24)[None] | ((mantissa[None] + combos[:, None, :]) & 0xFFFFFF)
        raw = np.ascontiguousarray(stored.astype(np.uint32)).view(np.uint8).reshape(-1, 4 * d)
    out = _decoded(raw, path).astype(float).reshape(len(combos), m, d)
    again = _encoded(out.reshape(-1, d), path, np.tile(each, len(combos))).view(raw.dtype).reshape(raw.shape)
    out[~np.all(again == raw, axis=1).reshape(len(combos), m)] = np.nan
    return out


class _Views:
    """Buffer views compressed with meshopt: rows appended per kind, written at the end."""

    def __init__(self, doc: gl.GLTF2, data: bytearray) -> None:
        self.doc, self.data = doc, data
        self.rows: dict[str, list[np.ndarray]] = {}
        self.pending: list[tuple[str, int, gl.Accessor]] = []

    def add(self, kind: str, rows: np.ndarray, accessor: gl.Accessor) -> int:
        """Append ``rows`` (m, stride bytes) to the view of ``kind``; the accessor gets
        its offset when the view is written."""
        parts = self.rows.setdefault(kind, [])
        self.pending.append((kind, sum(len(p) for p in parts) * rows.shape[1], accessor))
        parts.append(rows)
        self.doc.accessors.append(accessor)
        return len(self.doc.accessors) - 1

    def write(self, fallback: int) -> None:
        """Compress each kind's rows into one view of the fallback buffer's layout."""
        view_of, offset = {}, 0
        for kind, parts in self.rows.items():
            rows = np.concatenate(parts)
            stride = rows.shape[1]
            packed = meshopt.encode_vertex_buffer_level(rows, CODEC_LEVEL, CODEC_VERSION)
            self.data += b"\0" * (-len(self.data) % 4)
            filter = {"rotation": "QUATERNION", "vector": "EXPONENTIAL"}.get(kind, "NONE")
            ext = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(packed), "byteStride": stride,
                   "count": len(rows), "mode": "ATTRIBUTES"}
            if filter != "NONE":
                ext["filter"] = filter
            self.data += packed
            self.doc.bufferViews.append(gl.BufferView(buffer=fallback, byteOffset=offset, byteLength=rows.nbytes,
                                                      extensions={MESHOPT: ext}))
            view_of[kind] = len(self.doc.bufferViews) - 1
            offset += rows.nbytes + (-rows.nbytes % 4)
        for kind, at, accessor in self.pending:
            accessor.bufferView, accessor.byteOffset = view_of[kind], at
        self.doc.buffers.append(gl.Buffer(byteLength=max(offset, 4), extensions={MESHOPT: {"fallback": True}}))


def compact_glb(nodes: Sequence[Node], channels: Sequence[CompactChannel], *, animation: str = "take",
                meshes: Sequence[Mesh] = (), skins: Sequence[Skin] = (), cameras: Sequence[gl.Camera] = (),
                lights: Sequence[dict] = (), unit_m: float | None = None) -> bytes:
    """A .glb of ``nodes`` (as :func:`~sketchanim.formats.gltf.glb_bytes`) animated by
    ``channels`` stored compactly: each distinct key time array once, every rotation
    through the quaternion filter, every translation and scale through the exponential
    filter, each kind one meshopt-compressed view.

    >>> t = np.linspace(0, 1, 5)
    >>> q = np.c_[np.zeros((5, 2)), np.sin(t / 2), np.cos(t / 2)]
    >>> glb = compact_glb([Node("a")], [CompactChannel(0, "rotation", t, q, 12)])
    >>> doc = gl.GLTF2.load_from_bytes(glb)
    >>> doc.extensionsRequired, [v.extensions[MESHOPT].get("filter") for v in doc.bufferViews]
    (['EXT_meshopt_compression'], [None, 'QUATERNION'])
    """
    doc, buf = document(nodes, meshes=meshes, skins=skins, cameras=cameras, lights=lights, unit_m=unit_m)
    if channels:
        views = _Views(doc, buf.data)
        inputs: dict[bytes, int] = {}
        anim = gl.Animation(name=animation)
        for ch in channels:
            times = key_times(ch.times, last_key_free(ch.interpolation, ch.values))
            if times.tobytes() not in inputs:
                inputs[times.tobytes()] = views.add("time", times.view(np.uint8).reshape(-1, 4), gl.Accessor(
                    componentType=gl.FLOAT, count=len(times), type=gl.SCALAR, min=[float(times[0])],
                    max=[float(times[-1])]))
            width = ch.values.shape[-1]
            rotation = ch.path == "rotation"
            output = views.add("rotation" if rotation else "vector", _encoded(ch.values, ch.path, ch.bits), gl.Accessor(
                componentType=gl.SHORT if rotation else gl.FLOAT, normalized=True if rotation else None,
                count=len(ch.values), type={3: gl.VEC3, 4: gl.VEC4}[width]))
            anim.samplers.append(gl.AnimationSampler(input=inputs[times.tobytes()], output=output,
                                                     interpolation=ch.interpolation))
            anim.channels.append(gl.AnimationChannel(sampler=len(anim.samplers) - 1,
                                                     target=gl.AnimationChannelTarget(node=ch.node, path=ch.path)))
        doc.animations.append(anim)
        views.write(fallback=len(doc.buffers) + 1)    # after buffer 0, the binary chunk
        doc.extensionsUsed = [*doc.extensionsUsed, MESHOPT]
        doc.extensionsRequired = [*doc.extensionsRequired, MESHOPT]
    return finished(doc, buf)
