"""Orientation channels: quaternion curves with an angular tolerance, and Euler angles.

A quaternion channel is reduced to a B-spline of its four components whose value,
normalised, stays within ``tol_deg`` (the geodesic rotation angle) of every sample at
its own time. That is the curve a glTF CUBICSPLINE rotation sampler plays (cubic in each
component, then normalised), so exporting it is exact. The paper's Euler mode is here
too: angles unwrapped (no 2 pi jumps), each axis within ``tol_deg``.

Components stay in the caller's order, scalar-last ``(x, y, z, w)`` as scipy's
``Rotation`` by default; the angle bound does not depend on the order, which only
matters for converting to Euler angles (``scalar_first=True`` for ``(w, x, y, z)``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline
from scipy.sparse.linalg import spsolve
from scipy.spatial.transform import Rotation

from sketchanim.errors import ArgumentError, SampleError
from sketchanim.reducer import FeatureOptions, Piece, Reduction, StreamReducer, reduce
from sketchanim.reducer.stream import StreamStats
from sketchanim.reducer.conditioning import check_tolerance
from sketchanim.reducer.linear_keys import played_at
from sketchanim.reducer.metric import rotation_angle
from sketchanim.spline.knots import insert_knots

#: What a rotation channel is reduced as.
ROTATION_MODES = ("quaternion", "euler")

#: Quaternions shorter than this are not rotations (a zero or corrupt sample).
MIN_NORM = 1e-6


def _quaternion_array(quats: ArrayLike, offset: int = 0) -> tuple[np.ndarray, SampleError | None]:
    """Rows of ``quats`` up to the first that is not a rotation, and that row's error."""
    q = np.asarray(quats, dtype=float)
    if q.ndim != 2 or q.shape[1] != 4:
        raise ArgumentError("quats", f"needs shape (n, 4), got {q.shape}")
    # Column by column, so that a row's norm does not depend on the rows around it
    # (numpy's reductions may group the sum differently): streams in pieces equal batches.
    norms = np.sqrt(q[:, 0] ** 2 + q[:, 1] ** 2 + q[:, 2] ** 2 + q[:, 3] ** 2)
    bad = np.flatnonzero(~np.isfinite(norms) | (norms < MIN_NORM))
    if not bad.size:
        return q / norms[:, None], None
    i = int(bad[0])
    what = "is not finite" if not np.isfinite(norms[i]) else f"has norm {norms[i]:.3g}, not a rotation"
    return q[:i] / norms[:i, None], SampleError(what, index=offset + i, field="quaternion")


def continuous_quaternions(quats: ArrayLike, *, previous: ArrayLike | None = None) -> np.ndarray:
    """Unit quaternions with their signs chosen so that each is on the same side as the
    one before (``q`` and ``-q`` are one rotation), so the stream has no jumps.

    ``previous`` is the quaternion before the first (to continue a stream).

    >>> q = np.array([[0, 0, 0, 1.0], [0, 0, 0.1, -0.99], [0, 0, 0.2, -0.98]])
    >>> continuous_quaternions(q)[:, 3].round(2)
    array([1.  , 0.99, 0.98])
    """
    q, error = _quaternion_array(quats)
    if error is not None:
        raise error
    return _same_side(q, previous)


def _same_side(q: np.ndarray, previous: ArrayLike | None) -> np.ndarray:
    """Unit quaternions ``q`` with signs flipped where needed to follow ``previous``."""
    if not len(q):
        return q
    before = q[:1] if previous is None else np.asarray(previous, dtype=float).reshape(1, 4)
    flips = np.sum(q * np.vstack([before, q[:-1]]), axis=1) < 0
    sign = np.where(np.cumsum(flips) % 2 == 1, -1.0, 1.0)
    return q * sign[:, None]


def euler_angles(quats: ArrayLike, seq: str = "ZXY", *, scalar_first: bool = False,
                 previous: ArrayLike | None = None) -> np.ndarray:
    """Euler angles (radians, shape (n, 3)) of quaternions, unwrapped along time.

    ``seq`` is scipy's: upper case intrinsic (BVH's ``ZXY`` is ``"ZXY"``), lower case
    extrinsic. ``previous`` (the angles before the first) continues a stream.

    >>> q = Rotation.from_euler("Z", np.radians([[170], [179], [-179], [-170]])).as_quat()
    >>> np.degrees(euler_angles(q, "ZXY")[:, 0]).round(6)
    array([170., 179., 181., 190.])
    """
    q, error = _quaternion_array(quats)
    if error is not None:
        raise error
    return _unwrapped_euler(q, seq, scalar_first, previous)


