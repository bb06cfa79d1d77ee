"""A motion clip as tracks of the animation model: each joint's world position (in
metres) and world orientation over the clip's frames, reduced as a take is (one
``replace`` take per track, kept with it), so a joint is an object like any other: it
plays, shows in the curve editor, and a performance can be layered over it.

The scene has no hierarchy, so joints are not parented: each carries its own world
motion, found by forward kinematics (:func:`~sketchanim.motion.kinematics.world_pose`).
The clip's unit is its own (``Clip.unit_m``) or the one its rest figure's height
suggests (:meth:`~sketchanim.motion.skeleton.Clip.guess_unit_m`), else centimetres.

Markers (C3D's points, :class:`~sketchanim.mocap.markers.Markers`) become a world position
track each, reduced from the frames the marker was seen in (its gap-free runs,
:meth:`~sketchanim.mocap.markers.Markers.runs`); where it was not seen, its ``visible``
track is false (the curve passes the gap, but nothing is drawn or read there as seen).
"""

from __future__ import annotations

import re

import numpy as np

import dataclasses

from sketchanim.anim.attributes import BOOL, ORIENTATION, POSITION, AttributeType
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.mocap.markers import Markers
from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Clip

#: Metres per clip unit when neither the file nor the figure says (BVH's usual centimetres).
DEFAULT_UNIT_M = 0.01
#: Metres per marker unit when the file does not say (C3D's usual millimetres).
DEFAULT_MARKER_UNIT_M = 0.001
#: The B-spline order of a joint's tracks (cubic, as takes are recorded).
ORDER = 4
#: Longest object name the scene takes.
NAME_MAX = 64


def joint_tracks(clip: Clip, tol: float = POSITION.tol, rot_tol_deg: float = ORIENTATION.tol
                 ) -> dict[str, dict[str, ContinuousTrack]]:
    """Each joint's tracks by joint name: ``position`` (world, metres, within ``tol``)
    and ``orientation`` (world, within ``rot_tol_deg``),
    each with its frames as its take. Paths are ``<joint>.<attribute>``; the caller
    renames them for the scene (:func:`renamed`).

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("hips", "knee"), (-1, 0), np.array([[0.0, 90, 0], [0, -45, 0]]))
    >>> t = np.arange(60) / 30
    >>> clip = Clip.still(s, t)
    >>> tracks = joint_tracks(clip)
    >>> sorted(tracks["knee"]), tracks["knee"]["position"].evaluate([1.0]).round(3).tolist()
    (['orientation', 'position'], [[0.0, 0.45, 0.0]])
    """
    unit = clip.unit_m or clip.guess_unit_m() or DEFAULT_UNIT_M
    turns, positions = world_pose(clip.skeleton, clip.rotations, clip.translations)
    out: dict[str, dict[str, ContinuousTrack]] = {}
    for j, name in enumerate(clip.skeleton.names):
        samples: dict[str, tuple[AttributeType, np.ndarray]] = {"position": (POSITION, positions[:, j] * unit)}
        samples["orientation"] = (ORIENTATION, continuous(turns[j].as_quat()))
        out[name] = {}
        for attribute, (kind, values) in samples.items():
            limit = rot_tol_deg if kind.is_rotation else tol
            spline = reduce_samples(kind, clip.times, values, limit, ORDER)
            out[name][attribute] = ContinuousTrack(f"{name}.{attribute}", kind, spline, limit,
                                                   (Take(clip.times, values),))
    return out


