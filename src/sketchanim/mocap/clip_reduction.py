"""Whole-clip reduction: every joint's rotation as a quaternion curve within an angle,
every translating joint's position within a distance, and what it all costs. A reduced
clip is a set of tracks addressed by path (``Hips.orientation``, ``Hips.position``:
:mod:`sketchanim.mocap.tracks`).

The curves are straight pieces by default (:data:`ORDER`): glTF's LINEAR keys, a
rotation played spherically between them (:func:`~sketchanim.motion.rotations.spherical`),
as :meth:`ReducedClip.sample` and every check here play it.

Positions are reduced with ``tol / sqrt(3)`` on each axis, so that the distance between
curve and sample (not only each coordinate) stays within ``tol``. Both leave room for
float32 (:mod:`sketchanim.float32`): what a client plays from a file stores keys and key
times as float32, and computes in float32, so the budget the reducer runs to is the
tolerance less what that can move the curve.

Where the source plants an end joint on the ground (:mod:`sketchanim.mocap.contacts`),
the joints above it are tightened until it stays within ``CONTACT_SHARE`` of the
tolerance in the world on those frames (:func:`tighten`, which the world mode shares),
and within half that (then a quarter) where it would still slide more than the source's
plus ``SLIDING_SLACK_M_S``; a clip slower than the rate sliding is seen at is held between
its frames too (:func:`sliding_kept`).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from sketchanim.errors import ArgumentError, InputError
from sketchanim.float32 import KEEP, position_budget, rotation_budget, rotation_margin
from sketchanim.mocap.contacts import CONTACT_SHARE, SLIDING_SLACK_M_S, between_frames, planted, sliding, unit_m
from sketchanim.mocap.tracks import FLOAT32, ReducedTrack, curve_bytes, split_path, track_path
from sketchanim.motion import reduce_rotations
from sketchanim.motion.rotations import spherical as played_spherically
from sketchanim.motion.kinematics import shell_error, world_matrices
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.reducer import Reduction, reduce
from sketchanim.reducer.metric import rotation_angle
from sketchanim.reducer.result import load_versioned

SCHEMA = "sketchanim.clip"
VERSION = 1
#: Of a distance in the world, what the translating joints' curves may use (shared among
#: the moving ones down a chain); the rotations get what they leave.
TRANSLATION_SHARE = 0.25
#: A chain's first angles: its bound over ``turning ** START_SPREAD`` joints' reach (0: each
#: joint alone could use the whole bound; 1: the provable angles), since the errors of a
#: chain's joints add up in part.
START_SPREAD = 0.25
#: Rounds of measuring and tightening before the provable angles (:func:`tighten`).
ROUNDS = 6
#: The least share of a joint's tolerance derived from a distance (its share of it on a
#: planted chain, or in the world) its float32 budget keeps
#: (:func:`~sketchanim.float32.position_budget`'s ``keep``): less than the half a
#: tolerance asked keeps, since a fast joint late in a take may need most of a fine
#: derived tolerance for float32 while the distance holds. A tightened angle is never
#: less than float32's margin over ``1 - DERIVED_KEEP`` (:func:`tighten`).
DERIVED_KEEP = 0.02
#: The curves' order (degree + 1): 2, straight pieces, glTF's LINEAR keys. On motion
#: capture they take fewer bytes than cubic pieces at the same bound and reduce faster: on
#: every clip of the project's shared data, 18% fewer curve bytes at 0.5 cm / 0.5 degree
#: and 24% at 0.1 cm / 0.1 degree, in 0.57 and 0.53 of the time (``benchmarks/bench_clips.py``).
#: 4: cubic pieces.
ORDER = 2
#: Most frames a clip is resampled to (BVH, USD).
MAX_FRAMES = 1_000_000


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
    """A clip's curves, as tracks addressed by path.

    Attributes
    ----------
    skeleton : Skeleton
    channels : tuple of tuple of str
        The source's channel layout, per joint (for writing BVH back).
    tracks : dict of str to ReducedTrack
        ``"joint.orientation"`` (a quaternion curve, scalar-last, normalised when
        played) for every rotating joint, then ``"joint.position"`` for every joint
        with translation channels, each in joint order.
    frame_time : float
        The source's seconds per frame.
    n_frames : int
    unit_m : float or None
        Metres per clip unit, where known.
    """

    skeleton: Skeleton
    channels: tuple[tuple[str, ...], ...]
    tracks: dict[str, ReducedTrack]
    frame_time: float
    n_frames: int
    unit_m: float | None = None

    def __post_init__(self) -> None:
        for path in self.tracks:
            self.skeleton.index(split_path(path)[0])

    def joint_track(self, joint: int, attribute: str) -> ReducedTrack | None:
        """Joint ``joint``'s ``"orientation"`` or ``"position"`` track, if it has one."""
        return self.tracks.get(track_path(self.skeleton.names[joint], attribute))

    @property
    def start(self) -> float:
        return min((t.track.start for t in self.tracks.values()), default=0.0)

    @property
    def end(self) -> float:
        return max((t.track.end for t in self.tracks.values()), default=0.0)

    @property
    def plays(self) -> tuple[bool, ...]:
        """The ways clients play the curves, as :meth:`sample`'s ``spherical``: both where
        a rotation has straight pieces (glTF spherically, Blender's F-curves
        component-wise), else the one way every client plays them."""
        return (True, False) if any(c.is_rotation and c.spline.k == 1 for c in self.tracks.values()) else (True,)

    def sample(self, times: np.ndarray, *, spherical: bool = True) -> Clip:
        """The curves evaluated at ``times`` (rotations normalised; ends held) as a clip:
        straight pieces of rotations played spherically as glTF's LINEAR samplers play
        them, or with ``spherical=False`` component-wise, as Blender's F-curves and the
        tracks' own :meth:`~sketchanim.anim.tracks.ContinuousTrack.evaluate` do.

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
        rotating, translating = np.zeros(j, bool), np.zeros(j, bool)
        for path, curve in self.tracks.items():
            i = self.skeleton.index(split_path(path)[0])
            if curve.is_rotation:
                rot[:, i] = played_spherically(curve.spline, t) if spherical and curve.spline.k == 1 else \
                    curve.track.evaluate(t)
                rotating[i] = True
            else:
                trans[:, i], translating[i] = curve.track.evaluate(t), True
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
        return sum(curve_bytes(t.spline) for t in self.tracks.values())

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
            rot, pos = self.joint_track(i, "orientation"), self.joint_track(i, "position")
            if rot is None and pos is None:
                continue
            rows.append(JointReport(name, rot.track.n_coefficients if rot else 0, rot.error if rot else float("nan"),
                                    pos.track.n_coefficients if pos else 0,
                                    float(pos.reduction.report["max_distance"]) if pos else float("nan")))
        return rows

    def world_errors(self, clip: Clip, shell: float = 0.0, *,
                     source: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
        """Per frame and joint (n, J), at ``clip``'s times: how far these curves put the
        joint from ``clip``'s in the world, plus the most a point ``shell`` from the joint
        moves by the difference of their world rotations (``2 shell sin(angle / 2)``);
        the worst of the ways the curves play (:attr:`plays`).
        ``source``: ``clip``'s :func:`~sketchanim.motion.kinematics.world_matrices`, where
        the caller has it already.

        >>> s = Skeleton(("a",), (-1,), np.zeros((1, 3)))
        >>> clip = Clip.still(s, np.arange(5) / 30)
        >>> float(reduce_clip(clip, 0.1, 0.1).world_errors(clip, 3.0).max())
        0.0
        """
        source_turns, source_pos = source or world_matrices(clip.skeleton, clip.rotations, clip.translations)
        out = np.zeros((len(clip.times), len(clip.skeleton)))
        for way in self.plays:
            frames = self.sample(clip.times, spherical=way)
            turns, pos = world_matrices(clip.skeleton, frames.rotations, frames.translations)
            out = np.maximum(out, shell_error(turns, pos, source_turns, source_pos, shell))
        return out

    def to_json(self) -> str:
        """The skeleton and every curve as JSON (schema ``sketchanim.clip``, version 1:
        the curves by joint name under ``rotations`` and ``translations``)."""
        kinds = {"rotations": {}, "translations": {}}
        for path, curve in self.tracks.items():
            kinds["rotations" if curve.is_rotation else "translations"][split_path(path)[0]] = \
                json.loads(curve.reduction.to_json())
        doc = {
            "schema": SCHEMA, "version": VERSION,
            "joints": [{"name": n, "parent": p, "offset": o.tolist(), "channels": list(c)}
                       for n, p, o, c in zip(self.skeleton.names, self.skeleton.parents, self.skeleton.offsets,
                                             self.channels)],
            "frame_time": self.frame_time, "n_frames": self.n_frames, "unit_m": self.unit_m, **kinds,
        }
        return json.dumps(doc, indent=1)

    @classmethod
    def from_json(cls, text: str, *, source: str = "<json>") -> ReducedClip:
        """Read what :meth:`to_json` wrote; errors name ``source`` and the field.

        >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
        >>> r = reduce_clip(Clip.still(s, np.arange(10) / 30), 0.01, 0.1)
        >>> back = ReducedClip.from_json(r.to_json())
        >>> list(back.tracks), back.tracks["root.orientation"].track.n_coefficients
        (['root.orientation'], 2)
        """
        doc = load_versioned(text, source, SCHEMA, VERSION)
        try:
            joints = doc["joints"]
            skeleton = Skeleton(tuple(str(j["name"]) for j in joints), tuple(int(j["parent"]) for j in joints),
                                np.array([j["offset"] for j in joints], dtype=float).reshape(len(joints), 3))
            channels = tuple(tuple(str(c) for c in j["channels"]) for j in joints)
            curves = {}
            for kind, attribute in (("rotations", "orientation"), ("translations", "position")):
                found = {skeleton.index(name): Reduction.from_json(json.dumps(r), source=f"{source}: {kind} of {name}")
                         for name, r in doc[kind].items()}
                curves.update(_tracks(skeleton, attribute, found))
            unit = doc.get("unit_m")
            return cls(skeleton, channels, curves, float(doc["frame_time"]), int(doc["n_frames"]),
                       None if unit is None else float(unit))
        except InputError:
            raise
        except (KeyError, TypeError, ValueError, AttributeError) as err:
            raise InputError(f"{source}: malformed clip document ({type(err).__name__}: {err})") from None


def _tracks(skeleton: Skeleton, attribute: str, reductions: dict[int, Reduction]) -> dict[str, ReducedTrack]:
    """Joint index to reduction, as tracks by path in joint order."""
    return {(p := track_path(skeleton.names[i], attribute)): ReducedTrack.of(p, reductions[i])
            for i in sorted(reductions)}


def clip_tracks(clip: Clip, rotations: dict[int, Reduction], translations: dict[int, Reduction]) -> ReducedClip:
    """``clip``'s joints' curves (joint index to its rotation's, its translation's
    reduction) as a :class:`ReducedClip`."""
    return ReducedClip(clip.skeleton, clip.channels, {**_tracks(clip.skeleton, "orientation", rotations),
                                                      **_tracks(clip.skeleton, "position", translations)},
                       clip.frame_time, len(clip.times), clip.unit_m)


def reduce_clip(clip: Clip, tol: float, rot_tol_deg: float, *, method: str = "incremental", order: int = ORDER,
                contacts: np.ndarray | None = None) -> ReducedClip:
    """Reduce every joint of ``clip``: rotations within ``rot_tol_deg`` degrees (the
    geodesic angle), translating joints' positions within ``tol`` (a distance, clip
    units), at every frame; and where the source plants an end joint on the ground
    (:func:`~sketchanim.mocap.contacts.planted`), that joint within
    ``CONTACT_SHARE * tol`` of the source in the world on those frames, the joints above
    it tightened as they need (:func:`tighten`; less where it still slides:
    :func:`sliding_kept`).

    Parameters
    ----------
    clip : Clip
    tol : float
        Largest distance between a translating joint's curve and its samples.
    rot_tol_deg : float
        Largest rotation angle, degrees, between a joint's curve and its samples.
    method : {"incremental", "global"}
        The reducer's method: the incremental one is about ten times faster, for a few
        per cent more bytes (``benchmarks/bench_clips.py``).
    order : int
        The curves' order (:data:`ORDER`: straight pieces; 4: cubic).
    contacts : ndarray of bool, shape (n, J), optional
        The frames each joint is planted (default :func:`planted`; all False holds none).

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
    held = held_frames(clip, contacts)
    held_chain = on_chains(clip, held.any(axis=0))
    moving = most_moving(clip, held_chain)

    def reduced(clip: Clip, held: np.ndarray, share: float, framed: np.ndarray) -> ReducedClip:
        translations = {int(i): joint_position(clip, int(i), TRANSLATION_SHARE * share * tol / moving, method,
                                               order=order,
                                               why=f" (its share of tol {tol:.6g}, to hold the planted joints)")
                        if held_chain[i] else joint_position(clip, int(i), tol, method, order=order)
                        for i in np.flatnonzero(clip.translating)}
        angle = np.full(len(clip.skeleton), np.radians(rot_tol_deg))
        bound = np.where(held, share * tol, np.inf)
        start, provable = contact_angles(clip, translations, bound, 0.0)
        return tighten(clip, translations, np.minimum(angle, start), np.minimum(angle, provable), bound, 0.0, method,
                       framed, order=order, asked=float(np.radians(rot_tol_deg)),
                       why=f"to hold the planted joints within tol {tol:.6g}")

    return sliding_kept(clip, held, reduced)