def _unwrapped_euler(q: np.ndarray, seq: str, scalar_first: bool, previous: ArrayLike | None) -> np.ndarray:
    """Euler angles of unit quaternions ``q``, unwrapped from ``previous``."""
    if not len(q):
        return np.zeros((0, 3))
    try:
        angles = Rotation.from_quat(q, scalar_first=scalar_first).as_euler(seq)
    except ValueError as err:
        raise ArgumentError("seq", f"is not an Euler sequence ({err})") from None
    # Whole turns added to each angle: an integer count, so that a stream unwrapped in
    # pieces gives the same angles, to the bit, as the whole take at once.
    turn = 2.0 * np.pi
    turns = np.zeros_like(angles)
    turns[1:] = np.cumsum(np.round((angles[:-1] - angles[1:]) / turn), axis=0)
    if previous is not None:
        turns += np.round((np.asarray(previous, dtype=float).reshape(1, 3) - angles[:1]) / turn)
    return angles + turn * turns


def _check_mode(mode: str, tol_deg: float) -> float:
    if mode not in ROTATION_MODES:
        raise ArgumentError("mode", f"must be one of {', '.join(ROTATION_MODES)}, got {mode!r}")
    tol = float(check_tolerance(tol_deg, 1)[0])
    if mode == "quaternion" and tol > 180.0:
        raise ArgumentError("tol_deg", f"must be at most 180 degrees, got {tol_deg!r}")
    return np.radians(tol)


def unit_keys(spline: BSpline, times: np.ndarray, quats: np.ndarray, angle: float) -> tuple[BSpline, np.ndarray]:
    """A quaternion spline whose value at every breakpoint has unit norm, still within
    ``angle`` (radians) of every sample, and the angle at each sample.

    Keyframe formats store a curve's values at its breakpoints, and glTF requires a
    rotation key to be a unit quaternion. The smallest change of control points that
    moves each breakpoint's value onto the unit sphere along its own direction (the
    minimum-norm solution of the banded system) changes no key's rotation; between
    keys it may turn the curve slightly, so every sample is checked, and where one
    misses, a knot is inserted (exactly) at its time and the change made again: a
    sample at a breakpoint keeps the rotation the curve had there.

    >>> t = np.linspace(0, 2, 241)
    >>> q = Rotation.from_rotvec(np.c_[np.sin(3 * t), t, 0 * t]).as_quat()
    >>> r = reduce_rotations(t, q, 0.5)
    >>> s, err = unit_keys(r.spline, t, q, np.radians(0.5))
    >>> keys = s(np.unique(s.t))
    >>> bool(np.allclose(np.linalg.norm(keys, axis=1), 1.0)), bool(np.degrees(err.max()) <= 0.5)
    (True, True)
    """
    while True:
        k, knots = spline.k, np.asarray(spline.t)
        breaks = np.unique(knots[k : len(knots) - k])
        basis = BSpline.design_matrix(breaks, knots, k)
        c = np.asarray(spline.c, dtype=float)
        values = basis @ c
        shift = values / np.linalg.norm(values, axis=1, keepdims=True) - values
        moved = c + basis.T @ np.atleast_2d(spsolve((basis @ basis.T).tocsc(), shift)).reshape(len(breaks), -1)
        fixed = BSpline(knots, moved, k)
        err = rotation_angle(fixed(times), quats)
        missed = np.setdiff1d(times[err > angle], breaks)
        if not missed.size:
            return fixed, err
        spline = insert_knots(spline, missed)


