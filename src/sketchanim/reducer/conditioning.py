"""Input checks for the reducers: sample times, values, tolerances and order.

Times must be finite and strictly increasing once exact duplicate samples (same time,
same values) are dropped; everything else is an error that names the first bad sample.

Numbers must also be in range, not merely finite: times within :data:`TIME_RANGE`
seconds of 0, and each channel's values within :data:`VALUE_RANGE` tolerances of its
median (a stream: of its first sample). float64 resolves about 16 significant digits and
a fit loses a few, so beyond that no curve can promise the tolerance; ``1e308`` would
overflow the fits outright.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numba import njit
from numpy.typing import ArrayLike

from sketchanim.errors import ArgumentError, SampleError

#: Largest time magnitude, in seconds (about 32 million years).
TIME_RANGE = 1e15
#: Farthest a value may be from its channel's reference, in tolerances.
VALUE_RANGE = 1e12
#: Highest spline order (degree 31; what a project file holds).
MAX_ORDER = 32
#: Most knots in an incremental window (each window's fit is dense in its size).
MAX_WINDOW = 1024
#: Most knots an incremental window may span (its samples are held in memory).
MAX_SPAN = 65536


@dataclass(frozen=True)
class Samples:
    """Checked samples, ready for a reducer.

    Attributes
    ----------
    times : ndarray, shape (n,)
        Strictly increasing, finite, float64 seconds.
    values : ndarray, shape (n, d)
        Finite float64 values.
    tol : ndarray, shape (d,)
        Positive per-channel tolerance.
    scalar : bool
        The caller gave values of shape (n,): results evaluate to shape (m,).
    duplicates_dropped : int
        Exact duplicate samples removed (same time and same values as the one before).
    """

    times: np.ndarray
    values: np.ndarray
    tol: np.ndarray
    scalar: bool
    duplicates_dropped: int

    @property
    def n(self) -> int:
        """Number of samples kept."""
        return len(self.times)

    @property
    def dim(self) -> int:
        """Number of channels."""
        return self.values.shape[1]


def check_order(order: object) -> int:
    """Return ``order`` as an int from 2 to :data:`MAX_ORDER` (2 linear, 4 cubic), or
    raise :class:`ArgumentError`.

    >>> check_order(4)
    4
    """
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or not 2 <= order <= MAX_ORDER:
        raise ArgumentError("order", f"must be an integer from 2 to {MAX_ORDER} (4 is cubic), got {order!r}")
    return int(order)


def check_count(name: str, value: object, least: int, most: int | None = None) -> int:
    """Return ``value`` as an int >= ``least`` (and <= ``most``), or raise
    :class:`ArgumentError` naming ``name``.

    >>> check_count("window", 20, 1, MAX_WINDOW)
    20
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least \
            or (most is not None and value > most):
        bounds = f">= {least}" if most is None else f"from {least} to {most}"
        raise ArgumentError(name, f"must be an integer {bounds}, got {value!r}")
    return int(value)


def check_angle(angle: float | None, dim: int) -> float:
    """Return a rotation bound in radians, 0.0 for none; it needs 4 channels (a
    quaternion) and a value in (0, pi].

    >>> check_angle(None, 3), check_angle(0.1, 4)
    (0.0, 0.1)
    """
    if angle is None:
        return 0.0
    if dim != 4 or not 0.0 < angle <= np.pi:
        raise ArgumentError("angle", f"needs 4 channels (a quaternion) and a value in (0, pi], got {angle!r} "
                                     f"with {dim} channels")
    return float(angle)


def check_tolerance(tol: ArrayLike, dim: int) -> np.ndarray:
    """Broadcast ``tol`` to shape (dim,) and check every entry is finite and positive.

    >>> check_tolerance(0.5, 3)
    array([0.5, 0.5, 0.5])
    """
    arr = _as_float("tol", tol)
    if arr.size == 1 and arr.ndim <= 1:
        arr = np.full(dim, float(arr.reshape(())))
    if arr.shape != (dim,):
        raise ArgumentError("tol", f"needs 1 or {dim} values (one per channel), got {arr.size}")
    bad = np.flatnonzero(~np.isfinite(arr) | (arr <= 0))
    if bad.size:
        raise ArgumentError("tol", f"channel {bad[0]} tolerance must be finite and > 0, got {float(arr[bad[0]]):g}")
    return arr


