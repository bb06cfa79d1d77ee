"""Smoothing before reduction: local-linear regression with Gaussian weights in time.

Each sample is replaced by the value at its own time of the straight line fitted, by
least squares, to the samples within ``3 * sigma`` seconds of it, each weighted by a
Gaussian of width ``sigma`` in time. That keeps constant and linear motion exactly,
adds no phase lag, handles a take's ends (where a weighted mean would pull towards the
inside) and works on irregularly timed samples. The result is then clipped, channel by
channel, to the range of those window samples, so smoothing never overshoots what was
performed there. The fit is ``2 * sigma`` wide per standard deviation: a motion much
slower than ``sigma`` passes, jitter much faster is averaged away.

:func:`smooth` works on a whole take; :class:`StreamSmoother` takes samples as they
arrive and hands each one out smoothed once ``3 * sigma`` seconds of later samples
exist, with exactly the result of :func:`smooth` (the same arithmetic on the same
window), in memory and latency bound by ``sigma``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from sketchanim.errors import ArgumentError

#: The window's half width, in ``sigma``: samples further away get no weight.
REACH = 3.0
#: Rows of output computed at once by :func:`smooth` (bounds its memory).
_ROWS = 4096


def check_sigma(sigma: float | None, field: str = "sigma") -> float:
    """``sigma`` as a float, 0.0 for None (no smoothing); :class:`ArgumentError`
    naming ``field`` unless it is a finite number >= 0.

    >>> check_sigma(None), check_sigma(0.05)
    (0.0, 0.05)
    >>> check_sigma(-1, "smoothing")
    Traceback (most recent call last):
    sketchanim.errors.ArgumentError: smoothing: must be a finite number of seconds >= 0, got -1
    """
    if sigma is None:
        return 0.0
    try:
        s = float(sigma)
    except (TypeError, ValueError):
        raise ArgumentError(field, f"must be a finite number of seconds >= 0, got {sigma!r}") from None
    if not (np.isfinite(s) and s >= 0):
        raise ArgumentError(field, f"must be a finite number of seconds >= 0, got {sigma!r}")
    return s


def _samples(times: ArrayLike, values: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Times (n,) increasing and values (n, dim) as floats; errors name the argument."""
    t = np.asarray(times, dtype=float).reshape(-1)
    x = np.asarray(values, dtype=float)
    x = x.reshape(len(x), -1) if x.ndim != 2 else x
    if len(x) != len(t):
        raise ArgumentError("values", f"needs one row per time ({len(t)}), got {len(x)}")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise ArgumentError("times", "must be finite and increasing")
    if not np.all(np.isfinite(x)):
        raise ArgumentError("values", "must be finite")
    return t, x


def _fitted(t: np.ndarray, x: np.ndarray, rows: np.ndarray, lo: np.ndarray, hi: np.ndarray,
            sigma: float) -> np.ndarray:
    """The smoothed values at ``t[rows]``, row ``i`` from the samples ``lo[i]:hi[i]``.

    The sums run over the window's samples in order, one column at a time: a row's
    result depends only on its own window, whatever the others' widths (so a stream
    and a batch agree to the bit)."""
    n, dim = len(rows), x.shape[1]
    s0, s1, s2 = np.zeros(n), np.zeros(n), np.zeros(n)
    m0, m1 = np.zeros((n, dim)), np.zeros((n, dim))
    low, high = np.full((n, dim), np.inf), np.full((n, dim), -np.inf)
    t0 = t[rows]
    for j in range(int((hi - lo).max())):
        live = lo + j < hi
        k = np.where(live, lo + j, rows)
        d = t[k] - t0
        w = np.where(live, np.exp(-0.5 * (d / sigma) ** 2), 0.0)
        xk = x[k]
        s0 += w
        s1 += w * d
        s2 += w * d * d
        m0 += w[:, None] * xk
        m1 += (w * d)[:, None] * xk
        low = np.where(live[:, None], np.minimum(low, xk), low)
        high = np.where(live[:, None], np.maximum(high, xk), high)
    det = s0 * s2 - s1 * s1
    line = det > 1e-9 * s0 * s2                 # else one sample, or all at one time: the mean
    safe = np.where(line, det, 1.0)
    fit = np.where(line[:, None], (s2[:, None] * m0 - s1[:, None] * m1) / safe[:, None], m0 / s0[:, None])
    return np.clip(fit, low, high)


