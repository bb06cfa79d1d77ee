"""Motion clips for the interop tests: random skeletons with smooth random motion, and
checks shared by the tests (every frame and joint against a source clip; the glTF
validator; an independent evaluation of glTF CUBICSPLINE samplers)."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import meshopt
import numpy as np
import pygltflib as gl
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.reducer.metric import rotation_angle

ROOT = Path(__file__).resolve().parents[1]
ORDERS = ("ZXY", "ZYX", "XYZ", "YXZ", "YZX", "XZY")


@st.composite
def clips(draw: st.DrawFn) -> Clip:
    """A chain-and-branch skeleton of 2 to 6 joints, each with a random Euler order,
    the root (and sometimes another joint) translating, smooth motion of random speed
    (sums of sines, up to a few turns), 24 to 120 frames per second."""
    j = draw(st.integers(2, 6))
    parents = tuple([-1] + [draw(st.integers(0, i - 1)) for i in range(1, j)])
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    offsets = rng.normal(0, 20, (j, 3))
    rate = draw(st.sampled_from([24.0, 30.0, 60.0, 120.0]))
    n = draw(st.integers(20, 240))
    t = np.arange(n) / rate
    speed = draw(st.floats(0.2, 3.0))
    layout, rotating, translating = [], np.ones(j, bool), np.zeros(j, bool)
    translating[0] = True
    if j > 2 and draw(st.booleans()):
        translating[j - 1] = True
    rotations = np.empty((n, j, 4))
    translations = np.broadcast_to(offsets, (n, j, 3)).copy()
    for i in range(j):
        order = draw(st.sampled_from(ORDERS))
        amp = rng.uniform(5, 120, 3)
        freq, phase = rng.uniform(0.1, 2.0, 3) * speed, rng.uniform(0, 2 * np.pi, 3)
        angles = amp * np.sin(np.outer(t, freq) * 2 * np.pi + phase)
        rotations[:, i] = Rotation.from_euler(order, angles, degrees=True).as_quat()
        rot = tuple(f"{a}rotation" for a in order)
        if translating[i]:
            translations[:, i] = offsets[i] + rng.uniform(5, 50, 3) * np.sin(np.outer(t, freq) + phase)
            layout.append(("Xposition", "Yposition", "Zposition") + rot)
        else:
            layout.append(rot)
    skeleton = Skeleton(tuple(f"j{i}" for i in range(j)), parents, offsets)
    return Clip(skeleton, t, rotations, translations, rotating, translating, tuple(layout))


def assert_within(clip: Clip, source: Clip, tol: float, rot_tol_deg: float, slack: float = 1e-6) -> None:
    """Every frame and joint of ``clip`` within ``tol`` (distance) and ``rot_tol_deg``
    of ``source``, over the joints ``source`` moves."""
    assert np.allclose(clip.times, source.times, atol=1e-9)
    for j in np.flatnonzero(source.rotating):
        angle = np.degrees(rotation_angle(clip.rotations[:, j], source.rotations[:, j]))
        assert angle.max() <= rot_tol_deg + slack, (source.skeleton.names[j], angle.max())
    for j in np.flatnonzero(source.translating):
        dist = np.linalg.norm(clip.translations[:, j] - source.translations[:, j], axis=1)
        assert dist.max() <= tol + slack, (source.skeleton.names[j], dist.max())


def validate(*paths: Path) -> list[dict]:
    """The Khronos glTF-Validator's report of each file (scripts/validate-gltf.mjs)."""
    out = subprocess.run(["node", str(ROOT / "scripts" / "validate-gltf.mjs"), *map(str, paths)],
                         capture_output=True, text=True, check=True, cwd=ROOT)
    return [json.loads(line) for line in out.stdout.splitlines()]


def samplers(path: Path) -> dict[tuple[str, str], tuple[str, np.ndarray, np.ndarray]]:
    """Each animated (node name, path) of a .glb: its interpolation, key times and
    outputs ((m, 3, d) for CUBICSPLINE, else (m, d)), read with pygltflib from the
    file's bytes."""
    doc = gl.GLTF2().load_binary(str(path))
    blob = doc.binary_blob()
    views = {i: _view_bytes(v, blob) for i, v in enumerate(doc.bufferViews)}

    def accessor(i: int) -> np.ndarray:
        acc = doc.accessors[i]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[acc.type]
        kind = {gl.FLOAT: np.float32, gl.SHORT: np.int16}[acc.componentType]
        values = np.frombuffer(views[acc.bufferView], kind, acc.count * width, acc.byteOffset or 0)
        values = values.reshape(acc.count, width).astype(float)
        return np.maximum(values / 32767, -1.0) if acc.normalized else values

    out = {}
    for ch in (doc.animations[0].channels if doc.animations else []):
        sampler = doc.animations[0].samplers[ch.sampler]
        times = accessor(sampler.input)[:, 0]
        values = accessor(sampler.output)
        if sampler.interpolation == "CUBICSPLINE":
            values = values.reshape(len(times), 3, -1)
        out[(doc.nodes[ch.target.node].name, ch.target.path)] = (sampler.interpolation, times, values)
    return out


