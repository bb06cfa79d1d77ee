"""glTF 2.0 binary (.glb) writing, with pygltflib: nodes, meshes, skins, cameras and
KHR_lights_punctual lights, animated by samplers made exactly from our B-splines.

A cubic B-spline converts exactly to a CUBICSPLINE sampler: one key per breakpoint, its
value and one-sided derivatives (:func:`sketchanim.spline.hermite.to_hermite`). An
order-2 curve is exactly a LINEAR sampler, an order-3 one is raised to cubic exactly;
higher orders have no exact glTF form and are refused (reduce with ``order <= 4``).
Orientation curves are quaternion splines normalised when played: that is how glTF
plays a CUBICSPLINE rotation, so they too are exact (to float32), once their keys are
unit quaternions (:func:`sketchanim.motion.rotations.unit_keys`).

glTF's unit is the metre. Content in other units is written as it is, under one root
node that scales it to metres (``unit_m``), so every curve stays exact (a skinned mesh's
node stays at the root: its joints alone place it). Every sampler's last key time is
rounded up in float32 (:func:`key_times`), so its last frame plays inside the clip.
"""

from __future__ import annotations

import json
import struct
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pygltflib as gl
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError
from sketchanim.spline.hermite import to_hermite
from sketchanim.spline.knots import elevate_degree

GENERATOR = "sketchanim"
LIGHTS = "KHR_lights_punctual"

_FLOAT = gl.FLOAT
_TYPES = {1: gl.SCALAR, 3: gl.VEC3, 4: gl.VEC4, 16: gl.MAT4}


@dataclass
class Node:
    """A glTF node: name, parent index (-1 for the scene's roots), rest transform
    (translation, scalar-last rotation, scale), and what it carries (indices of a mesh,
    skin, camera, light)."""

    name: str
    parent: int = -1
    translation: list[float] | None = None
    rotation: list[float] | None = None
    scale: list[float] | None = None
    mesh: int | None = None
    skin: int | None = None
    camera: int | None = None
    light: int | None = None


@dataclass(frozen=True)
class Mesh:
    """Triangles: positions (v, 3), indices (f, 3), and for a skinned mesh the joints
    (v, 4) and weights (v, 4) of each vertex."""

    name: str
    positions: np.ndarray
    faces: np.ndarray
    joints: np.ndarray | None = None
    weights: np.ndarray | None = None


@dataclass(frozen=True)
class Skin:
    """Joint node indices and their inverse bind matrices (J, 4, 4)."""

    joints: list[int]
    inverse_binds: np.ndarray


@dataclass(frozen=True)
class Channel:
    """One animated property: node index, glTF path (translation, rotation, scale), and
    its sampler's interpolation, key times (m,) and outputs ((m, 3, d) for
    CUBICSPLINE: in-tangent, value, out-tangent; else (m, d))."""

    node: int
    path: str
    interpolation: str
    times: np.ndarray
    values: np.ndarray

    @classmethod
    def curve(cls, node: int, path: str, spline: BSpline) -> Channel:
        """The channel playing ``spline`` exactly (:func:`sampler_keys`)."""
        return cls(node, path, *sampler_keys(spline))


def sampler_keys(spline: BSpline) -> tuple[str, np.ndarray, np.ndarray]:
    """The glTF sampler of a B-spline: interpolation, input times (m,) and output
    values, exactly the same curve.

    CUBICSPLINE outputs are (m, 3, dim): in-tangent, value, out-tangent per key
    (derivatives per second, as the glTF spec takes them); LINEAR outputs (m, dim).

    >>> s = BSpline([0, 0, 0, 0, 1, 1, 1, 1], np.c_[[0.0, 1.0, 2.0, 3.0]], 3)   # the line 3t
    >>> kind, times, out = sampler_keys(s)
    >>> kind, times.tolist(), out[:, :, 0].tolist()
    ('CUBICSPLINE', [0.0, 1.0], [[3.0, 0.0, 3.0], [3.0, 3.0, 3.0]])
    """
    if spline.k == 1:
        t = np.asarray(spline.t)[1:-1]
        return "LINEAR", t, np.asarray(spline.c)
    if spline.k == 2:
        spline = elevate_degree(spline)
    if spline.k != 3:
        raise ArgumentError("spline", f"glTF has no exact form for order {spline.k + 1} curves; reduce with order <= 4")
    keys = to_hermite(spline)
    return "CUBICSPLINE", keys.times, np.stack([keys.in_tangents, keys.values, keys.out_tangents], axis=1)


