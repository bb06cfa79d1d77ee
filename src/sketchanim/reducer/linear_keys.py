"""LINEAR keys at a subset of the frames, for many tracks at once: the fewest keys this
method finds whose interpolation stays within a bound at every frame, checked on the
values a client will actually hold at the keys (quantised, for a compact file).

Keys are added top down: every track starts with its first and last frame; at each
pass, every span between two keys that misses its bound at some frame gets a key at
the frame that misses it most (relative to its bound there). Passes are whole-array
operations over all tracks and frames, so a clip's hundred tracks cost about as much as
one. Rotations are interpolated as every client does: spherically (glTF's LINEAR
rotation, the shorter way) and component-wise then normalised (Blender's F-curves,
after the keys are put on one hemisphere); the error is the worse of the two.
Tracks of a group share their key frames (one time array in the file).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from sketchanim.errors import ArgumentError
from sketchanim.reducer.metric import rotation_angle


def _ends(keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each frame's key at or before it, and at or after it (T, n)."""
    n = keep.shape[1]
    index = np.broadcast_to(np.arange(n), keep.shape)
    left = np.maximum.accumulate(np.where(keep, index, 0), axis=1)
    right = np.minimum.accumulate(np.where(keep, index, n - 1)[:, ::-1], axis=1)[:, ::-1]
    return left, right


