"""The incremental reducer: samples in as they arrive, finished curve pieces out.

The paper's windowed Lyche-Morken (section 2.2), with its guarantee made exact. Every
sample time is a knot of the initial curve. Once ``2k + m`` knots follow the start of the
window (``k`` the order, ``m`` the window), the ``m`` knots after the first ``k`` (past
context, already reduced) are candidates; the last ``k`` (future context) are not. The
window's coefficients are fitted by least squares to the raw samples under them, the
curve left of the window held, and knots are removed while every one of those samples
stays within tolerance. Then the window start moves past the surviving candidates, so
each knot is considered once, and the coefficients left behind are final.

What is kept is bounded whatever the take's length: the raw samples from the window's
start on (a removal that would put more than ``max_span`` samples between two knots is
refused, so the past context holds at most ``order * max_span``), the knots and
coefficients of the window, and optionally the finished curve (``keep``).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline, insert

from sketchanim.errors import ArgumentError, SampleError
from sketchanim.reducer import window_kernel
from sketchanim.reducer.conditioning import (MAX_SPAN, MAX_WINDOW, check_angle, check_count, check_order,
                                             check_tolerance, scan_samples)
from sketchanim.reducer.features import Feature, FeatureDetector, FeatureOptions
from sketchanim.reducer.metric import max_errors
from sketchanim.reducer.result import Reduction
from sketchanim.reducer.splice import hold, join
from sketchanim.reducer.starts import held_interpolant
from sketchanim.reducer.straighten import straightened
from sketchanim.reducer.swing import check_bounds, outside

#: Window constraint variants of the paper's figures 1 and 2.
CONSTRAINTS = ("end", "none", "pin", "pin+end")
REFERENCES = ("samples", "curve")


@dataclass(frozen=True)
class Piece:
    """A finished stretch of the curve: nothing later changes it.

    Attributes
    ----------
    knots : ndarray, shape (n + order,)
    coef : ndarray, shape (n, d)
        B-spline coefficients in the caller's units. The piece is the spline they
        define, on ``[start, end]``; consecutive pieces share their coefficients
        that act on both and join with the curve's continuity at the shared time.
    """

    knots: np.ndarray
    coef: np.ndarray

    @property
    def order(self) -> int:
        """Spline order."""
        return len(self.knots) - len(self.coef)

    @property
    def start(self) -> float:
        """Time where the piece starts."""
        return float(self.knots[self.order - 1])

    @property
    def end(self) -> float:
        """Time where the piece ends (the next piece starts there)."""
        return float(self.knots[len(self.coef)])

    @property
    def spline(self) -> BSpline:
        """The piece as a scipy spline, valid on ``[start, end]``."""
        return BSpline(self.knots, self.coef, self.order - 1)

    def trimmed(self) -> Piece:
        """The same piece without trailing coefficients that act only after ``end``.

        A piece that ends at a repeated knot (a C0 join) would otherwise end on an
        interval of zero length, where a spline evaluator finds no curve.
        """
        k, n = self.order, len(self.coef)
        while n > k and self.knots[n - 1] == self.knots[n]:
            n -= 1
        return Piece(self.knots[: n + k], self.coef[:n])


@dataclass
class StreamStats:
    """What the reducer did so far.

    Window times and removal counts are kept for the most recent ``history`` windows
    (so memory stays flat on endless streams); the counters cover the whole stream:
    ``straightened`` counts intervals made straight (:mod:`.straighten`), ``cuts`` the
    segments cut for them.
    """

    history: int = 65536
    windows: int = 0
    fits: int = 0
    removed: int = 0
    samples: int = 0
    duplicates_dropped: int = 0
    start_misses: int = 0
    straightened: int = 0
    cuts: int = 0
    max_window_seconds: float = 0.0
    total_window_seconds: float = 0.0
    _seconds: np.ndarray = field(init=False, repr=False)
    _removed: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._seconds = np.zeros(self.history)
        self._removed = np.zeros(self.history, dtype=np.int32)

    def record(self, seconds: float, removed: int, fits: int) -> None:
        """Count one window."""
        slot = self.windows % self.history
        self._seconds[slot] = seconds
        self._removed[slot] = removed
        self.windows += 1
        self.fits += fits
        self.removed += removed
        self.total_window_seconds += seconds
        self.max_window_seconds = max(self.max_window_seconds, seconds)

    def _recent(self, ring: np.ndarray) -> np.ndarray:
        """The filled part of a ring of per-window values, oldest first."""
        if self.windows <= self.history:
            return ring[: self.windows].copy()
        slot = self.windows % self.history
        return np.r_[ring[slot:], ring[:slot]]

    @property
    def window_seconds(self) -> np.ndarray:
        """Wall time of the recent windows, oldest first."""
        return self._recent(self._seconds)

    @property
    def removed_per_window(self) -> np.ndarray:
        """Knots removed by each of the recent windows, oldest first."""
        return self._recent(self._removed)

    def percentile_ms(self, q: float) -> float:
        """Percentile ``q`` (0-100) of the recent windows' wall time, in milliseconds."""
        times = self.window_seconds
        return float(np.percentile(times, q) * 1e3) if len(times) else 0.0