def sliding_kept(clip: Clip, held: np.ndarray,
                 reduced: Callable[[Clip, np.ndarray, float, np.ndarray], ReducedClip]) -> ReducedClip:
    """``reduced(clip, held, CONTACT_SHARE, framed)``: ``clip`` reduced with its joints
    planted at ``held`` (n, J) within that share of the tolerance; or where they then
    slide more than the source's plus ``SLIDING_SLACK_M_S``
    (:func:`~sketchanim.mocap.contacts.sliding`, every way the curves play:
    :attr:`ReducedClip.plays`), within half of it, then a quarter (taken
    regardless). A clip slower than ``SLIDING_RATE`` that plants anything is reduced with
    samples between its frames (:func:`~sketchanim.mocap.contacts.between_frames`), so that
    the curves hold the planted joints between frames as well; ``framed`` says which
    samples are the clip's frames, and the result keeps those.

    >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
    >>> clip = Clip.still(s, [0.0, 0.1])
    >>> asked = []                                  # nothing planted: the first share only
    >>> out = sliding_kept(clip, np.zeros((2, 1), bool),
    ...                    lambda c, h, share, framed: asked.append(share) or reduce_clip(c, 1, 1))
    >>> asked == [CONTACT_SHARE]
    True
    """
    fine, fine_held = between_frames(clip, held)
    framed = np.isin(fine.times, clip.times)
    most = None                                   # the source's sliding plus the slack, once it is needed
    for share in (CONTACT_SHARE, CONTACT_SHARE / 2, CONTACT_SHARE / 4):
        out = replace(reduced(fine, fine_held, share, framed), frame_time=clip.frame_time, n_frames=len(clip.times))
        if not held.any():
            break
        most = sliding(clip, contacts=held) + SLIDING_SLACK_M_S / unit_m(clip) if most is None else most
        if all(sliding(clip, lambda t: out.sample(t, spherical=way), contacts=held) <= most for way in out.plays):
            break
    return out


