"""A humanoid that walks along a performed ground path: the walker's goal is a ground
marker (a position track whose y is the ground height under it), and the figure follows
it, facing along the path, its step length and cadence following the path's speed
(Boulic, Magnenat-Thalmann & Thalmann 1990: relative velocity ``RV = v / H``, ``H`` the
leg length, relative cycle length ``RLc = 1.346 sqrt(RV)``), its feet planted during
stance and stepping when a foot drifts past a threshold, one leg at a time (running, with
a flight phase, above the walk-run speed).

The model is a deterministic simulation at :data:`RATE` ticks a second (the IK's, shared by
every derived pose: :data:`sketchanim.motion.ik.RATE`) from the start of
the animation: the caller samples the marker at ticks ``k / RATE``, :func:`start` stands
the figure still at the first marker and :func:`advance` steps it one tick, so the pose is
a pure function of the marker's curve. :func:`walk` is :func:`advance` in a loop. The page
runs the same algorithm (``studio/web/js/walk.js``), operation for operation, so the two
agree to 1e-6 rad; docs/walker.md describes the model. The figure is
:mod:`sketchanim.motion.humanoid`'s, the leg IK :mod:`sketchanim.motion.twobone`'s.

Conventions: y up (three.js), the figure faces +z at heading 0 (heading ``a`` faces
``(sin a, 0, cos a)``) with its left side on +x; rotations are local, scalar-last unit
quaternions as :mod:`sketchanim.motion.skeleton`'s, ``world = parent * local``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from sketchanim.errors import ArgumentError
from sketchanim.motion.humanoid import Rig, humanoid, rig
from sketchanim.motion.ik import RATE
from sketchanim.motion.skeleton import Skeleton
from sketchanim.motion.twobone import Frame, Vec, frame_quaternion, local_frame, two_bone

__all__ = ["RATE", "Gait", "Walk", "WalkState", "advance", "gait", "humanoid", "rig", "start", "walk"]

#: Boulic's relative cycle length per square root of relative velocity.
CYCLE = 1.346
#: Below this relative velocity (1/s) the cycle's timing is held at its value here.
RV_SLOW = 1.0
#: The walk-run speed, relative (Boulic's walking model holds up to RV 2.3).
RV_RUN = 2.3
#: The fastest run, relative: beyond ``RV_FASTEST * H`` m/s the figure falls behind.
RV_FASTEST = 7.5
#: A run's stance length (distance the body travels while a foot is planted), in leg lengths.
RUN_CONTACT = 0.8
#: The velocity's smoothing time constant, seconds.
SMOOTHING = 0.15
#: Fastest turn, rad/s.
TURN_RATE = 3.0
#: While the body turns (its heading or a planted foot's yaw more than ``DRIFT_YAW`` off
#: the path's) or stands still, the feet step at least at the cadence of this relative speed.
RV_TURN = 2.0
#: Slowest speed the body turns to face, relative (v / H).
RV_FACE = 0.1
#: Least drift (in leg lengths) that makes a planted foot step, and the yaw drift (rad).
DRIFT_MIN = 0.09
DRIFT_YAW = 0.35
#: The least drift (leg lengths) once the body is still (slower than ``RV_FACE``): the
#: stop steps that bring the feet under the hips.
DRIFT_SETTLE = 0.04
#: Shortest time a foot stays planted, seconds.
STANCE_MIN = 0.1
#: A foot drifted this far past its threshold lifts as soon as the other foot has been
#: planted ``STANCE_MIN`` (or, running, lifted that long ago), not waiting for half a
#: cycle since the other lifted.
OVERDUE = 1.1
#: Where a foot lands: this fraction of its stance's travel short of centred under its hip
#: (it lifts as far past centred plus this), as a heel strike lands nearer than a toe-off leaves.
LAND_SHIFT = 0.15
#: The most a planted foot's heel rises (rad, pivoting on the toe) to keep it in reach.
HEEL_MAX = 0.9
#: Swing foot clearance at mid-swing, in leg lengths.
CLEARANCE = 0.08
#: The pelvis's usual height, the fraction of the legs' reach it holds at most, and the
#: lowest it goes (fraction of its rest height above the ground) before a foot out of reach lifts.
CROUCH = 0.98
REACH = 0.995
FLOOR = 0.7
#: How far (leg lengths) a run sinks the hips at mid-stance.
RUN_SINK = 0.05
#: Arm swing (rad per leg length of foot separation) and its bound; elbow bend walking and running.
ARM_SWING = 0.7
ARM_MAX = 0.8
ELBOW_WALK = 0.25
ELBOW_RUN = 1.4
#: Forward lean of the spine: at rest and per m/s, and at most (rad).
LEAN_REST = 0.03
LEAN_SPEED = 0.03
LEAN_MAX = 0.3

#: The lift tick of a foot that has not stepped yet.
NEVER = -1000000


class Foot(NamedTuple):
    """One foot: its ankle's world position were the foot flat, its yaw and the pitch of
    its heel's rise about the toe (rad); planted since tick ``landed``, or swinging since
    tick ``lifted`` from ankle ``lift_at`` (heel risen ``lift_pitch``) and ``lift_yaw``, the
    hips then held down to ``lift_height`` by its reach, ``progress`` of the swing done (each
    tick a tick's share of the gait's swing then: a swing quickens as the body does)."""

    ankle: Vec
    yaw: float
    pitch: float
    planted: bool
    landed: int
    lifted: int
    lift_at: Vec
    lift_yaw: float
    lift_pitch: float
    progress: float
    lift_height: float


@dataclass(frozen=True)
class WalkState:
    """The walker at one tick.

    Attributes
    ----------
    rig : Rig
    tick : int
        The tick (0 at :func:`start`); its time is ``tick / RATE``.
    body : tuple
        The ground point under the pelvis (x, y, z): the marker's, unless behind it.
    velocity : tuple
        The body's smoothed ground velocity (x, z), m/s.
    heading : float
        The facing angle (rad); heading 0 faces +z.
    feet : tuple of Foot
        Left, right.
    marker : tuple
        The marker at this tick.
    behind_since : int
        The tick the body fell behind the marker, or -1 when it is on it.
    behind_speed : float
        The fastest marker speed (m/s) since then.
    rotations : ndarray, shape (J, 4)
        The pose's local rotations, scalar-last.
    root : ndarray, shape (3,)
        The hips' world translation.
    """

    rig: Rig
    tick: int
    body: Vec
    velocity: tuple[float, float]
    heading: float
    feet: tuple[Foot, Foot]
    marker: Vec
    behind_since: int
    behind_speed: float
    rotations: np.ndarray
    root: np.ndarray

    @property
    def stance(self) -> tuple[bool, bool]:
        """Whether the left and the right foot are planted."""
        return self.feet[0].planted, self.feet[1].planted


@dataclass(frozen=True)
class Walk:
    """A walk, one row per tick.

    Attributes
    ----------
    rotations : ndarray, shape (n, J, 4)
        Local rotations, scalar-last.
    root : ndarray, shape (n, 3)
        The hips' translation in the world.
    stance : ndarray of bool, shape (n, 2)
        Left, right foot planted.
    behind : list of (float, float, float)
        ``(start s, end s, fastest path speed m/s)`` where the path outran the fastest run:
        the first and the last tick's time the body was behind the marker.
    """

    rotations: np.ndarray
    root: np.ndarray
    stance: np.ndarray
    behind: list[tuple[float, float, float]]


def _marker(marker: object) -> Vec:
    try:
        x, y, z = marker  # type: ignore[misc]
        m = float(x), float(y), float(z)
    except (TypeError, ValueError):
        m = (math.nan,)  # type: ignore[assignment]
    if not all(math.isfinite(v) for v in m):
        raise ArgumentError("marker", f"must be 3 finite numbers, got {marker!r}")
    return m


def start(skeleton: Skeleton, marker: object) -> WalkState:
    """The walker standing still at ``marker`` (x, y, z; y the ground height), facing +z:
    tick 0.

    >>> s = start(humanoid(), [1.0, 0.0, 2.0])
    >>> s.stance, s.root.round(4).tolist()
    ((True, True), [1.0, 0.9628, 2.0])
    """
    r = rig(skeleton)
    m = _marker(marker)
    feet = tuple(Foot(a, 0.0, 0.0, True, 0, NEVER, a, 0.0, 0.0, 0.0, 0.0) for a in (
        (m[0] + r.hip[i][0], m[1] + r.ankle, m[2] + r.hip[i][2]) for i in (0, 1)))
    state = WalkState(r, 0, m, (0.0, 0.0), 0.0, feet, m, -1, 0.0,  # type: ignore[arg-type]
                      np.zeros((r.joints, 4)), np.zeros(3))
    return _posed(state, state.feet, 0.0)


def advance(state: WalkState, marker: object) -> WalkState:
    """The walker one tick later, the marker there being ``marker`` (x, y, z).

    >>> s = start(humanoid(), [0.0, 0.0, 0.0])
    >>> for k in range(1, 241):
    ...     s = advance(s, [0.0, 0.0, 1.2 * k / RATE])
    >>> round(s.body[2], 6), abs(s.heading) < 1e-9
    (2.4, True)
    """
    m = _marker(marker)
    r = state.rig
    tick = state.tick + 1
    dt = 1.0 / RATE
    # The body follows the marker on the ground, no faster than the fastest run.
    bx, bz = state.body[0], state.body[2]
    dx, dz = m[0] - bx, m[2] - bz
    gap = math.sqrt(dx * dx + dz * dz)
    most = RV_FASTEST * r.leg * dt
    if gap > most:
        nx, nz = bx + dx * (most / gap), bz + dz * (most / gap)
    else:
        nx, nz = m[0], m[2]
    body = (nx, m[1], nz)
    px, pz = m[0] - state.marker[0], m[2] - state.marker[2]
    path_speed = math.sqrt(px * px + pz * pz) * RATE
    if gap > most:
        since = state.behind_since if state.behind_since >= 0 else tick
        fastest = max(state.behind_speed, path_speed) if state.behind_since >= 0 else path_speed
    else:
        since, fastest = -1, 0.0
    # Smoothed velocity, speed and heading.
    a = dt / SMOOTHING
    vx = state.velocity[0] + a * ((nx - bx) * RATE - state.velocity[0])
    vz = state.velocity[1] + a * ((nz - bz) * RATE - state.velocity[1])
    speed = math.sqrt(vx * vx + vz * vz)
    heading = state.heading
    turning = speed <= RV_FACE * r.leg                 # (or still: settling steps are brisk too)
    if speed > RV_FACE * r.leg:
        turn = _wrap(math.atan2(vx, vz) - heading)
        step = TURN_RATE * dt
        heading = _wrap(heading + min(max(turn, -step), step))
        turning = abs(turn) > DRIFT_YAW
    for f in state.feet:
        turning = turning or f.planted and abs(_wrap(heading - f.yaw)) > DRIFT_YAW
    g = gait(speed, r.leg, RV_TURN * r.leg if turning else 0.0)
    moved = WalkState(r, tick, body, (vx, vz), heading, state.feet, m, since, fastest, state.rotations, state.root)
    return _posed(moved, _step_feet(moved, g), speed)


@dataclass(frozen=True)
class Gait:
    """The gait at a speed: cycle, stance and swing durations (s), whether it runs, and
    the drift (m) that makes a planted foot step."""

    cycle: float
    stance: float
    swing: float
    run: bool
    drift: float


def gait(speed: float, leg: float, pace: float = 0.0) -> Gait:
    """Boulic's walking cycle at ``speed`` m/s for legs ``leg`` m long: cycle length
    ``1.346 sqrt(v / H) H``, so duration ``1.346 sqrt(H / v)`` (timed as at ``RV_SLOW H``
    below it, and at ``pace`` m/s below that), stance ``0.752 cycle - 0.143`` s; above
    ``RV_RUN`` a run, stance ``RUN_CONTACT H / v``. The drift that makes a foot step is the
    body's travel in a stance (at least ``DRIFT_MIN H``, ``DRIFT_SETTLE H`` when still).

    >>> g = gait(1.4, 0.9275)
    >>> round(g.cycle, 4), round(g.stance, 4), round(g.swing, 4), g.run
    (1.0956, 0.6809, 0.4147, False)
    """
    slow = RV_SLOW * leg
    v = speed if speed > slow else slow
    v = pace if pace > v else v
    cycle = CYCLE * math.sqrt(leg / v)
    if speed > RV_RUN * leg:
        stance = RUN_CONTACT * leg / v
        run = True
    else:
        stance = 0.752 * cycle - 0.143
        run = False
    drift = speed * stance
    least = (DRIFT_MIN if speed > RV_FACE * leg else DRIFT_SETTLE) * leg
    return Gait(cycle, stance, cycle - stance, run, drift if drift > least else least)


def _wrap(angle: float) -> float:
    """``angle`` brought into [-pi, pi)."""
    return angle - 2.0 * math.pi * math.floor((angle + math.pi) / (2.0 * math.pi))


def _rest_spot(state: WalkState, side: int, ahead: float) -> tuple[float, float]:
    """Where foot ``side`` would be centred under its hip, the body ``ahead`` s on."""
    hx, _, hz = state.rig.hip[side]
    s, c = math.sin(state.heading), math.cos(state.heading)
    return (state.body[0] + c * hx + s * hz + state.velocity[0] * ahead,
            state.body[2] - s * hx + c * hz + state.velocity[1] * ahead)


def _reach_height(state: WalkState, side: int, ankle: Vec) -> float:
    """The highest the hips can be with foot ``side``'s ankle at ``ankle`` in reach (-inf
    if no height reaches it)."""
    r = state.rig
    hx, hy, hz = r.hip[side]
    s, c = math.sin(state.heading), math.cos(state.heading)
    dx = state.body[0] + c * hx + s * hz - ankle[0]
    dz = state.body[2] - s * hx + c * hz - ankle[2]
    reach = REACH * (r.thigh + r.shin)
    flat = reach * reach - (dx * dx + dz * dz)
    if flat <= 0.0:
        return -math.inf
    return ankle[1] + math.sqrt(flat) - hy


def _floor(state: WalkState) -> float:
    return state.body[1] + FLOOR * state.rig.pelvis


def _step_feet(state: WalkState, g: Gait) -> tuple[Foot, Foot]:
    """The feet one tick on: swings advance (landing when done); a planted foot lifts when
    out of reach, or when it has drifted past the gait's threshold -- or the other foot
    will have half a cycle on, this one having drifted further -- and the other foot lets
    it: planted (walking) and lifted half a cycle ago (walking and running), or planted a
    moment when this one is overdue."""
    feet = list(state.feet)
    land = g.stance * (0.5 - LAND_SHIFT)
    for i in (0, 1):
        f = feet[i]
        if f.planted:
            continue
        done = f.progress + 1.0 / (RATE * g.swing)
        if done >= 1.0:
            spot = _rest_spot(state, i, land)
            feet[i] = f._replace(ankle=(spot[0], state.body[1] + state.rig.ankle, spot[1]), yaw=state.heading,
                                 pitch=0.0, planted=True, landed=state.tick)
        else:
            feet[i] = f._replace(progress=done)
    ratios = [0.0, 0.0]
    later = [0.0, 0.0]
    for i in (0, 1):
        f = feet[i]
        if f.planted:
            spot = _rest_spot(state, i, land)
            ex, ez = f.ankle[0] - spot[0], f.ankle[2] - spot[1]
            yaw = abs(_wrap(state.heading - f.yaw)) / DRIFT_YAW
            ratio = math.sqrt(ex * ex + ez * ez) / g.drift
            ratios[i] = ratio if ratio > yaw else yaw
            fx, fz = ex - state.velocity[0] * g.cycle / 2.0, ez - state.velocity[1] * g.cycle / 2.0
            ratio = math.sqrt(fx * fx + fz * fz) / g.drift
            later[i] = ratio if ratio > yaw else yaw
    order = (1, 0) if ratios[1] > ratios[0] else (0, 1)
    for i in order:
        f, other = feet[i], feet[1 - i]
        if not f.planted:
            continue
        forced = _reach_height(state, i, _ankle(state.rig, f)) < _floor(state)
        wants = (ratios[i] >= 1.0 or later[1 - i] >= 1.0 and ratios[i] >= ratios[1 - i]) and \
            (state.tick - f.landed) / RATE >= STANCE_MIN
        free = (other.planted or g.run) and (state.tick - other.lifted) / RATE >= g.cycle / 2.0 or \
            ratios[i] >= OVERDUE and (other.planted and (state.tick - other.landed) / RATE >= STANCE_MIN or
                                      g.run and (state.tick - other.lifted) / RATE >= STANCE_MIN)
        if forced or (wants and free):
            ankle = _ankle(state.rig, f)
            feet[i] = f._replace(planted=False, lifted=state.tick, lift_at=ankle, lift_yaw=f.yaw, lift_pitch=f.pitch,
                                 progress=0.0, lift_height=_reach_height(state, i, ankle))
    for i in (0, 1):
        f = feet[i]
        if not f.planted:
            feet[i] = _swung(state, i, f, g)
    return feet[0], feet[1]


def _ankle(r: Rig, f: Foot) -> Vec:
    """Where ``f``'s ankle is: a swinging foot's as it is, a planted one's with its heel
    risen ``f.pitch`` about the toe."""
    if not f.planted or f.pitch == 0.0:
        return f.ankle
    _, ty, tz = r.toe
    s, c = math.sin(f.pitch), math.cos(f.pitch)
    up = -ty * c + tz * s
    back = -tz * c - ty * s
    return (f.ankle[0] + math.sin(f.yaw) * (tz + back), f.ankle[1] + ty + up, f.ankle[2] + math.cos(f.yaw) * (tz + back))


def _heel(r: Rig, f: Foot, hip: Vec) -> float:
    """How far (rad) planted foot ``f``'s heel must rise, pivoting on the toe, for the hip
    joint at ``hip`` to reach its ankle: 0 when it reaches it flat or the toe is ahead of
    the hip, at most ``HEEL_MAX``."""
    _, ty, tz = r.toe
    s, c = math.sin(f.yaw), math.cos(f.yaw)
    toe = (f.ankle[0] + s * tz, f.ankle[1] + ty, f.ankle[2] + c * tz)
    wx, wy, wz = hip[0] - toe[0], hip[1] - toe[1], hip[2] - toe[2]
    wf = wx * s + wz * c
    if wf <= 0.0:
        return 0.0
    reach = REACH * (r.thigh + r.shin)
    rho2 = ty * ty + tz * tz
    k = (reach * reach - (wx * wx + wy * wy + wz * wz) - rho2) / (2.0 * math.sqrt(rho2))
    a = math.sqrt(wf * wf + wy * wy)
    if k >= a:
        return 0.0
    turn = math.acos(k / a) if k > -a else math.pi
    pitch = turn - math.atan2(wy, wf) - math.atan2(-ty, tz)
    return 0.0 if pitch < 0.0 else HEEL_MAX if pitch > HEEL_MAX else pitch


def _swung(state: WalkState, side: int, f: Foot, g: Gait) -> Foot:
    """The swinging foot's ankle, yaw and pitch this tick: from where it lifted toward
    where it will land (under its hip, the body's motion to the landing and the stance's
    landing lead ahead), smoothstepped, raised by the clearance on a parabola, the heel
    coming down."""
    s = f.progress
    spot = _rest_spot(state, side, (1.0 - s) * g.swing + g.stance * (0.5 - LAND_SHIFT))
    e = s * s * (3.0 - 2.0 * s)
    lx, ly, lz = f.lift_at
    y = state.body[1] + state.rig.ankle
    ankle = (lx + (spot[0] - lx) * e, ly + (y - ly) * e + CLEARANCE * state.rig.leg * 4.0 * s * (1.0 - s),
             lz + (spot[1] - lz) * e)
    return f._replace(ankle=ankle, yaw=f.lift_yaw + _wrap(state.heading - f.lift_yaw) * e,
                      pitch=f.lift_pitch * (1.0 - e))


def _posed(state: WalkState, placed: tuple[Foot, Foot], speed: float) -> WalkState:
    """``state`` with feet ``placed`` and the pose of its feet and body: the hips at the body, as high as
    the feet's reach lets them (at most the crouched rest height, less a run's sink at
    mid-stance; at least the floor),
    two-bone IK on each leg, the spine leaning with speed, the arms swinging against the
    legs."""
    r = state.rig
    b = state.body
    s, c = math.sin(state.heading), math.cos(state.heading)
    run = (speed - 0.8 * RV_RUN * r.leg) / (0.4 * RV_RUN * r.leg)
    run = 0.0 if run < 0.0 else 1.0 if run > 1.0 else run
    top = b[1] + r.pelvis - (1.0 - CROUCH) * (r.thigh + r.shin)
    sink = 0.0
    for f in placed:                           # a run's stance: the hips lowest at its middle
        if run > 0.0 and f.planted:
            u = (state.tick - f.landed) / RATE * speed / (RUN_CONTACT * r.leg)
            u = 4.0 * u * (1.0 - u) if u < 1.0 else 0.0
            sink = u if u > sink else sink
    top = top - RUN_SINK * r.leg * run * sink
    y = top
    feet = list(placed)
    for i in (0, 1):
        f = feet[i]
        if f.planted:
            hx, hy, hz = r.hip[i]
            feet[i] = f._replace(pitch=_heel(r, f, (b[0] + c * hx + s * hz, top + hy, b[2] - s * hx + c * hz)))
    low = _floor(state)
    for i in (0, 1):
        f = feet[i]
        if f.planted:
            h = _reach_height(state, i, _ankle(r, f))
        else:                          # a swing lets the hips up from where it lifted, then down to where it lands
            e = 2.0 * f.progress
            if e < 1.0:
                h = f.lift_height
                e = e * e * (3.0 - 2.0 * e)
            else:
                h = _reach_height(state, i, _ankle(r, f))
                e = 2.0 - e
                e = 0.0 if e < 0.0 else e * e * (3.0 - 2.0 * e)
            h = low if h < low else h
            h = top if h > top else h
            h = h + (top - h) * e
        h = low if h < low else h
        y = h if h < y else y
    q = [(0.0, 0.0, 0.0, 1.0)] * r.joints
    half = 0.5 * state.heading
    sh, ch = math.sin(half), math.cos(half)
    q[r.index[0]] = (0.0, sh, 0.0, ch)
    hips = ((c, 0.0, -s), (0.0, 1.0, 0.0), (s, 0.0, c))     # the hips' frame: its x, y, z axes
    forward = [0.0, 0.0]
    for i in (0, 1):
        f = feet[i]
        hx, hy, hz = r.hip[i]
        joint = (b[0] + c * hx + s * hz, y + hy, b[2] - s * hx + c * hz)
        # The knee bends toward the foot's forward and the body's (the body's alone if opposite).
        px, pz = math.sin(f.yaw) + s, math.cos(f.yaw) + c
        if px * px + pz * pz < 0.01:
            px, pz = s, c
        thigh, shin = two_bone(joint, _ankle(r, f), r.thigh, r.shin, (px, 0.0, pz))
        q[r.index[6 + i]] = frame_quaternion(local_frame(hips, thigh))
        q[r.index[8 + i]] = frame_quaternion(local_frame(thigh, shin))
        q[r.index[10 + i]] = frame_quaternion(local_frame(shin, _foot(f.yaw, f.pitch)))
        forward[i] = (f.ankle[0] - b[0]) * s + (f.ankle[2] - b[2]) * c
    lean = LEAN_REST + LEAN_SPEED * speed
    lean = LEAN_MAX if lean > LEAN_MAX else lean
    q[r.index[1]] = (math.sin(0.5 * lean), 0.0, 0.0, math.cos(0.5 * lean))
    elbow = ELBOW_WALK + (ELBOW_RUN - ELBOW_WALK) * run
    for i in (0, 1):
        swing = ARM_SWING * (forward[1 - i] - forward[i]) / r.leg
        swing = ARM_MAX if swing > ARM_MAX else -ARM_MAX if swing < -ARM_MAX else swing
        q[r.index[2 + i]] = (-math.sin(0.5 * swing), 0.0, 0.0, math.cos(0.5 * swing))
        q[r.index[4 + i]] = (-math.sin(0.5 * elbow), 0.0, 0.0, math.cos(0.5 * elbow))
    return WalkState(r, state.tick, b, state.velocity, state.heading, (feet[0], feet[1]), state.marker,
                     state.behind_since, state.behind_speed, np.array(q), np.array((b[0], y, b[2])))


def _foot(yaw: float, pitch: float) -> Frame:
    """A foot's world frame: at ``yaw``, its heel risen ``pitch`` (rad)."""
    s, c = math.sin(yaw), math.cos(yaw)
    sp, cp = math.sin(pitch), math.cos(pitch)
    return (c, 0.0, -s), (sp * s, cp, sp * c), (cp * s, -sp, cp * c)