def _view_bytes(view: gl.BufferView, blob: bytes) -> bytes:
    """A buffer view's bytes: as stored, or decoded from EXT_meshopt_compression."""
    ext = (view.extensions or {}).get("EXT_meshopt_compression")
    if ext is None:
        start = view.byteOffset or 0
        return blob[start:start + view.byteLength]
    packed = blob[ext.get("byteOffset", 0):ext.get("byteOffset", 0) + ext["byteLength"]]
    return meshopt.decode_gltf_buffer(packed, ext["count"], ext["byteStride"], ext["mode"],
                                      ext.get("filter", "NONE")).tobytes()


def played_pose(path: Path, skeleton: Skeleton, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Local rotations (n, J, 4) and translations (n, J, 3) of ``skeleton``'s joints as a
    .glb of LINEAR samplers plays at ``t`` in float32 (:func:`linear_play32`): each node's
    own transform where it has no channel (read from the file independently of the
    writer)."""
    doc = gl.GLTF2().load_binary(str(path))
    nodes = {n.name: n for n in doc.nodes}
    rot = np.array([nodes[name].rotation or [0.0, 0, 0, 1] for name in skeleton.names], dtype=float)
    trans = np.array([nodes[name].translation or [0.0, 0, 0] for name in skeleton.names], dtype=float)
    rotations, translations = np.repeat(rot[None], len(t), axis=0), np.repeat(trans[None], len(t), axis=0)
    for (name, what), (kind, times, values) in samplers(path).items():
        if name in nodes and what in ("rotation", "translation"):
            assert kind == "LINEAR", (name, what, kind)
            out = rotations if what == "rotation" else translations
            out[:, skeleton.index(name)] = linear_play32(times, values, t, what == "rotation").astype(float)
    return rotations, translations


def world_misses(clip: Clip, rotations: np.ndarray, translations: np.ndarray, shell: float) -> np.ndarray:
    """Per frame and joint (n, J): how far local ``rotations`` and ``translations`` of
    ``clip``'s skeleton put each joint from the source's in the world, plus the most a
    point ``shell`` from it moves by their world rotations' difference."""
    turns, positions = world_pose(clip.skeleton, rotations, translations)
    source_turns, source = world_pose(clip.skeleton, clip.rotations, clip.translations)
    out = np.linalg.norm(positions - source, axis=-1)
    for j in range(len(clip.skeleton)):
        out[:, j] += 2 * shell * np.sin((turns[j] * source_turns[j].inv()).magnitude() / 2)
    return out


def hermite_play(times: np.ndarray, keys: np.ndarray, t: np.ndarray) -> np.ndarray:
    """A CUBICSPLINE sampler played at times ``t`` inside its keys' span
    (:func:`hermite_at` on the segment holding each)."""
    if len(times) == 1:
        return np.repeat(keys[:1, 1], len(t), axis=0)
    seg = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)
    return hermite_at(times, keys, seg, (t - times[seg]) / (times[seg + 1] - times[seg]))


def hermite_at(times: np.ndarray, keys: np.ndarray, segment: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The glTF spec's cubic Hermite formula, on ``segment`` k at normalised ``u``:
    p = (2u^3 - 3u^2 + 1) v_k + td (u^3 - 2u^2 + u) b_k + (-2u^3 + 3u^2) v_k+1 + td (u^3 - u^2) a_k+1."""
    td = (times[segment + 1] - times[segment])[:, None]
    a_next, v0, b0, v1 = keys[segment + 1, 0], keys[segment, 1], keys[segment, 2], keys[segment + 1, 1]
    u = u[:, None]
    return ((2 * u**3 - 3 * u**2 + 1) * v0 + td * (u**3 - 2 * u**2 + u) * b0 + (-2 * u**3 + 3 * u**2) * v1
            + td * (u**3 - u**2) * a_next)


def play32(times: np.ndarray, keys: np.ndarray, t: np.ndarray) -> np.ndarray:
    """A CUBICSPLINE sampler (float32 keys) played as a float32 client does: every
    operation in float32, the time clamped to the keys' span."""
    f = np.float32
    times, keys, t = times.astype(f), keys.astype(f), np.clip(t, times[0], times[-1]).astype(f)
    if len(times) == 1:
        return np.repeat(keys[:1, 1], len(t), axis=0)
    seg = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)
    td = (times[seg + 1] - times[seg])[:, None]
    u = ((t - times[seg]) / td[:, 0])[:, None]
    u2, u3 = u * u, u * u * u
    return ((f(2) * u3 - f(3) * u2 + f(1)) * keys[seg, 1] + td * (u3 - f(2) * u2 + u) * keys[seg, 2]
            + (f(-2) * u3 + f(3) * u2) * keys[seg + 1, 1] + td * (u3 - u2) * keys[seg + 1, 0])