def held_frames(clip: Clip, contacts: np.ndarray | None) -> np.ndarray:
    """``contacts`` checked against ``clip``'s frames and joints, or :func:`planted`.

    >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
    >>> held_frames(Clip.still(s, [0.0, 0.1]), None).shape
    (2, 1)
    """
    if contacts is None:
        return planted(clip)
    held = np.asarray(contacts, dtype=bool)
    if held.shape != (len(clip.times), len(clip.skeleton)):
        raise ArgumentError("contacts", f"must be (frames, joints) = ({len(clip.times)}, {len(clip.skeleton)}), "
                                        f"got {held.shape}")
    return held


def on_chains(clip: Clip, ends: np.ndarray) -> np.ndarray:
    """Per joint (J,), whether it is one of ``ends`` (J,) bool or above one.

    >>> s = Skeleton(("a", "b", "c"), (-1, 0, 0), np.zeros((3, 3)))
    >>> on_chains(Clip.still(s, [0.0]), np.array([False, True, False])).tolist()
    [True, True, False]
    """
    out = np.zeros(len(clip.skeleton), bool)
    for d in np.flatnonzero(ends):
        out[clip.skeleton.chains()[d]] = True
    return out


def most_moving(clip: Clip, among: np.ndarray) -> int:
    """The most joints with varying translations on one chain of a joint in ``among``
    (at least 1): they share a chain's translation budget.

    >>> s = Skeleton(("root", "arm"), (-1, 0), np.zeros((2, 3)))
    >>> most_moving(Clip.still(s, [0.0, 0.1]), np.ones(2, bool))
    1
    """
    varying = clip.translating & np.any(np.ptp(clip.translations, axis=0) > 0, axis=-1)
    counts = [sum(bool(varying[a]) for a in chain) for d, chain in enumerate(clip.skeleton.chains()) if among[d]]
    return max(counts, default=0) or 1


