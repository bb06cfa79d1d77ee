"""Rigs: the chains and walkers of a scene, whose pose is derived from a performed goal.

The animator performs a rig's ``goal`` (an ordinary position track: recorded, layered and
edited like any other); its pose is a pure function of the scene's tracks, found by
sampling the goal (and a chain's base) as the player plays them at the ticks ``k / RATE``
from time 0 and stepping the rig's solver tick by tick (:func:`sketchanim.motion.ik.solve`
for a chain, :func:`sketchanim.motion.walk.walk` for a walker). The page does the same
with the same algorithms (``web/js/ik.js``, ``walk.js``), so the figure it draws is the one
a file gets. Nothing is baked until export (:mod:`sketchanim.export.rig_bake`).

A rig's pose is a :class:`~sketchanim.motion.skeleton.Clip` in the world (metres): a
chain's joints ``j1`` .. ``jN`` and its ``tip``, the first at the base; a walker's
humanoid (:func:`~sketchanim.motion.walk.humanoid`), its hips carrying its world
translation.
"""

from __future__ import annotations

import numpy as np

from sketchanim.anim.scene import RIGS, Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.errors import ArgumentError
from sketchanim.motion import ik, walk
from sketchanim.motion.rotations import slerped
from sketchanim.motion.skeleton import JOINT_CHANNELS, ROOT_CHANNELS, Clip, Skeleton

#: Seconds a rig's pose runs past the scene's last key: a walker's stop steps, a chain's
#: catch-up to a goal that came back in reach.
SETTLE = 1.0

#: Ticks a rig's solver runs on its goal's first value before time 0 (from the rest pose),
#: so that at 0 the figure has settled on its goal: a chain reaching for it, a walker standing.
LEAD = int(2 * ik.RATE)


def played(scene: Scene, tracks: dict[str, Track], path: str, times: np.ndarray) -> np.ndarray:
    """``path``'s values at ``times`` (n, d) as the player plays them: its curve, held
    outside its span, or its scene value where it has no track.

    >>> scene = Scene(); _ = scene.add("box")
    >>> played(scene, {}, "box.position", np.array([0.0, 1.0])).tolist()
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """
    track = tracks.get(path)
    if isinstance(track, ContinuousTrack):
        return track.evaluate(times)
    return np.tile(np.asarray(scene.get(path), dtype=float), (len(times), 1))


def rigs(scene: Scene) -> list[str]:
    """The names of the scene's rigs (chains and walkers), in the scene's order.

    >>> scene = Scene(); _ = scene.add("box"); _ = scene.add("arm", "chain")
    >>> rigs(scene)
    ['arm']
    """
    return [name for name, obj in scene.objects.items() if obj.kind in RIGS]


def ticks(tracks: dict[str, Track]) -> np.ndarray:
    """The times a rig's pose is solved at: ``k / RATE`` from 0 to :data:`SETTLE` past
    the last end of any continuous track (just 0 and the settle without tracks).

    >>> ticks({}).size == int(SETTLE * ik.RATE) + 1
    True
    """
    end = max((t.end for t in tracks.values() if isinstance(t, ContinuousTrack)), default=0.0)
    return np.arange(int(np.ceil((max(end, 0.0) + SETTLE) * ik.RATE - 1e-9)) + 1) / ik.RATE


def chain(scene: Scene, name: str) -> ik.Chain:
    """The chain object ``name``'s structure, from its ``lengths``, ``limits`` and
    ``hinges`` (:data:`~sketchanim.anim.scene.CHAIN_SLOTS` slots each).

    >>> scene = Scene(); _ = scene.add("arm", "chain")
    >>> len(chain(scene, "arm").lengths)
    5
    >>> scene.set("arm.lengths", [0.5] + [0.0] * 7); chain(scene, "arm")
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: arm.lengths: a chain is 2 to 8 leading positive lengths, got 1
    """
    try:
        return ik.Chain.from_slots(*(scene.get(f"{name}.{a}") for a in ("lengths", "limits", "hinges")))
    except ArgumentError as err:                     # the chain's own field, named with the object
        raise ArgumentError(f"{name}.{err.argument}", str(err).removeprefix(f"{err.argument}: ")) from None


def height(scene: Scene, name: str) -> float:
    """The walker ``name``'s height, metres."""
    value = float(scene.get(f"{name}.height")[0])
    if not (np.isfinite(value) and value > 0):
        raise ArgumentError(f"{name}.height", f"a walker's height must be a positive length, got {value!r}")
    return value