def linear_play32(times: np.ndarray, keys: np.ndarray, t: np.ndarray, rotation: bool, spherical: bool = True
                  ) -> np.ndarray:
    """A LINEAR sampler played in float32 at ``t`` (clamped to its keys): rotations
    spherically (glTF's rule, three.js) or, ``spherical=False``, component-wise and
    normalised (Blender's F-curves)."""
    f = np.float32
    times, keys, t = times.astype(f), keys.astype(f), np.clip(t, times[0], times[-1]).astype(f)
    if len(times) == 1:
        return np.repeat(keys[:1], len(t), axis=0)
    seg = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)
    s = ((t - times[seg]) / (times[seg + 1] - times[seg]))[:, None]
    a, b = keys[seg], keys[seg + 1]
    if not rotation:
        return a + s * (b - a)
    if not spherical:
        out = (f(1) - s) * a + s * b
        return out / np.linalg.norm(out, axis=1, keepdims=True)
    dot = np.clip(np.sum(a * b, axis=1, keepdims=True), -1, 1)
    b = np.where(dot < 0, -b, b)
    angle = np.arccos(np.abs(dot)).astype(f)
    small = angle < f(1e-6)
    sin = np.where(small, f(1), np.sin(angle))
    out = np.where(small, (f(1) - s) * a + s * b, (np.sin((f(1) - s) * angle) * a + np.sin(s * angle) * b) / sin)
    return out / np.linalg.norm(out, axis=1, keepdims=True)


def sampler_play32(kind: str, times: np.ndarray, keys: np.ndarray, t: np.ndarray, rotation: bool,
                   spherical: bool = True) -> np.ndarray:
    """A CUBICSPLINE or LINEAR sampler played in float32 at ``t`` (:func:`play32`,
    :func:`linear_play32`; rotations normalised, a LINEAR one spherically or not)."""
    if kind == "LINEAR":
        return linear_play32(times, keys, t, rotation, spherical)
    assert kind == "CUBICSPLINE", kind
    out = play32(times, keys, t)
    return out / np.linalg.norm(out, axis=1, keepdims=True) if rotation else out


def played(path: Path, node: str, channel: str, times: np.ndarray) -> np.ndarray:
    """A glTF channel played at ``times`` as a float32 viewer plays it (the spec's
    Hermite rule in float32 on the float32 keys; rotations normalised)."""
    kind, keys_t, keys = samplers(path)[(node, channel)]
    assert kind == "CUBICSPLINE"
    out = play32(keys_t, keys, times).astype(float)
    return out / np.linalg.norm(out, axis=1, keepdims=True) if channel == "rotation" else out


def float32_shares(clip: Clip, tol: float, rot_tol_deg: float) -> tuple[float, float]:
    """The largest share of the tolerances that reduce_clip leaves to float32 over the
    clip's joints (rotation degrees, distance): how far a float32 client may play from
    our float64 curves."""
    from sketchanim.float32 import position_budget, rotation_budget

    angle = max(rot_tol_deg - rotation_budget(clip.times, clip.rotations[:, j], rot_tol_deg)
                for j in np.flatnonzero(clip.rotating))
    dist = max((tol - position_budget(clip.times, clip.translations[:, j], tol)
                for j in np.flatnonzero(clip.translating)), default=0.0)
    return angle, dist


def local_errors(rot: np.ndarray, trans: np.ndarray, clip: Clip) -> tuple[float, float]:
    """Largest joint-local rotation angle (degrees) and translation distance (clip
    units) of played rotations (n, J, 4) and translations (n, J, 3) against ``clip``,
    over the joints it moves."""
    angle = max(float(np.degrees(rotation_angle(rot[:, j], clip.rotations[:, j])).max())
                for j in np.flatnonzero(clip.rotating))
    dist = max((float(np.linalg.norm(trans[:, j] - clip.translations[:, j], axis=1).max())
                for j in np.flatnonzero(clip.translating)), default=0.0)
    return angle, dist
