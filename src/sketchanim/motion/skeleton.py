"""Skeletons and sampled clips: joints in a hierarchy, each with a local rotation and
translation per frame, as motion capture formats (BVH, ASF/AMC) hold them.

Conventions: a joint's local transform is ``T(translation) R(rotation)``, applied after
its parent's (``world_j = world_parent * local_j``); rotations are scalar-last unit
quaternions ``(x, y, z, w)`` as scipy's ``Rotation``; a joint without translation
channels sits at its rest ``offset`` from its parent. Times in seconds; positions in the
clip's own units (``Clip.unit_m`` metres each, where known). Forward kinematics is in
:mod:`sketchanim.motion.kinematics`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sketchanim.errors import ArgumentError
from sketchanim.motion.kinematics import world_matrices

#: Figure heights (metres) the unit guess accepts: a person standing, within reason.
FIGURE_HEIGHT_M = (0.9, 2.6)

#: Units a clip may be in, metres each. CMU's ASF says ``length 0.45``: its lengths
#: times 1/0.45 are inches, and the CMU BVH conversions keep those units.
UNITS_M = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048, "cmu": 0.0254 / 0.45}


#: BVH channel layouts: a joint that turns (Z, X, Y, as BVH files most often hold it), and
#: a root that also moves; what clips made without a source layout carry.
JOINT_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")
ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition") + JOINT_CHANNELS


@dataclass(frozen=True)
class Skeleton:
    """Joints in a hierarchy.

    Attributes
    ----------
    names : tuple of str
        Joint names, unique; a parent comes before its children.
    parents : tuple of int
        Index of each joint's parent, -1 for a root.
    offsets : ndarray, shape (J, 3)
        Rest translation of each joint from its parent.

    >>> s = Skeleton(("hips", "knee"), (-1, 0), np.array([[0, 1.0, 0], [0, -0.5, 0]]))
    >>> s.rest_positions()[1].tolist()
    [0.0, 0.5, 0.0]
    """

    names: tuple[str, ...]
    parents: tuple[int, ...]
    offsets: np.ndarray

    def __post_init__(self) -> None:
        if len(set(self.names)) != len(self.names):
            seen = [n for i, n in enumerate(self.names) if n in self.names[:i]]
            raise ArgumentError("names", f"joint {seen[0]!r} appears twice")
        if len(self.parents) != len(self.names) or np.shape(self.offsets) != (len(self.names), 3):
            raise ArgumentError("skeleton", f"{len(self.names)} names need as many parents and offsets (J, 3)")
        bad = [i for i, p in enumerate(self.parents) if not -1 <= p < i]
        if bad:
            raise ArgumentError("parents", f"joint {self.names[bad[0]]!r} has parent index {self.parents[bad[0]]}, "
                                           "which is not an earlier joint")

    def __len__(self) -> int:
        return len(self.names)

    def index(self, name: str) -> int:
        """The index of joint ``name``."""
        try:
            return self.names.index(name)
        except ValueError:
            raise ArgumentError("joint", f"no joint named {name!r}") from None

    def rest_pose(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """``n`` frames of the rest pose, to fill in: identity rotations (n, J, 4,
        scalar-last) and the offsets as translations (n, J, 3), both writable."""
        rotations = np.zeros((n, len(self), 4))
        rotations[..., 3] = 1.0
        return rotations, np.broadcast_to(self.offsets, (n, len(self), 3)).copy()

    def reach(self, bones: np.ndarray | None = None) -> np.ndarray:
        """For each joint, the longest path (summed bone lengths) from it down to a
        descendant: how far a turn of the joint can move a joint below it.

        ``bones`` (J,) are the lengths from each joint's parent to it; by default the
        offsets' lengths. A joint whose translation channels move it further than its
        offset needs the longest translation instead (see :meth:`Clip.bones`).

        >>> s = Skeleton(("a", "b", "c"), (-1, 0, 1), np.array([[5.0, 0, 0], [0, 2.0, 0], [0, 0, 3.0]]))
        >>> s.reach().tolist(), s.reach(np.array([5.0, 2.0, 30.0])).tolist()
        ([5.0, 3.0, 0.0], [32.0, 30.0, 0.0])
        """
        out = np.zeros(len(self))
        bones = np.linalg.norm(self.offsets, axis=1) if bones is None else bones
        for j in reversed(range(len(self))):
            p = self.parents[j]
            if p >= 0:
                out[p] = max(out[p], out[j] + bones[j])
        return out

    def chains(self) -> list[list[int]]:
        """Each joint with its ancestors, from itself up to its root.

        >>> Skeleton(("a", "b", "c"), (-1, 0, 0), np.zeros((3, 3))).chains()
        [[0], [1, 0], [2, 0]]
        """
        out: list[list[int]] = []
        for j, p in enumerate(self.parents):
            out.append([j] + (out[p] if p >= 0 else []))
        return out

    def rest_positions(self) -> np.ndarray:
        """World positions (J, 3) with every rotation the identity."""
        out = np.zeros((len(self), 3))
        for j, p in enumerate(self.parents):
            out[j] = self.offsets[j] + (out[p] if p >= 0 else 0.0)
        return out


@dataclass(frozen=True)
class Clip:
    """A skeleton's motion sampled at times.

    Attributes
    ----------
    skeleton : Skeleton
    times : ndarray, shape (n,)
        Seconds, increasing.
    rotations : ndarray, shape (n, J, 4)
        Local rotations, scalar-last unit quaternions.
    translations : ndarray, shape (n, J, 3)
        Local translations (the offset where a joint has no translation channels).
    rotating, translating : ndarray of bool, shape (J,)
        Which joints have rotation / translation channels in the source.
    channels : tuple of tuple of str
        Each joint's channels in the source's order, in BVH's names (``Xposition``,
        ``Zrotation``, ...): the Euler order a BVH writer uses for it.
    unit_m : float or None
        Metres per clip unit, where the source says (ASF ``length``) or it was given.

    >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
    >>> c = Clip.still(s, np.arange(3) / 30)
    >>> c.frame_time, c.rotations.shape
    (0.03333333333333333, (3, 1, 4))
    """

    skeleton: Skeleton
    times: np.ndarray
    rotations: np.ndarray
    translations: np.ndarray
    rotating: np.ndarray
    translating: np.ndarray
    channels: tuple[tuple[str, ...], ...]
    unit_m: float | None = None

    def __post_init__(self) -> None:
        n, j = len(self.times), len(self.skeleton)
        if np.shape(self.rotations) != (n, j, 4) or np.shape(self.translations) != (n, j, 3):
            raise ArgumentError("clip", f"{n} frames of {j} joints need rotations ({n}, {j}, 4) and translations "
                                        f"({n}, {j}, 3), got {np.shape(self.rotations)} and "
                                        f"{np.shape(self.translations)}")
        if len(self.channels) != j:
            raise ArgumentError("channels", f"needs one tuple per joint ({j}), got {len(self.channels)}")

    @classmethod
    def still(cls, skeleton: Skeleton, times: ArrayLike) -> Clip:
        """The rest pose held at ``times``, rotation channels on every joint."""
        t = np.asarray(times, dtype=float)
        j = len(skeleton)
        return cls(skeleton, t, *skeleton.rest_pose(len(t)), np.ones(j, bool), np.zeros(j, bool),
                   (JOINT_CHANNELS,) * j)

    @property
    def frame_time(self) -> float:
        """The median time between frames, seconds."""
        return frame_time(self.times)

    def bones(self) -> np.ndarray:
        """For each joint, the longest distance from its parent over the clip (J,): its
        offset's length, or its translation's where translation channels move it.

        >>> s = Skeleton(("root", "arm"), (-1, 0), np.array([[0.0, 0, 0], [1.0, 0, 0]]))
        >>> clip = Clip.still(s, [0.0, 0.1])
        >>> clip.translations[1, 1] = [0, 4.0, 3.0]
        >>> clip.bones().tolist()
        [0.0, 5.0]
        """
        return np.linalg.norm(self.translations, axis=-1).max(axis=0, initial=0.0)

    def world_positions(self) -> np.ndarray:
        """Joint positions in the world, shape (n, J, 3) (forward kinematics)."""
        return world_matrices(self.skeleton, self.rotations, self.translations)[1]

    def guess_unit_m(self) -> float | None:
        """Metres per clip unit: ``unit_m`` if known, else the unit of :data:`UNITS_M` in
        which the rest figure's height is a person's (:data:`FIGURE_HEIGHT_M`), else None.

        >>> s = Skeleton(("foot", "hips", "head"), (-1, 0, 1), np.array([[0, 0, 0], [0, 90.0, 0], [0, 80, 0]]))
        >>> Clip.still(s, [0.0, 0.1]).guess_unit_m()
        0.01
        """
        if self.unit_m is not None:
            return self.unit_m
        rest = self.skeleton.rest_positions()
        height = float(np.ptp(rest, axis=0).max()) if len(rest) > 1 else 0.0
        lo, hi = FIGURE_HEIGHT_M
        fits = [u for u in UNITS_M.values() if lo <= height * u <= hi]
        return fits[0] if len(fits) == 1 else None


def frame_time(times: np.ndarray) -> float:
    """The median time between ``times``, seconds (0 for one frame).

    >>> frame_time(np.array([0.0, 0.5, 1.0, 2.0]))
    0.5
    """
    return float(np.median(np.diff(times))) if len(times) > 1 else 0.0
