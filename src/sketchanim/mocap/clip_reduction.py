"""Whole-clip reduction: every joint's rotation as a quaternion curve within an angle,
every translating joint's position within a distance, and what it all costs.

Positions are reduced with ``tol / sqrt(3)`` on each axis, so that the distance between
curve and sample (not only each coordinate) stays within ``tol``. Both leave room for
float32 (:func:`float32_margin`): what a client plays from a file stores keys and key
times as float32, and computes in float32, so the budget the reducer runs to is the
tolerance less what that can move the curve.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from sketchanim.motion.skeleton import Clip, Skeleton, world_pose
from sketchanim.anim.tracks import held_values
from sketchanim.errors import ArgumentError, InputError
from sketchanim.motion import reduce_rotations
from sketchanim.reducer import Reduction, reduce
from sketchanim.reducer.result import load_versioned

SCHEMA = "sketchanim.clip"
VERSION = 1
#: Most frames a clip is resampled to (BVH, USD).
MAX_FRAMES = 1_000_000

#: Bytes per stored number, for the compression ratio (raw channels kept as float32).
FLOAT32 = 4

#: float32's unit roundoff: storing a number as float32 moves it by at most this, relative.
EPS32 = 2.0**-24

#: float32 roundings a played curve may gather: its keys, its key times, a client's own
#: float32 arithmetic (Blender evaluates F-curves in float32, three.js keeps float32 results).
ROUNDINGS = 16


def float32_margin(times: np.ndarray, size: float, speed: float) -> float:
    """How far a curve of values up to ``size`` (a norm), moving at up to ``speed`` per
    second over ``times``, may move once stored and played in float32: ``ROUNDINGS``
    roundings of its values, and of its times (a time rounded moves the value by the
    speed times the rounding).

    >>> m = float32_margin(np.array([0.0, 30.0]), 200.0, 300.0)     # a hips in cm, 30 s
    >>> bool(1e-4 < m < 1e-2)
    True
    """
    span = float(np.abs(np.asarray(times, dtype=float)).max()) if len(times) else 0.0
    return ROUNDINGS * EPS32 * (size + speed * span)


def position_budget(times: np.ndarray, points: np.ndarray, tol: float) -> float:
    """The distance a reducer may use of ``tol`` for points (n, d) sampled at ``times``
    so that the float32 file still plays within ``tol`` (:func:`float32_margin`; never
    less than half of ``tol``).

    >>> t = np.arange(100) / 30
    >>> 0.49 < position_budget(t, np.c_[100 * np.sin(t), 90 + 0 * t, t], 0.5) < 0.5
    True
    """
    x = np.asarray(points, dtype=float).reshape(len(times), -1)
    speed = float((np.linalg.norm(np.diff(x, axis=0), axis=1) / np.diff(times)).max()) if len(times) > 1 else 0.0
    return tol - min(float32_margin(times, float(np.linalg.norm(x, axis=1).max()), speed), tol / 2)


def rotation_budget(times: np.ndarray, quats: np.ndarray, tol_deg: float) -> float:
    """The angle (degrees) a reducer may use of ``tol_deg`` for quaternions sampled at
    ``times``, so that the float32 file still plays within ``tol_deg``: an error ``e``
    in a unit quaternion turns it by up to ``2 e`` radians.

    >>> t = np.arange(100) / 30
    >>> q = Rotation.from_euler("Z", 3 * t[:, None]).as_quat()
    >>> 0.499 < rotation_budget(t, q, 0.5) < 0.5
    True
    """
    q = np.asarray(quats, dtype=float)
    turn = np.arccos(np.clip(np.abs(np.sum(q[1:] * q[:-1], axis=1)) / (np.linalg.norm(q[1:], axis=1)
                                                                     * np.linalg.norm(q[:-1], axis=1)), 0, 1))
    speed = float((turn / np.diff(times)).max()) if len(times) > 1 else 0.0     # of the unit quaternion, per s
    margin = float(np.degrees(2 * float32_margin(times, 1.0, speed)))
    return tol_deg - min(margin, tol_deg / 2)


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


@dataclass(frozen=True)
class JointReport:
    """One joint's reduced curves: control points, and the largest errors at the
    frames (rotation in degrees, position distance in clip units; NaN where the joint
    has no such curve)."""

    joint: str
    rotation_points: int
    rotation_error_deg: float
    position_points: int
    position_error: float


@dataclass(frozen=True)
class ReducedClip:
    """A clip's curves.

    Attributes
    ----------
    skeleton : Skeleton
    channels : tuple of tuple of str
        The source's channel layout, per joint (for writing BVH back).
    rotations : dict of int to Reduction
        Joint index to its quaternion curve (scalar-last, normalised when played).
    translations : dict of int to Reduction
        Joint index to its position curve, for joints with translation channels.
    frame_time : float
        The source's seconds per frame.
    n_frames : int
    unit_m : float or None
        Metres per clip unit, where known.
    """

    skeleton: Skeleton
    channels: tuple[tuple[str, ...], ...]
    rotations: dict[int, Reduction]
    translations: dict[int, Reduction]
    frame_time: float
    n_frames: int
    unit_m: float | None = None

    @property
    def curves(self) -> list[Reduction]:
        """Every curve: the rotations, then the translations."""
        return [*self.rotations.values(), *self.translations.values()]

    @property
    def start(self) -> float:
        return min((float(r.spline.t[r.spline.k]) for r in self.curves), default=0.0)

    @property
    def end(self) -> float:
        return max((float(r.spline.t[-r.spline.k - 1]) for r in self.curves), default=0.0)

    def sample(self, times: np.ndarray) -> Clip:
        """The curves evaluated at ``times`` (rotations normalised, ends held) as a clip.

        >>> from scipy.spatial.transform import Rotation
        >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
        >>> t = np.linspace(0, 1, 31)
        >>> q = Rotation.from_euler("Z", t[:, None]).as_quat()[:, None]
        >>> clip = Clip(s, t, q, np.zeros((31, 1, 3)), np.ones(1, bool), np.zeros(1, bool), (("Zrotation",),))
        >>> r = reduce_clip(clip, 0.01, 0.1)
        >>> bool(np.allclose(r.sample(t).rotations, q, atol=1e-3))
        True
        """
        t = np.asarray(times, dtype=float)
        j = len(self.skeleton)
        rot, trans = self.skeleton.rest_pose(len(t))
        for i, r in self.rotations.items():
            rot[:, i] = held_values(r.columns, t, True)
        for i, r in self.translations.items():
            trans[:, i] = held_values(r.columns, t, False)
        rotating = np.array([i in self.rotations for i in range(j)])
        translating = np.array([i in self.translations for i in range(j)])
        return Clip(self.skeleton, t, rot, trans, rotating, translating, self.channels, self.unit_m)

    def resample(self, rate: float) -> Clip:
        """The curves sampled at ``rate`` frames per second over their span (for
        formats that store frames: BVH, USD); at most :data:`MAX_FRAMES` of them.

        >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
        >>> r = reduce_clip(Clip.still(s, np.arange(31) / 30), 0.01, 0.1)
        >>> r.resample(60).times[[0, -1]].tolist(), len(r.resample(60).times)
        ([0.0, 1.0], 61)
        """
        if not np.isfinite(rate) or rate <= 0:
            raise ArgumentError("rate", f"must be a positive number of frames per second, got {rate!r}")
        span = (self.end - self.start) * rate
        if not span < MAX_FRAMES:
            raise ArgumentError("rate", f"{rate!r} frames per second gives {span:.3g} frames over "
                                        f"{self.end - self.start:g} s, at most {MAX_FRAMES:,} are written")
        n = int(np.floor(span + 1e-9)) + 1
        return self.sample(self.start + np.arange(n) / rate)

    def reduced_bytes(self) -> int:
        """Bytes to store every curve (:func:`curve_bytes`)."""
        return sum(curve_bytes(r.columns) for r in self.curves)

    def raw_bytes(self) -> int:
        """Bytes of the source's channels at every frame as float32."""
        return FLOAT32 * self.n_frames * sum(len(c) for c in self.channels)

    def compression(self) -> float:
        """Raw bytes over reduced bytes."""
        return self.raw_bytes() / max(self.reduced_bytes(), 1)

    def joint_reports(self) -> list[JointReport]:
        """Per joint with any curve: control points and max errors at the source frames."""
        rows = []
        for i, name in enumerate(self.skeleton.names):
            rot, pos = self.rotations.get(i), self.translations.get(i)
            if rot is None and pos is None:
                continue
            rows.append(JointReport(
                name,
                rot.n_coefficients if rot else 0, float(np.degrees(rot.max_error[0])) if rot else float("nan"),
                pos.n_coefficients if pos else 0, float(pos.report["max_distance"]) if pos else float("nan")))
        return rows

    def world_errors(self, clip: Clip, shell: float = 0.0, *,
                     source: tuple[list[Rotation], np.ndarray] | None = None) -> np.ndarray:
        """Per frame and joint (n, J), at ``clip``'s times: how far these curves put the
        joint from ``clip``'s in the world, plus the most a point ``shell`` from the joint
        moves by the difference of their world rotations (``2 shell sin(angle / 2)``).
        ``source``: ``clip``'s :func:`~sketchanim.motion.skeleton.world_pose`, where the
        caller has it already.

        >>> s = Skeleton(("a",), (-1,), np.zeros((1, 3)))
        >>> clip = Clip.still(s, np.arange(5) / 30)
        >>> float(reduce_clip(clip, 0.1, 0.1).world_errors(clip, 3.0).max())
        0.0
        """
        source_rot, source_pos = source or world_pose(clip.skeleton, clip.rotations, clip.translations)
        frames = self.sample(clip.times)
        rot, pos = world_pose(clip.skeleton, frames.rotations, frames.translations)
        out = np.linalg.norm(pos - source_pos, axis=-1)
        if shell:
            for j in range(len(clip.skeleton)):
                out[:, j] += 2 * shell * np.sin((rot[j] * source_rot[j].inv()).magnitude() / 2)
        return out

    def to_json(self) -> str:
        """The skeleton and every curve as JSON (schema ``sketchanim.clip``, version 1)."""
        doc = {
            "schema": SCHEMA, "version": VERSION,
            "joints": [{"name": n, "parent": p, "offset": o.tolist(), "channels": list(c)}
                       for n, p, o, c in zip(self.skeleton.names, self.skeleton.parents, self.skeleton.offsets,
                                             self.channels)],
            "frame_time": self.frame_time, "n_frames": self.n_frames, "unit_m": self.unit_m,
            "rotations": {self.skeleton.names[i]: json.loads(r.to_json()) for i, r in self.rotations.items()},
            "translations": {self.skeleton.names[i]: json.loads(r.to_json()) for i, r in self.translations.items()},
        }
        return json.dumps(doc, indent=1)

    @classmethod
    def from_json(cls, text: str, *, source: str = "<json>") -> ReducedClip:
        """Read what :meth:`to_json` wrote; errors name ``source`` and the field.

        >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
        >>> r = reduce_clip(Clip.still(s, np.arange(10) / 30), 0.01, 0.1)
        >>> ReducedClip.from_json(r.to_json()).rotations[0].n_coefficients == r.rotations[0].n_coefficients
        True
        """
        doc = load_versioned(text, source, SCHEMA, VERSION)
        try:
            joints = doc["joints"]
            skeleton = Skeleton(tuple(str(j["name"]) for j in joints), tuple(int(j["parent"]) for j in joints),
                                np.array([j["offset"] for j in joints], dtype=float).reshape(len(joints), 3))
            channels = tuple(tuple(str(c) for c in j["channels"]) for j in joints)
            curves = {kind: {skeleton.index(name): Reduction.from_json(json.dumps(r), source=f"{source}: {kind} "
                                                                                           f"of {name}")
                             for name, r in doc[kind].items()}
                      for kind in ("rotations", "translations")}
            unit = doc.get("unit_m")
            return cls(skeleton, channels, curves["rotations"], curves["translations"], float(doc["frame_time"]),
                       int(doc["n_frames"]), None if unit is None else float(unit))
        except InputError:
            raise
        except (KeyError, TypeError, ValueError, AttributeError) as err:
            raise InputError(f"{source}: malformed clip document ({type(err).__name__}: {err})") from None