class _Rows:
    """Rows appended to one array that grows by doubling: the finished curve's knots or
    coefficients, copied in, so that no window's arrays stay alive behind views (a kept
    curve costs its own numbers, not a Python object per window).

    >>> r = _Rows(2); r.append(np.ones((3, 2))); r.append(np.zeros((1, 2))); r.array().shape
    (4, 2)
    """

    def __init__(self, width: int | None) -> None:
        self._store = np.empty((64,) if width is None else (64, width))
        self.n = 0

    def append(self, rows: np.ndarray) -> None:
        m = len(rows)
        if self.n + m > len(self._store):
            grown = np.empty((max(2 * len(self._store), self.n + m),) + self._store.shape[1:])
            grown[: self.n] = self._store[: self.n]
            self._store = grown
        self._store[self.n : self.n + m] = rows
        self.n += m

    def array(self) -> np.ndarray:
        """The rows so far (a copy)."""
        return self._store[: self.n].copy()


def _took_all(out: tuple) -> bool:
    """Whether a window (the result of :func:`window_kernel.window_step`) removed
    knots with its first trial and tried no other: its start fit and one more."""
    return out[2] > 0 and out[3] == 2


def _with_knot(knots: np.ndarray, coef: np.ndarray, order: int, at: float, multiplicity: int
               ) -> tuple[np.ndarray, np.ndarray]:
    """The same curve with the knot ``at`` raised to ``multiplicity`` (knot insertion;
    the knot vector need not be clamped).

    >>> t, c = _with_knot(np.r_[[0.0] * 4, [2.0] * 4], np.c_[[0.0, 1.0, 3.0, 2.0]], 4, 1.0, 3)
    >>> t.tolist()
    [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0]
    """
    missing = multiplicity - int(np.count_nonzero(knots == at))
    if missing <= 0:
        return knots, coef
    refined = insert(at, BSpline(knots, coef, order - 1), m=missing)
    t = np.asarray(refined.t)
    return t, np.asarray(refined.c)[: len(t) - order]                 # scipy pads c to len(t)


