"""Pauses and breaks: where a take holds still, and where its velocity jumps.

The paper's algorithm smooths both away (its section 4): a hold comes out as a slow
wobble inside the tolerance, and the take-off of a jump as a rounded corner bought with
a cluster of control points. The reducers cut the take at what this module finds and
join the pieces so that a pause is exactly still and a break stays a corner
(:mod:`.splice`).

Detection runs sample by sample with a bounded look-ahead, so a stream and a whole take
find the same features:

* **pause**: a run of samples whose every channel stays in a band of twice the
  tolerance (for a rotation, a box in which every quaternion is within the angle of the
  box's centre) for at least ``min_pause`` seconds and ``3 * order`` samples, after a
  move: some channel spread over more than :data:`APPROACH` tolerances in the
  ``min_pause`` seconds up to the run (or the run starts the take). A channel that only
  drifts by a few tolerances is idling, and holds there would cost more than the smooth
  curve that follows the drift. The pause's value is the box's centre, fixed when the
  pause is found; the pause goes on while samples stay within tolerance of that value.
  Look-ahead: ``min_pause``; look-back: ``min_pause``.
* **break**: at sample ``c``, the velocity jumps by more than one tolerance per
  sampling interval, a single smooth cubic over the ``2w + 1`` samples around ``c``
  misses them by more than twice the tolerance, while two quadratics joined at ``c``
  (different slopes on each side) stay within it, and the jump is the largest within
  ``w`` samples. Look-ahead: ``w + 1`` samples. A corner where the motion stops dead
  (the ``w`` samples after it would fit a pause) is left to the pause, whose edges are
  corners too.

Features are at least ``2 * order`` samples apart, so every piece between two of them
has samples to fit. A pause may start at the take's first sample.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from sketchanim.errors import ArgumentError
from sketchanim.reducer.approximate import PASS
from sketchanim.reducer.metric import max_errors

FEATURE_KINDS = ("pause", "break", "gap", "jump")

#: Codes the scanner returns.
NOTHING, BREAK, PAUSE_START, PAUSE_END = 0, 1, 2, 3
#: A smooth cubic must miss by more than this (in tolerances) for a break.
SMOOTH_MISS = 2.0
#: A pause must follow motion over more than this many tolerances (or start the take).
APPROACH = 4.0
#: Slots of the scanner's integer state.
_I, _RUN, _SEG, _MODE, _A, _B, _AT, _FIRST = range(8)


@dataclass(frozen=True)
class FeatureOptions:
    """Which features the reducers look for, and their thresholds.

    Attributes
    ----------
    pauses, breaks : bool
        Look for pauses, for breaks.
    min_pause : float
        Shortest pause, in seconds (also at least ``3 * order`` samples).
    break_window : int
        Samples on each side of a break that must follow one smooth arc (``w``).
    jumps : bool
        :func:`sketchanim.reduce` cuts the take beforehand at its jumps (a value step
        over one interval, :func:`.gaps.find_jumps`) and bridges them; off, a step is
        bridged only where the curve swings beside it (as the stream, which finds no
        jumps, keeps it).
    gap : float or None
        :func:`sketchanim.reduce` also cuts the take where an interval is longer than
        this many median sampling intervals, and bridges it (:mod:`.gaps`); None (the
        default): an interval is bridged only where the curve would swing across it.

    >>> FeatureOptions(breaks=False).enabled
    True
    """

    pauses: bool = True
    breaks: bool = True
    min_pause: float = 0.5
    break_window: int = 4
    jumps: bool = True
    gap: float | None = None

    def __post_init__(self) -> None:
        if self.gap is not None and not (isinstance(self.gap, (int, float)) and not isinstance(self.gap, bool)
                                         and np.isfinite(self.gap) and self.gap > 1):
            raise ArgumentError("gap", f"must be a number of median sampling intervals above 1, or None, "
                                       f"got {self.gap}")
        if not (np.isfinite(self.min_pause) and self.min_pause > 0):
            raise ArgumentError("min_pause", f"must be a positive number of seconds, got {self.min_pause!r}")
        if isinstance(self.break_window, bool) or not isinstance(self.break_window, (int, np.integer)) \
                or self.break_window < 2:
            raise ArgumentError("break_window", f"must be an integer >= 2, got {self.break_window!r}")

    @property
    def enabled(self) -> bool:
        """Whether any feature is looked for."""
        return self.pauses or self.breaks

    @classmethod
    def of(cls, features: bool | FeatureOptions | None) -> FeatureOptions:
        """Options from a reducer's ``features`` argument: True (the defaults), False or
        None (off), or options.

        >>> FeatureOptions.of(False).enabled
        False
        """
        if isinstance(features, FeatureOptions):
            return features
        if features is None or features is False:
            return cls(pauses=False, breaks=False, jumps=False)
        if features is True:
            return cls()
        raise ArgumentError("features", f"must be True, False or FeatureOptions, got {features!r}")


@dataclass(frozen=True)
class Feature:
    """A feature found in a take.

    Attributes
    ----------
    kind : {"pause", "break", "gap", "jump"}
    start, end : float
        Its time span in seconds (equal for a break; a gap's is the interval without
        samples).
    """

    kind: str
    start: float
    end: float

    def to_dict(self) -> dict[str, object]:
        """The feature as plain JSON values.

        >>> Feature("break", 1.5, 1.5).to_dict()
        {'kind': 'break', 'start': 1.5, 'end': 1.5}
        """
        return {"kind": self.kind, "start": self.start, "end": self.end}


@njit(cache=True, error_model="numpy")
def _fit_miss(T: np.ndarray, X: np.ndarray, c: int, w: int, hinge: bool) -> float:
    """Largest residual (in tolerances, over channels) of the least-squares fit to samples
    ``c - w .. c + w`` of one cubic, or with ``hinge`` of two quadratics joined at ``c``."""
    n = 2 * w + 1
    width = T[c + w] - T[c - w]
    cols = 5 if hinge else 4
    A = np.empty((n, cols))
    for s in range(n):
        u = (T[c - w + s] - T[c]) / width
        A[s, 0] = 1.0
        A[s, 1] = u
        A[s, 2] = u * u
        if hinge:
            v = max(u, 0.0)
            A[s, 3] = v
            A[s, 4] = v * v
        else:
            A[s, 3] = u * u * u
    B = np.ascontiguousarray(X[c - w : c + w + 1])
    coef = np.linalg.lstsq(A, B)[0]
    return np.abs(A @ coef - B).max()


@njit(cache=True, error_model="numpy")
def _jump(T: np.ndarray, X: np.ndarray, c: int) -> float:
    """Velocity change at sample ``c`` times the mean sampling interval, in tolerances."""
    h0 = T[c] - T[c - 1]
    h1 = T[c + 1] - T[c]
    h = 0.5 * (h0 + h1)
    out = 0.0
    for j in range(X.shape[1]):
        out = max(out, abs((X[c + 1, j] - X[c, j]) / h1 - (X[c, j] - X[c - 1, j]) / h0) * h)
    return out


@njit(cache=True, error_model="numpy")
def _span(X: np.ndarray, a: int, b: int, j: int) -> tuple[float, float]:
    """Least and greatest value of channel ``j`` over samples ``a .. b``."""
    lo = X[a, j]
    hi = X[a, j]
    for s in range(a + 1, b + 1):
        lo = min(lo, X[s, j])
        hi = max(hi, X[s, j])
    return lo, hi


@njit(cache=True, error_model="numpy")
def _wide(X: np.ndarray, a: int, b: int, band: float) -> bool:
    """Whether some channel spreads over more than ``band`` on samples ``a .. b``."""
    for j in range(X.shape[1]):
        lo, hi = _span(X, a, b, j)
        if hi - lo > band:
            return True
    return False


@njit(cache=True, error_model="numpy")
def _arrives(T: np.ndarray, X: np.ndarray, r: int, before: float, start: float) -> bool:
    """Whether a still run from sample ``r`` is a stop: the take starts there (at time
    ``start``), or some channel moved over more than :data:`APPROACH` tolerances in the
    ``before`` seconds up to it."""
    if T[r] == start:
        return True
    s = r
    while s > 0 and T[s - 1] >= T[r] - before:
        s -= 1
    return _wide(X, s, r, APPROACH)


@njit(cache=True, error_model="numpy")
def scan_features(T: np.ndarray, X: np.ndarray, n: int, st: np.ndarray, jumps: np.ndarray, p: np.ndarray,
         half_band: float, min_pause: float, min_count: int, gap: int, w: int, pauses: bool,
         breaks: bool, start: float) -> int:
    """Advance the detector over samples ``st[_I] .. n - 1`` of ``T``, ``X`` (values in
    tolerances), stopping after the first feature event (its code is returned; 0 when
    the samples ran out). ``st`` is the integer state (see the ``_I`` .. ``_FIRST`` slots),
    ``jumps[c]`` caches :func:`_jump`, ``p`` is the pause value."""
    d = X.shape[1]
    while st[_I] < n:
        i = st[_I]
        if st[_MODE] == 1:
            inside = True
            for j in range(d):
                if abs(X[i, j] - p[j]) > half_band * PASS:
                    inside = False
            if inside:
                st[_B] = i
                st[_I] = i + 1
                continue
            st[_MODE] = 0
            st[_SEG] = st[_B]
            st[_RUN] = i
            return PAUSE_END
        st[_I] = i + 1
        if pauses:
            # a pause starts at the take's first sample, or gap samples after a feature
            r = max(st[_RUN], st[_SEG] + (0 if st[_FIRST] else gap))
            while r <= i and _wide(X, r, i, 2.0 * half_band * PASS):
                r += 1
            st[_RUN] = r
            if r <= i and i - r + 1 >= min_count and T[i] - T[r] >= min_pause:
                if _arrives(T, X, r, min_pause, start):
                    for j in range(d):
                        lo, hi = _span(X, r, i, j)
                        p[j] = 0.5 * (lo + hi)
                    st[_MODE] = 1
                    st[_A] = r
                    st[_B] = i
                    st[_FIRST] = 0
                    return PAUSE_START
                # idling, not stopping: slide the run along (it stays min_pause long, so
                # the look-back, the look-ahead and the work per sample stay bounded)
                st[_RUN] = r + 1
        if breaks and i >= 2:
            jumps[i - 1] = _jump(T, X, i - 1)
            c = i - 1 - w
            if c >= st[_SEG] + max(gap, w) and jumps[c] > 1.0:
                peak = True
                for q in range(c - w, c + w + 1):
                    if jumps[q] > jumps[c] or (q < c and jumps[q] == jumps[c]):
                        peak = False
                        break
                if pauses and peak:
                    # Stopping dead: if the samples after c would fit a pause, the pause
                    # (if it lasts) keeps the corner at its start.
                    peak = _wide(X, c, c + w, 2.0 * half_band * PASS)
                if peak and _fit_miss(T, X, c, w, False) > SMOOTH_MISS and _fit_miss(T, X, c, w, True) <= 1.0:
                    st[_SEG] = c
                    st[_AT] = c
                    st[_FIRST] = 0
                    return BREAK
    return NOTHING


class FeatureDetector:
    """Find pauses and breaks in samples as they arrive, and say which samples go where.

    :meth:`extend` and :meth:`close` return *operations* for a segmenting reducer, in
    order: ``("samples", t, x)`` (add these samples to the current piece), ``("break",
    time, value)`` (end the piece at its last sample, on ``value``, the sample's own;
    the next starts there, from it), ``("hold", time, value)`` (end the piece at its
    last sample, at ``time``, on ``value``; the curve holds it from there) and
    ``("resume", time)`` (the hold ends; the next piece starts there, from ``value``). A sample at a break or at either end
    of a pause belongs to both pieces. :attr:`found` lists the features settled so far.

    Parameters
    ----------
    dim : int
    tol : ndarray, shape (dim,)
        Tolerance per channel.
    order : int
        Spline order of the reducer (features are ``2 * order`` samples apart).
    options : FeatureOptions
    angle : float
        If > 0, the four channels are a quaternion whose rotation angle is the bound,
        with ``tol = sin(angle / 2)``: the pause box is then half as wide, so that every
        sample in it is within the angle of its centre.

    Examples
    --------
    >>> t = np.linspace(0, 2, 201)
    >>> x = np.c_[np.where(t < 1, t, 1.0)]           # moves, then holds from t = 1
    >>> det = FeatureDetector(1, np.array([0.01]), 4, FeatureOptions())
    >>> ops = det.extend(t, x) + det.close()
    >>> [(op[0], round(op[1], 2)) for op in ops if op[0] != "samples"]
    [('hold', 0.99), ('resume', 2.0)]
    >>> [(f.kind, round(f.start, 2), f.end) for f in det.found]
    [('pause', 0.99, 2.0)]
    """

    def __init__(self, dim: int, tol: np.ndarray, order: int, options: FeatureOptions, *,
                 angle: float = 0.0) -> None:
        self.options = options
        self.angle = angle
        self.tol = np.asarray(tol, dtype=float)
        self.gap = 2 * order
        self.min_count = 3 * order
        self.w = options.break_window
        self.half_band = 0.5 if angle else 1.0
        # samples in the look-ahead and look-back, in a store that grows by doubling
        # and slides down as old samples are dropped (values centred, in tolerances)
        self._n = 0
        self._t = np.empty(1024)
        self._x = np.empty((1024, dim))
        self._jumps = np.empty(1024)
        self._center: np.ndarray | None = None
        self._start = 0.0                        # the take's first time
        self._st = np.zeros(8, dtype=np.int64)
        self._st[_FIRST] = 1
        self._p = np.zeros(dim)
        self._released = 0                       # buffer index of the first sample not handed out
        self._hold: tuple[float, int] = (0.0, 0)    # the pause's start time, its first sample not measured
        self.found: list[Feature] = []
        #: Largest error of the samples in pauses so far (per channel, or the angle)
        self.pause_error = np.zeros(1 if angle else dim)

    @property
    def pending(self) -> int:
        """Samples held back for the look-ahead."""
        return self._n - self._released

    @property
    def stored(self) -> int:
        """Samples kept for the look-ahead and the look-back (bounded however long the
        take, even while it holds still)."""
        return self._n

    def _grow(self, t: np.ndarray, x: np.ndarray) -> None:
        if self._center is None:
            self._center = x[0].copy()
            self._start = float(t[0])
        n, m = self._n, len(t)
        if n + m > len(self._t):
            size = max(2 * len(self._t), n + m)
            self._t = np.r_[self._t[:n], np.empty(size - n)]
            self._x = np.r_[self._x[:n], np.empty((size - n, x.shape[1]))]
            self._jumps = np.r_[self._jumps[:n], np.empty(size - n)]
        self._t[n : n + m] = t
        self._x[n : n + m] = (x - self._center) / self.tol
        self._jumps[n : n + m] = 0.0
        self._n = n + m

    def _hand_out(self, upto: int) -> list[tuple]:
        """Samples ``_released .. upto - 1`` as a samples operation."""
        if upto <= self._released:
            return []
        s = slice(self._released, upto)
        self._released = upto
        return [("samples", self._t[s].copy(), self._units(self._x[s]))]

    def _forget(self) -> None:
        """Drop samples no decision looks at any more, shifting the state's indices."""
        st = self._st
        keep_from = min(self._released, int(st[_I]) - 2 * self.w - 2)
        if keep_from < 4096 and keep_from < self._n // 2:
            return                                   # not worth sliding yet
        if st[_MODE] == 0:                           # the look-back of a still run's start
            run = min(int(st[_RUN]), self._n - 1)
            keep_from = min(keep_from, int(np.searchsorted(self._t[: self._n], self._t[run] - self.options.min_pause)))
        drop = max(keep_from, 0)
        left = self._n - drop
        for store in (self._t, self._x, self._jumps):
            store[:left] = store[drop : self._n]
        self._n = left
        self._released -= drop
        st[_I] -= drop
        st[_RUN] = max(st[_RUN] - drop, 0)
        st[_SEG] -= drop
        st[_A] -= drop
        st[_B] -= drop
        self._hold = (self._hold[0], self._hold[1] - drop)

    def extend(self, t: np.ndarray, x: np.ndarray) -> list[tuple]:
        """Take checked samples ``t`` (n,), ``x`` (n, dim); return the operations they settle."""
        if not len(t):
            return []
        self._grow(np.asarray(t, dtype=float), np.asarray(x, dtype=float))
        ops: list[tuple] = []
        o = self.options
        st = self._st
        while True:
            event = scan_features(self._t, self._x, self._n, st, self._jumps, self._p, self.half_band, o.min_pause,
                         self.min_count, self.gap, self.w, o.pauses, o.breaks, self._start)
            if event == NOTHING:
                break
            ops += self._settle(event)
        if st[_MODE] == 0:
            # Samples before the earliest possible feature point are settled.
            ops += self._hand_out(max(self._released, min(int(st[_RUN]), int(st[_I]) - self.w - 1)))
        else:
            self._measure(int(st[_B]) + 1)
        self._forget()
        return ops

    def _settle(self, event: int) -> list[tuple]:
        st = self._st
        if event == BREAK:
            c = int(st[_AT])
            ops = self._hand_out(c + 1) + [("break", float(self._t[c]), self._units(self._x[c]))]
            self._released = c
            self.found.append(Feature("break", float(self._t[c]), float(self._t[c])))
            return ops
        if event == PAUSE_START:
            a = int(st[_A])
            self._hold = (float(self._t[a]), a)
            return self._hand_out(a + 1) + [("hold", float(self._t[a]), self._value())]
        return self._resume() + self._hand_out(int(st[_I]))

    def _units(self, x: np.ndarray) -> np.ndarray:
        """Values kept centred and in tolerances, back in the caller's units."""
        return x * self.tol + self._center

    def _value(self) -> np.ndarray:
        """The pause's value, in the caller's units."""
        return self._units(self._p)

    def _measure(self, upto: int) -> None:
        """Count the errors of the pause's samples up to ``upto`` in :attr:`pause_error`."""
        s = slice(self._hold[1], upto)
        if upto <= self._hold[1]:
            return
        x = self._units(self._x[s])
        err = max_errors(np.broadcast_to(self._value(), x.shape), x, self.angle)
        np.maximum(self.pause_error, err, out=self.pause_error)
        self._hold = (self._hold[0], upto)
        self._released = max(self._released, upto - 1)   # the hold stands for them

    def _resume(self) -> list[tuple]:
        """End the pause at its last sample ``b``; the next piece starts there."""
        b = int(self._st[_B])
        self._measure(b + 1)
        self.found.append(Feature("pause", self._hold[0], float(self._t[b])))
        self._released = b
        return [("resume", float(self._t[b]))]

    def close(self) -> list[tuple]:
        """End of the take: the operations for the samples still held."""
        if self._st[_MODE] == 1:
            self._st[_MODE] = 0
            ops = self._resume()
            self._released = self._n
            return ops
        return self._hand_out(self._n)


def detect(times: np.ndarray, values: np.ndarray, tol: np.ndarray, order: int, options: FeatureOptions, *,
           angle: float = 0.0) -> tuple[list[tuple], list[Feature]]:
    """The operations of :class:`FeatureDetector` for a whole take (checked samples),
    and the features found.

    >>> t = np.linspace(0, 1, 101)
    >>> x = np.c_[np.abs(t - 0.5)]                   # a V: one corner at 0.5
    >>> detect(t, x, np.array([1e-3]), 4, FeatureOptions())[1]
    [Feature(kind='break', start=0.5, end=0.5)]
    """
    det = FeatureDetector(values.shape[1], tol, order, options, angle=angle)
    ops = det.extend(times, values) + det.close()
    return ops, det.found