def spherical_mix(a: np.ndarray, b: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Quaternions ``a`` and ``b`` (..., 4; unit, or as near as a file's keys are; ``b``
    on ``a``'s side) mixed at ``s`` (..., 1) as glTF's LINEAR rotations play: spherically,
    with the weights of the angle between them (normalise the result for a unit
    quaternion; ``a`` itself at 0).

    >>> half = np.radians([[0.0], [90.0]]) / 2
    >>> a, b = (np.c_[0 * h, 0 * h, np.sin(h), np.cos(h)] for h in half)
    >>> mid = spherical_mix(a, b, np.array([[0.5]]))
    >>> round(float(np.degrees(2 * np.arctan2(mid[0, 2], mid[0, 3]))), 9)
    45.0
    """
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    shape = a.shape
    s = np.broadcast_to(np.asarray(s, dtype=float), shape[:-1] + (1,))
    return _slerped(np.ascontiguousarray(a.reshape(-1, 4)), np.ascontiguousarray(b.reshape(-1, 4)),
                    np.ascontiguousarray(s.reshape(-1))).reshape(shape)


@njit(cache=True, error_model="numpy")
def _slerped(a: np.ndarray, b: np.ndarray, s: np.ndarray) -> np.ndarray:
    """:func:`spherical_mix` of rows (m, 4) at ``s`` (m,), compiled."""
    out = np.empty_like(a)
    for r in range(len(a)):
        na = 0.0
        nb = 0.0
        for c in range(4):
            na += a[r, c] * a[r, c]
            nb += b[r, c] * b[r, c]
        na, nb = np.sqrt(na), np.sqrt(nb)
        diff = 0.0
        total = 0.0
        for c in range(4):
            ua, ub = a[r, c] / na, b[r, c] / nb
            diff += (ua - ub) * (ua - ub)
            total += (ua + ub) * (ua + ub)
        angle = 2.0 * np.arctan2(np.sqrt(diff), np.sqrt(total))
        sin = np.sin(angle)
        if sin < 1e-9:
            wa, wb = 1.0 - s[r], s[r]
        else:
            wa, wb = np.sin((1.0 - s[r]) * angle) / sin, np.sin(s[r] * angle) / sin
        for c in range(4):
            out[r, c] = wa * a[r, c] + wb * b[r, c]
    return out


def _mixed(a: np.ndarray, b: np.ndarray, s: np.ndarray, rotation: bool) -> np.ndarray:
    """Keys ``a`` and ``b`` (m, d) mixed at ``s`` (m, 1) as they play: (m, d), or for
    rotations (m, 2, 4), spherically and component-wise."""
    if not rotation:
        return a + s * (b - a)
    b = np.where(np.sum(a * b, axis=-1, keepdims=True) < 0, -b, b)    # one hemisphere for F-curves
    return np.stack([spherical_mix(a, b, s), a + s * (b - a)], axis=-2)


def _played(times: np.ndarray, held: np.ndarray, rows: np.ndarray, frames: np.ndarray, left: np.ndarray,
            right: np.ndarray, rotation: bool) -> np.ndarray:
    """What plays at ``frames`` of tracks ``rows`` between their keys ``left`` and
    ``right``: (m, d), or for rotations (m, 2, 4), spherically and component-wise."""
    span = times[right] - times[left]
    s = np.divide(times[frames] - times[left], span, out=np.zeros_like(span), where=span > 0)[:, None]
    return _mixed(held[rows, left], held[rows, right], s, rotation)


def _errors(times: np.ndarray, values: np.ndarray, held: np.ndarray, rows: np.ndarray, frames: np.ndarray,
            left: np.ndarray, right: np.ndarray, rotation: bool) -> np.ndarray:
    """Error (m,) at ``frames`` of tracks ``rows`` (the worse interpolation, for rotations)."""
    played = _played(times, held, rows, frames, left, right, rotation)
    source = values[rows, frames]
    if not rotation:
        return np.linalg.norm(played - source, axis=-1)
    return np.maximum(rotation_angle(played[:, 0], source), rotation_angle(played[:, 1], source))


def played(times: np.ndarray, held: np.ndarray, keep: np.ndarray, rotation: bool) -> np.ndarray:
    """What plays at every frame from the keys ``keep`` (T, n) of ``held`` (T, n, d):
    (T, n, d), or for rotations (T, n, 2, 4), spherically then component-wise.

    >>> t = np.arange(5.0)
    >>> keep = np.array([[True, False, False, False, True]])
    >>> played(t, np.c_[t, t][None], keep, False)[0, :, 0].tolist()
    [0.0, 1.0, 2.0, 3.0, 4.0]
    """
    held = np.asarray(held, float)
    out = np.repeat(held[..., None, :], 2, axis=-2) if rotation else held.copy()   # a key plays as held
    rows, frames = np.nonzero(~keep)
    if len(rows):
        left, right = _ends(keep)
        out[rows, frames] = _played(np.asarray(times, float), held, rows, frames, left[rows, frames],
                                    right[rows, frames], rotation)
    return out


def played_at(times: np.ndarray, held: np.ndarray, keep: np.ndarray, at: np.ndarray, rotation: bool) -> np.ndarray:
    """What plays at the times ``at`` (m,) from the keys ``keep`` (T, n) of ``held``
    (T, n, d) at ``times`` (n,): (T, m, d), or for rotations (T, m, 2, 4), spherically
    then component-wise; before the first key and after the last, those keys.

    >>> t = np.arange(5.0)
    >>> keep = np.array([[True, False, False, False, True]])
    >>> played_at(t, np.c_[t, t][None], keep, np.array([-1.0, 0.5, 3.25, 9.0]), False)[0, :, 0].tolist()
    [0.0, 0.5, 3.25, 4.0]
    """
    times, held, at = np.asarray(times, float), np.asarray(held, float), np.asarray(at, float)
    out = []
    for row in range(len(held)):
        keys = np.flatnonzero(keep[row])
        right = np.clip(np.searchsorted(times[keys], at), 1, max(len(keys) - 1, 1)) if len(keys) > 1 else 0 * at
        right = np.asarray(right, int)
        left = np.maximum(right - 1, 0)
        span = times[keys[right]] - times[keys[left]]
        s = np.clip(np.divide(at - times[keys[left]], span, out=np.zeros_like(span), where=span > 0), 0, 1)
        out.append(_mixed(held[row, keys[left]], held[row, keys[right]], s[:, None], rotation))
    return np.stack(out) if out else np.zeros((0, len(at)) + ((2, 4) if rotation else held.shape[2:]))


def misses(times: np.ndarray, values: np.ndarray, held: np.ndarray, keep: np.ndarray, rotation: bool) -> np.ndarray:
    """Error (T, n) at every frame of what plays from the keys ``keep`` of ``held``
    (T, n, d), against ``values``: a distance, or an angle in radians (for rotations
    the worse of spherical and component-wise interpolation).

    >>> t = np.arange(3.0)
    >>> v = np.c_[[0.0, 1.0, 0.0]][None]
    >>> misses(t, v, v, np.array([[True, False, True]]), False).tolist()
    [[0.0, 1.0, 0.0]]
    """
    values, held = np.asarray(values, float), np.asarray(held, float)
    out = np.zeros(keep.shape)
    rows, frames = np.nonzero(keep)               # a key plays as held
    out[rows, frames] = (rotation_angle(held[rows, frames], values[rows, frames]) if rotation else
                         np.linalg.norm(held[rows, frames] - values[rows, frames], axis=-1))
    rows, frames = np.nonzero(~keep)
    if len(rows):
        left, right = _ends(keep)
        out[rows, frames] = _errors(np.asarray(times, float), values, held, rows, frames, left[rows, frames],
                                    right[rows, frames], rotation)
    return out


def linear_keys(times: np.ndarray, values: np.ndarray, bound: np.ndarray, *, held: np.ndarray | None = None,
                rotation: bool = False, groups: np.ndarray | None = None,
                keep: np.ndarray | None = None) -> np.ndarray:
    """Which frames to key (T, n) so that every track's interpolation stays within
    ``bound`` at every frame.

    Parameters
    ----------
    times : ndarray, shape (n,)
        Frame times, increasing.
    values : ndarray, shape (T, n, d)
        Each track's values at the frames (rotations: quaternions, scalar-last).
    bound : float or ndarray broadcasting to (T, n)
        The largest error at each frame (a distance, or an angle in radians).
    held : ndarray, shape (T, n, d), optional
        The values a client holds at each frame if it is keyed (quantised ``values``);
        ``values`` themselves if omitted.
    rotation : bool
        Interpolate as rotations (:func:`interpolated`).
    groups : ndarray of int, shape (T,), optional
        Tracks with the same group share their keys.
    keep : ndarray of bool, shape (T, n), optional
        Keys to start from (kept); first and last frames otherwise. A tighter ``bound``
        only adds keys to an earlier answer.

    Raises
    ------
    ArgumentError
        A keyed frame alone misses its bound (what ``held`` holds there is too far).

    Examples
    --------
    >>> t = np.arange(7.0)
    >>> linear_keys(t, np.c_[t, np.minimum(t, 3)][None], 1e-9)[0].nonzero()[0].tolist()
    [0, 3, 6]
    """
    times = np.asarray(times, dtype=float)
    values = np.asarray(values, dtype=float)
    held = values if held is None else np.asarray(held, dtype=float)
    T, n = values.shape[:2]
    limit = np.broadcast_to(np.asarray(bound, dtype=float), (T, n))
    if keep is None:
        keep = np.zeros((T, n), bool)
        keep[:, [0, -1]] = True
    else:
        keep = keep.copy()
    members = [np.flatnonzero(groups == g) for g in np.unique(groups)] if groups is not None else []
    for m in members:
        keep[m] = keep[m].any(axis=0)
    ratio = misses(times, values, held, keep, rotation) / np.maximum(limit, 1e-300)
    left, right = _ends(keep)
    while True:
        if np.any(ratio[keep] > 1):
            row, frame = np.argwhere(keep & (ratio > 1))[0]
            raise ArgumentError("bound", f"track {row}: the key at frame {frame} alone misses its bound "
                                         f"{limit[row, frame]:.3g} (what it holds is too coarse)")
        over = np.argwhere(ratio > 1)
        if not len(over):
            return keep
        span = over[:, 0] * n + left[over[:, 0], over[:, 1]]        # the span each miss lies in
        worst = np.lexsort((-ratio[over[:, 0], over[:, 1]], span))
        _, first = np.unique(span[worst], return_index=True)
        added = over[worst[first]]
        keep[added[:, 0], added[:, 1]] = True
        for m in members:
            keep[m] = keep[m].any(axis=0)
        was = left, right
        left, right = _ends(keep)
        rows, frames = np.nonzero((left != was[0]) | (right != was[1]))   # the spans split: measured again
        ratio[rows, frames] = _errors(times, values, held, rows, frames, left[rows, frames], right[rows, frames],
                                      rotation) / np.maximum(limit[rows, frames], 1e-300)
