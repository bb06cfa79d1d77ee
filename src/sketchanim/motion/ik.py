"""Inverse kinematics of an articulated chain: its pose derived from a goal, tick by tick.

A chain's frame: its base at the origin; at rest (every local rotation identity) it points
straight up +y; joint i sits at the start of segment i, its segment along its local +y,
``lengths[i]`` long; the effector is the end of the last segment. A hinge turns about its
local x axis only, a ball freely; ``limits[i]`` is the most joint i's rotation angle may be
(a hinge's angle is in ``[-limit, limit]``). A pose is each joint's local rotation, a
quaternion scalar-last ``(x, y, z, w)``, shape ``(J, 4)``.

The pose is a deterministic simulation at :data:`RATE` ticks per second from the start
pose (:func:`rest`): the caller samples the goal at ticks ``k / RATE`` and each tick
(:func:`step`) is solved from the one before, so the pose is a pure function of the goal's
curve and continuous in time. A tick is :data:`ITERATIONS` iterations of damped least
squares on the 3 x m position Jacobian (Maciejewski 1990, the paper's [26]):

- the tick's target is the goal, but at most the goal's own step plus :data:`CATCH_UP`
  reaches per second from the effector, and no farther out than the reach; the effector
  never moves farther in a tick (a tick that would, from the solver's second-order motion,
  is pulled back toward its start by bisection);
- the error is clamped to :data:`STEP` reaches per iteration (Buss);
- the 3 x 3 ``J J^T`` is diagonalised by cyclic Jacobi; each singular direction whose
  singular value ``s`` is below ``EPS`` reaches is damped by ``DAMPING^2 (1 - (s / EPS)^2)``
  (Nakamura and Hanafusa's schedule, direction by direction, so that a chain that cannot
  move one way at all, a planar one, is still undamped in the others);
- a bias ``z = -BIAS * (coordinates - rest coordinates)`` in the null space: ``dq = z +
  J^T y``, ``y`` the damped solution for the error minus the solution for ``J z`` (damped
  by only ``PROJECTED`` of it while the goal is in reach, so reachable goals are reached
  exactly while the redundant freedom relaxes toward rest); from 1 to ``1 + BAND`` reaches
  out the bias turns to straight, with the full damping, and the base's bias fades out, so
  a goal out of reach gets a straight chain pointing at it;
- every joint turns at most :data:`MAX_TURN` per iteration (the whole update scaled);
- a joint the update would take past its limit is held and the update solved again without
  it (once); then every limit is clamped (the rotation angle brought back about its axis).

The straight pose is singular along the chain (a goal straight below the tip cannot be
reached from it by the Jacobian alone): the rest pose is slightly bent (:data:`CURL` in all,
shared by the joints after the base), and the bias toward that bend is not cancelled along a
singular direction, so a straight chain bends again as soon as its goal comes back in.

The page runs the same algorithm (``studio/web/js/ik.js``), operation for operation, with
no library trigonometry, so both agree to the bit (tests/motion/test_ik.py checks 1e-6 rad).
Plain floats: for 8 joints they are faster than numpy's small-array calls
(benchmarks/bench_ik.py). docs/rigs.md describes the model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike

from sketchanim.errors import ArgumentError

#: Ticks per second of every derived pose (chains and walkers).
RATE: float = 120.0

#: Iterations of damped least squares per tick.
ITERATIONS = 3
#: Jacobi sweeps over the 3 x 3 ``J J^T`` (4 are machine precision for a 3 x 3).
SWEEPS = 4
#: An off-diagonal entry this small against its diagonal ones is not rotated away.
NEGLIGIBLE = 1e-18
#: The rest pose's bend (radians), shared by the joints after the base: never straight.
CURL = 0.2
#: How fast (reaches per second) the effector may move beyond the goal's own step.
CATCH_UP = 2.0
#: The error clamp per iteration, in reaches.
STEP = 0.1
#: The most a joint turns per iteration (radians).
MAX_TURN = 0.1
#: Singular values below this (in reaches) are damped.
EPS = 0.05
#: The damping at a zero singular value (in reaches).
DAMPING = 0.05
#: The rest bias's gain per iteration.
BIAS = 0.05
#: Goals from 1 to ``1 + BAND`` reaches out turn the rest bias from the rest bend to straight.
BAND = 0.05
#: The share of the damping the bias's projection keeps while the goal is in reach.
PROJECTED = 1e-4
#: Bisection steps pulling a tick back that would move the effector beyond its allowance.
BACKOFF = 12

#: The most joints a chain has (the scene's slots).
MAX_JOINTS = 8


@dataclass(frozen=True)
class Chain:
    """An articulated chain: 2 to 8 segments, each with the joint at its start.

    Parameters
    ----------
    lengths : tuple of float
        Segment lengths, each > 0 (scene units).
    limits : tuple of float
        Each joint's largest rotation angle from rest, radians in (0, pi].
    hinges : tuple of bool
        Each joint a hinge (about its local x axis) or a ball.

    Examples
    --------
    >>> Chain((1.0, 0.5), (math.pi, 0.5), (False, True)).lengths
    (1.0, 0.5)
    >>> Chain((1.0,), (1.0,), (False,))
    Traceback (most recent call last):
    sketchanim.errors.ArgumentError: lengths: a chain has 2 to 8 segments, got 1
    """

    lengths: tuple[float, ...]
    limits: tuple[float, ...]
    hinges: tuple[bool, ...]

    def __post_init__(self) -> None:
        # Plain floats and bools whatever the caller passed (numpy scalars behave otherwise).
        object.__setattr__(self, "lengths", tuple(float(x) for x in self.lengths))
        object.__setattr__(self, "limits", tuple(float(x) for x in self.limits))
        object.__setattr__(self, "hinges", tuple(bool(x) for x in self.hinges))
        n = len(self.lengths)
        if not 2 <= n <= MAX_JOINTS:
            raise ArgumentError("lengths", f"a chain has 2 to {MAX_JOINTS} segments, got {n}")
        if len(self.limits) != n or len(self.hinges) != n:
            raise ArgumentError("limits", f"one limit and one hinge flag per joint ({n}), got "
                                          f"{len(self.limits)} and {len(self.hinges)}")
        for i, (length, limit) in enumerate(zip(self.lengths, self.limits)):
            if not (math.isfinite(length) and length > 0):
                raise ArgumentError("lengths", f"segment {i} is {length}, not a finite length > 0")
            if not 0 < limit <= math.pi:
                raise ArgumentError("limits", f"joint {i} is {limit} rad, not in (0, pi]")

    @classmethod
    def from_slots(cls, lengths: ArrayLike, limits_degrees: ArrayLike, hinges: ArrayLike) -> Chain:
        """The chain of the scene's encoding (``anim/scene.py`` ``KINDS["chain"]``).

        Parameters
        ----------
        lengths, limits_degrees, hinges : array_like, shape (slots,)
            The same number of slots each (the scene has 8); every entry finite and >= 0.
            The chain is the leading slots of positive length (2 to 8 of them); limits in
            degrees, in (0, 180] for those joints; a hinge where its entry is > 0.5.

        Raises
        ------
        ArgumentError
            Naming the field: a negative or NaN entry, fewer than 2 leading positive
            lengths, a used joint's limit outside (0, 180], slots of different counts.

        Examples
        --------
        >>> c = Chain.from_slots([0.5, 0.4, 0, 0], [90, 180, 150, 150], [0, 1, 0, 0])
        >>> c.lengths, [round(x, 4) for x in c.limits], c.hinges
        ((0.5, 0.4), [1.5708, 3.1416], (False, True))
        """
        fields = {"lengths": lengths, "limits": limits_degrees, "hinges": hinges}
        arrays = {name: np.asarray(v, dtype=float) for name, v in fields.items()}
        slots = arrays["lengths"].shape
        for name, values in arrays.items():
            if values.ndim != 1 or values.shape != slots:
                raise ArgumentError(name, f"needs {slots[0] if len(slots) == 1 else 'n'} slots as lengths, "
                                          f"got shape {values.shape}")
            bad = np.flatnonzero(~np.isfinite(values) | (values < 0))
            if bad.size:
                raise ArgumentError(name, f"slot {bad[0]} is {values[bad[0]]}, not a finite number >= 0")
        length = arrays["lengths"]
        n = int(np.argmin(length > 0)) if (length <= 0).any() else len(length)
        if not 2 <= n <= MAX_JOINTS:
            raise ArgumentError("lengths", f"a chain is 2 to {MAX_JOINTS} leading positive lengths, got {n}")
        degrees = arrays["limits"][:n]
        bad = np.flatnonzero(~((degrees > 0) & (degrees <= 180)))
        if bad.size:
            raise ArgumentError("limits", f"joint {bad[0]} is {degrees[bad[0]]} degrees, not in (0, 180]")
        return cls(tuple(float(x) for x in length[:n]), tuple(float(x) * math.pi / 180 for x in degrees),
                   tuple(bool(x > 0.5) for x in arrays["hinges"][:n]))


@dataclass(frozen=True)
class _Prepared:
    """A chain's constants: cos and sin of half each limit (the least ``|w|`` within it and
    the vector part's length at it), the rest pose's bend (x and w), the reach."""

    n: int
    lengths: tuple[float, ...]
    hinge: tuple[bool, ...]
    cos_lim: tuple[float, ...]
    sin_lim: tuple[float, ...]
    rest_x: tuple[float, ...]
    rest_w: tuple[float, ...]
    reach: float


def _half_turn(angle: float) -> tuple[float, float]:
    """cos and sin of half an angle in [0, pi], by their Taylor series to 1e-16 (arithmetic
    alone, so that the page and the model, whose libraries' cos may differ in the last bit,
    agree to the bit: a chain at a bifurcation, folding toward a goal behind it, would
    amplify that bit).

    >>> c, s = _half_turn(math.pi / 2)
    >>> abs(c - math.cos(math.pi / 4)) < 1e-15, abs(s - math.sin(math.pi / 4)) < 1e-15
    (True, True)
    """
    x = 0.5 * angle
    x2 = x * x
    c, s, tc, ts = 1.0, x, 1.0, x
    for k in range(1, 13):
        tc = -tc * x2 / ((2 * k - 1) * (2 * k))
        ts = -ts * x2 / ((2 * k) * (2 * k + 1))
        c += tc
        s += ts
    return c, s


@lru_cache(maxsize=256)
def _prepare(chain: Chain) -> _Prepared:
    n = len(chain.lengths)
    halves = [_half_turn(x) for x in chain.limits]
    rest_x, rest_w = [], []
    reach = 0.0
    for i, length in enumerate(chain.lengths):
        # The rest bend as an update turns a joint (below): by 2 atan(bend / 2), nearly bend.
        h = 0.5 * (0.0 if i == 0 else min(CURL / (n - 1), 0.5 * chain.limits[i]))
        hn = math.sqrt(h * h + 1)
        rest_x.append(h / hn)
        rest_w.append(1 / hn)
        reach += length
    return _Prepared(n, chain.lengths, chain.hinges, tuple(c for c, _ in halves), tuple(s for _, s in halves),
                     tuple(rest_x), tuple(rest_w), reach)


def rest(chain: Chain) -> np.ndarray:
    """The start pose, shape (J, 4): a slight bend about x at each joint after the base
    (about ``CURL`` radians in all, at most half a joint's limit), so that the chain is never
    straight at rest, where the Jacobian is singular along it; the rest bias relaxes to it.

    Examples
    --------
    >>> chain = Chain((1.0, 1.0), (math.pi, math.pi), (False, True))
    >>> rest(chain).round(4).tolist()
    [[0.0, 0.0, 0.0, 1.0], [0.0995, 0.0, 0.0, 0.995]]
    """
    p = _prepare(chain)
    out = np.zeros((p.n, 4))
    out[:, 0] = p.rest_x
    out[:, 3] = p.rest_w
    return out


def _forward(p: _Prepared, q: list[float], pos: list[float], world: list[float]) -> None:
    """Forward kinematics of flat ``q`` into ``pos`` (base, joints, effector) and ``world``."""
    wx = wy = wz = 0.0
    ww = 1.0
    pos[0] = pos[1] = pos[2] = 0.0
    lengths = p.lengths
    for i in range(p.n):
        k = 4 * i
        lx, ly, lz, lw = q[k], q[k + 1], q[k + 2], q[k + 3]
        nx = ww * lx + wx * lw + wy * lz - wz * ly
        ny = ww * ly - wx * lz + wy * lw + wz * lx
        nz = ww * lz + wx * ly - wy * lx + wz * lw
        nw = ww * lw - wx * lx - wy * ly - wz * lz
        wx, wy, wz, ww = nx, ny, nz, nw
        world[k], world[k + 1], world[k + 2], world[k + 3] = wx, wy, wz, ww
        length = lengths[i]
        j = 3 * i
        # The segment (0, length, 0) rotated: the second column of the rotation matrix.
        pos[j + 3] = pos[j] + length * (2 * (wx * wy - ww * wz))
        pos[j + 4] = pos[j + 1] + length * (1 - 2 * (wx * wx + wz * wz))
        pos[j + 5] = pos[j + 2] + length * (2 * (wy * wz + ww * wx))


def _rotate(q: list[float], k: int, inverse: bool, x: float, y: float, z: float) -> tuple[float, float, float]:
    """(x, y, z) rotated by the quaternion at ``q[k:k+4]`` (``inverse``: by its conjugate)."""
    s = -1 if inverse else 1
    ux, uy, uz, w = s * q[k], s * q[k + 1], s * q[k + 2], q[k + 3]
    cx, cy, cz = uy * z - uz * y, uz * x - ux * z, ux * y - uy * x
    return (x + 2 * (w * cx + (uy * cz - uz * cy)),
            y + 2 * (w * cy + (uz * cx - ux * cz)),
            z + 2 * (w * cz + (ux * cy - uy * cx)))


def _givens(aii: float, ajj: float, aij: float) -> tuple[float, float, float]:
    """The Jacobi rotation's tan, cos and sin that zero ``aij`` between ``aii`` and ``ajj``."""
    theta = (ajj - aii) / (2 * aij)
    t = 1 / (abs(theta) + math.sqrt(theta * theta + 1))
    if theta < 0:
        t = -t
    c = 1 / math.sqrt(t * t + 1)
    return t, c, t * c


def _jacobi(a: list[float]) -> list[float]:
    """Eigen-decomposition of the symmetric 3 x 3 ``a`` (row-major, changed in place) by
    cyclic Jacobi, ``SWEEPS`` sweeps over the pairs (0, 1), (0, 2), (1, 2): eigenvalues on
    its diagonal, eigenvectors the columns of the returned 3 x 3. (The page's loop, unrolled:
    the same operations on each entry.)"""
    d0, d1, d2, o01, o02, o12 = a[0], a[4], a[8], a[1], a[2], a[5]
    v00, v01, v02, v10, v11, v12, v20, v21, v22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
    for _ in range(SWEEPS):
        # Negligible already (the same test in the page): the rotation would change nothing.
        if not abs(o01) <= NEGLIGIBLE * (abs(d0) + abs(d1)):
            t, c, s = _givens(d0, d1, o01)
            d0 -= t * o01
            d1 += t * o01
            o01 = 0.0
            o02, o12 = c * o02 - s * o12, s * o02 + c * o12
            v00, v01 = c * v00 - s * v01, s * v00 + c * v01
            v10, v11 = c * v10 - s * v11, s * v10 + c * v11
            v20, v21 = c * v20 - s * v21, s * v20 + c * v21
        if not abs(o02) <= NEGLIGIBLE * (abs(d0) + abs(d2)):
            t, c, s = _givens(d0, d2, o02)
            d0 -= t * o02
            d2 += t * o02
            o02 = 0.0
            o01, o12 = c * o01 - s * o12, s * o01 + c * o12
            v00, v02 = c * v00 - s * v02, s * v00 + c * v02
            v10, v12 = c * v10 - s * v12, s * v10 + c * v12
            v20, v22 = c * v20 - s * v22, s * v20 + c * v22
        if not abs(o12) <= NEGLIGIBLE * (abs(d1) + abs(d2)):
            t, c, s = _givens(d1, d2, o12)
            d1 -= t * o12
            d2 += t * o12
            o12 = 0.0
            o01, o02 = c * o01 - s * o02, s * o01 + c * o02
            v01, v02 = c * v01 - s * v02, s * v01 + c * v02
            v11, v12 = c * v11 - s * v12, s * v11 + c * v12
            v21, v22 = c * v21 - s * v22, s * v21 + c * v22
    a[0], a[4], a[8] = d0, d1, d2
    a[1] = a[3] = o01
    a[2] = a[6] = o02
    a[5] = a[7] = o12
    return [v00, v01, v02, v10, v11, v12, v20, v21, v22]


def _clamp(p: _Prepared, q: list[float], i: int) -> None:
    """Hold joint i of ``q`` within its limit: a rotation angle past it is brought back to
    it about the same axis (a hinge's x keeps its sign). Joints start each tick with w >= 0
    (rotation angles up to pi), so a w pushed below cos(limit / 2), even below 0 (an update
    that carried a limit near pi past pi), is brought back on the side the joint came from."""
    k = 4 * i
    w = q[k + 3]
    c = p.cos_lim[i]
    if w >= c:
        return
    x, y, z = q[k], q[k + 1], q[k + 2]
    f = p.sin_lim[i] / math.sqrt(x * x + y * y + z * z)
    q[k], q[k + 1], q[k + 2] = x * f, y * f, z * f
    q[k + 3] = c


def _dls(p: _Prepared, dx: float, dy: float, dz: float, cols: list[float], bias: list[float],
         skip: list[bool], turn: list[float], keep: float) -> float:
    """The damped least-squares update of every joint not skipped into ``turn`` (a hinge's
    angle, a ball's world rotation vector; skipped joints their bias alone) for the error
    (dx, dy, dz);
    returns the factor that holds every joint's turn to ``MAX_TURN``."""
    n, reach, hinge = p.n, p.reach, p.hinge
    a0 = a1 = a2 = a4 = a5 = a8 = 0.0
    jx = jy = jz = 0.0                  # J z: the rest bias's effector motion
    for i in range(n):
        j = 3 * i
        cx, cy, cz = cols[j], cols[j + 1], cols[j + 2]
        bx, by, bz = bias[j], bias[j + 1], bias[j + 2]
        if hinge[i]:
            if not skip[i]:
                a0 += cx * cx
                a1 += cx * cy
                a2 += cx * cz
                a4 += cy * cy
                a5 += cy * cz
                a8 += cz * cz
            jx += bx * cx
            jy += bx * cy
            jz += bx * cz
        else:
            if not skip[i]:
                # Its three world-axis columns w x r (r = cols) give |r|^2 I - r r^T.
                rr = cx * cx + cy * cy + cz * cz
                a0 += rr - cx * cx
                a1 -= cx * cy
                a2 -= cx * cz
                a4 += rr - cy * cy
                a5 -= cy * cz
                a8 += rr - cz * cz
            jx += by * cz - bz * cy
            jy += bz * cx - bx * cz
            jz += bx * cy - by * cx
    a = [a0, a1, a2, a1, a4, a5, a2, a5, a8]
    v = _jacobi(a)
    eps2 = EPS * reach * EPS * reach
    damp2 = DAMPING * reach * DAMPING * reach
    # The bias's own motion is taken out with less damping (PROJECTED of it) while the goal
    # is in reach, so that it does not pull a reachable goal's effector off it; with all of
    # it beyond, so that the bias straightens a chain the error alone barely can (singular).
    projected = PROJECTED + (1 - PROJECTED) * (1 - keep)
    yx = yy = yz = 0.0
    for m in range(3):
        s = max(a[4 * m], 0.0)
        lambda2 = damp2 * (1 - s / eps2) if s < eps2 else 0.0
        ux, uy, uz = v[m], v[3 + m], v[6 + m]
        g = (ux * dx + uy * dy + uz * dz) / (s + lambda2) - (ux * jx + uy * jy + uz * jz) / (s + projected * lambda2)
        yx += g * ux
        yy += g * uy
        yz += g * uz
    most = 0.0
    for i in range(n):
        j = 3 * i
        cx, cy, cz = cols[j], cols[j + 1], cols[j + 2]
        if skip[i]:
            # A joint held at its limit still relaxes by its bias (toward rest: inward), the
            # others making up for its motion.
            bx, by, bz = bias[j], bias[j + 1], bias[j + 2]
            turn[j], turn[j + 1], turn[j + 2] = bx, by, bz
            most = max(most, math.sqrt(bx * bx + by * by + bz * bz))
        elif hinge[i]:
            d = bias[j] + (cx * yx + cy * yy + cz * yz)
            turn[j] = d
            most = max(most, abs(d))
        else:
            # J^T y for a ball: r x y.
            ox = bias[j] + (cy * yz - cz * yy)
            oy = bias[j + 1] + (cz * yx - cx * yz)
            oz = bias[j + 2] + (cx * yy - cy * yx)
            turn[j], turn[j + 1], turn[j + 2] = ox, oy, oz
            most = max(most, math.sqrt(ox * ox + oy * oy + oz * oz))
    return MAX_TURN / most if most > MAX_TURN else 1


def _turned(p: _Prepared, q: list[float], world: list[float], i: int, scale: float, turn: list[float],
            out: list[float]) -> None:
    """Joint i of ``q`` turned by ``scale * turn`` (not yet held to its limit) into ``out``."""
    k, j = 4 * i, 3 * i
    x, y, z, w = q[k], q[k + 1], q[k + 2], q[k + 3]
    if p.hinge[i]:
        h = 0.5 * scale * turn[j]
        hn = math.sqrt(h * h + 1)
        hx, hw = h / hn, 1 / hn
        nx, nw = hx * w + hw * x, hw * w - hx * x
        norm = math.sqrt(nx * nx + nw * nw)
        out[k], out[k + 1], out[k + 2], out[k + 3] = nx / norm, 0.0, 0.0, nw / norm
        return
    # The world turn in the parent's frame, then applied on the left of the local rotation.
    ox, oy, oz = scale * turn[j], scale * turn[j + 1], scale * turn[j + 2]
    if i > 0:
        ox, oy, oz = _rotate(world, k - 4, True, ox, oy, oz)
    hx0, hy0, hz0 = 0.5 * ox, 0.5 * oy, 0.5 * oz
    hn = math.sqrt(hx0 * hx0 + hy0 * hy0 + hz0 * hz0 + 1)
    hx, hy, hz, hw = hx0 / hn, hy0 / hn, hz0 / hn, 1 / hn
    nx = hw * x + hx * w + hy * z - hz * y
    ny = hw * y - hx * z + hy * w + hz * x
    nz = hw * z + hx * y - hy * x + hz * w
    nw = hw * w - hx * x - hy * y - hz * z
    norm = math.sqrt(nx * nx + ny * ny + nz * nz + nw * nw)
    out[k], out[k + 1], out[k + 2], out[k + 3] = nx / norm, ny / norm, nz / norm, nw / norm


def _iterate(p: _Prepared, q: list[float], pos: list[float], world: list[float],
             tx: float, ty: float, tz: float, keep: float) -> None:
    """One damped least-squares iteration of ``q`` (in place) toward (tx, ty, tz); ``keep``
    is how much of the rest bend the bias keeps (1 all, 0 straight). A joint the update
    would take past its limit is held (moved by its rest bias alone) and the update solved
    again without it (once), so the others make up for it rather than pushing it in vain."""
    n, hinge, rest_x = p.n, p.hinge, p.rest_x
    _forward(p, q, pos, world)
    ex, ey, ez = pos[3 * n], pos[3 * n + 1], pos[3 * n + 2]
    dx, dy, dz = tx - ex, ty - ey, tz - ez
    dn = math.sqrt(dx * dx + dy * dy + dz * dz)
    if dn > STEP * p.reach:
        f = STEP * p.reach / dn
        dx *= f
        dy *= f
        dz *= f
    cols = [0.0] * (3 * n)
    bias = [0.0] * (3 * n)
    for i in range(n):
        j, k = 3 * i, 4 * i
        rx, ry, rz = ex - pos[j], ey - pos[j + 1], ez - pos[j + 2]
        # The base points the chain: it is not biased upright when the goal is out of reach.
        gain = -BIAS * keep if i == 0 else -BIAS
        if hinge[i]:
            wx, wy, wz, ww = world[k], world[k + 1], world[k + 2], world[k + 3]
            # The hinge's world axis: the first column of its world rotation; its column a x r.
            ax, ay, az = 1 - 2 * (wy * wy + wz * wz), 2 * (wx * wy + ww * wz), 2 * (wx * wz - ww * wy)
            cols[j], cols[j + 1], cols[j + 2] = ay * rz - az * ry, az * rx - ax * rz, ax * ry - ay * rx
            bias[j] = gain * (2 * q[k] - keep * 2 * rest_x[i])
        else:
            cols[j], cols[j + 1], cols[j + 2] = rx, ry, rz
            lx = gain * (2 * q[k] - keep * 2 * rest_x[i])
            ly = gain * (2 * q[k + 1])
            lz = gain * (2 * q[k + 2])
            if i == 0:
                # Out of reach, a ball base keeps the bias on its twist about its own segment
                # (which does not move a straight chain's effector), so no twist from the swing
                # there stays to make its rotation angle larger than pointing needs.
                l0 = p.lengths[0]
                ax, ay, az = pos[3] / l0, pos[4] / l0, pos[5] / l0
                twist = -BIAS * (1 - keep) * (2 * q[0] * ax + 2 * q[1] * ay + 2 * q[2] * az)
                bias[0], bias[1], bias[2] = lx + twist * ax, ly + twist * ay, lz + twist * az
            else:
                bias[j], bias[j + 1], bias[j + 2] = _rotate(world, k - 4, False, lx, ly, lz)
    skip = [False] * n
    turn = [0.0] * (3 * n)
    trial = [0.0] * (4 * n)
    scale = _dls(p, dx, dy, dz, cols, bias, skip, turn, keep)
    held = False
    for i in range(n):
        _turned(p, q, world, i, scale, turn, trial)
        if trial[4 * i + 3] < p.cos_lim[i]:
            skip[i] = True
            held = True
    if held:
        scale = _dls(p, dx, dy, dz, cols, bias, skip, turn, keep)
        for i in range(n):
            _turned(p, q, world, i, scale, turn, trial)
    q[:] = trial
    for i in range(n):
        _clamp(p, q, i)


def _blend(p: _Prepared, start: list[float], end: list[float], t: float, out: list[float]) -> None:
    """Each joint's rotation a fraction ``t`` of the way from ``start`` to ``end``
    (normalised linear interpolation on the shorter arc: within the limits both are in)."""
    for i in range(p.n):
        k = 4 * i
        dot = start[k] * end[k] + start[k + 1] * end[k + 1] + start[k + 2] * end[k + 2] + start[k + 3] * end[k + 3]
        u = -t if dot < 0 else t
        x = (1 - t) * start[k] + u * end[k]
        y = (1 - t) * start[k + 1] + u * end[k + 1]
        z = (1 - t) * start[k + 2] + u * end[k + 2]
        w = (1 - t) * start[k + 3] + u * end[k + 3]
        norm = math.sqrt(x * x + y * y + z * z + w * w)
        out[k], out[k + 1], out[k + 2], out[k + 3] = x / norm, y / norm, z / norm, w / norm


def _pull_back(p: _Prepared, start: list[float], out: list[float], pos: list[float], world: list[float],
               sx: float, sy: float, sz: float, allowance: float) -> None:
    """Where the tick moved the effector farther than ``allowance`` from (sx, sy, sz) (the
    solver's second-order motion may), bring ``out`` back toward ``start`` by bisection."""
    n = p.n
    _forward(p, out, pos, world)
    fx, fy, fz = pos[3 * n] - sx, pos[3 * n + 1] - sy, pos[3 * n + 2] - sz
    if math.sqrt(fx * fx + fy * fy + fz * fz) <= allowance:
        return
    end = list(out)
    low, high = 0.0, 1.0
    for _ in range(BACKOFF):
        t = 0.5 * (low + high)
        _blend(p, start, end, t, out)
        _forward(p, out, pos, world)
        ox, oy, oz = pos[3 * n] - sx, pos[3 * n + 1] - sy, pos[3 * n + 2] - sz
        if math.sqrt(ox * ox + oy * oy + oz * oz) <= allowance:
            low = t
        else:
            high = t
    _blend(p, start, end, low, out)


def _advance(p: _Prepared, pose: list[float], gx: float, gy: float, gz: float,
             gx0: float, gy0: float, gz0: float) -> list[float]:
    """One tick of a prepared chain: the flat pose after ``pose`` for goal (gx, gy, gz),
    (gx0, gy0, gz0) the goal a tick before."""
    n, reach = p.n, p.reach
    pos = [0.0] * (3 * n + 3)
    world = [0.0] * (4 * n)
    # Unit quaternions with w >= 0: a joint's coordinates (twice the vector part) and its
    # limit test (w >= cos(limit / 2)) read the rotation angle from 0 to pi.
    start = [0.0] * (4 * n)
    for k in range(0, 4 * n, 4):
        x, y, z, w = pose[k], pose[k + 1], pose[k + 2], pose[k + 3]
        f = (-1 if w < 0 else 1) / math.sqrt(x * x + y * y + z * z + w * w)
        start[k], start[k + 1], start[k + 2], start[k + 3] = x * f, y * f, z * f, w * f
    _forward(p, start, pos, world)
    sx, sy, sz = pos[3 * n], pos[3 * n + 1], pos[3 * n + 2]
    mx, my, mz = gx - gx0, gy - gy0, gz - gz0
    allowance = math.sqrt(mx * mx + my * my + mz * mz) + CATCH_UP * reach / RATE
    dx, dy, dz = gx - sx, gy - sy, gz - sz
    dn = math.sqrt(dx * dx + dy * dy + dz * dz)
    if dn > allowance:
        f = allowance / dn
        dx *= f
        dy *= f
        dz *= f
    tx, ty, tz = sx + dx, sy + dy, sz + dz
    # A target out of reach is brought onto the reach's sphere (no nearer to the effector:
    # the ball is convex), where the straight chain pointing at it ends: the error the solver
    # sees is then one it can remove, not one that makes it overshoot straight and back.
    tn = math.sqrt(tx * tx + ty * ty + tz * tz)
    if tn > reach:
        f = reach / tn
        tx *= f
        ty *= f
        tz *= f
    far = (math.sqrt(gx * gx + gy * gy + gz * gz) - reach) / (BAND * reach)
    keep = 1 - min(max(far, 0.0), 1.0)
    out = list(start)
    for _ in range(ITERATIONS):
        _iterate(p, out, pos, world, tx, ty, tz, keep)
    _pull_back(p, start, out, pos, world, sx, sy, sz, allowance)
    return out


def _pose_list(p: _Prepared, pose: ArrayLike) -> list[float]:
    q = np.asarray(pose, dtype=float)
    if q.shape != (p.n, 4) or not np.isfinite(q).all():
        raise ArgumentError("pose", f"needs ({p.n}, 4) finite quaternions, got shape {q.shape}")
    norms = np.sqrt(np.sum(q * q, axis=1))
    if (norms < 1e-6).any():
        raise ArgumentError("pose", f"joint {int(np.argmax(norms < 1e-6))} is not a rotation (norm {norms.min():.3g})")
    return q.ravel().tolist()


def _goal(name: str, goal: ArrayLike) -> list[float]:
    g = np.asarray(goal, dtype=float)
    if g.shape != (3,) or not np.isfinite(g).all():
        raise ArgumentError(name, f"needs 3 finite numbers, got {g.tolist()}")
    return g.tolist()


def step(chain: Chain, pose: ArrayLike, goal: ArrayLike, previous: ArrayLike | None = None) -> np.ndarray:
    """One tick: the pose after ``pose`` for ``goal``.

    Parameters
    ----------
    chain : Chain
    pose : array_like, shape (J, 4)
        Local rotations, scalar-last, within the limits (either sign; normalised here).
    goal : array_like, shape (3,)
        The goal in the chain's base frame (world goal minus the base's position).
    previous : array_like, shape (3,), optional
        The goal a tick before (default: ``goal``, the goal has not moved).

    Returns
    -------
    numpy.ndarray, shape (J, 4)
        Unit quaternions with ``w >= 0``. The effector has moved at most
        ``|goal - previous| + CATCH_UP * reach / RATE``; each joint has turned at most
        ``ITERATIONS * MAX_TURN``; the limits hold.

    Examples
    --------
    >>> chain = Chain((1.0, 1.0), (math.pi, math.pi), (False, True))
    >>> pose = rest(chain)
    >>> for _ in range(200):
    ...     pose = step(chain, pose, [1.0, 1.0, 0.0])
    >>> points(chain, pose)[-1].round(6).tolist() == [1.0, 1.0, 0.0]
    True
    """
    p = _prepare(chain)
    g = _goal("goal", goal)
    g0 = g if previous is None else _goal("previous", previous)
    return np.array(_advance(p, _pose_list(p, pose), *g, *g0)).reshape(p.n, 4)


def solve(chain: Chain, goals: ArrayLike) -> np.ndarray:
    """The pose at every tick of a goal path, each tick stepped from the one before, the
    first from :func:`rest` (its goal a tick before taken as itself).

    Parameters
    ----------
    chain : Chain
    goals : array_like, shape (n, 3)
        The goal at ticks ``k / RATE`` in the chain's base frame.

    Returns
    -------
    numpy.ndarray, shape (n, J, 4)
        Local rotations, scalar-last.

    Examples
    --------
    >>> chain = Chain((1.0, 1.0), (math.pi, math.pi), (False, True))
    >>> poses = solve(chain, np.tile([0.0, 2.5, 0.0], (240, 1)))
    >>> poses.shape, points(chain, poses[-1])[-1].round(3).tolist()
    ((240, 2, 4), [0.0, 2.0, 0.0])
    """
    p = _prepare(chain)
    g = np.asarray(goals, dtype=float)
    if g.ndim != 2 or g.shape[1] != 3:
        raise ArgumentError("goals", f"needs shape (n, 3), got {g.shape}")
    bad = np.flatnonzero(~np.isfinite(g).all(axis=1))
    if bad.size:
        raise ArgumentError("goals", f"tick {bad[0]} is not finite")
    out = np.empty((len(g), p.n, 4))
    pose = rest(chain).ravel().tolist()
    rows = g.tolist()
    before = rows[0] if rows else None
    for k, here in enumerate(rows):
        pose = _advance(p, pose, here[0], here[1], here[2], before[0], before[1], before[2])
        out[k] = np.reshape(pose, (p.n, 4))
        before = here
    return out


def points(chain: Chain, pose: ArrayLike) -> np.ndarray:
    """Forward kinematics: the base, each joint and the effector in the chain's base frame.

    Parameters
    ----------
    chain : Chain
    pose : array_like, shape (..., J, 4)
        Local rotations, scalar-last (any batch shape in front).

    Returns
    -------
    numpy.ndarray, shape (..., J + 1, 3)

    Examples
    --------
    >>> chain = Chain((1.0, 0.5), (math.pi, math.pi), (False, True))
    >>> quarter = [math.sin(math.pi / 4), 0.0, 0.0, math.cos(math.pi / 4)]
    >>> points(chain, [[0.0, 0.0, 0.0, 1.0], quarter]).round(12).tolist()
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.5]]
    """
    p = _prepare(chain)
    q = np.asarray(pose, dtype=float)
    if q.shape[-2:] != (p.n, 4):
        raise ArgumentError("pose", f"needs shape (..., {p.n}, 4), got {q.shape}")
    out = np.zeros(q.shape[:-2] + (p.n + 1, 3))
    w = np.zeros(q.shape[:-2] + (4,))
    w[..., 3] = 1.0
    for i in range(p.n):
        wx, wy, wz, ww = w[..., 0], w[..., 1], w[..., 2], w[..., 3]
        lx, ly, lz, lw = q[..., i, 0], q[..., i, 1], q[..., i, 2], q[..., i, 3]
        w = np.stack([ww * lx + wx * lw + wy * lz - wz * ly,
                      ww * ly - wx * lz + wy * lw + wz * lx,
                      ww * lz + wx * ly - wy * lx + wz * lw,
                      ww * lw - wx * lx - wy * ly - wz * lz], axis=-1)
        wx, wy, wz, ww = w[..., 0], w[..., 1], w[..., 2], w[..., 3]
        length = p.lengths[i]
        out[..., i + 1, 0] = out[..., i, 0] + length * (2 * (wx * wy - ww * wz))
        out[..., i + 1, 1] = out[..., i, 1] + length * (1 - 2 * (wx * wx + wz * wz))
        out[..., i + 1, 2] = out[..., i, 2] + length * (2 * (wy * wz + ww * wx))
    return out