def _windows(t: np.ndarray, rows: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """Where each row's window starts and ends in ``t``."""
    h = REACH * sigma
    return np.searchsorted(t, t[rows] - h, side="left"), np.searchsorted(t, t[rows] + h, side="right")


def smooth(times: ArrayLike, values: ArrayLike, sigma: float | None) -> np.ndarray:
    """``values`` (n, dim) at ``times`` (n,) smoothed with width ``sigma`` seconds (see
    the module's description); ``sigma`` 0 or None gives them back unchanged.

    Raises :class:`ArgumentError` naming ``sigma``, ``times`` or ``values``.

    >>> t = np.array([0.0, 0.1, 0.25, 0.3, 0.5])
    >>> smooth(t, np.c_[2 * t + 1], 0.2)[:, 0].round(12).tolist()        # a line stays
    [1.0, 1.2, 1.5, 1.6, 2.0]
    >>> t = np.linspace(0, 1, 11)                 # a line with +-0.1 of jitter
    >>> smooth(t, np.c_[t + 0.1 * (-1) ** np.arange(11)], 0.1)[:, 0].round(3).tolist()
    [0.072, 0.106, 0.202, 0.299, 0.401, 0.499, 0.601, 0.699, 0.802, 0.906, 1.072]
    """
    sigma = check_sigma(sigma)
    t, x = _samples(times, values)
    if sigma == 0 or not len(t):
        return x.copy()
    out = np.empty_like(x)
    for a in range(0, len(t), _ROWS):
        rows = np.arange(a, min(a + _ROWS, len(t)))
        out[rows] = _fitted(t, x, rows, *_windows(t, rows, sigma), sigma)
    return out


class StreamSmoother:
    """:func:`smooth` for samples arriving in time order: :meth:`push` returns the
    samples whose window is complete (``3 * sigma`` seconds of later samples exist),
    smoothed; :meth:`close` returns the rest. Together they are exactly
    :func:`smooth` of all the samples, however they were split.

    Parameters
    ----------
    dim : int
        Values per sample.
    sigma : float or None
        Width in seconds; 0 or None passes every sample straight through.

    Examples
    --------
    >>> t = np.linspace(0, 1, 101)
    >>> x = np.c_[np.sin(6 * t), np.cos(6 * t)]
    >>> s = StreamSmoother(2, 0.02)
    >>> parts = [s.push(t[a : a + 10], x[a : a + 10]) for a in range(0, 101, 10)] + [s.close()]
    >>> times = np.concatenate([p[0] for p in parts])
    >>> bool(np.array_equal(times, t)), bool(np.array_equal(np.vstack([p[1] for p in parts]), smooth(t, x, 0.02)))
    (True, True)
    >>> len(parts[0][0]), s.pending                  # 0.06 s held back
    (4, 0)
    """

    def __init__(self, dim: int, sigma: float | None) -> None:
        self.sigma = check_sigma(sigma)
        self.dim = int(dim)
        self._t = np.empty(0)                   # from the earliest a pending window needs
        self._x = np.empty((0, self.dim))
        self._next = 0                          # the first pending sample in _t

    @property
    def pending(self) -> int:
        """Samples taken but not handed out yet."""
        return len(self._t) - self._next

    def push(self, times: ArrayLike, values: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Take samples (after the last taken); return (times, smoothed values) of those
        now complete, in order."""
        t, x = _samples(times, values)
        if x.shape[1] != self.dim:
            raise ArgumentError("values", f"needs {self.dim} columns, got {x.shape[1]}")
        if len(t) and len(self._t) and t[0] <= self._t[-1]:
            raise ArgumentError("times", f"must be after the last taken ({self._t[-1]!r}), got {t[0]!r}")
        if self.sigma == 0:
            return t, x.copy()
        self._t, self._x = np.r_[self._t, t], np.vstack([self._x, x])
        if not len(self._t):
            return self._t.copy(), self._x.copy()
        h = REACH * self.sigma
        ready = int(np.searchsorted(self._t + h, self._t[-1], side="right"))
        return self._release(max(ready, self._next))

    def close(self) -> tuple[np.ndarray, np.ndarray]:
        """The samples still held back, smoothed (the take ended: no later sample)."""
        return self._release(len(self._t))

    def _release(self, end: int) -> tuple[np.ndarray, np.ndarray]:
        rows = np.arange(self._next, end)
        if not len(rows):
            return np.empty(0), np.empty((0, self.dim))
        out = self._t[rows], _fitted(self._t, self._x, rows, *_windows(self._t, rows, self.sigma), self.sigma)
        self._next = end
        first = self._t[min(end, len(self._t) - 1)]     # no later sample's window reaches before
        keep = int(np.searchsorted(self._t, first - REACH * self.sigma, side="left"))
        self._t, self._x, self._next = self._t[keep:], self._x[keep:], self._next - keep
        return out
