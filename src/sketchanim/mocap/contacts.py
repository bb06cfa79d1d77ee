"""Contacts: where a clip holds an end joint (a leaf of the skeleton: a toe, a hand) still
on the ground, and how much a clip's planted joints slide there.

A leaf is planted at a frame when it is near its ground height and slow. The ground is
flat and level, across the up axis (+y, as BVH, ASF/AMC and the walker hold it): a
leaf's ground height is the lowest it goes (:data:`GROUND_PERCENTILE` of its heights, so
that a stray frame does not set it), and only leaves whose ground height is within
:data:`GROUND_REACH_M` of the lowest leaf's touch the ground at all (a hand that never
comes down to the floor never plants). Near is within :data:`HEIGHT_M` above it, slow is
under :data:`SPEED_M_S`, both in metres through the clip's unit (guessed from the
figure's height where the clip does not say it; a figure of unknown unit is taken as
:data:`FIGURE_M` tall).

A planted joint's error reads as sliding: the reductions hold the planted joints of a
clip within :data:`CONTACT_SHARE` of their world tolerance on the frames they are
planted (:mod:`sketchanim.mocap.clip_reduction`, :mod:`sketchanim.mocap.world_reduction`).
:func:`sliding` measures what is left: the median speed of the planted joints while
planted, sampled at :data:`SLIDING_RATE` frames a second.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from sketchanim.anim.rigs import resampled
from sketchanim.errors import ArgumentError
from sketchanim.motion.skeleton import Clip

#: Of the world tolerance, what a planted joint's world error may use on its planted frames.
CONTACT_SHARE = 0.15

#: A planted leaf is at most this far above its ground height, metres.
HEIGHT_M = 0.05
#: And slower than this, metres per second.
SPEED_M_S = 0.3
#: Leaves whose ground height is this far above the lowest leaf's never plant, metres.
GROUND_REACH_M = 0.15
#: The percentile of a leaf's heights taken as its ground height.
GROUND_PERCENTILE = 2.0
#: Height of a figure whose unit is unknown, metres (to scale the thresholds).
FIGURE_M = 1.7
#: Frames per second :func:`sliding` samples at.
SLIDING_RATE = 60.0
#: How much faster than the source's the planted joints of a reduced clip or a compact
#: file may slide (:func:`sliding`, as played), metres per second.
SLIDING_SLACK_M_S = 0.01
#: The up axis (y).
UP = 1


def leaves(clip: Clip) -> np.ndarray:
    """Indices of the joints without children.

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> leaves(Clip.still(Skeleton(("a", "b", "c"), (-1, 0, 0), np.zeros((3, 3))), [0.0])).tolist()
    [1, 2]
    """
    parents = np.asarray(clip.skeleton.parents)
    return np.setdiff1d(np.arange(len(parents)), parents[parents >= 0])


def unit_m(clip: Clip) -> float:
    """Metres per clip unit: the clip's own or guessed unit, else the one that makes the
    rest figure :data:`FIGURE_M` tall (1 for a figure of no height)."""
    unit = clip.guess_unit_m()
    if unit is not None:
        return unit
    rest = clip.skeleton.rest_positions()
    height = float(np.ptp(rest, axis=0).max()) if len(rest) > 1 else 0.0
    return FIGURE_M / height if height > 0 else 1.0


def planted(clip: Clip, world: np.ndarray | None = None) -> np.ndarray:
    """Per frame and joint (n, J), whether the joint is a leaf held on the ground: near
    its ground height and slow (the module's thresholds). ``world``: the clip's joint
    positions (n, J, 3) where the caller has them.

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("hips", "toe"), (-1, 0), np.array([[0.0, 1.0, 0], [0, -1.0, 0]]))
    >>> clip = Clip.still(s, np.arange(120) / 60)
    >>> clip.translating[0] = True
    >>> clip.translations[:, 0, 1] = 1 + 0.2 * np.clip(np.sin(np.pi * (clip.times - 1)), 0, 1)  # stands, hops
    >>> p = planted(clip)
    >>> bool(p[:, 0].any()), bool(p[30, 1]), bool(p[90, 1])
    (False, True, False)
    """
    n = len(clip.times)
    out = np.zeros((n, len(clip.skeleton)), bool)
    ends = leaves(clip)
    if n < 2 or not ends.size:
        return out
    points = (clip.world_positions() if world is None else world)[:, ends]
    metre = 1.0 / unit_m(clip)
    height = points[..., UP]
    ground = np.percentile(height, GROUND_PERCENTILE, axis=0)
    touching = ground <= ground.min() + GROUND_REACH_M * metre
    speed = np.linalg.norm(np.gradient(points, clip.times, axis=0), axis=-1)
    out[:, ends] = touching & (height <= ground + HEIGHT_M * metre) & (speed < SPEED_M_S * metre)
    return out


def nearest_frames(times: np.ndarray, at: np.ndarray) -> np.ndarray:
    """For each of the times ``at``, the index of the nearest of ``times`` (at least two,
    increasing; a time halfway takes the later).

    >>> nearest_frames(np.array([0.0, 1.0, 2.0]), np.array([0.2, 0.5, 1.9, 7.0])).tolist()
    [0, 1, 2, 2]
    """
    nearest = np.clip(np.searchsorted(times, at), 1, len(times) - 1)
    return nearest - (at - times[nearest - 1] < times[nearest] - at)


def between_frames(clip: Clip, held: np.ndarray, rate: float = SLIDING_RATE) -> tuple[Clip, np.ndarray]:
    """``clip`` and its planted frames ``held`` (n, J), with samples between its frames
    at ``rate`` where it is slower and plants anything: the source as :func:`sliding`
    sees it there (rotations slerped, translations lerped), each sample planted as the
    frame nearest it. ``clip`` and ``held`` themselves otherwise.

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("hips", "toe"), (-1, 0), np.array([[0.0, 1.0, 0], [0, -1.0, 0]]))
    >>> clip = Clip.still(s, np.arange(4) / 30)
    >>> fine, held = between_frames(clip, np.ones((4, 2), bool))
    >>> (fine.times * 60).round(6).tolist(), held.shape
    ([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0], (7, 2))
    """
    steps = np.diff(clip.times)
    if not held.any() or not len(steps) or steps.max() * rate <= 1 + 1e-9:
        return clip, held
    parts = np.maximum(np.ceil(steps * rate - 1e-9), 1).astype(int)
    at = np.concatenate([t + step * np.arange(k) / k for t, step, k in zip(clip.times[:-1], steps, parts)]
                        + [clip.times[-1:]])
    return resampled(clip, at), held[nearest_frames(clip.times, at)]


def planted_steps(times: np.ndarray, held: np.ndarray, rate: float = SLIDING_RATE
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The steps :func:`sliding` measures: sample times ``1 / rate`` s apart from the
    first frame (m,), and for each step between consecutive samples both at planted
    frames (the source frame nearest each sample, ``held``: (n, J) of ``times``), its
    first sample's index and its joint.

    >>> held = np.zeros((5, 2), bool); held[1:4, 1] = True
    >>> at, first, joint = planted_steps(np.arange(5) / 30, held, 60.0)
    >>> len(at), first.tolist(), joint.tolist()
    (9, [1, 2, 3, 4, 5], [1, 1, 1, 1, 1])
    """
    if not np.isfinite(rate) or rate <= 0:
        raise ArgumentError("rate", f"must be a positive number of samples per second, got {rate!r}")
    if len(times) < 2:
        return np.asarray(times[:1], float), np.zeros(0, int), np.zeros(0, int)
    at = times[0] + np.arange(int(np.floor((times[-1] - times[0]) * rate + 1e-9)) + 1) / rate
    on = held[nearest_frames(times, at)]
    first, joint = np.nonzero(on[1:] & on[:-1])
    return at, first, joint


