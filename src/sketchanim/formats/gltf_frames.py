"""glTF keys at frames, for importers that ignore CUBICSPLINE tangents.

Blender's own glTF importer (and others) keep a CUBICSPLINE key's value and drop its
tangents, so a curve written exactly with few keys plays wrong there. ``keys="frames"``
writes the same curve as a key at every frame instead: LINEAR samplers, which every
client plays alike, translations and scales interpolated linearly and rotations
spherically (glTF's LINEAR rotation; Blender interpolates the components and
normalises, which :func:`~sketchanim.reducer.linear_keys.linear_keys` checks too). A key that its neighbours'
interpolation already reproduces within ``allowance`` is dropped.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.anim.tracks import held_values
from sketchanim.formats.gltf import Channel
from sketchanim.formats.gltf_compact import QUANTISATION_SHARE, CompactChannel, bits_for, held
from sketchanim.reducer.linear_keys import linear_keys

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


def frame_channel(node: int, path: str, spline: BSpline, times: np.ndarray, allowance: float) -> Channel:
    """A curve as a LINEAR channel: its values at ``times``, less the keys that the
    neighbours' interpolation reproduces within ``allowance``
    (:func:`~sketchanim.reducer.linear_keys.linear_keys`).

    >>> s = BSpline(np.r_[[0.0] * 4, [1.0] * 4], np.c_[[0.0, 0.0, 0.0, 0.0]], 3)     # still: two keys
    >>> ch = frame_channel(0, "translation", s, np.linspace(0, 1, 31), 1e-6)
    >>> ch.interpolation, ch.times.tolist(), ch.values.tolist()
    ('LINEAR', [0.0, 1.0], [[0.0], [0.0]])
    """
    rotation = path == "rotation"
    times = np.asarray(times, dtype=float)
    values = frame_values(spline, times, rotation)
    keep = linear_keys(times, values[None], allowance, rotation=rotation)[0]
    return Channel(node, path, "LINEAR", times[keep], values[keep])


def compact_channel(node: int, path: str, spline: BSpline, times: np.ndarray, allowance: float) -> CompactChannel:
    """A curve as a compact LINEAR channel: its values at ``times``, stored with the
    bits that leave :data:`~sketchanim.formats.gltf_compact.QUANTISATION_SHARE` of
    ``allowance`` to the filter's rounding, less the keys that the neighbours'
    interpolation of the decoded values reproduces within ``allowance``.

    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> ch = compact_channel(0, "translation", s, np.linspace(0, 1, 31), 1e-3)
    >>> ch.times.tolist(), ch.bits
    ([0.0, 1.0], 16)
    """
    rotation = path == "rotation"
    times = np.asarray(times, dtype=float)
    values = frame_values(spline, times, rotation)
    bits = bits_for(path, QUANTISATION_SHARE * allowance, float(np.abs(values).max(initial=0.0)))
    keep = linear_keys(times, values[None], allowance, held=held(values, path, bits)[None], rotation=rotation)[0]
    return CompactChannel(node, path, times[keep], values[keep], bits)


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