class Buffer:
    """One binary buffer: accessors appended, each in its own 4-byte aligned view."""

    def __init__(self, doc: gl.GLTF2) -> None:
        self.doc = doc
        self.data = bytearray()

    def add(self, values: np.ndarray, width: int, *, component: int = _FLOAT, bounds: bool = False,
            target: int | None = None) -> int:
        arr = np.ascontiguousarray(values, dtype=np.float32 if component == _FLOAT else np.uint16)
        rows = arr.reshape(-1, width)
        self.data += b"\0" * (-len(self.data) % 4)
        self.doc.bufferViews.append(gl.BufferView(buffer=0, byteOffset=len(self.data), byteLength=arr.nbytes,
                                                  target=target))
        self.data += arr.tobytes()
        accessor = gl.Accessor(bufferView=len(self.doc.bufferViews) - 1, componentType=component, count=len(rows),
                               type=_TYPES[width])
        if bounds:
            accessor.min = rows.min(axis=0).astype(float).tolist()
            accessor.max = rows.max(axis=0).astype(float).tolist()
        self.doc.accessors.append(accessor)
        return len(self.doc.accessors) - 1

    def mesh(self, mesh: Mesh) -> gl.Mesh:
        attributes = gl.Attributes(POSITION=self.add(mesh.positions, 3, bounds=True, target=gl.ARRAY_BUFFER))
        if mesh.joints is not None and mesh.weights is not None:
            attributes.JOINTS_0 = self.add(mesh.joints, 4, component=gl.UNSIGNED_SHORT, target=gl.ARRAY_BUFFER)
            attributes.WEIGHTS_0 = self.add(mesh.weights, 4, target=gl.ARRAY_BUFFER)
        indices = self.add(mesh.faces.reshape(-1), 1, component=gl.UNSIGNED_SHORT, target=gl.ELEMENT_ARRAY_BUFFER)
        return gl.Mesh(name=mesh.name, primitives=[gl.Primitive(attributes=attributes, indices=indices)])


def glb_bytes(nodes: Sequence[Node], channels: Sequence[Channel] = (), *, animation: str = "take",
              meshes: Sequence[Mesh] = (), skins: Sequence[Skin] = (), cameras: Sequence[gl.Camera] = (),
              lights: Sequence[dict] = (), unit_m: float | None = None) -> bytes:
    """A .glb of ``nodes`` (and the ``meshes``, ``skins``, ``cameras`` and
    KHR_lights_punctual ``lights`` they refer to), animated by ``channels``; content in
    units of ``unit_m`` metres sits under a root node scaling it to metres.

    >>> glb = glb_bytes([Node("box", translation=[0.0, 1.0, 0.0])], unit_m=0.01)
    >>> doc = gl.GLTF2.load_from_bytes(glb)
    >>> [(n.name, n.scale) for n in doc.nodes], doc.scenes[0].nodes
    ([('box', None), ('to metres', [0.01, 0.01, 0.01])], [1])
    """
    doc, buf = document(nodes, meshes=meshes, skins=skins, cameras=cameras, lights=lights, unit_m=unit_m)
    if channels:
        anim = gl.Animation(name=animation)
        for ch in channels:
            width = ch.values.shape[-1]
            times = key_times(ch.times, last_key_free(ch.interpolation, ch.values))
            anim.samplers.append(gl.AnimationSampler(input=buf.add(times, 1, bounds=True),
                                                     output=buf.add(ch.values, width), interpolation=ch.interpolation))
            anim.channels.append(gl.AnimationChannel(sampler=len(anim.samplers) - 1,
                                                     target=gl.AnimationChannelTarget(node=ch.node, path=ch.path)))
        doc.animations.append(anim)
    return finished(doc, buf)


