"""A scene's skeletons as BVH: the joint objects an imported clip made, each naming its
parent joint in its :data:`~sketchanim.anim.scene.BONE_PARENT` attribute, written back as
a hierarchy with local rotations.

The scene keeps each joint's world motion (:mod:`sketchanim.mocap.scene_clip`); a BVH
keeps a root's world translation and every joint's rotation in its parent's frame, over
fixed bone offsets. So each joint's world position and orientation are sampled at the
frame rate (as the player plays them, held outside their tracks), and its local rotation
and translation are found from its parent's (``R_local = R_parent⁻¹ R``,
``t_local = R_parent⁻¹ (p - p_parent)``). A bone's offset is the median of its local
translation over the frames; a joint whose local translation strays from it by more than
its position track's tolerance (a hips joint that moves off a floor root, a bone a layer
stretched) gets position channels too, as a root has.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.scene import BONE_PARENT, Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.errors import ArgumentError
from sketchanim.motion.skeleton import Clip, Skeleton

ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")
JOINT_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")


class NoSkeleton(ArgumentError):
    """A BVH asked of a scene that has no skeleton."""


def skeletons(scene: Scene) -> list[list[str]]:
    """The scene's skeletons: for each root (a joint some object names as its parent,
    naming none itself), its joints in the scene's order, but each after its parent.

    >>> from sketchanim.anim.attributes import AttributeType
    >>> scene = Scene(); _ = scene.add("hips"); _ = scene.add("box")
    >>> _ = scene.add("knee").add(BONE_PARENT, AttributeType.enum(["hips"]), "hips")
    >>> skeletons(scene)
    [['hips', 'knee']]
    """
    parent = {name: obj.attributes[BONE_PARENT].value for name, obj in scene.objects.items()
              if BONE_PARENT in obj.attributes}
    children: dict[str, list[str]] = {}
    for name, up in parent.items():
        children.setdefault(str(up), []).append(name)
    out = []
    for root in scene.objects:
        if root in children and root not in parent:
            members, i = [root], 0
            while i < len(members):
                members += children.get(members[i], [])
                i += 1
            joints, rest = [root], [name for name in scene.objects if name in set(members[1:])]
            while rest:                               # the first in the scene's order whose parent is in
                name = next(n for n in rest if parent[n] in joints)
                joints.append(name)
                rest.remove(name)
            out.append(joints)
    return out


def _world(scene: Scene, tracks: dict[str, Track], path: str, times: np.ndarray) -> np.ndarray:
    """``path``'s values at ``times`` as the player plays them (its scene value without a track)."""
    track = tracks.get(path)
    if isinstance(track, ContinuousTrack):
        return track.evaluate(times)
    return np.tile(np.asarray(scene.get(path), dtype=float), (len(times), 1))


def skeleton_clip(scene: Scene, tracks: dict[str, Track], fps: float) -> Clip:
    """The scene's skeletons (:func:`skeletons`; several are several roots) as one
    :class:`Clip` at ``fps`` frames a second over their tracks' span (metres; each root's
    world translation, every joint's local rotation); :class:`ArgumentError` if the scene
    has none.

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import POSITION, AttributeType
    >>> scene = Scene(); _ = scene.add("hips")
    >>> _ = scene.add("knee").add(BONE_PARENT, AttributeType.enum(["hips"]), "hips")
    >>> walk = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 1, 0], [1.0, 1, 0]]), 1)
    >>> knee = BSpline(walk.t, walk.c - [0, 0.5, 0], 1)
    >>> clip = skeleton_clip(scene, {"hips.position": ContinuousTrack("hips.position", POSITION, walk, 0.005),
    ...                              "knee.position": ContinuousTrack("knee.position", POSITION, knee, 0.005)}, 4)
    >>> len(clip.times), clip.translations[-1, 0].tolist(), clip.skeleton.offsets[1].tolist()
    (5, [1.0, 1.0, 0.0], [0.0, -0.5, 0.0])
    """
    if not (np.isfinite(fps) and fps > 0):
        raise ArgumentError("fps", f"must be > 0, got {fps!r}")
    found = skeletons(scene)
    if not found:
        raise NoSkeleton("format", "the scene has no skeleton to write as BVH (import a clip: its joints make one)")
    joints = [name for skeleton in found for name in skeleton]
    roots = {skeleton[0] for skeleton in found}
    spans = [(t.start, t.end) for name in joints for a in ("position", "orientation")
             if isinstance(t := tracks.get(f"{name}.{a}"), ContinuousTrack)]
    start = min((a for a, _ in spans), default=0.0)
    end = max((b for _, b in spans), default=0.0)
    times = start + np.arange(int(np.ceil((end - start) * fps - 1e-9)) + 1) / fps
    index = {name: i for i, name in enumerate(joints)}
    parents = tuple(-1 if name in roots else index[str(scene.get(f"{name}.{BONE_PARENT}"))] for name in joints)
    positions = np.stack([_world(scene, tracks, f"{name}.position", times) for name in joints], axis=1)
    turns = [Rotation.from_quat(_world(scene, tracks, f"{name}.orientation", times)) for name in joints]
    rotations = np.empty((len(times), len(joints), 4))
    translations = np.empty((len(times), len(joints), 3))
    for i, up in enumerate(parents):
        if up < 0:
            rotations[:, i] = turns[i].as_quat()
            translations[:, i] = positions[:, i]
        else:
            rotations[:, i] = (turns[up].inv() * turns[i]).as_quat()
            translations[:, i] = turns[up].inv().apply(positions[:, i] - positions[:, up])
    offsets = np.median(translations, axis=0)
    tols = np.array([_tol(tracks, f"{name}.position") for name in joints])
    moving = np.array([up < 0 for up in parents]) | (np.linalg.norm(translations - offsets, axis=2).max(axis=0) > tols)
    offsets[moving] = translations[0, moving]
    translations[:, ~moving] = offsets[~moving]
    channels = tuple(ROOT_CHANNELS if m else JOINT_CHANNELS for m in moving)
    return Clip(Skeleton(tuple(joints), parents, offsets), times, rotations, translations,
                np.ones(len(joints), bool), moving, channels, unit_m=1.0)


def _tol(tracks: dict[str, Track], path: str) -> float:
    """The tolerance of the position track at ``path`` (the attribute type's, without one)."""
    track = tracks.get(path)
    return float(track.tol) if isinstance(track, ContinuousTrack) else POSITION.tol