def reduce_clip(clip: Clip, tol: float, rot_tol_deg: float, *, method: str = "global") -> ReducedClip:
    """Reduce every joint of ``clip``: rotations within ``rot_tol_deg`` degrees (the
    geodesic angle), translating joints' positions within ``tol`` (a distance, clip
    units), at every frame.

    Parameters
    ----------
    clip : Clip
    tol : float
        Largest distance between a translating joint's curve and its samples.
    rot_tol_deg : float
        Largest rotation angle, degrees, between a joint's curve and its samples.
    method : {"global", "incremental"}

    Returns
    -------
    ReducedClip

    Examples
    --------
    >>> from scipy.spatial.transform import Rotation
    >>> s = Skeleton(("root", "arm"), (-1, 0), np.array([[0.0, 1, 0], [0.5, 0, 0]]))
    >>> t = np.arange(240) / 120
    >>> clip = Clip.still(s, t)
    >>> clip.rotations[:, 1] = Rotation.from_euler("Z", np.sin(3 * t)[:, None]).as_quat()
    >>> r = reduce_clip(clip, 0.005, 0.5)
    >>> r.joint_reports()[1].rotation_error_deg <= 0.5, r.compression() > 5
    (True, True)
    """
    if not np.isfinite(tol) or tol <= 0:
        raise ArgumentError("tol", f"must be a positive distance, got {tol!r}")
    rotations = {int(i): joint_rotation(clip, int(i), rot_tol_deg, method) for i in np.flatnonzero(clip.rotating)}
    translations = {int(i): joint_position(clip, int(i), tol, method) for i in np.flatnonzero(clip.translating)}
    return ReducedClip(clip.skeleton, clip.channels, rotations, translations, clip.frame_time, len(clip.times),
                       clip.unit_m)