def slerped(times: ArrayLike, quats: ArrayLike, at: ArrayLike) -> np.ndarray:
    """Quaternions ``quats`` (n, ..., 4; scalar-last, any norm) keyed at ``times`` (n,
    increasing) as glTF's LINEAR rotation samplers play them at ``at`` (m,): spherically,
    the shorter way, between the keys about each time, held before the first and after
    the last. Unit quaternions (m, ..., 4).

    >>> half = np.radians([0.0, 90.0]) / 2
    >>> q = np.c_[0 * half, 0 * half, np.sin(half), np.cos(half)]
    >>> out = slerped([0.0, 1.0], q, [0.25, 2.0])
    >>> np.degrees(2 * np.arctan2(out[:, 2], out[:, 3])).round(9).tolist()
    [22.5, 90.0]
    """
    q = np.asarray(quats, dtype=float)
    at = np.asarray(at, dtype=float)
    rows = np.moveaxis((q / np.linalg.norm(q, axis=-1, keepdims=True)).reshape(len(q), -1, 4), 0, 1)   # (R, n, 4)
    out = played_at(times, rows, np.ones(rows.shape[:2], bool), at, rotation=True)[:, :, 0]          # spherically
    out = np.moveaxis(out, 0, 1).reshape((len(at),) + q.shape[1:])
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def spherical(spline: BSpline, times: ArrayLike) -> np.ndarray:
    """A quaternion curve of degree 1 played as glTF's LINEAR rotation samplers play it:
    spherically between its values at its breakpoints (its keys), held outside them
    (:func:`slerped`). Unit quaternions (m, 4), scalar-last.

    >>> half = np.radians([0.0, 45.0]) / 2
    >>> s = BSpline([0.0, 0.0, 1.0, 1.0], np.c_[0 * half, 0 * half, np.sin(half), np.cos(half)], 1)
    >>> mid = spherical(s, [0.5])
    >>> round(float(np.degrees(2 * np.arctan2(mid[0, 2], mid[0, 3]))), 9)        # half way round
    22.5
    """
    if spline.k != 1:
        raise ArgumentError("spline", f"is of degree {spline.k}: only straight pieces are played spherically")
    breaks = np.unique(np.asarray(spline.t))
    return slerped(breaks, spline(breaks), times)


def reduce_rotations(times: ArrayLike, quats: ArrayLike, tol_deg: float, *, scalar_first: bool = False,
                     mode: str = "quaternion", seq: str = "ZXY", method: str = "global", order: int = 4,
                     window: int = 20, features: bool | FeatureOptions = True, keys: bool = False) -> Reduction:
    """Reduce an orientation channel, keeping every sample's rotation within ``tol_deg``.

    Parameters
    ----------
    times : array_like, shape (n,)
        Sample times in seconds, increasing.
    quats : array_like, shape (n, 4)
        Quaternions, scalar-last ``(x, y, z, w)`` unless ``scalar_first``; any norm and
        either sign (they are normalised and made continuous).
    tol_deg : float
        Quaternion mode: the largest rotation angle, in degrees, between the curve's
        normalised value and each sample. Euler mode: the tolerance of each angle.
    mode : {"quaternion", "euler"}
        A quaternion B-spline (evaluates to (m, 4) in the caller's component order,
        before normalisation), or the paper's unwrapped Euler angles in radians
        (evaluates to (m, 3) in ``seq`` order).
    seq : str
        Euler sequence for Euler mode (scipy's convention; BVH ``ZXY`` is ``"ZXY"``).
    method, order, window, features
        As for :func:`sketchanim.reduce` (a pause holds the orientation exactly still).
    keys : bool
        Quaternion mode: make the curve's value at every breakpoint a unit quaternion
        (:func:`unit_keys`), as keyframe formats (glTF) require; may add a few knots.

    Returns
    -------
    Reduction
        Quaternion mode: ``metric == "rotation"``, ``tol`` and ``max_error`` one angle
        each, in radians. Euler mode: per-axis radians.

    Examples
    --------
    >>> t = np.linspace(0, 4, 481)
    >>> q = Rotation.from_rotvec(np.c_[np.sin(t), 0.5 * t, np.cos(2 * t)]).as_quat()
    >>> r = reduce_rotations(t, q, 0.5)
    >>> bool(np.degrees(r.max_error[0]) <= 0.5), r.n_coefficients < 60, r.spline(t).shape
    (True, True, (481, 4))
    """
    angle = _check_mode(mode, tol_deg)
    if mode == "euler":
        r = reduce(times, euler_angles(quats, seq, scalar_first=scalar_first), angle, method=method, order=order,
                   window=window, features=features)
    else:
        q = continuous_quaternions(quats)
        r = reduce(times, q, np.sin(angle / 2), method=method, order=order, window=window, angle=angle,
                   features=features)
        if keys:
            before = r.n_coefficients
            spline, err = unit_keys(r.spline, np.asarray(times, dtype=float), q, angle)
            r = replace(r, spline=spline, max_error=np.array([err.max()]))
            r.report["unit_keys_added"] = r.n_coefficients - before
    return _described(r, mode, seq, scalar_first)


