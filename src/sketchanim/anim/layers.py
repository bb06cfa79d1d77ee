"""Recording over existing motion: takes, punch-in, additive layers.

A :class:`Take` is what one recording of one attribute captured: its raw samples and how
it goes onto the track. The track's curve is rebuilt from its takes, in order
(:func:`compose`), so it can be re-reduced at any tolerance from the raw data and never
reduces a reduced curve.

A take recorded over an existing curve ``S`` replaces it on the take's span ``[a, b]``
only (a punch-in): outside, the curve is ``S`` itself (cut exactly by knot insertion);
inside, it is a reduction of the take; at ``a`` and ``b`` it meets ``S`` with the same
value and the same first derivative (C1; C0 for a linear spline). To make that join
reachable within tolerance, the take fades in and out over ``blend`` seconds at each
seam (smoothstep weights, as an NLA strip's blend in and out): its targets are
``S + w (take - S)``. An *additive* take's samples are offsets added to ``S`` (vectors),
or rotations applied on top of it (orientations: ``offset * S`` in the world frame),
faded the same way. Every target is kept within the tolerance. A take with
``smoothing`` is reduced from its samples smoothed (:mod:`.smoothed`), so the tolerance
holds against those; its raw samples stay in the take (:func:`resmoothed` changes it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.smoothed import smoothed_samples
from sketchanim.anim.tracks import ContinuousTrack, Take, held_values
from sketchanim.errors import ArgumentError
from sketchanim.motion.rotations import reduce_rotations
from sketchanim.reducer import reduce
from sketchanim.reducer.metric import max_errors
from sketchanim.reducer.splice import hold, join, snapped, split
from sketchanim.spline import elevate_degree, insert_knots


#: How takes are reduced when a track is composed: the windowed (incremental) reducer, the
#: one that reduced the take while it was recorded, so composing again at the same
#: tolerance gives the curve back; it is several times faster than the global method on
#: long takes (a tolerance slider answers while it is dragged), for a few more points.
METHOD = "incremental"


def reduce_samples(type: AttributeType, times: np.ndarray, values: np.ndarray, tol: float, order: int,
                   method: str = METHOD) -> BSpline:
    """A reduction of samples of an attribute of ``type`` within ``tol`` (in the type's
    unit: degrees for an orientation), as a spline of (m, dim) values, by the reducer's
    ``method`` (:data:`METHOD` as tracks are composed; ``"global"`` for the fewest points).

    >>> from sketchanim.anim.attributes import POSITION
    >>> t = np.linspace(0, 1, 121)
    >>> s = reduce_samples(POSITION, t, np.c_[t, t * t, np.sin(t)], 0.001, 4)
    >>> bool(np.abs(s(t) - np.c_[t, t * t, np.sin(t)]).max() <= 0.001), len(s.c) < 20
    (True, True)
    """
    if type.is_rotation:
        r = reduce_rotations(times, values, tol, order=order, method=method)
    else:
        r = reduce(times, values, tol, order=order, bounds=type.bounds, method=method)
    return r.columns


def _weights(times: np.ndarray, a: float, b: float, blend: float, left: bool, right: bool) -> np.ndarray:
    """Fade-in and fade-out weights of a take on ``[a, b]`` at ``times`` (smoothstep,
    zero slope at the seams)."""
    blend = min(blend, (b - a) / 2)
    w = np.ones(len(times))
    for seam, on in ((np.abs(times - a), left), (np.abs(b - times), right)):
        if on and blend > 0:
            u = np.minimum(seam / blend, 1.0)
            w *= u * u * (3 - 2 * u)
    return w


def _targets(type: AttributeType, old: np.ndarray, values: np.ndarray, mode: str, w: np.ndarray) -> np.ndarray:
    """What the curve must keep at a take's times: its ``values`` faded onto ``old``
    (clamped to the type's bounds: an offset may carry a target past them)."""
    x = np.asarray(values, dtype=float)
    if not type.is_rotation:
        targets = old + w[:, None] * (x - old if mode == "replace" else x)
        return targets if type.bounds is None else np.clip(targets, *type.bounds)
    if mode == "additive":
        x = (Rotation.from_rotvec(w[:, None] * Rotation.from_quat(x).as_rotvec()) * Rotation.from_quat(old)).as_quat()
        w = np.ones(len(w))
    x = x / np.linalg.norm(x, axis=1, keepdims=True)
    x *= np.where(np.sum(x * old, axis=1) < 0, -1.0, 1.0)[:, None]          # old's hemisphere
    q = old + w[:, None] * (x - old)
    return q / np.linalg.norm(q, axis=1, keepdims=True)


class Overlay:
    """The targets of a take over a curve (see the module's description), as its samples
    arrive: what a streaming reducer is fed while the take goes on.

    A sample's fade weight is known once the take has run ``2 * blend`` seconds and the
    sample is ``blend`` seconds old; until then it is held back. The take fades in if it
    starts after ``old`` does, and out if it ends before ``old`` does (:attr:`seams`);
    :func:`punch_in` takes the streamed curve only where it decides the same.

    Examples
    --------
    >>> from sketchanim.anim.attributes import FLOAT
    >>> old = BSpline(np.r_[[0.0] * 2, [4.0] * 2], np.c_[[0.0, 4.0]], 1)     # x = t
    >>> over = Overlay(FLOAT, old, "replace", 0.1)
    >>> t = np.linspace(1, 2, 121)
    >>> first = over.push(t[:100], np.c_[t[:100] + 1])       # the last 0.1 s held back
    >>> second = over.push(t[100:], np.c_[t[100:] + 1])
    >>> rest = over.close()
    >>> [len(first[0]), len(second[0]), len(rest[0])], over.seams
    ([87, 22, 12], (True, True))
    >>> float(first[1][0, 0]), float(rest[1][-1, 0])        # faded from and onto x = t
    (1.0, 2.0)
    """

    def __init__(self, type: AttributeType, old: BSpline | None, mode: str, blend: float) -> None:
        self.type, self.old, self.mode, self.blend = type, old, mode, blend
        self._t = np.empty(0)                    # samples held back
        self._x = np.empty((0, type.dim))
        self._start: float | None = None
        self._end = 0.0                          # the latest time taken
        self._left = False
        self._right = False

    @property
    def seams(self) -> tuple[bool, bool]:
        """Whether the take fades in and out (the end is known once closed)."""
        return self._left, self._right

    def push(self, times: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Take samples; return the times and targets of those whose weight is known."""
        if self._start is None:
            self._start = float(times[0])
            self._left = self.old is not None and bool(self._start > self.old.t[self.old.k])
        self._t = np.r_[self._t, times]
        self._x = np.vstack([self._x, values])
        self._end = float(self._t[-1])
        if self._end - self._start < 2 * self.blend:
            return self._release(0)
        return self._release(int(np.searchsorted(self._t, self._end - self.blend, side="right")))

    def close(self) -> tuple[np.ndarray, np.ndarray]:
        """The rest of the targets, with the take's end known."""
        self._right = self.old is not None and bool(self._end < self.old.t[-self.old.k - 1])
        return self._release(len(self._t))

    def _release(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        t, x = self._t[:n], self._x[:n]
        self._t, self._x = self._t[n:], self._x[n:]
        w = _weights(t, self._start, self._end, self.blend, self._left, self._right)
        if self.old is None:
            old = np.tile(np.asarray(self.type.default, dtype=float), (n, 1))
        else:
            old = held_values(self.old, t, self.type.is_rotation)
        return t, _targets(self.type, old, x, self.mode, w)


def _reversed(s: BSpline) -> BSpline:
    return BSpline(-np.asarray(s.t)[::-1], np.asarray(s.c)[::-1], s.k)


def _seat_start(m: BSpline, value: np.ndarray, slope: np.ndarray, times: np.ndarray, targets: np.ndarray,
                angle: float, bound: np.ndarray) -> BSpline:
    """``m`` moved to start on ``value`` with derivative ``slope``: its first two
    coefficients set, after knots are inserted close enough to the start that the
    change keeps the samples there within ``bound`` of their ``targets``."""
    k = m.k + 1
    a, b = float(m.t[k - 1]), float(m.t[-k])
    h = min(float(m.t[k]) - a, (b - a) / 3)
    for _ in range(100):
        s = insert_knots(m, [x for x in (a + h, a + 2 * h) if x not in m.t])
        c = np.array(s.c, dtype=float)
        c[0] = value
        if k > 2:
            c[1] = value + slope * (s.t[k] - a) / (k - 1)
        seated = BSpline(s.t, c, s.k)
        # Only samples before s.t[k + 1] moved; the one at `a` is on `value` (its target
        # there, or within tolerance of it), so once 2h is under the first sample gap
        # nothing else moves: this returns long before the guard below.
        near = slice(0, int(np.searchsorted(times, s.t[k + 1], side="right")))
        if np.all(max_errors(seated(times[near]), targets[near], angle) <= bound):
            return seated
        h /= 2
    raise ArgumentError("take", f"cannot join the take at {a} s within tolerance")


@dataclass(frozen=True)
class _Plan:
    """How :func:`punch_in` puts a take over a curve: its times and targets, the curve
    it goes over (``base``, None: nothing below a replacing take), cut at ``cut_a`` and
    ``cut_b`` into ``left`` and ``right`` (None where the take reaches past the curve),
    and the bound its targets are kept within (radians for an orientation: ``angle``)."""

    times: np.ndarray
    targets: np.ndarray
    base: BSpline | None = None
    left: BSpline | None = None
    right: BSpline | None = None
    cut_a: float = 0.0
    cut_b: float = 0.0
    angle: float = 0.0
    bound: np.ndarray | None = None

    @property
    def seams(self) -> tuple[bool, bool]:
        return self.left is not None, self.right is not None


def _plan(type: AttributeType, old: BSpline | None, take: Take, tol: float, order: int) -> _Plan:
    times = np.asarray(take.times, dtype=float)
    values = smoothed_samples(type, times, take.values, take.smoothing)
    a, b = take.start, take.end
    if old is None and take.mode == "replace":
        return _Plan(times, np.asarray(values, dtype=float))
    base = hold(a, b, type.default, order) if old is None else old
    if base.k + 1 < order:
        base = elevate_degree(base, order - base.k - 1)
    k0 = base.k
    lo, hi = float(base.t[k0]), float(base.t[-k0 - 1])
    ext = [base]
    if a < lo:
        ext.insert(0, hold(a, lo, np.asarray(base.c)[0], k0 + 1))
    if b > hi:
        ext.append(hold(hi, b, np.asarray(base.c)[-1], k0 + 1))
    ext = join(ext)
    cut_a, cut_b = snapped(ext, a), snapped(ext, b)
    left, rest = split(ext, cut_a) if cut_a > ext.t[k0] else (None, ext)
    right = split(rest, cut_b)[1] if cut_b < rest.t[-k0 - 1] else None
    angle = np.radians(tol) if type.is_rotation else 0.0
    bound = np.array([angle]) if angle else np.full(type.dim, tol)
    old_values = held_values(base, times, type.is_rotation)
    seams = (left is not None, right is not None)
    targets = _targets(type, old_values, values, take.mode, _weights(times, a, b, take.blend, *seams))
    for side, i, seam in (("start", 0, left), ("end", -1, right)):
        gap = max_errors(old_values[[i]], targets[[i]], angle)
        if seam is not None and np.any(gap > bound):
            raise ArgumentError("blend", f"the take's {side} at {times[i]} s is {gap.max():.6g} from the curve, "
                                         f"more than the tolerance {tol}: a continuous join needs blend > 0")
    return _Plan(times, targets, base, left, right, cut_a, cut_b, angle, bound)


def punch_in(type: AttributeType, old: BSpline | None, take: Take, tol: float, order: int,
             streamed: tuple[BSpline, tuple[bool, bool]] | None = None) -> BSpline:
    """The curve ``old`` with ``take`` recorded over it (see the module's description).

    Parameters
    ----------
    type : AttributeType
    old : BSpline or None
        The existing curve, held outside its span; None: the attribute's default holds.
    take : Take
    tol : float
        In the type's unit (degrees for an orientation).
    order : int
        Of the take's curve (at least 3 for a C1 join); an ``old`` of a lower order is
        raised to it (exactly), one of a higher order sets it.
    streamed : (BSpline, (bool, bool)) or None
        The take's targets already reduced while it was recorded, fed by an
        :class:`Overlay` with those :attr:`~Overlay.seams`: used instead of reducing
        them again if the seams and the order agree with this function's.

    Raises
    ------
    ArgumentError
        With ``blend == 0``, a take whose seam sample is further than ``tol`` from
        ``old``: no continuous curve can keep both.

    Examples
    --------
    >>> from sketchanim.anim.attributes import FLOAT
    >>> old = BSpline(np.r_[[0.0] * 2, [4.0] * 2], np.c_[[0.0, 4.0]], 1)     # x = t
    >>> t = np.linspace(1, 2, 121)
    >>> new = punch_in(FLOAT, old, Take(t, np.c_[t + np.sin(np.pi * (t - 1))]), 0.01, 4)
    >>> round(float(new(0.5)[0]), 12), float(new(3.0)[0])   # untouched outside [1, 2]
    (0.5, 3.0)
    >>> d = new.derivative()
    >>> [round(float(d(x)[0]), 6) for x in (1.0, 2.0)]      # slope 1 on both sides: C1
    [1.0, 1.0]
    """
    return _punch(type, _plan(type, old, take, tol, order), tol, order, streamed)


def _punch(type: AttributeType, plan: _Plan, tol: float, order: int,
           streamed: tuple[BSpline, tuple[bool, bool]] | None = None, method: str = METHOD) -> BSpline:
    """:func:`punch_in` as ``plan`` says (its takes reduced by the reducer's ``method``)."""
    if plan.base is None:
        return reduce_samples(type, plan.times, plan.targets, tol, order, method)
    k0, times, targets, angle, bound = plan.base.k, plan.times, plan.targets, plan.angle, plan.bound
    left, right, seams, cut_a, cut_b = plan.left, plan.right, plan.seams, plan.cut_a, plan.cut_b
    if streamed is not None and streamed[0].k == k0 and streamed[1] == seams:
        mid = streamed[0]
    else:
        mid = reduce_samples(type, times, targets, tol, k0 + 1, method)
    knots = np.array(mid.t)
    knots[: k0 + 1], knots[-k0 - 1 :] = cut_a, cut_b
    mid = BSpline(knots, mid.c, mid.k)
    pieces = [mid]
    if left is not None:
        mid = _seat_start(mid, np.asarray(left.c)[-1], left.derivative()(cut_a), times, targets, angle, bound)
        pieces = [left, mid]
    if right is not None:
        mid = _reversed(_seat_start(_reversed(mid), np.asarray(right.c)[0], -right.derivative()(cut_b), -times[::-1],
                                    targets[::-1], angle, bound))
        pieces = pieces[:-1] + [mid, right]
    return join(pieces)


def recorded_over(path: str, type: AttributeType, below: ContinuousTrack | None, take: Take, tol: float,
                  order: int, streamed: tuple[BSpline, tuple[bool, bool] | None] | None = None) -> ContinuousTrack:
    """The track at ``path`` after ``take`` is recorded over ``below`` (None: no track):
    its curve :func:`punch_in`'s, its takes ``below``'s and ``take``, its tolerance ``tol``.
    What the recorder makes of a take when it stops, and what a recovery makes of a take
    found in a journal.

    ``streamed`` is the curve the reducer processes made while the take was recorded:
    with seams None, the take's own curve (nothing below), used as it is; otherwise
    :func:`punch_in`'s ``streamed``.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 1, 30)
    >>> track = recorded_over("a.x", FLOAT, None, Take(t, np.c_[t]), 0.01, 4)
    >>> len(track.takes), bool(np.abs(track.evaluate(t) - np.c_[t]).max() <= 0.01)
    (1, True)
    """
    if streamed is not None and streamed[1] is None:
        return ContinuousTrack(path, type, streamed[0], tol, (take,))
    spline = punch_in(type, None if below is None else below.spline, take, tol, order, streamed)
    if below is None:
        return ContinuousTrack(path, type, spline, tol, (take,))
    return ContinuousTrack(path, type, spline, tol, below.takes + (take,), below.edited)     # its edits stay outside the take


def compose(type: AttributeType, takes: Sequence[Take], tol: float, order: int) -> BSpline:
    """The curve that ``takes``, recorded in order, leave on a track (muted takes left out).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 2, 241)
    >>> takes = [Take(t, np.c_[np.sin(t)]), Take(t[60:120], np.c_[0.2 * np.ones(60)], "additive")]
    >>> s = compose(FLOAT, takes, 0.001, 4)
    >>> round(float(s(0.75)[0] - np.sin(0.75)), 2), bool(abs(s(1.5)[0] - np.sin(1.5)) <= 0.001)
    (0.2, True)
    """
    return composition(type, takes, tol, order).curve


@dataclass(frozen=True)
class Composition:
    """What :func:`composition` makes of takes: the ``curve``, and the samples it keeps
    within the tolerance: each take's targets (its samples faded onto what was below,
    smoothed if it was) where no later take covers them, in time order, ``times`` (n,)
    and ``targets`` (n, dim)."""

    curve: BSpline
    times: np.ndarray
    targets: np.ndarray


def composition(type: AttributeType, takes: Sequence[Take], tol: float, order: int,
                method: str = METHOD) -> Composition:
    """The curve ``takes`` leave on a track (:func:`compose`) and the samples it keeps
    (the takes reduced by the reducer's ``method``: :data:`METHOD`, or ``"global"`` for
    the fewest points).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 2, 201)
    >>> made = composition(FLOAT, [Take(t, np.c_[t]), Take(t[50:100], np.c_[t[50:100] + 1])], 0.01, 4)
    >>> len(made.times), float(made.targets[made.times == 1.0][0, 0])
    (201, 1.0)
    """
    playing = [take for take in takes if not take.muted]
    if not playing:
        raise ArgumentError("takes", "needs at least one take that is not muted")
    curve, plans = None, []
    for take in playing:
        plans.append(_plan(type, curve, take, tol, order))
        curve = _punch(type, plans[-1], tol, order, method=method)
    times, targets = [], []
    for i, plan in enumerate(plans):
        keep = np.ones(len(plan.times), dtype=bool)
        for later in plans[i + 1:]:
            keep &= (plan.times < later.times[0]) | (plan.times > later.times[-1])
        times.append(plan.times[keep])
        targets.append(plan.targets[keep])
    t, x = np.concatenate(times), np.concatenate(targets)
    by_time = np.argsort(t, kind="stable")
    return Composition(curve, t[by_time], x[by_time])


def largest_error(type: AttributeType, spline: BSpline, times: np.ndarray, values: np.ndarray) -> float:
    """The largest distance of ``spline`` from ``values`` at ``times``, in the type's unit
    (per channel; the angle in degrees for an orientation), as tolerances are kept.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.c_[[0.0, 1.0]], 1)
    >>> largest_error(FLOAT, s, np.array([0.0, 0.5]), np.c_[[0.1, 0.5]])
    0.1
    """
    if not len(times):
        return 0.0
    angle = 1.0 if type.is_rotation else 0.0
    errors = max_errors(held_values(spline, times, type.is_rotation), values, angle)
    worst = float(np.max(errors))
    return float(np.degrees(worst)) if type.is_rotation else worst


@dataclass(frozen=True)
class Rereduction:
    """A track re-reduced from its takes (:func:`rereduced`): the ``source`` track, the
    new ``track``, and its largest ``error`` from the samples it keeps (the type's unit)."""

    source: ContinuousTrack
    track: ContinuousTrack
    error: float


def rereduced(track: ContinuousTrack, tol: float, order: int, method: str = METHOD) -> Rereduction:
    """``track`` reduced again from its raw takes within ``tol`` (never from its curve,
    by the reducer's ``method``), with its largest error from the samples it keeps.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 1, 121)
    >>> track = recorded_over("a.x", FLOAT, None, Take(t, np.c_[np.sin(3 * t)]), 0.0005, 4)
    >>> made = rereduced(track, 0.01, 4)
    >>> made.track.n_coefficients < track.n_coefficients, made.error <= 0.01
    (True, True)
    """
    if not track.takes:
        raise ArgumentError("track", f"{track.path}: has no takes to re-reduce it from")
    made = composition(track.type, track.takes, tol, order, method)
    new = ContinuousTrack(track.path, track.type, made.curve, float(tol), track.takes)
    return Rereduction(track, new, largest_error(track.type, made.curve, made.times, made.targets))


def recomposed(track: ContinuousTrack, takes: Sequence[Take] | None = None, tol: float | None = None,
               order: int = 4) -> ContinuousTrack:
    """``track`` composed again (:func:`compose`) from ``takes`` (its own if None) within
    ``tol`` (its own if None): hand edits of its curve are dropped. A track without
    takes (a curve made otherwise) cannot be: :class:`ArgumentError`.

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 1, 101)
    >>> track = recorded_over("a.x", FLOAT, None, Take(t, np.c_[np.sin(3 * t)]), 0.001, 4)
    >>> looser = recomposed(track, tol=0.01)
    >>> looser.tol, looser.n_coefficients < track.n_coefficients
    (0.01, True)
    """
    takes = track.takes if takes is None else tuple(takes)
    tol = track.tol if tol is None else float(tol)
    if not takes:
        raise ArgumentError("track", f"{track.path}: has no takes to compose it from")
    return ContinuousTrack(track.path, track.type, compose(track.type, takes, tol, order), tol, tuple(takes))


def resmoothed(track: ContinuousTrack, smoothing: float, order: int, index: int = -1) -> ContinuousTrack:
    """``track`` rebuilt from its raw takes (:func:`compose`, at its tolerance) with
    take ``index`` (the last by default) smoothed over ``smoothing`` seconds (0: not).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 1, 101)
    >>> track = recorded_over("a.x", FLOAT, None, Take(t, np.c_[t + 0.01 * (-1) ** np.arange(101)]), 0.002, 4)
    >>> smooth = resmoothed(track, 0.05, 4)
    >>> smooth.takes[0].smoothing, smooth.n_coefficients < track.n_coefficients
    (0.05, True)
    """
    if not track.takes:
        raise ArgumentError("track", f"{track.path}: has no takes to re-reduce")
    takes = list(track.takes)
    try:
        takes[index] = replace(takes[index], smoothing=smoothing)
    except IndexError:
        raise ArgumentError("index", f"{track.path}: has {len(takes)} takes, got {index}") from None
    return recomposed(track, takes, order=order)
