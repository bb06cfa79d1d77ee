"""A scene of the animation model as USD (needs the optional ``usd-core``): one Xform
prim per object at the stage's root, its position, orientation and scale as translate,
orient and scale ops (written by :func:`~sketchanim.formats.usd.write_usd_xforms`). A
chain or walker is a prim with its joints nested under it, each its parent's child, their
derived pose (:func:`~sketchanim.anim.rigs.rig_clip`) as samples at the solver's ticks,
and its goal, ``goal``, beside them.

USD transforms have no B-spline form, so each track is written as time samples of its
curve, in double precision, where the track was sampled
(:func:`~sketchanim.export.scene_gltf.track_times`: its takes' sample times, or
``FRAME_RATE`` per second for a track without takes). At those times a USD client plays
the curve itself, so what the curve keeps (the track's tolerance of its takes) it keeps;
between them it interpolates (linearly, orientations spherically). An attribute without a
track is written as its current value. Like the glTF export, the other tracks (colour,
visibility, events...) are left out and listed.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from sketchanim.anim.rigs import rig_clip
from sketchanim.anim.scene import RIGS, Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.export.scene_gltf import left_out, track_times
from sketchanim.formats.usd import OpValues, XformSamples, write_usd_xforms

#: The Xform op each transform attribute becomes.
USD_OPS = {"position": "translate", "orientation": "orient", "scale": "scale"}


def _prim_name(name: str, taken: set[str]) -> str:
    """A USD identifier for the object ``name`` (``-`` becomes ``_``), numbered if taken."""
    base = name.replace("-", "_")
    prim, n = base, 1
    while prim in taken:
        n += 1
        prim = f"{base}_{n}"
    taken.add(prim)
    return prim


def _op(scene: Scene, tracks: dict[str, Track], path: str) -> OpValues:
    """An attribute's op values: its track's curve at the track's sample times, or its
    current value."""
    track = tracks.get(path)
    if isinstance(track, ContinuousTrack):
        times = track_times(track)
        values = track.evaluate(times)
        if track.type.is_rotation:
            values = values / np.linalg.norm(values, axis=1, keepdims=True)
        return times, values
    return None, np.asarray(scene.get(path), dtype=float)


def _rig_xforms(scene: Scene, tracks: dict[str, Track], name: str, prim: str) -> list[XformSamples]:
    """A rig as nested Xforms: ``/prim`` (at the origin), its joints under it (each under
    its parent, its pose at the solver's ticks) and ``/prim/goal``."""
    clip = rig_clip(scene, tracks, name)
    sk = clip.skeleton
    paths: list[str] = []
    out = [XformSamples(prim)]
    for j, (joint, up) in enumerate(zip(sk.names, sk.parents)):
        paths.append(f"{paths[up] if up >= 0 else prim}/{joint}")
        moves = (clip.times, clip.translations[:, j]) if clip.translating[j] else (None, sk.offsets[j])
        turns = (clip.times, clip.rotations[:, j]) if clip.rotating[j] else None
        out.append(XformSamples(paths[j], translate=moves, orient=turns))
    out.append(XformSamples(f"{prim}/goal", translate=_op(scene, tracks, f"{name}.goal")))
    return out


def scene_usd(path: str | os.PathLike[str], scene: Scene, tracks: dict[str, Track], rate: float) -> list[str]:
    """Write the scene to ``path`` (.usd, .usda, .usdc) atomically, time codes at
    ``rate`` per second (the project's frame rate); the paths of the tracks left out
    (USD here holds transforms only).

    >>> import tempfile
    >>> from pxr import Usd
    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import POSITION
    >>> scene = Scene(); _ = scene.add("box"); _ = scene.add("lamp", "light")
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> out = Path(tempfile.mkdtemp()) / "scene.usda"
    >>> scene_usd(out, scene, {"box.position": ContinuousTrack("box.position", POSITION, s, 0.005)}, 30.0)
    []
    >>> stage = Usd.Stage.Open(str(out))
    >>> stage.GetPrimAtPath("/box").GetAttribute("xformOp:translate").Get(15.0)
    Gf.Vec3d(0.5, 1.0, 1.5)
    """
    taken: set[str] = set()
    xforms = []
    for obj in scene.objects.values():
        if obj.kind in RIGS:
            xforms += _rig_xforms(scene, tracks, obj.name, _prim_name(obj.name, taken))
            continue
        if "position" not in obj.attributes:          # a cue object: events, no place in space (left out)
            continue
        ops = {USD_OPS[a]: _op(scene, tracks, f"{obj.name}.{a}") for a in USD_OPS if a in obj.attributes}
        xforms.append(XformSamples(_prim_name(obj.name, taken), **ops))
    write_usd_xforms(Path(path), rate, xforms, 1.0)
    return left_out(scene, tracks)