def walk(skeleton: Skeleton, markers: object) -> Walk:
    """The walk of ``skeleton`` following ``markers`` (n, 3): the marker at each tick
    ``k / RATE`` (its y the ground height).

    >>> path = np.c_[np.zeros(600), np.zeros(600), np.minimum(np.arange(600), 240) * 1.4 / RATE]
    >>> w = walk(humanoid(), path)
    >>> w.rotations.shape, w.stance[-1].tolist(), w.behind
    ((600, 21, 4), [True, True], [])
    """
    m = np.asarray(markers, dtype=float)
    if m.ndim != 2 or m.shape[1] != 3 or len(m) == 0:
        raise ArgumentError("markers", f"must be (n, 3) with n >= 1, got shape {m.shape}")
    bad = np.flatnonzero(~np.isfinite(m).all(axis=1))
    if len(bad):
        raise ArgumentError("markers", f"marker {bad[0]} is not finite")
    n = len(m)
    rows = m.tolist()
    state = start(skeleton, rows[0])
    rotations = np.empty((n, len(skeleton), 4))
    root = np.empty((n, 3))
    stance = np.empty((n, 2), bool)
    behind: list[tuple[float, float, float]] = []
    for k in range(n):
        if k:
            previous = state
            state = advance(state, rows[k])
            if previous.behind_since >= 0 and state.behind_since < 0:
                behind.append((previous.behind_since / RATE, (k - 1) / RATE, previous.behind_speed))
        rotations[k], root[k], stance[k] = state.rotations, state.root, state.stance
    if state.behind_since >= 0:
        behind.append((state.behind_since / RATE, (n - 1) / RATE, state.behind_speed))
    return Walk(rotations, root, stance, behind)