def document(nodes: Sequence[Node], *, meshes: Sequence[Mesh] = (), skins: Sequence[Skin] = (),
             cameras: Sequence[gl.Camera] = (), lights: Sequence[dict] = (),
             unit_m: float | None = None) -> tuple[gl.GLTF2, Buffer]:
    """A glTF document of ``nodes`` and what they refer to (as :func:`glb_bytes`), not
    yet animated, and its binary buffer (buffer 0)."""
    doc = gl.GLTF2(asset=gl.Asset(version="2.0", generator=GENERATOR), scene=0, scenes=[gl.Scene(nodes=[])])
    buf = Buffer(doc)
    doc.meshes = [buf.mesh(m) for m in meshes]
    doc.skins = [gl.Skin(joints=list(s.joints), inverseBindMatrices=buf.add(np.transpose(s.inverse_binds, (0, 2, 1)),
                                                                             16)) for s in skins]
    doc.cameras = list(cameras)
    if lights:
        doc.extensions = {LIGHTS: {"lights": list(lights)}}
        doc.extensionsUsed = [LIGHTS]
    roots = []
    for node in nodes:
        doc.nodes.append(gl.Node(name=node.name, translation=node.translation, rotation=node.rotation,
                                 scale=node.scale, mesh=node.mesh, skin=node.skin, camera=node.camera,
                                 extensions={LIGHTS: {"light": node.light}} if node.light is not None else {}))
    skinned = []         # a skinned mesh is placed by its joints alone: kept at the root, as the spec advises
    for i, node in enumerate(nodes):
        (roots if node.parent < 0 else doc.nodes[node.parent].children).append(i)
    if unit_m is not None and unit_m != 1.0:
        skinned = [i for i in roots if nodes[i].skin is not None]
        doc.nodes.append(gl.Node(name="to metres", scale=[unit_m] * 3, children=[i for i in roots if i not in skinned]))
        roots = [len(doc.nodes) - 1]
    doc.scenes[0].nodes = roots + skinned
    return doc, buf


def finished(doc: gl.GLTF2, buf: Buffer) -> bytes:
    """The .glb of ``doc`` with ``buf`` as its binary chunk (buffer 0), other buffers
    as ``doc`` has them."""
    if not buf.data:
        return _glb(doc, b"")
    buf.data += b"\0" * (-len(buf.data) % 4)
    doc.buffers.insert(0, gl.Buffer(byteLength=len(buf.data)))
    return _glb(doc, bytes(buf.data))


def last_key_free(interpolation: str, values: np.ndarray) -> bool:
    """Whether a sampler's last key time may round up (:func:`key_times`): a STEP key
    moved would change what plays before it, unless it repeats the key before.

    >>> last_key_free("STEP", np.array([[0.0], [1.0]])), last_key_free("LINEAR", np.array([[0.0], [1.0]]))
    (False, True)
    """
    return interpolation != "STEP" or len(values) < 2 or np.array_equal(values[-1], values[-2])


def key_times(times: np.ndarray, round_up: bool = True) -> np.ndarray:
    """Key times as float32 for a sampler's input, the last one rounded *up* past its
    float64 time (to the next float32 above it) unless ``round_up`` is false.

    A player's clip lasts until its last key, and one that loops (three.js's default)
    wraps to the start at that time or after: rounded to the nearest float32, the last
    key may fall at or just below the last frame, which then plays as the first. One ulp
    more changes no value a player shows by more than float32 does anyway.

    >>> t = key_times(np.array([0.0, 1 / 3, 8.3]))
    >>> t.dtype, bool(np.float32(1 / 3) == t[1]), float(t[2]) > 8.3, bool(np.nextafter(t[2], 0) <= 8.3)
    (dtype('float32'), True, True, True)
    """
    out = np.asarray(times, dtype=np.float32).copy()
    if out.size and round_up:
        end = float(np.asarray(times, dtype=float)[-1])
        out[-1] = np.nextafter(np.float32(end), np.float32(np.inf)) if float(out[-1]) <= end else out[-1]
    return out