def joint_rotation(clip: Clip, joint: int, tol_deg: float, method: str = "global") -> Reduction:
    """Joint ``joint``'s rotation as a quaternion curve within ``tol_deg`` degrees at
    every frame (less float32's share, :func:`rotation_budget`), its keys unit
    quaternions; errors name the joint."""
    quats = clip.rotations[:, joint]
    return _named(clip.skeleton.names[joint], "rotation", lambda: reduce_rotations(
        clip.times, quats, rotation_budget(clip.times, quats, tol_deg), method=method, keys=True))


def joint_position(clip: Clip, joint: int, tol: float, method: str = "global") -> Reduction:
    """Joint ``joint``'s translation as a curve within the distance ``tol`` at every
    frame (less float32's share, :func:`position_budget`; ``report["max_distance"]``);
    errors name the joint."""
    points = clip.translations[:, joint]
    r = _named(clip.skeleton.names[joint], "position", lambda: reduce(
        clip.times, points, position_budget(clip.times, points, tol) / np.sqrt(3.0), method=method))
    r.report["max_distance"] = float(np.linalg.norm(r.spline(clip.times) - clip.translations[:, joint],
                                                    axis=1).max())
    return r


def _named(joint: str, what: str, run: Callable[[], Reduction]) -> Reduction:
    """``run()``, with an input error prefixed by the joint and channel it came from."""
    try:
        return run()
    except InputError as err:
        raise InputError(f"joint {joint!r} {what}: {err}") from None