def rig_clip(scene: Scene, tracks: dict[str, Track], name: str, times: np.ndarray | None = None) -> Clip:
    """The rig ``name``'s pose at :func:`ticks` (or at ``times``, the pose between ticks
    interpolated: rotations spherically, translations linearly), as a world-space clip.

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import POSITION
    >>> scene = Scene(); _ = scene.add("arm", "chain")
    >>> reach = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.5, 1.1, 0], [0.3, 0.6, 0.4]]), 1)
    >>> clip = rig_clip(scene, {"arm.goal": ContinuousTrack("arm.goal", POSITION, reach, 0.005)}, "arm")
    >>> clip.skeleton.names, bool(np.linalg.norm(clip.world_positions()[-1, -1] - [0.3, 0.6, 0.4]) < 1e-3)
    (('j1', 'j2', 'j3', 'j4', 'j5', 'tip'), True)
    """
    obj = scene.objects.get(name)
    if obj is None or obj.kind not in RIGS:
        raise ArgumentError("object", f"{name!r} is not a chain or a walker")
    at = ticks(tracks)
    held = np.r_[np.zeros(LEAD), at]                  # LEAD ticks at the goal's first value, then the ticks
    goals = played(scene, tracks, f"{name}.goal", held)
    if obj.kind == "chain":
        clip = _chain_clip(chain(scene, name), at, goals, played(scene, tracks, f"{name}.position", held))
    else:
        clip = _walker_clip(height(scene, name), at, goals)
    return clip if times is None else resampled(clip, np.asarray(times, dtype=float))


def _chain_clip(structure: ik.Chain, at: np.ndarray, goals: np.ndarray, base: np.ndarray) -> Clip:
    """A chain's clip: joints ``j1`` (at the base) .. ``jN`` and its ``tip``."""
    lengths = np.asarray(structure.lengths)
    joints = len(lengths)
    names = tuple(f"j{i + 1}" for i in range(joints)) + ("tip",)
    offsets = np.zeros((joints + 1, 3))
    offsets[1:, 1] = lengths
    offsets[0] = base[LEAD]
    skeleton = Skeleton(names, tuple(range(-1, joints)), offsets)
    rotations, translations = skeleton.rest_pose(len(at))
    rotations[:, :joints] = ik.solve(structure, goals - base)[LEAD:]
    translations[:, 0] = base[LEAD:]
    rotating = np.r_[np.ones(joints, bool), False]
    translating = np.zeros(joints + 1, bool)
    translating[0] = True
    channels = (ROOT_CHANNELS,) + (JOINT_CHANNELS,) * joints
    return Clip(skeleton, at, rotations, translations, rotating, translating, channels, unit_m=1.0)


def _walker_clip(tall: float, at: np.ndarray, goals: np.ndarray) -> Clip:
    """A walker's clip: its humanoid, the hips moving in the world."""
    skeleton = walk.humanoid(tall)
    done = walk.walk(skeleton, goals)
    _, translations = skeleton.rest_pose(len(at))
    translations[:, 0] = done.root[LEAD:]
    translating = np.zeros(len(skeleton), bool)
    translating[0] = True
    channels = (ROOT_CHANNELS,) + (JOINT_CHANNELS,) * (len(skeleton) - 1)
    return Clip(skeleton, at, np.asarray(done.rotations[LEAD:], dtype=float), translations, np.ones(len(skeleton), bool),
                translating, channels, unit_m=1.0)


def resampled(clip: Clip, times: np.ndarray) -> Clip:
    """``clip`` at ``times``: between its frames rotations slerped and translations
    lerped, held outside them.

    >>> s = Skeleton(("a",), (-1,), np.zeros((1, 3)))
    >>> c = Clip.still(s, [0.0, 1.0]); c.translations[1, 0] = [2.0, 0, 0]
    >>> resampled(c, np.array([0.5, 3.0])).translations[:, 0, 0].tolist()
    [1.0, 2.0]
    """
    at = np.clip(times, clip.times[0], clip.times[-1])
    rotations = slerped(clip.times, clip.rotations, at)
    translations = np.stack([np.stack([np.interp(at, clip.times, clip.translations[:, j, d]) for d in range(3)], -1)
                             for j in range(len(clip.skeleton))], axis=1)
    return Clip(clip.skeleton, np.asarray(times, dtype=float), rotations, translations, clip.rotating,
                clip.translating, clip.channels, clip.unit_m)