def marker_tracks(markers: Markers, tol: float = POSITION.tol) -> dict[str, dict[str, Track]]:
    """Each seen marker's tracks by marker name: ``position`` (world, metres, within ``tol``
    of every frame it was seen in, those frames its take; one frame: held a frame on) and, for a marker with gaps,
    ``visible`` (false from each gap's first frame, true from each run's). A marker never
    seen has none.

    >>> p = np.zeros((6, 2, 3)); p[:, :, 1] = 1000.0; p[2:4, 1] = np.nan; p[:, 0] = np.nan
    >>> tracks = marker_tracks(Markers(("lost", "toe"), np.arange(6) / 100, p, 0.001))
    >>> list(tracks), tracks["toe"]["position"].evaluate([0.05]).round(3).tolist()
    (['toe'], [[0.0, 1.0, 0.0]])
    >>> tracks["toe"]["visible"].times, tracks["toe"]["visible"].values
    ([0.0, 0.02, 0.04], [True, False, True])
    """
    unit = markers.unit_m or DEFAULT_MARKER_UNIT_M
    out: dict[str, dict[str, Track]] = {}
    for m, name in enumerate(markers.names):
        runs = markers.runs(m)
        if not runs:
            continue
        seen = np.concatenate([np.arange(a, b) for a, b in runs])
        t, x = markers.times[seen], markers.positions[seen, m] * unit
        if len(t) == 1:                                 # seen once: held a frame on, a constant
            t, x = np.r_[t, t[0] + (markers.frame_time or 1.0)], np.r_[x, x]
        spline = reduce_samples(POSITION, t, x, tol, ORDER)
        out[name] = {"position": ContinuousTrack(f"{name}.position", POSITION, spline, tol, (Take(t, x),))}
        if len(seen) < len(markers.times):
            steps = [(markers.times[0], False)] if runs[0][0] > 0 else []
            for a, b in runs:
                steps.append((markers.times[a], True))
                if b < len(markers.times):
                    steps.append((markers.times[b], False))
            out[name]["visible"] = DiscreteTrack(f"{name}.visible", BOOL, [float(s[0]) for s in steps],
                                                 [s[1] for s in steps])
    return out


def continuous(quats: np.ndarray) -> np.ndarray:
    """Unit quaternions (n, 4) with each one's sign flipped where needed to stay on its
    predecessor's side (the same rotations, no jump through the other hemisphere).

    >>> continuous(np.array([[0, 0, 0.6, 0.8], [0, 0, -0.6, -0.8], [0, 0, 0.6, 0.8]]))[:, 3].tolist()
    [0.8, 0.8, 0.8]
    """
    q = np.array(quats, dtype=float)
    flips = np.sum(q[1:] * q[:-1], axis=1) < 0
    signs = np.r_[1.0, np.where(np.cumsum(flips) % 2, -1.0, 1.0)]
    return q * signs[:, None]


def object_names(prefix: str, joints: tuple[str, ...], taken: set[str]) -> list[str]:
    """Scene object names for a clip's joints: ``<prefix>_<joint>``, characters the
    scene does not take made ``_``, at most :data:`NAME_MAX` long, numbered where taken.

    >>> object_names("walk 1", ("mixamorig:Hips", "Head"), {"walk_1_Head"})
    ['walk_1_mixamorig_Hips', 'walk_1_Head_2']
    """
    base = re.sub(r"[^A-Za-z0-9_\-]", "_", prefix) or "clip"
    base = base if re.match(r"[A-Za-z_]", base) else f"_{base}"
    names: list[str] = []
    seen = set(taken)
    for joint in joints:
        stem = f"{base}_{re.sub(r'[^A-Za-z0-9_-]', '_', joint)}"[:NAME_MAX]
        name, n = stem, 1
        while name in seen:
            n += 1
            name = f"{stem[:NAME_MAX - len(str(n)) - 1]}_{n}"
        seen.add(name)
        names.append(name)
    return names


def renamed(track: Track, name: str) -> Track:
    """``track`` as the track of the object ``name`` (the same attribute).

    >>> from scipy.interpolate import BSpline
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.zeros((2, 3)), 1)
    >>> renamed(ContinuousTrack("hips.position", POSITION, s, 0.005), "walk_hips").path
    'walk_hips.position'
    """
    return dataclasses.replace(track, path=f"{name}.{track.path.split('.')[1]}")