def _described(r: Reduction, mode: str, seq: str, scalar_first: bool) -> Reduction:
    """``r`` with its report saying how the rotation was read and reduced."""
    r.report.update(mode=mode, **({"seq": seq} if mode == "euler" else {"scalar_first": scalar_first}))
    return r


class RotationStream:
    """The streaming counterpart of :func:`reduce_rotations`: quaternions in as they
    arrive, a rotation curve out (see :class:`sketchanim.StreamReducer`).

    Sign flips are fixed and Euler angles unwrapped against the last sample taken, so
    a stream fed in pieces gives the same curve as the whole take; with ``grow=True``
    (windows grow on smooth motion, see :class:`~sketchanim.StreamReducer`), the curve
    of :func:`reduce_rotations` with ``method="incremental"``.

    Examples
    --------
    >>> t = np.linspace(0, 4, 481)
    >>> q = Rotation.from_rotvec(np.c_[np.sin(t), 0.5 * t, np.cos(2 * t)]).as_quat()
    >>> rs = RotationStream(0.5)
    >>> for a in range(0, 481, 100):
    ...     rs.extend(t[a : a + 100], q[a : a + 100])
    >>> r = rs.finish()
    >>> bool(np.degrees(r.max_error[0]) <= 0.5), r.n_coefficients < 60
    (True, True)
    """

    def __init__(self, tol_deg: float, *, scalar_first: bool = False, mode: str = "quaternion", seq: str = "ZXY",
                 order: int = 4, window: int = 20, keep: bool = True,
                 on_piece: Callable[[Piece], object] | None = None, features: bool | FeatureOptions = True,
                 grow: bool = False) -> None:
        angle = _check_mode(mode, tol_deg)
        self.mode, self.seq, self.scalar_first = mode, seq, scalar_first
        if mode == "euler":
            self.stream = StreamReducer(3, angle, order=order, window=window, keep=keep, on_piece=on_piece,
                                        features=features, grow=grow)
        else:
            self.stream = StreamReducer(4, np.sin(angle / 2), order=order, window=window, keep=keep,
                                        on_piece=on_piece, angle=angle, features=features, grow=grow)
        self._last: np.ndarray | None = None

    def push(self, t: float, quat: ArrayLike) -> None:
        """Add one sample (see :meth:`extend`)."""
        self.extend(np.array([t], dtype=float), np.asarray(quat, dtype=float).reshape(1, 4))

    def extend(self, times: ArrayLike, quats: ArrayLike) -> None:
        """Add samples in time order. A bad one (not a rotation, NaN, time going back)
        raises :class:`~sketchanim.errors.SampleError` naming its stream index, after the
        ones before it are taken; the stream stays usable."""
        t = np.asarray(times, dtype=float).reshape(-1)
        base = self.stream.pushed
        q, bad = _quaternion_array(quats, offset=base)
        if len(q) != len(t) and bad is None:
            raise ArgumentError("quats", f"needs one row per time ({len(t)}), got {len(q)}")
        if self.mode == "euler":
            values = _unwrapped_euler(q, self.seq, self.scalar_first, self._last)
        else:
            values = _same_side(q, self._last)
        try:
            self.stream.extend(t[: len(values)], values)
        except SampleError as err:
            taken = (err.index or base) - base
            self._remember(values[:taken])
            raise
        self._remember(values)
        if bad is not None:
            self.stream.skip()
            raise bad

    def _remember(self, values: np.ndarray) -> None:
        if len(values):
            self._last = values[-1].copy()

    @property
    def taken(self) -> int:
        """Distinct samples taken so far (:meth:`finish` needs two)."""
        return self.stream.taken

    def close(self) -> StreamStats:
        """End the stream (see :meth:`StreamReducer.close`)."""
        return self.stream.close()

    def finish(self) -> Reduction:
        """End the stream and return the curve (as :func:`reduce_rotations` would)."""
        return _described(self.stream.finish(), self.mode, self.seq, self.scalar_first)