def contact_angles(clip: Clip, translations: dict[int, Reduction], bound: np.ndarray,
                   shell: float) -> tuple[np.ndarray, np.ndarray]:
    """The first and the provable angles (radians, (J,); inf where free) that the
    joints above the bounded joints of ``bound`` (n, J; inf where free) need, given the
    translations' errors: a joint starts at what is left of the tightest bound below it
    over how far its turn reaches (plus ``shell``), and provably keeps the chain within
    it with that over the most turning joints on a bounded chain (a chain's errors at
    most add up).

    >>> s = Skeleton(("hips", "toe"), (-1, 0), np.array([[0.0, 1, 0], [0, -1.0, 0]]))
    >>> bound = np.array([[np.inf, 0.01]])
    >>> start, provable = contact_angles(Clip.still(s, [0.0]), {}, bound, 0.0)
    >>> round(float(start[0]), 5), round(float(provable[0]), 5)       # the hips, 1 from the toe
    (0.00841, 0.005)
    """
    sk = clip.skeleton
    tightest = bound.min(axis=0, initial=np.inf)
    ends = np.isfinite(tightest)
    start, provable = np.full(len(sk), np.inf), np.full(len(sk), np.inf)
    if not ends.any():
        return start, provable
    chains = sk.chains()
    moved = {i: float(r.report["max_distance"]) for i, r in translations.items()}
    turning = max(sum(bool(clip.rotating[a]) for a in chains[d]) for d in np.flatnonzero(ends)) or 1
    arm = np.maximum(sk.reach(clip.bones()) + shell, 1e-300)
    for d in np.flatnonzero(ends):
        left = max(tightest[d] - sum(moved.get(a, 0.0) for a in chains[d]), 0.0)
        start[chains[d]] = np.minimum(start[chains[d]], left / (turning ** START_SPREAD * arm[chains[d]]))
        provable[chains[d]] = np.minimum(provable[chains[d]], left / (turning * arm[chains[d]]))
    return start, provable


