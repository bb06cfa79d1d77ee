"""glTF keys at frames, for importers that ignore CUBICSPLINE tangents.

Blender's own glTF importer (and others) keep a CUBICSPLINE key's value and drop its
tangents, so a curve written exactly with few keys plays wrong there. ``keys="frames"``
writes the same curve as a key at every frame instead: LINEAR samplers, which every
client plays alike, translations and scales interpolated linearly and rotations
spherically (glTF's LINEAR rotation; Blender interpolates the components and
normalises, which :func:`thin_keys` checks too). A key that its neighbours'
interpolation already reproduces within ``allowance`` is dropped.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.tracks import held_values
from sketchanim.formats.gltf import Channel
from sketchanim.reducer.metric import rotation_angle

#: Of a curve's tolerance, the most that dropping keys may add to its error.
FRAME_SHARE = 0.1

#: How a curve is written: exactly (CUBICSPLINE keys at its breakpoints), as LINEAR
#: keys at frames, or as the fewest LINEAR keys at frames, quantised and compressed
#: (:mod:`sketchanim.formats.gltf_compact`).
KEYS = ("curves", "frames", "compact")


def frame_values(spline: BSpline, times: np.ndarray, rotation: bool) -> np.ndarray:
    """The curve at ``times`` (ends held), as keys: rotations normalised, each
    quaternion on the side of the previous one (every client then turns the short way).

    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0, 2], [0, 0, 0, -2]]), 1)
    >>> (frame_values(s, np.array([0.0, 1.0]), True) + 0.0).tolist()
    [[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 1.0]]
    """
    values = held_values(spline, np.asarray(times, dtype=float), rotation)
    if rotation:
        flips = np.cumsum(np.r_[0, np.sum(values[1:] * values[:-1], axis=1) < 0]) % 2
        values = np.where(flips[:, None] == 1, -values, values)
    return values


def _miss(times: np.ndarray, values: np.ndarray, a: int, b: int, rotation: bool) -> float:
    """Largest error at the frames strictly between keys ``a`` and ``b`` of what a
    client interpolates between those two keys (rotations: the worse of spherical and
    normalised component-wise interpolation, as an angle)."""
    if b - a < 2:
        return 0.0
    s = ((times[a + 1 : b] - times[a]) / (times[b] - times[a]))[:, None]
    inner = values[a + 1 : b]
    if not rotation:
        return float(np.linalg.norm(values[a] + s * (values[b] - values[a]) - inner, axis=1).max())
    nlerp = (1 - s) * values[a] + s * values[b]
    angle = np.arccos(np.clip(np.dot(values[a], values[b]), -1.0, 1.0))
    if angle < 1e-12:
        slerp = nlerp
    else:
        slerp = (np.sin((1 - s) * angle) * values[a] + np.sin(s * angle) * values[b]) / np.sin(angle)
    return float(max(rotation_angle(nlerp, inner).max(), rotation_angle(slerp, inner).max()))


def thin_keys(times: np.ndarray, values: np.ndarray, allowance: float, rotation: bool) -> np.ndarray:
    """Indices of the keys to keep: from each kept key, the farthest next one (found by
    doubling, then bisection) whose interpolation with it stays within ``allowance``
    (a distance, or an angle in radians) at every frame between them.

    >>> t = np.arange(7.0)
    >>> thin_keys(t, np.c_[t, np.minimum(t, 3)], 1e-9, False).tolist()
    [0, 3, 6]
    """
    n = len(times)
    keep = [0]
    while keep[-1] < n - 1:
        a = keep[-1]
        good, step = a + 1, 1
        while good + step < n and _miss(times, values, a, good + step, rotation) <= allowance:
            good += step
            step *= 2
        bad = min(good + step, n)                  # the first that failed (or the end)
        while bad - good > 1:
            mid = (good + bad) // 2
            if _miss(times, values, a, mid, rotation) <= allowance:
                good = mid
            else:
                bad = mid
        keep.append(good)
    return np.array(keep)


def frame_channel(node: int, path: str, spline: BSpline, times: np.ndarray, allowance: float) -> Channel:
    """A curve as a LINEAR channel: its values at ``times``, less the keys that the
    neighbours' interpolation reproduces within ``allowance`` (:func:`thin_keys`).

    >>> s = BSpline(np.r_[[0.0] * 4, [1.0] * 4], np.c_[[0.0, 0.0, 0.0, 0.0]], 3)     # still: two keys
    >>> ch = frame_channel(0, "translation", s, np.linspace(0, 1, 31), 1e-6)
    >>> ch.interpolation, ch.times.tolist(), ch.values.tolist()
    ('LINEAR', [0.0, 1.0], [[0.0], [0.0]])
    """
    rotation = path == "rotation"
    times = np.asarray(times, dtype=float)
    values = frame_values(spline, times, rotation)
    keep = thin_keys(times, values, allowance, rotation)
    return Channel(node, path, "LINEAR", times[keep], values[keep])


def allowance(tol: float, error: float) -> float:
    """What dropping keys may add to a curve within ``tol`` whose error is ``error``:
    ``FRAME_SHARE`` of the tolerance, and never past it.

    >>> [round(allowance(0.5, e), 9) for e in (0.2, 0.49, 0.5)]
    [0.05, 0.01, 0.0]
    """
    return float(min(FRAME_SHARE * tol, max(tol - error, 0.0)))


def frame_times(start: float, end: float, rate: float) -> np.ndarray:
    """Times at ``rate`` per second from ``start`` through ``end`` (the end itself
    when the rate does not land on it).

    >>> frame_times(0.0, 1.0, 4).tolist(), frame_times(0.0, 0.9, 4).tolist()
    ([0.0, 0.25, 0.5, 0.75, 1.0], [0.0, 0.25, 0.5, 0.75, 0.9])
    """
    n = int(np.floor((end - start) * rate + 1e-9))
    times = start + np.arange(n + 1) / rate
    if end - times[-1] <= 1e-9 * max(1.0, abs(end)):
        times[-1] = end                            # the end exactly, where the rate lands on it
        return times
    return np.r_[times, end]