def _as_float(name: str, data: ArrayLike) -> np.ndarray:
    try:
        return np.asarray(data, dtype=float)
    except (TypeError, ValueError) as err:
        raise ArgumentError(name, f"must be numbers ({err})") from None


def condition(times: ArrayLike, values: ArrayLike, tol: ArrayLike, *, min_samples: int = 2) -> Samples:
    """Check and clean samples for reduction.

    Parameters
    ----------
    times : array_like, shape (n,)
        Sample times in seconds.
    values : array_like, shape (n,) or (n, d)
        Sample values, one column per channel.
    tol : float or array_like, shape (d,)
        Tolerance per channel (a scalar applies to all).
    min_samples : int
        Fewest samples accepted after duplicates are dropped.

    Returns
    -------
    Samples

    Raises
    ------
    SampleError
        NaN or infinite time or value, time going backwards, two samples at the same
        time with different values, or too few samples; names the first offending index.
    ArgumentError
        Shapes that do not match, or a tolerance that is not positive.

    Examples
    --------
    >>> s = condition([0.0, 0.1, 0.1, 0.2], [1.0, 2.0, 2.0, 3.0], 0.01)
    >>> s.times, s.duplicates_dropped
    (array([0. , 0.1, 0.2]), 1)
    """
    t = _as_float("times", times)
    x = _as_float("values", values)
    if t.ndim != 1:
        raise ArgumentError("times", f"must be 1-D, got shape {t.shape}")
    scalar = x.ndim == 1
    if scalar:
        x = x[:, None]
    if x.ndim != 2:
        raise ArgumentError("values", f"must be of shape (n,) or (n, d), got {x.shape}")
    if x.shape[0] != t.shape[0]:
        raise ArgumentError("values", f"has {x.shape[0]} rows but times has {t.shape[0]}")
    if x.shape[1] == 0:
        raise ArgumentError("values", "has no channels")
    tol_arr = check_tolerance(tol, x.shape[1])

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)       # all-NaN channels: scan_samples names them
        reference = np.nanmedian(np.where(np.isinf(x), np.nan, x), axis=0) if len(x) else np.zeros(x.shape[1])
    keep, error = scan_samples(t, x, tol=tol_arr, reference=reference)
    if error is not None:
        raise error
    t, x = t[keep], x[keep]
    if len(t) < min_samples:
        raise SampleError(
            f"{len(t)} distinct samples, at least {min_samples} needed", index=None, field="times"
        )
    return Samples(t, np.ascontiguousarray(x), tol_arr, scalar, int(np.count_nonzero(~keep)))


#: What :func:`_first_bad` found.
_GOOD, _BAD_TIME, _BAD_VALUE, _BACKWARDS, _CONFLICT, _FAR = range(6)


@njit(cache=True)
def _first_bad(t: np.ndarray, x: np.ndarray, has_previous: bool, prev_t: float, prev_x: np.ndarray,
               keep: np.ndarray) -> tuple[int, int, int]:
    """(index, what, channel) of the first bad sample, or (n, _GOOD, 0); ``keep`` is
    False at exact duplicates of the sample before."""
    d = x.shape[1]
    for i in range(len(t)):
        if not np.isfinite(t[i]) or abs(t[i]) > TIME_RANGE:
            return i, _BAD_TIME, 0
        for j in range(d):
            if not np.isfinite(x[i, j]):
                return i, _BAD_VALUE, j
        keep[i] = True
        if i or has_previous:
            before_t = t[i - 1] if i else prev_t
            before_x = x[i - 1] if i else prev_x
            if t[i] < before_t:
                return i, _BACKWARDS, 0
            if t[i] == before_t:
                for j in range(d):
                    if x[i, j] != before_x[j]:
                        return i, _CONFLICT, 0
                keep[i] = False
    return len(t), _GOOD, 0