def sliding(clip: Clip, sample: Callable[[np.ndarray], Clip] | None = None, *,
            contacts: np.ndarray | None = None, rate: float = SLIDING_RATE) -> float:
    """The median speed (clip units per second) of ``clip``'s planted joints while they
    are planted, over :func:`planted_steps`. ``sample`` gives the motion measured at
    given times (``ReducedClip.sample``, a played file); by default ``clip`` itself,
    its rotations slerped between frames. ``contacts``: :func:`planted` of ``clip``
    where the caller has it. NaN if nothing is planted.

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("hips", "toe"), (-1, 0), np.array([[0.0, 1.0, 0], [0, -1.0, 0]]))
    >>> clip = Clip.still(s, np.arange(121) / 120)
    >>> clip.translating[0] = True
    >>> clip.translations[:, 0, 0] = 0.02 * clip.times                  # creeps at 2 cm/s
    >>> round(sliding(clip), 6)
    0.02
    """
    held = planted(clip) if contacts is None else contacts
    at, first, joint = planted_steps(clip.times, held, rate)
    if not len(first):
        return float("nan")
    moved = (sample(at) if sample is not None else resampled(clip, at)).world_positions()
    return float(np.median(step_speeds(moved, first, joint, rate)))


def step_speeds(positions: np.ndarray, first: np.ndarray, joint: np.ndarray, rate: float = SLIDING_RATE
                ) -> np.ndarray:
    """Each step's speed (units per second): its joint's move from sample ``first`` to
    the next of ``positions`` (m, J, 3, at ``rate`` samples per second; the steps as
    :func:`planted_steps` gives them).

    >>> p = np.zeros((3, 1, 3)); p[1:, 0, 0] = [0.5, 1.0]
    >>> step_speeds(p, np.array([0, 1]), np.array([0, 0]), 60.0).tolist()
    [30.0, 30.0]
    """
    return np.linalg.norm(positions[first + 1, joint] - positions[first, joint], axis=-1) * rate
