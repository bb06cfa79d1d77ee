"""glTF 2.0 binary (.glb) export, with pygltflib: reduced clips as a skinned skeleton
animated by CUBICSPLINE samplers.

A cubic B-spline converts exactly to a CUBICSPLINE sampler: one key per breakpoint, its
value and one-sided derivatives (:func:`sketchanim.spline.hermite.to_hermite`). An
order-2 curve is exactly a LINEAR sampler, an order-3 one is raised to cubic exactly;
higher orders have no exact glTF form and are refused (reduce with ``order <= 4``).
Orientation curves are quaternion splines normalised when played: that is how glTF
plays a CUBICSPLINE rotation, so they too are exact (to float32).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pygltflib as gl
from scipy.interpolate import BSpline

from sketchanim.anim.clip_reduction import ReducedClip
from sketchanim.errors import ArgumentError
from sketchanim.spline.hermite import to_hermite
from sketchanim.spline.knots import elevate_degree

GENERATOR = "sketchanim"

_FLOAT = gl.FLOAT
_TYPES = {1: gl.SCALAR, 3: gl.VEC3, 4: gl.VEC4, 16: gl.MAT4}


@dataclass
class Node:
    """A glTF node: name, parent index (-1 for the scene's roots), rest translation, and
    the mesh and skin it carries."""

    name: str
    parent: int = -1
    translation: list[float] | None = None
    mesh: int | None = None
    skin: int | None = None


@dataclass(frozen=True)
class Channel:
    """One animated property: node index, glTF path (translation, rotation, scale) and
    the curve (evaluating to (n, 3) or (n, 4))."""

    node: int
    path: str
    spline: BSpline


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


class _Buffer:
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


def glb_bytes(nodes: list[Node], channels: list[Channel], *, animation: str = "take",
              mesh: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None,
              skin_joints: list[int] | None = None, inverse_binds: np.ndarray | None = None) -> bytes:
    """A .glb of ``nodes`` animated by ``channels``; an optional skinned ``mesh``
    (positions (v, 3), triangle indices (f, 3), joints (v, 4), weights (v, 4)) bound to
    ``skin_joints`` with ``inverse_binds`` (J, 4, 4), carried by a root node of its own."""
    doc = gl.GLTF2(asset=gl.Asset(version="2.0", generator=GENERATOR), scene=0, scenes=[gl.Scene(nodes=[])])
    buf = _Buffer(doc)
    all_nodes = list(nodes)
    if mesh is not None:
        positions, faces, joints, weights = mesh
        prim = gl.Primitive(attributes=gl.Attributes(
            POSITION=buf.add(positions, 3, bounds=True, target=gl.ARRAY_BUFFER),
            JOINTS_0=buf.add(joints, 4, component=gl.UNSIGNED_SHORT, target=gl.ARRAY_BUFFER),
            WEIGHTS_0=buf.add(weights, 4, target=gl.ARRAY_BUFFER)),
            indices=buf.add(faces.reshape(-1), 1, component=gl.UNSIGNED_SHORT, target=gl.ELEMENT_ARRAY_BUFFER))
        doc.meshes.append(gl.Mesh(name="bones", primitives=[prim]))
        doc.skins.append(gl.Skin(name="skeleton", joints=list(skin_joints or []),
                                 inverseBindMatrices=buf.add(np.transpose(inverse_binds, (0, 2, 1)), 16)))
        all_nodes.append(Node("bones", mesh=0, skin=0))
    for node in all_nodes:
        doc.nodes.append(gl.Node(name=node.name, translation=node.translation, mesh=node.mesh, skin=node.skin))
    for i, node in enumerate(all_nodes):
        (doc.scenes[0].nodes if node.parent < 0 else doc.nodes[node.parent].children).append(i)
    if channels:
        anim = gl.Animation(name=animation)
        for ch in channels:
            kind, times, out = sampler_keys(ch.spline)
            width = out.shape[-1]
            anim.samplers.append(gl.AnimationSampler(input=buf.add(times, 1, bounds=True),
                                                     output=buf.add(out, width), interpolation=kind))
            anim.channels.append(gl.AnimationChannel(sampler=len(anim.samplers) - 1,
                                                     target=gl.AnimationChannelTarget(node=ch.node, path=ch.path)))
        doc.animations.append(anim)
    buf.data += b"\0" * (-len(buf.data) % 4)
    doc.buffers.append(gl.Buffer(byteLength=len(buf.data)))
    doc.set_binary_blob(bytes(buf.data))
    return b"".join(doc.save_to_bytes())


def bone_mesh(rest: np.ndarray, parents: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A thin double pyramid from each joint's parent to the joint, at rest positions
    ``rest`` (J, 3), skinned to the parent: positions, faces, joints, weights.

    >>> pos, faces, joints, weights = bone_mesh(np.array([[0.0, 0, 0], [0, 1.0, 0]]), (-1, 0))
    >>> pos.shape, faces.shape, joints[:, 0].tolist(), weights.sum(axis=1).tolist()
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
    return np.array(positions, dtype=float).reshape(n, 3), np.array(faces, dtype=int).reshape(-1, 3), joint_rows, \
        weight_rows


def clip_glb(clip: ReducedClip, *, name: str = "clip") -> bytes:
    """A reduced clip as a .glb: one node per joint (rest offsets), a skinned bone mesh,
    and one animation whose channels are the clip's curves, exactly."""
    sk = clip.skeleton
    nodes = [Node(n, p, translation=o.tolist()) for n, p, o in zip(sk.names, sk.parents, sk.offsets)]
    channels = [Channel(i, "rotation", r.columns) for i, r in sorted(clip.rotations.items())]
    channels += [Channel(i, "translation", r.columns) for i, r in sorted(clip.translations.items())]
    rest = sk.rest_positions()
    inverse = np.tile(np.eye(4), (len(sk), 1, 1))
    inverse[:, :3, 3] = -rest
    mesh = bone_mesh(rest, sk.parents)
    if not len(mesh[0]):
        return glb_bytes(nodes, channels, animation=name)
    return glb_bytes(nodes, channels, animation=name, mesh=mesh, skin_joints=list(range(len(sk))),
                     inverse_binds=inverse)