def _far(values: np.ndarray, tol: np.ndarray, reference: np.ndarray) -> tuple[int, int]:
    """(index, channel) of the first value more than :data:`VALUE_RANGE` tolerances from
    ``reference``, or (n, 0)."""
    with np.errstate(all="ignore"):
        far = np.abs(values - reference) > VALUE_RANGE * tol
    rows = np.flatnonzero(far.any(axis=1))
    if not rows.size:
        return len(values), 0
    return int(rows[0]), int(np.argmax(far[rows[0]]))


def scan_samples(times: np.ndarray, values: np.ndarray, *, offset: int = 0,
         previous: tuple[float, np.ndarray] | None = None, tol: np.ndarray | None = None,
         reference: np.ndarray | None = None) -> tuple[np.ndarray, SampleError | None]:
    """Find the first bad sample of a batch, and the exact duplicates before it.

    Parameters
    ----------
    times : ndarray, shape (n,)
    values : ndarray, shape (n, d)
    offset : int
        Index of ``times[0]`` in the whole stream, for error messages.
    previous : (time, values) or None
        The last sample accepted before this batch, if any.
    tol, reference : ndarray, shape (d,), or None
        With both, a value more than :data:`VALUE_RANGE` tolerances from ``reference``
        is an error too.

    Returns
    -------
    keep : ndarray of bool, shape (m,)
        For the good prefix ``times[:m]`` (all of them when there is no error): False
        at exact duplicates of the sample before.
    error : SampleError or None
        What is wrong with sample ``offset + m``, if anything: a NaN or infinite time or
        value, time going backwards, or the same time as the sample before with
        different values.

    Examples
    --------
    >>> keep, err = scan_samples(np.array([0.0, 1.0, 1.0, 0.5]), np.array([[0.0], [1.0], [1.0], [2.0]]))
    >>> keep.tolist(), str(err)
    ([True, True, False], 'sample 3, time: time goes backwards (0.5 after 1.0)')
    """
    t = np.ascontiguousarray(times, dtype=float)
    x = np.ascontiguousarray(values, dtype=float)
    keep = np.empty(len(t), dtype=np.bool_)
    has_previous = previous is not None
    prev_t, prev_x = (previous[0], previous[1]) if has_previous else (0.0, np.zeros(x.shape[1]))
    end, code, j = _first_bad(t, x, has_previous, float(prev_t), np.asarray(prev_x, dtype=float), keep)
    if tol is not None and reference is not None:
        far, channel = _far(x[:end], tol, reference)
        if far < end:
            end, code, j = far, _FAR, channel
    if code == _GOOD:
        return keep, None
    index = end + offset
    if code == _BAD_TIME:
        beyond = f": beyond the range of +/-{TIME_RANGE:g} s" if np.isfinite(t[end]) else ""
        error = SampleError(f"time is {float(t[end])!r}{beyond}", index=index, field="time")
    elif code == _FAR:
        error = SampleError(f"value {float(x[end, j])!r} is more than {VALUE_RANGE:g} tolerances "
                            f"({float(tol[j])!r}) from the channel's other values (around {float(reference[j])!r}): beyond what "
                            "float64 resolves (a spike, or a tolerance too small)", index=index, field=f"channel {j}")
    elif code == _BAD_VALUE:
        error = SampleError(f"value is {float(x[end, j])!r}", index=index, field=f"channel {j}")
    else:
        before = float(t[end - 1]) if end else float(prev_t)
        if code == _BACKWARDS:
            message = f"time goes backwards ({float(t[end])!r} after {before!r})"
        else:
            what = f"sample {index - 1}" if end else "the sample before"
            message = f"same time {float(t[end])!r} as {what} but different values"
        error = SampleError(message, index=index, field="time")
    return keep[:end], error