def tighten(clip: Clip, translations: dict[int, Reduction], angle: np.ndarray, provable: np.ndarray,
            bound: np.ndarray, shell: float, method: str, framed: np.ndarray | None = None, *, order: int = ORDER,
            asked: float = np.inf, why: str = "to hold the joints within tol") -> ReducedClip:
    """``clip``'s rotations reduced within ``angle`` (radians, (J,)) as curves of
    ``order`` (:func:`joint_rotation`), tightened until
    every joint's world error (:meth:`ReducedClip.world_errors` with ``shell``) is within
    ``bound`` (n, J; inf where free) at every frame, with ``translations`` as given.
    Where ``framed`` (n,) says which of ``clip``'s samples are the source's frames (the
    others between them: :func:`sliding_kept`), a joint bounded only at those, and with
    every joint below it so, is reduced from those samples alone.

    Each round measures the errors; the joints above a joint that misses get the
    measured ratio (at least 5% tighter, at most half), and only the joints whose angle
    changed are reduced again. After :data:`ROUNDS` rounds the joints above any that
    still miss get their ``provable`` angles (which keep every bound), and after one
    more every joint gets them, so the result always holds, unless float32 kept a joint
    from its provable angle (below): then the distance is refused naming ``tol``.

    A bound float32 would take more than half of at a joint's world positions is refused
    naming ``tol`` (:func:`~sketchanim.float32.position_budget`, ``why`` in the message),
    and an angle float32 would take more than half of (:func:`joint_rotation`) naming
    ``rot_tol_deg`` where it is the angle ``asked`` (radians). An angle tightened
    below ``asked`` (``why``: to hold which distance, said in a refusal) is never less
    than the joint's float32 margin (:func:`~sketchanim.float32.rotation_margin`) over
    ``1 - DERIVED_KEEP`` (what a float32 file can keep of it), nor more than ``asked``;
    the distances are measured on the curves.

    >>> from scipy.spatial.transform import Rotation
    >>> s = Skeleton(("hips", "toe"), (-1, 0), np.array([[0.0, 1, 0], [0, -1.0, 0]]))
    >>> t = np.arange(120) / 60
    >>> clip = Clip.still(s, t)
    >>> clip.rotations[:, 0] = Rotation.from_euler("Z", np.sin(3 * t)[:, None]).as_quat()
    >>> bound = np.full((120, 2), np.inf); bound[:60, 1] = 1e-4
    >>> r = tighten(clip, {}, np.radians([1.0, 1.0]), np.array([5e-5, 5e-5]), bound, 0.0, "incremental")
    >>> bool(r.world_errors(clip)[:60, 1].max() <= 1e-4)
    True
    """
    sk = clip.skeleton
    chains = sk.chains()
    angle = np.array(angle, dtype=float)
    watched = np.isfinite(bound).any(axis=0)
    source = world_matrices(sk, clip.rotations, clip.translations)
    between = None if framed is None or framed.all() else ~framed
    coarse = clip if between is None else replace(clip, times=clip.times[framed], rotations=clip.rotations[framed],
                                                   translations=clip.translations[framed])
    between_chain = np.ones(len(sk), bool) if between is None else \
        on_chains(clip, np.isfinite(bound[between]).any(axis=0))
    sampled = {int(i): clip if between_chain[i] else coarse for i in np.flatnonzero(clip.rotating)}
    tightest = bound.min(axis=0, initial=np.inf)
    for j in np.flatnonzero(watched):                  # a distance in the world float32 cannot keep: refused
        position_budget(clip.times, source[1][:, j], float(tightest[j]), whose="the clip's times",
                        subject=f"in the world for joint {sk.names[j]!r} ({why})")
    rotations: dict[int, Reduction] = {}
    made: dict[int, float] = {}
    least = {i: np.radians(rotation_margin(c.times, c.rotations[:, i])) / (1 - DERIVED_KEEP) * (1 + 1e-9)
             for i, c in sampled.items()}                # what float32 lets a tightened angle keep
    for round in range(ROUNDS + 2):
        for i, c in sampled.items():
            now = min(max(angle[i], least[i]), asked) if angle[i] < asked else angle[i]
            if made.get(i) != now:
                tightened = bool(now < asked)
                rotations[i] = joint_rotation(c, i, float(np.degrees(now)), method, order=order,
                                              field="tol" if tightened else "rot_tol_deg",
                                              why=f", tightened {why}," if tightened else "")
                made[i] = now
        reduced = clip_tracks(clip, rotations, translations)
        if not watched.any():
            return reduced
        ratio = (reduced.world_errors(clip, shell, source=source) / bound).max(axis=0)
        over = np.flatnonzero(ratio > 1)
        if not over.size:
            return reduced
        if round >= ROUNDS:                          # the last resort: every chain provably within
            angle = np.minimum(angle, provable)
            continue
        factor = np.ones(len(sk))                    # each joint tightened once, by its worst descendant
        for d in over:
            factor[chains[d]] = np.minimum(factor[chains[d]], np.clip(0.95 / ratio[d], 0.5, 0.95))
        tight = factor < 1
        if round < ROUNDS - 1:
            angle[tight] *= factor[tight]
        else:
            angle[tight] = np.minimum(angle[tight], provable[tight])
    d = int(over[np.argmax(ratio[over])])
    floored = [sk.names[a] for a in chains[d] if made.get(a, 0.0) > provable[a]]
    if floored:                                      # float32 kept the provable angle from them
        raise ArgumentError("tol", f"{float(bound[:, d].min()):.6g} in the world for joint {sk.names[d]!r} ({why}) "
                                   f"cannot be kept in float32: the angles of {', '.join(floored)} would have to be "
                                   f"finer than float32 keeps them late in the clip; ask for a larger tolerance")
    raise AssertionError(f"world errors up to {ratio.max():.6g} times their bound after the provable angles")


