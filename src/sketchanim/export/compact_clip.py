"""A skeletal clip as the smallest glTF we can make that plays within a distance in the
world at every frame: LINEAR keys picked from the source's frames, quantised and
compressed (:mod:`sketchanim.formats.gltf_compact`), checked as a client decodes and
plays them.

The distance ``tol`` bounds every joint's world position and every point ``shell`` from a
joint (a vertex its skin could carry), as :mod:`sketchanim.mocap.world_reduction` does
for curves; the joints' first bounds are the same (a joint's angle from how far its turn
reaches). Of each joint's bound, a share (:data:`JOINT_QUANTISATION_SHARE`) is the
filters' (it sets their bits, key by key), and the keys take what the decoded values
leave: keys are chosen on the values the file will hold
(:func:`~sketchanim.reducer.linear_keys.linear_keys`). Where the source holds an end
joint still (a foot on the ground: :func:`~sketchanim.mocap.contacts.planted`), the
world bound there is the first of :data:`PLANTED_M` (at most ``tol``) whose file keeps
the planted joints' sliding (their median speed over the steps
:func:`~sketchanim.mocap.contacts.sliding` measures, as played) within
:data:`~sketchanim.mocap.contacts.SLIDING_SLACK_M_S` of the source's. The decoded clip
is then played (spherically as glTF clients do, and component-wise as Blender's
F-curves do) and measured in the world at every frame; the joints above any miss are
tightened at that frame and keyed again, for :data:`ROUNDS` rounds, then given bounds
that provably keep their chains within. Last, where a joint is held on the ground, the
keys of the legs above it are stored as the roundings that keep it steadiest, of those
a step either side that keep every point within the bound
(:mod:`~sketchanim.export.planted_rounding`): the rounding, not the keys, is what makes
a quantised foot slide.

A track whose one value holds within its bound at every frame is no track: its value
is the node's. Key times are the skeleton's, or each track's own where keys are sparse
(:data:`SHARING`, :data:`SPARSE`); of these the smaller file is kept, and its report
says which.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import minimum_filter1d
from scipy.spatial.transform import Rotation

from sketchanim.errors import ArgumentError
from sketchanim.float32 import float32_margin, margin_refusal
from sketchanim.formats.gltf import Node, Skin, bone_mesh
from sketchanim.export.planted_rounding import PlantedRounding
from sketchanim.formats.gltf_compact import BITS, CompactChannel, bits_for, compact_glb, held, roundings
from sketchanim.mocap.contacts import SLIDING_SLACK_M_S, planted, planted_steps, sliding, step_speeds, unit_m
from sketchanim.mocap.clip_reduction import TRANSLATION_SHARE, held_frames, most_moving
from sketchanim.mocap.world_reduction import MAX_ANGLE_DEG
from sketchanim.motion.kinematics import shell_error, world_matrices
from sketchanim.motion.rotations import continuous_quaternions
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.reducer.linear_keys import linear_keys, misses, played, played_at
from sketchanim.reducer.metric import rotation_angle

#: Of each joint's bound, what the quantisation may take (it sets the filters' bits). With
#: keys at most frames the rounding is what the bound is spent on: 0.5 never made a
#: smaller file than this (every clip of the project's shared data, at 0.5 and 1 cm), and
#: 0.9 or 0.95 were within 3% either way.
JOINT_QUANTISATION_SHARE = 0.8

#: Each track's own key times are tried only where the skeleton's keyed fewer than this
#: share of its tracks' frames: with keys at most frames, one time array always made the
#: smaller file (every clip of the project's shared data, at 0.5 and 1 cm).
SPARSE = 0.5

#: Rounds of measuring in the world and tightening before the provable bounds.
ROUNDS = 6

#: The world bounds tried on planted frames (metres, through the clip's unit; at most
#: ``tol``), in turn, until one keeps the planted joints' sliding within the slack of the
#: source's; the last the filters and float32 can hold is taken regardless. Sliding is a speed, so the bound that keeps it
#: is a distance whatever ``tol`` is. With the legs' roundings picked to hold the feet
#: (:mod:`~sketchanim.export.planted_rounding`), 5 mm kept it on four of the six clips
#: of the project's shared data at 0.5 cm and three at 1 cm, 4 to 2 mm on the others;
#: with the nearest roundings it took 1.5 mm.
PLANTED_M = (0.005, 0.004, 0.003, 0.002, 0.0015, 0.00075, 0.000375)

#: Key times per track, or one array for the whole skeleton.
SHARING = ("track", "skeleton")


@dataclass(frozen=True)
class CompactReport:
    """How a compact clip came out.

    Attributes
    ----------
    tol, shell : float
        The world distance asked, and the shell, clip units.
    quantisation_share : float
        Of each joint's bound, what the filters' rounding was given.
    rotation_bits, translation_bits : tuple of int
        The fewest and most bits given to any track (empty: no such track).
    quantisation_error : float
        The largest world error of the decoded keys alone at their frames, clip units.
    max_world_error : float
        The largest world error of what plays, at every frame, clip units, as computed
        in float64 (it is kept a float32 margin under ``tol``).
    float32_margin : float
        The most a client's float32 (key times, values, arithmetic) may add to a world
        error at any frame: what is kept under ``tol`` for it there, clip units.
    max_rotation_error_deg, max_position_error : float
        The largest error of any joint's rotation (degrees) and translation (clip
        units) at the frames, as played.
    frames, tracks, constant_tracks, keys : int
        Source frames; tracks of the source; those written as their node's value; keys
        written over all tracks.
    sharing : str
        One of :data:`SHARING`.
    planted, planted_bound, planted_error : int, float, float
        Frames of joints held on the ground (summed over joints), their world bound there
        (of :data:`PLANTED_M`, clip units; ``tol`` where nothing is planted), and their
        largest world error there, as played.
    sliding : tuple of float
        The planted joints' median speed over the planted steps in the source and as
        played (the faster of the two ways), clip units per second; empty where nothing
        is planted.
    bytes : int
        Of the .glb.
    """

    tol: float
    shell: float
    quantisation_share: float
    rotation_bits: tuple[int, ...]
    translation_bits: tuple[int, ...]
    quantisation_error: float
    max_world_error: float
    float32_margin: float
    max_rotation_error_deg: float
    max_position_error: float
    frames: int
    tracks: int
    constant_tracks: int
    keys: int
    sharing: str
    planted: int
    planted_bound: float
    planted_error: float
    sliding: tuple[float, ...]
    bytes: int


@dataclass(frozen=True)
class CompactClip:
    """A compact .glb and its report."""

    glb: bytes
    report: CompactReport


@dataclass
class _Tracks:
    """Tracks of one kind (rotations or translations) of the joints ``joints``."""

    path: str
    joints: np.ndarray
    values: np.ndarray            # (T, n, d)
    bound: np.ndarray             # (T, n): the largest error at each frame
    bits: np.ndarray              # (T, n): the filter's bits for each frame's key
    held: np.ndarray              # (T, n, d): each frame's value as decoded (rounded, or as picked)
    stored: np.ndarray            # (T, n, d): as given to the filter (the source's, or the rounding picked)
    constant: np.ndarray          # (T,) bool
    share: float                  # of the bound, the quantisation's
    keep: np.ndarray | None = None  # (T, n) bool: the keyed frames
    error: np.ndarray | None = None  # (T, n): the error at each frame of what plays

    @property
    def rotation(self) -> bool:
        return self.path == "rotation"


def _tracks(path: str, joints: np.ndarray, values: np.ndarray, bound: np.ndarray, share: float) -> _Tracks:
    """Tracks with their bits at each frame (from ``share`` of their bound there and at
    the frames beside it, the quantisation's), decoded values, and which are constant."""
    scale = np.abs(values).max(axis=(1, 2), initial=0.0)
    near = minimum_filter1d(bound, 3, axis=1, mode="nearest") if bound.size else bound
    bits = np.array([bits_for(path, share * b, float(s)) for b, s in zip(near, scale)], dtype=int).reshape(bound.shape)
    decoded = np.stack([held(v, path, k) for v, k in zip(values, bits)]) if len(values) else values
    tracks = _Tracks(path, joints, values, bound, bits, decoded.astype(float), values.copy(),
                     np.zeros(len(joints), bool), share)
    tracks.constant = np.array([_error(tracks, i, _steady(tracks, i)).max() <= b.min()
                                for i, b in enumerate(bound)], dtype=bool)
    return tracks


def _steady(tracks: _Tracks, i: int) -> np.ndarray:
    """The one value nearest all of track ``i``'s: the middle of its range (rotations: the
    mean quaternion, normalised)."""
    v = tracks.values[i]
    if tracks.rotation:
        mean = v.mean(axis=0)
        return mean / np.linalg.norm(mean)
    return (v.min(axis=0) + v.max(axis=0)) / 2


def _error(tracks: _Tracks, i: int, value: np.ndarray, frames: np.ndarray | slice = slice(None)) -> np.ndarray:
    """Track ``i``'s error at every frame (or at ``frames``) if it held ``value`` (one
    value, one per frame, or (K, frames, d): K of them)."""
    v = tracks.values[i, frames]
    if tracks.rotation:
        shape = np.broadcast_shapes(np.shape(value), v.shape)
        return rotation_angle(np.broadcast_to(value, shape).reshape(-1, 4),
                              np.broadcast_to(v, shape).reshape(-1, 4)).reshape(shape[:-1])
    return np.linalg.norm(v - value, axis=-1)


def _keyed(times: np.ndarray, tracks: _Tracks, sharing: str) -> None:
    """Key the tracks that are not constant within their bounds, from the keys they have."""
    if tracks.keep is None:
        tracks.keep = np.zeros((len(tracks.joints), len(times)), bool)
        tracks.keep[:, [0, -1]] = True
    moving = np.flatnonzero(~tracks.constant)
    if len(moving):
        groups = np.zeros(len(moving), int) if sharing == "skeleton" else None
        tracks.keep[moving] = linear_keys(times, tracks.values[moving], tracks.bound[moving],
                                          held=tracks.held[moving], rotation=tracks.rotation, groups=groups,
                                          keep=tracks.keep[moving])
    tracks.error = np.zeros((len(tracks.joints), len(times)))
    for i in np.flatnonzero(tracks.constant):
        tracks.error[i] = _error(tracks, i, _steady(tracks, i))
    if len(moving):
        tracks.error[moving] = misses(times, tracks.values[moving], tracks.held[moving], tracks.keep[moving],
                                      tracks.rotation)


def _pose(clip: Clip, rotations: _Tracks, translations: _Tracks, variant: int, at: np.ndarray | None = None
          ) -> tuple[np.ndarray, np.ndarray]:
    """Local rotations (n, J, 4) and translations (n, J, 3) as the file plays at the
    frames, or at the times ``at`` (``variant`` 0: rotations spherically, 1:
    component-wise)."""
    rot, trans = clip.skeleton.rest_pose(len(clip.times) if at is None else len(at))
    for tracks, out in ((rotations, rot), (translations, trans)):
        moving = np.flatnonzero(~tracks.constant)
        for i in np.flatnonzero(tracks.constant):
            out[:, tracks.joints[i]] = _steady(tracks, i)
        if len(moving):
            held, keep = tracks.held[moving], tracks.keep[moving]
            values = (played(clip.times, held, keep, tracks.rotation) if at is None else
                      played_at(clip.times, held, keep, at, tracks.rotation))
            if tracks.rotation:
                values = values[:, :, variant]
                values = values / np.linalg.norm(values, axis=-1, keepdims=True)
            out[:, tracks.joints[moving]] = np.swapaxes(values, 0, 1)
    return rot, trans


def _world_errors(skeleton: Skeleton, source: tuple[np.ndarray, np.ndarray], rot: np.ndarray, trans: np.ndarray,
                  shell: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per frame and joint (n, J): the joint's distance from the source's in the world,
    plus the most a point ``shell`` from it moves by their rotations' difference
    (``source``: :func:`~sketchanim.motion.kinematics.world_matrices` of the source);
    and the joints' world positions (n, J, 3) and rotations (n, J, 3, 3)."""
    turns, positions = world_matrices(skeleton, rot, trans)
    return shell_error(turns, positions, *source, shell), positions, turns


def compact_clip(clip: Clip, tol: float, shell: float, *, contacts: np.ndarray | None = None,
                 sharing: str | None = None, mesh: bool = True, name: str = "clip") -> CompactClip:
    """``clip`` as a compact .glb whose every joint, and every point ``shell`` from a
    joint, plays within ``tol`` (clip units) of the source in the world at every frame.

    Parameters
    ----------
    clip : Clip
    tol, shell : float
        Clip units.
    contacts : ndarray of bool, shape (n, J), optional
        The frames each joint is held on the ground (default
        :func:`~sketchanim.mocap.contacts.planted`; all False holds none): there, it is
        bound by the first of :data:`PLANTED_M` that keeps its sliding within
        :data:`~sketchanim.mocap.contacts.SLIDING_SLACK_M_S` of the source's.
    sharing : one of :data:`SHARING`, optional
        Key times per track or for the skeleton; the smaller file if omitted.
    mesh : bool
        Add the skinned bone mesh (as :func:`~sketchanim.export.mocap_gltf.clip_glb`).

    Raises
    ------
    ArgumentError
        A ``tol`` or ``shell`` that is not a positive distance, ``contacts`` not of the
        clip's frames and joints, an unknown ``sharing``,
        or a ``tol`` the file cannot keep at some frame: float32 times late in a fast
        clip, or a bound finer than the most bits of a key hold (named with the frame
        and the joint).

    Examples
    --------
    >>> s = Skeleton(("hips", "knee", "toe"), (-1, 0, 1), np.array([[0.0, 90, 0], [0, -45, 0], [0, -45, 0]]))
    >>> t = np.arange(240) / 120
    >>> clip = Clip.still(s, t)
    >>> clip.rotations[:, 1] = Rotation.from_euler("X", np.sin(5 * t)[:, None]).as_quat()
    >>> out = compact_clip(clip, 0.5, 3.0)
    >>> out.report.max_world_error <= 0.5, out.report.constant_tracks, out.glb[:4]
    (True, 2, b'glTF')
    """
    for what, value in (("tol", tol), ("shell", shell)):
        if not np.isfinite(value) or value < 0 or (what == "tol" and value == 0):
            raise ArgumentError(what, f"must be a positive distance, got {value!r}")
    if sharing is not None and sharing not in SHARING:
        raise ArgumentError("sharing", f"one of {', '.join(SHARING)}, got {sharing!r}")
    source = world_matrices(clip.skeleton, clip.rotations, clip.translations)
    still = planted(clip, source[1]) if contacts is None else held_frames(clip, contacts)
    steps = planted_steps(clip.times, still)
    slides = sliding(clip, contacts=still) if len(steps[1]) else None
    metre = 1.0 / unit_m(clip)
    bounds = list(dict.fromkeys(min(m * metre, float(tol)) for m in PLANTED_M)) if len(steps[1]) else [float(tol)]
    best = None
    for s in ("skeleton", "track") if sharing is None else (sharing,):
        if sharing is None and s == "track" and best.report.keys > SPARSE * best.report.frames * best.report.tracks:
            break                                    # keys at most frames: one time array is the smaller file
        made = None
        for bound in bounds[bounds.index(best.report.planted_bound):] if best else bounds:
            asked = np.where(still, bound, float(tol))
            try:
                world_bound = _budget(clip, source, asked, shell)
                made = _compact(clip, source, float(tol), world_bound, float((asked - world_bound).max(initial=0.0)),
                                still, steps, slides, bound, shell, s, mesh, name)
            except ArgumentError:
                if made is None and best is None:
                    raise
                break                                # finer than the filters' bits or float32 hold: the last one
            if not made.report.sliding or made.report.sliding[1] <= made.report.sliding[0] + SLIDING_SLACK_M_S * metre:
                break
        if made is not None and (best is None or len(made.glb) < len(best.glb)):
            best = made
    return best


def _budget(clip: Clip, source: tuple[np.ndarray, np.ndarray], asked: np.ndarray, shell: float) -> np.ndarray:
    """What the keys and the filters may use of the world bound ``asked`` (n, J) at each
    frame and joint, less what float32 key times and a client's float32 arithmetic may
    move the joint's points there (:func:`~sketchanim.float32.float32_margin` at the
    frame's time, the clip's largest world position, and the speed on either side of the
    frame of the joint or a point ``shell`` from it, played up to ``asked`` away at both
    ends). A jump into the first pose costs only the first frame's margin.

    Raises :class:`~sketchanim.errors.ArgumentError` where the margin is more than half
    of what was asked, naming the frame and the joint
    (:func:`~sketchanim.float32.margin_refusal`)."""
    turns, positions = source
    if len(clip.times) < 2:
        return asked
    dt = np.diff(clip.times)[:, None]
    step = np.linalg.norm(np.diff(positions, axis=0), axis=-1)
    cos = (np.einsum("njab,njab->nj", turns[1:], turns[:-1]) - 1) / 2
    step = (step + shell * np.arccos(np.clip(cos, -1.0, 1.0)) + asked[1:] + asked[:-1]) / dt
    speed = np.maximum(np.concatenate([step[:1], step]), np.concatenate([step, step[-1:]]))
    size = float(np.linalg.norm(positions, axis=-1).max()) + shell
    margin = float32_margin(clip.times, size, speed)
    short = np.argwhere(margin > asked / 2)
    if len(short):
        f, j = short[0]
        raise margin_refusal(float(asked[f, j]), float(margin[f, j]), float(float32_margin(clip.times[:0], size, 0.0)),
                             f"at frame {f} ({clip.times[f]:.6g} s) of joint {clip.skeleton.names[j]!r}",
                             f"points up to {size:.4g} from the origin, moving up to {speed[f, j]:.3g} per s",
                             whose="the clip's times")
    return asked - margin


def _sliding(clip: Clip, steps: tuple[np.ndarray, np.ndarray, np.ndarray], rotations: _Tracks,
             translations: _Tracks) -> float:
    """The planted joints' median speed over ``steps`` (:func:`~sketchanim.mocap.contacts.planted_steps`:
    sample times, each step's first and its joint) as the file plays at those times,
    each step the faster way (clip units per second)."""
    at, first, joint = steps
    moved = [world_matrices(clip.skeleton, *_pose(clip, rotations, translations, v, at))[1] for v in (0, 1)]
    return float(np.median(np.max([step_speeds(p, first, joint) for p in moved], axis=0)))


def _compact(clip: Clip, source: tuple[np.ndarray, np.ndarray], tol: float, world_bound: np.ndarray, margin: float,
             still: np.ndarray, steps: tuple[np.ndarray, np.ndarray, np.ndarray], slides: float | None,
             planted_bound: float, shell: float, sharing: str, mesh: bool, name: str) -> CompactClip:
    """The compact file with key times shared as ``sharing`` says, every joint within
    ``world_bound`` (n, J) in the world at every frame (the budget of ``tol``, of
    ``planted_bound`` where ``still`` holds it on the ground, less float32's ``margin``
    at most), and its planted ``steps``' sliding, beside the source's (``slides``;
    None: nothing planted). Where anything is held on the ground,
    the legs' roundings are picked to hold it still (:func:`_planted_roundings`)."""
    sk = clip.skeleton
    n = len(clip.times)
    chains = sk.chains()
    varying = clip.translating & np.any(np.ptp(clip.translations, axis=0) > 0, axis=-1)
    share = TRANSLATION_SHARE * world_bound / most_moving(clip, np.ones(len(sk), bool))      # (n, J)
    budget = world_bound - share * np.array([sum(bool(varying[a]) for a in c) for c in chains])
    turning = max(max(sum(bool(clip.rotating[a]) for a in chain) for chain in chains), 1)
    arm = sk.reach(clip.bones()) + shell
    # a joint's bound at a frame: the tightest its descendants' world bounds there allow
    below = np.full((n, len(sk)), np.inf)
    for d, chain in enumerate(chains):
        below[:, chain] = np.minimum(below[:, chain], budget[:, [d]])
    cap = np.radians(MAX_ANGLE_DEG)
    angle = np.minimum(below / np.maximum(arm, 1e-300), cap)
    provable = np.minimum(below / np.maximum(turning * arm, 1e-300), cap)
    r_joints = np.flatnonzero(clip.rotating)
    t_joints = np.flatnonzero(clip.translating)
    quats = np.stack([continuous_quaternions(clip.rotations[:, j]) for j in r_joints]).reshape(len(r_joints), n, 4)
    rotations = _tracks("rotation", r_joints, quats,
                        angle.T[r_joints].copy(), JOINT_QUANTISATION_SHARE)
    translations = _tracks("translation", t_joints, np.swapaxes(clip.translations[:, t_joints], 0, 1),
                           np.broadcast_to(share.min(axis=1), (len(t_joints), n)).copy(), JOINT_QUANTISATION_SHARE)
    for tracks in (rotations, translations):
        _refuse_finer_than_bits(clip, tracks, tol)
    for round in range(ROUNDS + 3):
        for tracks in (rotations, translations):
            _keyed(clip.times, tracks, sharing)
        played = [_world_errors(sk, source, *_pose(clip, rotations, translations, v), shell) for v in (0, 1)]
        errors = np.maximum(played[0][0], played[1][0])
        over = errors > world_bound
        if not over.any():
            break
        if round == ROUNDS + 2:
            f, d = np.unravel_index(np.argmax(errors - world_bound), errors.shape)
            raise AssertionError(f"world error {errors[f, d]:.6g} > {world_bound[f, d]:.6g} at frame {f} of joint "
                                 f"{sk.names[d]!r} after the provable bounds")
        factor = np.ones((n, len(sk)))               # each joint tightened where a descendant misses, once
        for f, d in np.argwhere(over):
            ratio = np.clip(0.95 * world_bound[f, d] / errors[f, d], 0.5, 0.95)
            factor[f, chains[d]] = np.minimum(factor[f, chains[d]], ratio)
        tight = factor < 1
        for tracks in (rotations, translations):
            # below what each joint misses by now, where a descendant misses: every round gains
            now = np.where(tight.T[tracks.joints], tracks.error * factor.T[tracks.joints], np.inf)
            if round >= ROUNDS and tracks.rotation:  # the joints that still miss, then every joint
                limit = provable.T[tracks.joints]
                now = np.minimum(now, np.where(tight.T[tracks.joints], limit, np.inf) if round == ROUNDS else limit)
            _tighten(tracks, now)
    if still.any():
        _planted_roundings(clip, source, world_bound, still, shell, played, rotations, translations)
        played = [_world_errors(sk, source, *_pose(clip, rotations, translations, v), shell) for v in (0, 1)]
        errors = np.maximum(played[0][0], played[1][0])
        assert (errors <= world_bound).all(), "a rounding picked left the world bound"
    slid = (slides, _sliding(clip, steps, rotations, translations)) if slides is not None else ()
    return _written(clip, source, rotations, translations, errors, margin, tol, still, planted_bound, slid, shell,
                    sharing, mesh, name)


def _planted_roundings(clip: Clip, source: tuple[np.ndarray, np.ndarray], world_bound: np.ndarray, still: np.ndarray,
                       shell: float, played: list[tuple[np.ndarray, np.ndarray, np.ndarray]], rotations: _Tracks,
                       translations: _Tracks) -> None:
    """The legs' keys at the frames they hold a joint on the ground (``still``) stored as
    the roundings that keep it steadiest (:mod:`~sketchanim.export.planted_rounding`),
    top down, each within its track's bound and every point within ``world_bound``
    (``played``: the world errors, positions and rotations of both ways the file plays,
    as keyed and rounded)."""
    state = PlantedRounding(clip.skeleton, source, np.stack([played[0][2], played[1][2]]),
                            np.stack([played[0][1], played[1][1]]), world_bound, still, shell)
    for joint in np.flatnonzero(state.legs()):
        for tracks in (translations, rotations):
            track = np.flatnonzero(tracks.joints == joint)
            if not len(track) or tracks.constant[track[0]]:
                continue
            i = track[0]
            frames = np.flatnonzero(tracks.keep[i] & state.frames(joint, tracks.rotation))
            if not len(frames):
                continue
            values = tracks.values[i, frames]
            near = roundings(values, tracks.path, tracks.bits[i, frames])
            allowed = _error(tracks, i, near, frames) <= tracks.bound[i, frames]
            picked = state.pick(joint, tracks.rotation, tracks.keep[i], frames, tracks.held[i, frames], near, allowed)
            at = picked >= 0
            tracks.held[i, frames[at]] = tracks.stored[i, frames[at]] = near[picked[at], np.flatnonzero(at)]


def _refuse_finer_than_bits(clip: Clip, tracks: _Tracks, tol: float) -> None:
    """Raises :class:`~sketchanim.errors.ArgumentError` where a track's decoded value
    misses its bound at its most bits (the bound ``tol`` asks of a joint there is too
    fine), naming the frame and the joint. Below the most bits, ``bits_for`` holds it."""
    most = BITS[tracks.path][1]
    for i in np.flatnonzero(~tracks.constant):
        short = np.flatnonzero(_error(tracks, i, tracks.held[i]) > tracks.bound[i])
        if len(short):
            f, j = short[0], tracks.joints[i]
            assert tracks.bits[i, f] == most, "bits_for gave too few bits"
            raise ArgumentError("tol", f"{tol:.6g} asks the {tracks.path} of joint {clip.skeleton.names[j]!r} to "
                                       f"{tracks.bound[i, f]:.3g} at frame {f} ({clip.times[f]:.6g} s), finer than "
                                       f"{most} bits hold it: ask for a larger tolerance")


def _tighten(tracks: _Tracks, bound: np.ndarray) -> None:
    """New bounds for ``tracks``: a constant track that no longer holds is keyed from its
    ends, and where a track's decoded values take half their bound, those frames get more
    bits."""
    for i in range(len(tracks.joints)):
        # never below twice what the decoded value misses by alone: more bits come first
        tracks.bound[i] = np.minimum(tracks.bound[i], np.maximum(bound[i], 2 * _error(tracks, i, tracks.held[i])))
        if tracks.constant[i] and _error(tracks, i, _steady(tracks, i)).max() > tracks.bound[i].min():
            tracks.constant[i] = False
            tracks.keep[i] = False
            tracks.keep[i, [0, -1]] = True
        coarse = (2 * _error(tracks, i, tracks.held[i]) >= tracks.bound[i]) & (tracks.bits[i] < BITS[tracks.path][1])
        if coarse.any():
            scale = float(np.abs(tracks.values[i]).max(initial=0.0))
            tracks.bits[i, coarse] = np.maximum(tracks.bits[i, coarse] + 1,
                                                bits_for(tracks.path, tracks.share * tracks.bound[i, coarse], scale))
            tracks.held[i, coarse] = held(tracks.values[i, coarse], tracks.path, tracks.bits[i, coarse])
            tracks.bound[i] = np.maximum(tracks.bound[i], 2 * _error(tracks, i, tracks.held[i]))


def _written(clip: Clip, source: tuple[np.ndarray, np.ndarray], rotations: _Tracks, translations: _Tracks,
             errors: np.ndarray, margin: float, tol: float, still: np.ndarray, planted_bound: float,
             slid: tuple[float, ...], shell: float, sharing: str, mesh: bool, name: str) -> CompactClip:
    """The .glb of the keyed tracks, and its report (``still``: the frames and joints held
    on the ground, within ``planted_bound`` there, sliding as ``slid`` says)."""
    sk = clip.skeleton
    nodes = [Node(n, p, translation=o.tolist()) for n, p, o in zip(sk.names, sk.parents, sk.offsets)]
    channels = []
    keys = 0
    for tracks in (rotations, translations):
        moving = np.flatnonzero(~tracks.constant)
        for i in np.flatnonzero(tracks.constant):
            setattr(nodes[tracks.joints[i]], tracks.path, _steady(tracks, i).tolist())
        for i in moving:
            frames = np.flatnonzero(tracks.keep[i])
            keys += len(frames)
            channels.append(CompactChannel(int(tracks.joints[i]), tracks.path, clip.times[frames],
                                           tracks.stored[i, frames], tracks.bits[i, frames]))
    channels.sort(key=lambda c: (c.node, c.path != "rotation"))
    extra = {}
    if mesh:
        rest = sk.rest_positions()
        bones = bone_mesh(rest, sk.parents)
        if len(bones.positions):
            inverse = np.tile(np.eye(4), (len(sk), 1, 1))
            inverse[:, :3, 3] = -rest
            nodes.append(Node("bones", mesh=0, skin=0))
            extra = {"meshes": [bones], "skins": [Skin(list(range(len(sk))), inverse)]}
    glb = compact_glb(nodes, channels, animation=name, unit_m=clip.unit_m, **extra)
    quantisation = _quantisation_error(clip, source, rotations, translations, shell)
    report = CompactReport(tol, float(shell), JOINT_QUANTISATION_SHARE, _range(rotations), _range(translations),
                           quantisation, float(errors.max(initial=0.0)), margin,
                           float(np.degrees(rotations.error.max(initial=0.0))),
                           float(translations.error.max(initial=0.0)),
                           len(clip.times),
                           len(rotations.joints) + len(translations.joints),
                           int(rotations.constant.sum() + translations.constant.sum()), keys, sharing,
                           int(still.sum()), planted_bound, float(errors[still].max(initial=0.0)), slid,
                           len(glb))
    return CompactClip(glb, report)


def _range(tracks: _Tracks) -> tuple[int, ...]:
    """The fewest and most bits of the keys written."""
    bits = tracks.bits[~tracks.constant][tracks.keep[~tracks.constant]]
    return (int(bits.min()), int(bits.max())) if len(bits) else ()


def _quantisation_error(clip: Clip, source: tuple[np.ndarray, np.ndarray], rotations: _Tracks, translations: _Tracks,
                        shell: float) -> float:
    """The largest world error of the decoded values alone, held at every frame."""
    rot, trans = clip.rotations.copy(), clip.translations.copy()
    for tracks, out in ((rotations, rot), (translations, trans)):
        for i in np.flatnonzero(~tracks.constant):
            out[:, tracks.joints[i]] = tracks.held[i]
    return float(_world_errors(clip.skeleton, source, rot, trans, shell)[0].max(initial=0.0))
