"""A scene's skeletons as BVH: the joint objects an imported clip made, each naming its
parent joint in its :data:`~sketchanim.anim.scene.BONE_PARENT` attribute, written back as
a hierarchy with local rotations; and its chains and walkers, their derived pose sampled
at the frame rate.

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
from sketchanim.anim.rigs import played, rig_clip, rigs, ticks
from sketchanim.anim.scene import BONE_PARENT, Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.errors import ArgumentError
from sketchanim.motion.skeleton import JOINT_CHANNELS, ROOT_CHANNELS, Clip, Skeleton



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


def skeleton_clip(scene: Scene, tracks: dict[str, Track], fps: float) -> Clip:
    """The scene's skeletons (:func:`skeletons`; several are several roots) and rigs (a
    chain's or walker's derived pose, :func:`~sketchanim.anim.rigs.rig_clip`, its joints
    named ``<object>.<joint>``) as one :class:`Clip` at ``fps`` frames a second over
    their span (metres; each root's world translation, every joint's local rotation);
    :class:`NoSkeleton` if the scene has neither.

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import POSITION, AttributeType
    >>> scene = Scene(); _ = scene.add("hips")
    >>> _ = scene.add("knee").add(BONE_PARENT, AttributeType.enum(["hips"]), "hips")
    >>> walk = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 1, 0], [1.0, 1, 0]]), 1)
    >>> knee = BSpline(walk.t, walk.c - [0, 0.5, 0], 1)
    >>> clip = skeleton_clip(scene, {"hips.position": ContinuousTrack("hips.position", POSITION, walk, 0.005),
    ...                              "knee.position": ContinuousTrack("knee.position", POSITION, knee, 0.005)}, 4)
    >>> len(clip.times), clip.translations[4, 0].tolist(), clip.skeleton.offsets[1].tolist()
    (5, [1.0, 1.0, 0.0], [0.0, -0.5, 0.0])
    >>> _ = scene.add("arm", "chain")
    >>> skeleton_clip(scene, {}, 4).skeleton.names[2:4]
    ('arm.j1', 'arm.j2')
    """
    if not (np.isfinite(fps) and fps > 0):
        raise ArgumentError("fps", f"must be > 0, got {fps!r}")
    found = skeletons(scene)
    rigged = rigs(scene)
    if not found and not rigged:
        raise NoSkeleton("format", "the scene has no skeleton to write as BVH (import a clip: its joints make one; "
                                   "or add a chain or a walker)")
    joints = [name for skeleton in found for name in skeleton]
    spans = [(t.start, t.end) for name in joints for a in ("position", "orientation")
             if isinstance(t := tracks.get(f"{name}.{a}"), ContinuousTrack)]
    if rigged:
        spans.append((0.0, float(ticks(tracks)[-1])))
    start = min((a for a, _ in spans), default=0.0)
    end = max((b for _, b in spans), default=0.0)
    times = start + np.arange(int(np.ceil((end - start) * fps - 1e-9)) + 1) / fps
    clips = [_joint_clip(scene, tracks, found, times)] if found else []
    for name in rigged:
        clip = rig_clip(scene, tracks, name, times)
        named = Skeleton(tuple(f"{name}.{j}" for j in clip.skeleton.names), clip.skeleton.parents,
                         clip.skeleton.offsets)
        clips.append(Clip(named, times, clip.rotations, clip.translations, clip.rotating, clip.translating,
                          clip.channels, unit_m=1.0))
    return _joined(clips)


def _joint_clip(scene: Scene, tracks: dict[str, Track], found: list[list[str]], times: np.ndarray) -> Clip:
    """The joint objects of the skeletons ``found`` as a clip at ``times``."""
    joints = [name for skeleton in found for name in skeleton]
    roots = {skeleton[0] for skeleton in found}
    index = {name: i for i, name in enumerate(joints)}
    parents = tuple(-1 if name in roots else index[str(scene.get(f"{name}.{BONE_PARENT}"))] for name in joints)
    positions = np.stack([played(scene, tracks, f"{name}.position", times) for name in joints], axis=1)
    turns = [Rotation.from_quat(played(scene, tracks, f"{name}.orientation", times)) for name in joints]
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


def _joined(clips: list[Clip]) -> Clip:
    """Clips at the same times as one, their skeletons side by side (each its own roots)."""
    if len(clips) == 1:
        return clips[0]
    names, parents, first = [], [], 0
    for clip in clips:
        names += clip.skeleton.names
        parents += [p + first if p >= 0 else -1 for p in clip.skeleton.parents]
        first += len(clip.skeleton)
    skeleton = Skeleton(tuple(names), tuple(parents), np.concatenate([c.skeleton.offsets for c in clips]))
    return Clip(skeleton, clips[0].times, np.concatenate([c.rotations for c in clips], axis=1),
                np.concatenate([c.translations for c in clips], axis=1),
                np.concatenate([c.rotating for c in clips]), np.concatenate([c.translating for c in clips]),
                tuple(ch for c in clips for ch in c.channels), unit_m=1.0)


def _tol(tracks: dict[str, Track], path: str) -> float:
    """The tolerance of the position track at ``path`` (the attribute type's, without one)."""
    track = tracks.get(path)
    return float(track.tol) if isinstance(track, ContinuousTrack) else POSITION.tol