def joint_rotation(clip: Clip, joint: int, tol_deg: float, method: str = "incremental", *, order: int = ORDER,
                   field: str = "rot_tol_deg", why: str = "") -> Reduction:
    """Joint ``joint``'s rotation as a quaternion curve of ``order`` within ``tol_deg``
    degrees at every frame (less float32's share, :func:`rotation_budget`), its keys unit
    quaternions. Straight pieces are kept within the budget both as glTF plays them,
    spherically (:func:`~sketchanim.motion.rotations.spherical`), and component-wise, as
    the reducer fits them (``max_error``: the worse); where the spherical play would miss,
    the joint gets a cubic curve. Errors name the joint: an
    :class:`~sketchanim.errors.ArgumentError` naming ``field`` where float32 would take
    more than half of ``tol_deg`` (more than ``1 - DERIVED_KEEP`` where ``why`` says how
    it was derived from ``field``).

    >>> from scipy.spatial.transform import Rotation
    >>> s = Skeleton(("root",), (-1,), np.zeros((1, 3)))
    >>> clip = Clip.still(s, np.linspace(0, 1, 61))
    >>> clip.rotations[:, 0] = Rotation.from_euler("Z", np.sin(3 * clip.times)[:, None]).as_quat()
    >>> r = joint_rotation(clip, 0, 0.5)
    >>> r.spline.k, bool(np.degrees(r.max_error[0]) <= 0.5)
    (1, True)
    """
    quats = clip.rotations[:, joint]
    name = clip.skeleton.names[joint]
    budget = rotation_budget(clip.times, quats, tol_deg, field=field, subject=f"for joint {name!r} rotation{why}",
                             whose="the clip's times", keep=DERIVED_KEEP if why else KEEP)

    def run() -> Reduction:
        r = reduce_rotations(clip.times, quats, budget, method=method, order=order, keys=True)
        if r.spline.k != 1:
            return r
        played = float(rotation_angle(played_spherically(r.spline, clip.times), quats).max())
        if played > np.radians(budget):
            return reduce_rotations(clip.times, quats, budget, method=method, order=4, keys=True)
        return replace(r, max_error=np.array([max(played, float(r.max_error[0]))]))

    return _named(name, "rotation", run)