#: Properties glTF gives a default, by the array of objects that have them.
DEFAULTS = {"accessors": {"byteOffset": 0, "normalized": False}, "bufferViews": {"byteOffset": 0},
            "samplers": {"interpolation": "LINEAR"}}


def _without_defaults(doc: dict) -> dict:
    """``doc`` (glTF JSON) without the properties that only repeat their default, nor
    empty extensions and extras (a compact file's JSON is much of its size).

    >>> _without_defaults({"accessors": [{"byteOffset": 0, "count": 2, "extras": {}}]})
    {'accessors': [{'count': 2}]}
    """
    def clean(value, defaults=None):
        if isinstance(value, dict):
            return {k: clean(v, DEFAULTS.get(k)) for k, v in value.items()
                    if not (defaults and k in defaults and v == defaults[k]) and not (k in ("extensions", "extras")
                                                                                    and v in ({}, None))}
        if isinstance(value, list):
            return [clean(v, defaults) for v in value]
        return value
    return clean(doc)


def _glb(doc: gl.GLTF2, blob: bytes) -> bytes:
    """A .glb of a document: the header, the JSON chunk and (if ``blob``) the binary
    chunk, ``blob`` being buffer 0 (pygltflib would merge every buffer into it, and
    always writes a BIN chunk, which is invalid empty)."""
    body = json.dumps(_without_defaults(json.loads(doc.gltf_to_json())), separators=(",", ":")).encode("utf-8")
    body += b" " * (-len(body) % 4)
    chunks = struct.pack("<I4s", len(body), b"JSON") + body
    if blob:
        chunks += struct.pack("<I4s", len(blob), b"BIN\0") + blob
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def bone_mesh(rest: np.ndarray, parents: tuple[int, ...]) -> Mesh:
    """A thin double pyramid from each joint's parent to the joint, at rest positions
    ``rest`` (J, 3), skinned to the parent.

    >>> m = bone_mesh(np.array([[0.0, 0, 0], [0, 1.0, 0]]), (-1, 0))
    >>> m.positions.shape, m.faces.shape, m.joints[:, 0].tolist(), m.weights.sum(axis=1).tolist()
    ((6, 3), (8, 3), [0, 0, 0, 0, 0, 0], [1.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    """
    positions, faces, joints = [], [], []
    for j, p in enumerate(parents):
        a, b = (rest[p], rest[j]) if p >= 0 else (None, None)
        if a is None or np.linalg.norm(b - a) < 1e-9:
            continue
        axis = (b - a) / np.linalg.norm(b - a)
        side = np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
        side /= np.linalg.norm(side)
        other = np.cross(axis, side)
        width = 0.1 * np.linalg.norm(b - a)
        mid = a + 0.2 * (b - a)
        ring = [mid + width * (np.cos(k * np.pi / 2) * side + np.sin(k * np.pi / 2) * other) for k in range(4)]
        base = len(positions)
        positions += [a, b, *ring]
        for k in range(4):
            r0, r1 = base + 2 + k, base + 2 + (k + 1) % 4
            faces += [[base, r1, r0], [base + 1, r0, r1]]
        joints += [p] * 6
    n = len(positions)
    joint_rows = np.zeros((n, 4), dtype=np.uint16)
    joint_rows[:, 0] = joints
    weight_rows = np.zeros((n, 4))
    weight_rows[:, 0] = 1.0
    return Mesh("bones", np.array(positions, dtype=float).reshape(n, 3), np.array(faces, dtype=int).reshape(-1, 3),
                joint_rows, weight_rows)


def octahedron(name: str, radius: float) -> Mesh:
    """An octahedron of ``radius`` about the origin: a marker, a light, a camera.

    >>> m = octahedron("dot", 2.0)
    >>> float(m.positions.max()), m.faces.shape
    (2.0, (8, 3))
    """
    positions = radius * np.vstack([np.eye(3), -np.eye(3)])
    faces = [[a, b, c] for a in (0, 3) for b in (1, 4) for c in (2, 5)]
    # outward winding: flip the faces whose corners are an odd number of negative axes
    faces = [f if (sum(i >= 3 for i in f) % 2 == 0) else f[::-1] for f in faces]
    return Mesh(name, positions, np.array(faces))