class StreamReducer:
    """Reduce samples while they arrive, a window of knots at a time.

    Parameters
    ----------
    dim : int
        Channels per sample.
    tol : float or array_like, shape (dim,)
        Tolerance per channel: every sample ends within it of the curve at its own time.
    order : int
        Spline order (4: cubic).
    window : int
        Candidate knots per window (the paper's m), at least ``max(1, order // 2)``.
    constraints : {"end", "none", "pin", "pin+end"}
        How a window meets its neighbours. The curve left of the window is always held
        exactly (its coefficients are final), so a window never moves finished samples.
        ``end``: the samples under the future context must stay within ``end_tol``
        tolerances, which leaves the next window room to remove knots. ``none``: no
        more. ``pin`` and ``pin+end`` are the paper's variants: also hold the first
        ``order`` coefficients of the window at the previous window's values (their
        B-splines still change as knots go, so this costs control points; measured
        by ``sketchanim paper``). The tolerance holds in every variant.
    end_tol : float
        Share of the tolerance for the future context with ``end`` and ``pin+end``,
        in (0, 1].
    reference : {"samples", "curve"}
        Fit and check against the raw samples (the guarantee), or, as the paper did,
        against the window's starting curve, so that errors can creep across windows
        (for reproducing the paper; ``max_error`` then tells the truth).
    max_span : int or None
        Most samples allowed between two knots; bounds memory and window time.
        Default ``max(64, 8 * window)``.
    exhaustive_below : int
        Windows with fewer candidates try every removal count; larger ones bisect.
    minimax_iterations : int
        Lawson re-weightings when a fit misses by a little (0: plain least squares).
    keep : bool
        Keep the finished curve so that :meth:`finish` can return it; with False only
        :attr:`on_piece` sees it and memory stays flat however long the take.
    on_piece : callable or None
        Called with each finished :class:`Piece`, in time order.
    angle : float or None
        If given, the four channels are a quaternion and what every sample keeps is its
        rotation: the curve's value, normalised, within ``angle`` radians of it
        (:mod:`.metric`); ``tol`` then only scales the fit (``sin(angle / 2)`` suits),
        and :attr:`max_error` is that one angle.
    features : bool or FeatureOptions
        Find pauses and breaks while samples arrive (:mod:`.features`; True: the
        default thresholds, False: off). The take is cut there: a pause comes out as a
        constant piece, a break as a corner (a knot of multiplicity ``order - 1``).
        Samples then reach the windows up to ``min_pause`` seconds late.
    bounds : (low, high) or None
        Bounds of the channels (each a number or ``dim`` numbers; ±inf: unbounded). A
        sample outside them is refused (:class:`~sketchanim.errors.SampleError`).
    grow : bool
        Let windows grow where the motion is smooth, for reducing a whole take: after a
        window whose first trial removed every candidate it could, the next takes twice
        as many candidates, up to ``max_span`` (at most 1024); a grown window whose
        first trial fails is done again at ``window``. Where knots are far apart, a
        window's time is mostly its past context, so a grown window costs little more
        than one of ``window`` and smooth, densely sampled takes go several times
        faster; but pieces come out later (up to ``max_span`` samples), so live display
        leaves it off.

    A removal is accepted only if, besides every sample staying within tolerance, the
    window's curve leaves the no-swing range of no interval between samples
    (:func:`sketchanim.reducer.swing.local_ranges`: the four samples around it widened
    by the tolerance, cut to ``bounds``; with ``angle``, widened by ``2 sin(angle / 4)``
    per component, the most a unit quaternion within ``angle`` of a sample differs from
    it) further than the window's starting curve, its interpolant, does there.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 10, 1201)
    >>> pieces = []
    >>> sr = StreamReducer(2, 0.01, window=20, on_piece=pieces.append)
    >>> for ti, xi in zip(t, np.c_[np.sin(t), np.cos(t)]):
    ...     sr.push(ti, xi)
    >>> len(pieces) > 0, pieces[-1].end < 10.0          # finished while samples arrive
    (True, True)
    >>> r = sr.finish()
    >>> bool(np.all(r.max_error <= 0.01)), r.n_coefficients < 40
    (True, True)
    """

    def __init__(
        self,
        dim: int,
        tol: float | ArrayLike,
        *,
        order: int = 4,
        window: int = 20,
        constraints: str = "end",
        end_tol: float = 0.5,
        reference: str = "samples",
        max_span: int | None = None,
        exhaustive_below: int = 32,
        minimax_iterations: int = 1,
        keep: bool = True,
        on_piece: Callable[[Piece], object] | None = None,
        angle: float | None = None,
        features: bool | FeatureOptions = True,
        bounds: tuple[ArrayLike, ArrayLike] | None = None,
        grow: bool = False,
    ) -> None:
        self.dim = check_count("dim", dim, 1)
        self.tol = check_tolerance(tol, self.dim)
        self.angle = check_angle(angle, self.dim)
        self.bounds = check_bounds(bounds, self.dim)
        #: how far a curve may leave its samples' range between them (the tolerance)
        self._widen = np.full(self.dim, 2.0 * np.sin(self.angle / 4.0)) if self.angle else self.tol
        self.order = k = check_order(order)
        self.window = check_count("window", window, max(1, k // 2), MAX_WINDOW)
        if constraints not in CONSTRAINTS:
            raise ArgumentError("constraints", f"must be one of {', '.join(CONSTRAINTS)}, got {constraints!r}")
        if reference not in REFERENCES:
            raise ArgumentError("reference", f"must be one of {', '.join(REFERENCES)}, got {reference!r}")
        if not 0.0 < end_tol <= 1.0:
            raise ArgumentError("end_tol", f"must be in (0, 1], got {end_tol!r}")
        self.constraints = constraints
        self.end_tol = float(end_tol) if constraints.endswith("end") else 1.0
        self.reference = reference
        self._curve_reference = reference == "curve"
        self.max_span = check_count("max_span", max(64, 8 * self.window) if max_span is None else max_span, 2, MAX_SPAN)
        self.exhaustive_below = check_count("exhaustive_below", exhaustive_below, 0)
        self.minimax_iterations = check_count("minimax_iterations", minimax_iterations, 0)
        self.keep = keep
        self.on_piece = on_piece
        self.stats = StreamStats()
        #: most candidate knots a window takes
        self.max_window = max(self.window, min(self.max_span, MAX_WINDOW)) if grow else self.window
        #: Most raw samples ever held: the past context, the window and its tail.
        self.buffer_bound = k * self.max_span + self.max_window + 2 * k
        # The held samples are the first _bn of the views _bt, _bx, which slide along
        # a store of twice the bound, so dropping finished samples copies nothing
        # until the views reach the store's end.
        self._store_t = np.empty(2 * self.buffer_bound)
        self._store_x = np.empty((2 * self.buffer_bound, self.dim))
        self._b0 = 0
        self._bt = self._store_t[: self.buffer_bound]
        self._bx = self._store_x[: self.buffer_bound]
        self._previous: tuple[float, np.ndarray] | None = None
        self._reference: np.ndarray | None = None    # the first sample: values stay in range of it
        self._pushed = 0
        self._taken = 0
        self._max_error = np.zeros(1 if self.angle else self.dim)
        self.features = FeatureOptions.of(features)
        self._detector = FeatureDetector(self.dim, self.tol, k, self.features, angle=self.angle) \
            if self.features.enabled else None
        self._segments: list[BSpline] = []           # finished pieces between features (keep)
        self._pause: tuple[float, np.ndarray] | None = None
        self._closed = False
        self._begin(None)

    def _begin(self, start: np.ndarray | None) -> None:
        """Start a piece of the take (at its start, or after a feature), from ``start``
        (the value its first coefficient keeps) or free."""
        k = self.order
        self._bn = 0
        self._origin: float | None = None
        self._center = np.zeros(self.dim)
        self._start_value = start
        #: window coefficients after the past context still holding the start value
        self._start_held = 0 if start is None else 1
        self._before = np.zeros((0, self.dim))       # the sample before the held ones (scaled)
        self._end_value: np.ndarray | None = None
        self._seg_n = 0
        self._last_t = 0.0
        # What the last window left to the next: its knots from the first that acts on
        # the next window (local index k - 1 is its start), through its clamped end, and
        # their coefficients; before any window, a clamped start at time 0.
        self._left = (np.zeros(3 * k - 1), np.zeros((2 * k - 1, self.dim)))
        self._pinned = False                         # a window has run
        # Buffer index of the first sample that is not a knot yet. As in the paper's
        # initial curve (knots t_3 .. t_n-2 for a cubic), the first ``order // 2``
        # samples of the take and the last ``order - order // 2`` held are not knots:
        # the knots then sit centred on the coefficients they separate, which keeps the
        # window's least squares well conditioned.
        self._next_knot = k // 2
        self._m = self.window                        # candidate knots of the next window
        self._free_tail = k - k // 2                # the last held samples not yet knots
        self._held: tuple[np.ndarray, np.ndarray] | None = None
        self._joint: np.ndarray | None = None         # the value a cut segment ended on
        self._final_knots = _Rows(None)
        self._final_coef = _Rows(self.dim)

    # -- input -------------------------------------------------------------------------

    def push(self, t: float, x: ArrayLike) -> None:
        """Add one sample (time in seconds, ``dim`` values).

        Raises :class:`~sketchanim.errors.SampleError` (naming the sample's index in the
        stream) for a NaN or infinite time or value, or time going backwards; the
        reducer is unchanged by a bad sample and takes the next one.
        """
        self.extend(np.array([t], dtype=float), np.asarray(x, dtype=float).reshape(1, -1))

    def extend(self, times: ArrayLike, values: ArrayLike) -> None:
        """Add samples ``times`` (n,) and ``values`` (n, dim) in time order.

        If one is bad, the samples before it are taken, then the error is raised
        (naming its index in the stream); the reducer stays usable.
        """
        if self._closed:
            raise ArgumentError("push", "the stream is finished")
        t = np.asarray(times, dtype=float).reshape(-1)
        x = np.asarray(values, dtype=float)
        if x.ndim == 1 and self.dim == 1:
            x = x[:, None]
        if x.ndim != 2 or x.shape != (len(t), self.dim):
            raise ArgumentError("values", f"needs shape ({len(t)}, {self.dim}), got {x.shape}")
        if self._reference is None and len(x) and np.all(np.isfinite(x[0])):
            self._reference = x[0].copy()
        keep, error = scan_samples(t, x, offset=self._pushed, previous=self._previous, tol=self.tol,
                           reference=self._reference)
        good = len(keep)
        bad = outside(x[:good], self.bounds)
        if bad is not None:
            assert self.bounds is not None
            good, keep = bad, keep[:bad]
            error = SampleError(f"value {x[bad].tolist()} is outside the bounds [{self.bounds[0].tolist()}, "
                                f"{self.bounds[1].tolist()}]", index=self._pushed + bad, field="values")
        if good:
            self._pushed += good
            self._previous = (float(t[good - 1]), x[good - 1].copy())
            self.stats.duplicates_dropped += int(good - np.count_nonzero(keep))
            self._ingest(t[:good][keep], x[:good][keep])
        if error is not None:
            self._pushed += 1
            raise error

    def skip(self) -> None:
        """Count one sample that the caller rejected before it reached the reducer, so
        that the stream indices in later errors stay the caller's."""
        self._pushed += 1

    def _ingest(self, t: np.ndarray, x: np.ndarray) -> None:
        self._taken += len(t)
        if self._detector is None:
            self._feed(t, x)
            return
        for op in self._detector.extend(t, x):
            self._apply(op)

    def _apply(self, op: tuple) -> None:
        """Carry out one operation of the feature detector."""
        kind = op[0]
        if kind == "samples":
            self._feed(op[1], op[2])
            return
        # A break's or a pause's value, in the bounds: closer to every sample there.
        value = None if len(op) < 3 else op[2] if self.bounds is None else np.clip(op[2], *self.bounds)
        if kind == "break":
            self._end(value)
            self._begin(value)
        elif kind == "hold":
            self._end(value)
            self._pause = (op[1], value)
        else:
            assert self._pause is not None
            start, value = self._pause
            still = hold(start, op[1], value, self.order)
            if self.keep:
                self._segments.append(still)
            if self.on_piece is not None:
                self.on_piece(Piece(np.asarray(still.t), np.asarray(still.c)))
            self._begin(value)

    def _end(self, value: np.ndarray | None) -> None:
        """End the current piece at its last sample, on ``value`` (or free)."""
        n = self._seg_n
        if n == 0 or (n == 1 and (self._start_value is not None or value is not None)):
            return                                   # only the sample it shares with a neighbour
        self._end_value = value
        if n < self.order:
            self._close_short()
        else:
            self._run_window(final=True)
        if self.keep:
            self._segments.append(BSpline(self._final_knots.array(), self._final_coef.array(), self.order - 1))

    def _feed(self, t: np.ndarray, x: np.ndarray) -> None:
        """Add checked samples to the current piece's windows."""
        if not len(t):
            return
        self._seg_n += len(t)
        self._last_t = float(t[-1])
        if self._origin is None:
            self._origin = float(t[0])
            self._center = x[0].copy() if self._start_value is None else self._start_value.copy()
        t = t - self._origin
        x = (x - self._center) / self.tol
        done = 0
        while done < len(t):
            take = min(self.buffer_bound - self._bn, len(t) - done)
            self._bt[self._bn : self._bn + take] = t[done : done + take]
            self._bx[self._bn : self._bn + take] = x[done : done + take]
            self._bn += take
            done += take
            self.stats.samples += take
            while self._bn - self._free_tail - self._next_knot >= self._needed():
                self._run_window(final=False)

    # -- windows -----------------------------------------------------------------------

    @property
    def _kt(self) -> np.ndarray:
        """The knots the next window starts from: through the last window's last knot."""
        return self._left[0][: -self.order]

    @property
    def _kc(self) -> np.ndarray:
        """The coefficients of the first ``2 * order - 1`` of them."""
        return self._left[1][: 2 * self.order - 1]

    def _scaled_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The channels' bounds in the windows' units (tolerances from the centre)."""
        if self.bounds is None:
            return np.full(self.dim, -np.inf), np.full(self.dim, np.inf)
        low, high = ((b - self._center) / self.tol for b in self.bounds)
        return low, high

    def _step(self, kt: np.ndarray, kc: np.ndarray, a: int, b: int, f0: int, f_back: int, final: bool) -> tuple:
        """One window from knots ``kt`` and coefficients ``kc`` (see
        :func:`window_kernel.window_step`), with this reducer's settings."""
        end = np.zeros((0, self.dim))
        if final and self._end_value is not None:
            end = ((self._end_value - self._center) / self.tol).reshape(1, -1)
        low, high = self._scaled_bounds()
        return window_kernel.window_step(
            self.order, kt, kc, self._bt, self._bx, self._bn, a, b, self._m, f0, f_back, self.end_tol, final,
            self.max_span, self.exhaustive_below, self.minimax_iterations, self._curve_reference,
            self._origin, self.tol, self._center, self.angle, end, self._before, self._widen / self.tol, low, high)

    def _needed(self) -> int:
        """Sample knots the next window takes (the future context is ``order`` knots)."""
        k = self.order
        return max(0, 2 * k + self._m - (len(self._kt) - (k - 1)))

    def _run_window(self, *, final: bool) -> None:
        clock = time.perf_counter()
        k = self.order
        a = self._next_knot
        b = max(a, self._bn - self._free_tail) if final else a + self._needed()
        f0 = 2 * k - 1 if (self._pinned and self.constraints.startswith("pin")) else k - 1
        f0 = max(f0, k - 1 + self._start_held)
        f_back = max(2 * k - 1 if self._pinned else f0, f0)
        out = self._step(self._kt, self._kc, a, b, f0, f_back, final)
        spent = 0                                      # fits of a grown window done again
        if not final and self._m > self.window and not _took_all(out):
            spent = out[3]
            self._m = self.window                      # harder motion: a window of ``window`` removes more there
            b = a + self._needed()
            out = self._step(self._kt, self._kc, a, b, f0, f_back, final)
        restarted = out[4] > window_kernel.PASS and self._pinned
        if restarted:
            self.stats.start_misses += 1
            out = self._restart(a, b, final)
        knots, coef, removed, fits, start, advance, done, err, piece_knots, piece_coef, lo, hi, swings = out
        n_final = len(swings) if final else done
        if np.any(swings[:n_final] > window_kernel.SWING_SLACK):
            knots, coef, advance, piece_knots, piece_coef = self._straighten(knots, coef, lo, hi, n_final, advance,
                                                                             final)
        if final:
            # The piece ends exactly at its last sample (origin + (t - origin) need not
            # be t), where a neighbour after a feature starts.
            piece_knots[-k:] = self._last_t
            if self._end_value is not None:
                piece_coef[-1] = self._end_value        # exactly, not to rounding
        if not final:
            self._m = min(2 * self._m, self.max_window) if _took_all(out) and not restarted else self.window
            self._left = (knots[advance:], coef[advance:])
            self._pinned = True
            self._start_held = max(0, self._start_held - advance)
            # The window's last knot is its last sample knot.
            self._next_knot = int(np.searchsorted(self._bt[: self._bn], self._kt[-1], side="right")) \
                if restarted else b
        if done:
            np.maximum(self._max_error, err, out=self._max_error)
            self._drop(done)
            self._next_knot -= done
        if advance > 0 and (self.keep or self.on_piece is not None):
            self._emit(piece_knots, piece_coef, final)
        self.stats.record(time.perf_counter() - clock, removed, fits + spent)

    def _straighten(self, knots: np.ndarray, coef: np.ndarray, lo: np.ndarray, hi: np.ndarray, n_final: int,
                    advance: int, final: bool) -> tuple:
        """The window's curve with its finished intervals that swing made straight
        (:mod:`.straighten`; rare: where no smooth curve through the knots can stay in
        range, as next to a step). Returns ``(knots, coef, advance, piece_knots,
        piece_coef)`` as :meth:`_run_window` uses them.

        A straight interval within ``order - 1`` knots of the window's start changes
        coefficients the piece before already handed out; the curve is then cut at the
        window's start (a C0 join, the curve unchanged) and goes on as a new segment.
        """
        k = self.order
        ts = self._bt[: len(lo) + 1]
        start = knots[k - 1]
        # The value at the start is the piece before's (or a held one); at a take's start it is free.
        opening = start == 0.0 and self._start_value is None          # local time 0: the piece's first sample
        fixed = ([] if opening else [start]) + ([ts[-1]] if final and self._end_value is not None else [])
        end = knots[k - 1 + advance]
        rk, rc, count = straightened(knots, coef, k, ts, lo, hi, n_final, fixed, movable=not self.angle)
        self.stats.straightened += count
        if not (np.array_equal(rk[: 2 * k - 1], knots[: 2 * k - 1]) and np.array_equal(rc[: k - 1], coef[: k - 1])):
            self._cut(knots, start)
            # From the window's start on, clamped there (a nodal coefficient), behind the
            # k - 1 coefficients of zero support that a segment's first window starts with.
            rk, rc = _with_knot(rk, rc, k, start, k - 1)
            r = int(np.searchsorted(rk, start, side="right"))
            rk = np.r_[[start] * (2 * k - 1), rk[r:]]
            rc = np.vstack([np.repeat(rc[r - k : r - k + 1], k - 1, axis=0), rc[r - k :]])
        stop = len(rc) if final else int(np.searchsorted(rk, end, side="left"))
        piece_coef = rc[:stop] * self.tol + self._center
        if self._joint is not None:                    # the cut segment ends on it, exactly
            piece_coef[: k] = self._joint
            self._joint = None
        return rk, rc, stop - (k - 1), rk[: stop + k] + self._origin, piece_coef

    def _cut(self, knots: np.ndarray, start: float) -> None:
        """End the kept segment at the window's ``start`` (local time), where the curve
        handed out so far ends: its kept coefficients on the kept knots and the window's
        next ``order`` knots, clamped there."""
        k = self.order
        self._held = None                              # it only closed intervals of zero length
        self.stats.cuts += 1
        if self.keep and self._final_coef.n:
            kt, kc = _with_knot(np.r_[self._final_knots.array(), knots[k - 1 : 2 * k - 1] + self._origin],
                                self._final_coef.array(), k, start + self._origin, k)
            i = int(np.searchsorted(kt, start + self._origin, side="left"))
            if i > k - 1:
                self._segments.append(BSpline(kt[: i + k], kc[:i], k - 1))
                self._joint = kc[i - 1].copy()
        self._final_knots = _Rows(None)
        self._final_coef = _Rows(self.dim)

    def _drop(self, done: int) -> None:
        """Forget the first ``done`` held samples (they are finished)."""
        self._before = self._bx[done - 1 : done].copy()
        self._bn -= done
        self._b0 += done
        if self._b0 > self.buffer_bound:
            live = slice(self._b0, self._b0 + self._bn)
            self._store_t[: self._bn] = self._store_t[live]
            self._store_x[: self._bn] = self._store_x[live]
            self._b0 = 0
        self._bt = self._store_t[self._b0 : self._b0 + self.buffer_bound]
        self._bx = self._store_x[self._b0 : self._b0 + self.buffer_bound]

    def _restart(self, a: int, b: int, final: bool) -> tuple:
        """The window again, when no fit of it from the held curve stays in tolerance
        (rare: wild samples right after the last window).

        The last window's curve is kept exactly up to its last knot ``E``, which is
        raised to multiplicity ``order - 1`` (a C0 join), and the curve after ``E``
        starts afresh, as at the start of a take, through the samples after it. That
        start always fits, so the guarantee holds; later windows remove the extra
        copies of ``E`` where the tolerance allows.
        """
        k, h, m = self.order, self.order // 2, self.window
        end = self._kt[-1]
        missing = k - 1 - int(np.count_nonzero(self._kt == end))
        refined = BSpline(*self._left, k - 1)
        if missing > 0:
            refined = insert(end, refined, m=missing)
        kt = np.asarray(refined.t)[: len(self._kt) + max(missing, 0)]
        kc = np.asarray(refined.c)[: len(kt) - k + 1]
        last = self._bn - self._free_tail          # the last sample that can be a knot
        a = min(a - 1 + h, last)
        b = last if final else max(a + 1, min(b, a + 2 * k + m - (len(kt) - (k - 1))))
        return self._step(np.ascontiguousarray(kt), np.ascontiguousarray(kc), a, min(b, last), len(kc), len(kc),
                          final)

    def _emit(self, piece_knots: np.ndarray, piece_coef: np.ndarray, final: bool) -> None:
        """Hand out the curve up to the window's last final coefficient (in the caller's
        units; held back while it only closes intervals of zero length, such as the
        clamped start). The coefficients after the first ``order - 1`` just became final."""
        k = self.order
        if self.keep:
            self._final_knots.append(piece_knots[k - 1 : None if final else len(piece_coef)])
            self._final_coef.append(piece_coef[k - 1 :])
        if self.on_piece is None:
            return
        if self._held is not None:
            held_knots, held_coef = self._held
            piece_knots = np.concatenate([held_knots, piece_knots])
            piece_coef = np.concatenate([held_coef, piece_coef])
            self._held = None
        n = len(piece_coef)
        if piece_knots[n] > piece_knots[k - 1] or final:
            piece = Piece(piece_knots, piece_coef)
            self.on_piece(piece.trimmed() if piece_knots[n - 1] == piece_knots[n] else piece)
        else:
            shared = len(piece_coef) - (k - 1)        # the next piece repeats the rest
            self._held = (piece_knots[:shared], piece_coef[:shared])

    # -- output ------------------------------------------------------------------------

    @property
    def pushed(self) -> int:
        """Samples offered so far, good or bad: the stream index of the next one."""
        return self._pushed

    @property
    def taken(self) -> int:
        """Distinct samples taken so far (:meth:`finish` needs two)."""
        return self._taken

    @property
    def buffered(self) -> int:
        """Raw samples held now (at most :attr:`buffer_bound`)."""
        return self._bn

    @property
    def max_error(self) -> np.ndarray:
        """Largest |curve - sample| per channel over the samples finished so far (with
        ``angle``, the largest rotation angle, shape (1,))."""
        if self._detector is None:
            return self._max_error.copy()
        return np.maximum(self._max_error, self._detector.pause_error)

    @property
    def pending(self) -> int:
        """Samples taken but held back for the features' look-ahead (at most about
        ``min_pause`` of them, or a few for breaks alone; none without features)."""
        return 0 if self._detector is None else self._detector.pending

    @property
    def found(self) -> list[Feature]:
        """The pauses and breaks settled so far, in time order."""
        return [] if self._detector is None else list(self._detector.found)

    def close(self) -> StreamStats:
        """End the stream: reduce what is left and hand out the last pieces."""
        if not self._closed:
            self._closed = True
            if self._detector is not None:
                for op in self._detector.close():
                    self._apply(op)
            self._end(None)
        return self.stats

    def _close_short(self) -> None:
        """Fewer samples than the order: the interpolating polynomial through them (and
        through the held end values instead of the end samples), all finished."""
        k = self.order
        t = self._bt[: self._bn] + self._origin
        x = self._bx[: self._bn] * self.tol + self._center
        t[-1] = self._last_t                            # exactly (see _run_window)
        if len(t) == 1:
            t, x = np.r_[t, t + 1.0], np.vstack([x, x])
        poly = held_interpolant(t, x, k, (self._start_value, self._end_value))
        assert poly is not None                         # a polynomial through < order samples
        # straightened in tolerances, as the windows are (its slack is in tolerances)
        lo, hi = window_kernel.local_ranges((x - self._center) / self.tol, self._before, self._widen / self.tol,
                                            *self._scaled_bounds())
        ends = np.asarray(poly.c)[[0, -1]]
        knots, coef, count = straightened(np.asarray(poly.t), (np.asarray(poly.c) - self._center) / self.tol, k, t,
                                          lo, hi, len(t) - 1, (t[0], t[-1]), movable=not self.angle)
        coef = coef * self.tol + self._center
        coef[[0, -1]] = ends                            # never moved: exactly, not to rounding
        self.stats.straightened += count
        piece = Piece(knots, coef)
        if self.keep:
            self._final_knots.append(piece.knots)
            self._final_coef.append(piece.coef)
        np.maximum(self._max_error, max_errors(piece.spline(t), x, self.angle), out=self._max_error)
        self._bn = 0
        if self.on_piece is not None:
            self.on_piece(piece)

    def finish(self) -> Reduction:
        """End the stream (see :meth:`close`) and return the whole curve.

        Raises :class:`~sketchanim.errors.ArgumentError` if ``keep`` is False (the
        curve was only handed out piece by piece), and
        :class:`~sketchanim.errors.SampleError` if fewer than 2 distinct samples came
        (as :func:`sketchanim.reduce` does).
        """
        if not self.keep:
            raise ArgumentError("keep", "is False: the curve went out piece by piece; call close()")
        clock = time.perf_counter()
        self.close()
        if self._taken < 2:
            raise SampleError(f"{self._taken} distinct samples, at least 2 needed", field="times")
        spline = join(self._segments)
        if self.dim == 1:
            spline = BSpline(spline.t, spline.c[:, 0], spline.k)
        s = self.stats
        report = {
            "window": self.window,
            "max_window": self.max_window,
            "constraints": self.constraints,
            "reference": self.reference,
            "windows": s.windows,
            "fits": s.fits,
            "knots_removed": s.removed,
            "duplicates_dropped": s.duplicates_dropped,
            "start_misses": s.start_misses,
            "straightened": s.straightened,
            "cuts": s.cuts,
            "max_span": self.max_span,
        }
        timings = {
            "total": s.total_window_seconds + time.perf_counter() - clock,
            "window_mean": s.total_window_seconds / max(s.windows, 1),
            "window_max": s.max_window_seconds,
        }
        tol = np.array([self.angle]) if self.angle else self.tol.copy()
        return Reduction(spline=spline, tol=tol, max_error=self.max_error, n_samples=self._taken,
                         method="incremental", timings=timings, report=report,
                         metric="rotation" if self.angle else "channels", features=tuple(self.found))