def joint_position(clip: Clip, joint: int, tol: float, method: str = "incremental", *, order: int = ORDER,
                   why: str = "") -> Reduction:
    """Joint ``joint``'s translation as a curve of ``order`` within the distance ``tol`` at every
    frame (less float32's share, :func:`position_budget`; ``report["max_distance"]``);
    errors name the joint: an :class:`~sketchanim.errors.ArgumentError` naming ``tol``
    where float32 would take more than half of it (more than ``1 - DERIVED_KEEP`` where
    ``why`` says how it is a share of the one asked)."""
    points = clip.translations[:, joint]
    name = clip.skeleton.names[joint]
    budget = position_budget(clip.times, points, tol, subject=f"for joint {name!r} position{why}",
                             whose="the clip's times", keep=DERIVED_KEEP if why else KEEP)
    r = _named(name, "position", lambda: reduce(clip.times, points, budget / np.sqrt(3.0), method=method,
                                                    order=order))
    r.report["max_distance"] = float(np.linalg.norm(r.spline(clip.times) - clip.translations[:, joint],
                                                    axis=1).max())
    return r


def _named(joint: str, what: str, run: Callable[[], Reduction]) -> Reduction:
    """``run()``, with an input error prefixed by the joint and channel it came from."""
    try:
        return run()
    except InputError as err:
        raise InputError(f"joint {joint!r} {what}: {err}") from None
