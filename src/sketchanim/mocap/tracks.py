"""A reduced clip's curves as tracks addressed by path: ``"Hips.orientation"`` (a
quaternion curve, normalised when played) and ``"Hips.position"`` (a translating
joint's position), each the animation model's :class:`~sketchanim.anim.tracks.ContinuousTrack`
beside the :class:`~sketchanim.reducer.Reduction` it was made by (its errors at the
source's frames), and what storing a curve costs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import ORIENTATION, POSITION, AttributeType
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.errors import ArgumentError
from sketchanim.reducer import Reduction

#: A joint's attributes that a clip animates, and their types.
JOINT_ATTRIBUTES: dict[str, AttributeType] = {"orientation": ORIENTATION, "position": POSITION}

#: Bytes per stored number, for the compression ratio (raw channels kept as float32).
FLOAT32 = 4


def track_path(name: str, attribute: str) -> str:
    """The path of ``name``'s ``attribute``.

    >>> track_path("Hips", "orientation")
    'Hips.orientation'
    """
    return f"{name}.{attribute}"


def split_path(path: str) -> tuple[str, str]:
    """A path's name and attribute (a name may hold dots, an attribute does not).

    >>> split_path("mixamo.Hips.position")
    ('mixamo.Hips', 'position')
    """
    name, _, attribute = path.rpartition(".")
    return name, attribute


@dataclass(frozen=True)
class ReducedTrack:
    """One reduced curve of a clip.

    Attributes
    ----------
    track : ContinuousTrack
        Path, type, curve, and the tolerance the curve was reduced to (the float32
        budget of the clip's: degrees for an orientation, a distance for a position).
    reduction : Reduction
        What the reducer made it of: errors at the source's frames, report.

    >>> from sketchanim.reducer import reduce
    >>> t = np.linspace(0, 1, 20)
    >>> r = ReducedTrack.of("root.position", reduce(t, np.c_[t, t, t], 0.001))
    >>> r.track.type.name, r.path, bool(r.error <= np.sqrt(3) * 0.001)
    ('position', 'root.position', True)
    """

    track: ContinuousTrack
    reduction: Reduction

    @classmethod
    def of(cls, path: str, reduction: Reduction) -> ReducedTrack:
        """The track of ``reduction`` at ``path`` (``joint.orientation`` or ``joint.position``)."""
        attribute = split_path(path)[1]
        if attribute not in JOINT_ATTRIBUTES:
            raise ArgumentError("path", f"{path!r}: a joint's track is one of {', '.join(JOINT_ATTRIBUTES)}")
        tol = float(reduction.tol[0])
        budget = float(np.degrees(tol)) if attribute == "orientation" else tol * np.sqrt(3.0)
        return cls(ContinuousTrack(path, JOINT_ATTRIBUTES[attribute], reduction.columns, budget), reduction)

    @property
    def path(self) -> str:
        return self.track.path

    @property
    def spline(self) -> BSpline:
        return self.track.spline

    @property
    def is_rotation(self) -> bool:
        return self.track.type.is_rotation

    @property
    def error(self) -> float:
        """The largest error at the source's frames: an angle in degrees for an
        orientation, a distance for a position (``report["max_distance"]``, else the
        per-axis errors' norm)."""
        if self.is_rotation:
            return float(np.degrees(self.reduction.max_error[0]))
        return float(self.reduction.report.get("max_distance", np.linalg.norm(self.reduction.max_error)))


def curve_bytes(spline: BSpline) -> int:
    """Bytes to store a curve: each distinct knot as a float32 and a byte of
    multiplicity, each control point as float32s; a curve whose control points are all
    equal (a joint that does not move) as its one value.

    >>> curve_bytes(BSpline(np.r_[[0.0] * 4, [1.0] * 4], np.arange(8.0).reshape(4, 2), 3))
    42
    """
    c = np.asarray(spline.c).reshape(len(spline.c), -1)
    if np.all(c == c[0]):
        return FLOAT32 * c.shape[1]
    return (FLOAT32 + 1) * len(np.unique(spline.t)) + FLOAT32 * c.size
