"""``reduce``: samples in, a B-spline within tolerance of every sample out."""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError, SampleError, ToleranceUnreachableError
from sketchanim.reducer.conditioning import Samples, check_angle, check_count, check_order, condition
from sketchanim.reducer.features import Feature, FeatureOptions
from sketchanim.reducer.gaps import without_swing
from sketchanim.reducer.global_method import STARTS, GlobalOptions, reduce_global
from sketchanim.reducer.metric import max_errors
from sketchanim.reducer.result import Reduction
from sketchanim.reducer.segments import reduce_segmented
from sketchanim.reducer.starts import interpolant, polynomial_through
from sketchanim.reducer.stream import StreamReducer
from sketchanim.reducer.swing import Bounds, check_bounds, local_ranges, outside

METHODS = ("global", "incremental")

#: Samples handed to the streaming reducer at a time by the incremental method.
STREAM_CHUNK = 1 << 16


def _guaranteed(spline: BSpline, samples: Samples, order: int, angle: float) -> tuple[BSpline, np.ndarray, bool]:
    """The spline if every sample is within tolerance, else the interpolant; or raise."""
    bound = np.array([angle]) if angle else samples.tol
    err = max_errors(spline(samples.times), samples.values, angle)
    if np.all(err <= bound):
        return spline, err, False
    exact = interpolant(samples.times, samples.values, order) or spline
    err = max_errors(exact(samples.times), samples.values, angle)
    if not np.all(err <= bound):
        j = int(np.argmax(err / bound))
        what = "angle" if angle else f"tol: channel {j} tolerance"
        raise ToleranceUnreachableError(
            f"{what} {float(bound[j]):g} is below what floating point can "
            f"resolve for these values (the interpolant misses by {float(err[j]):g})"
        )
    return exact, err, True


def _checked_bounds(values: ArrayLike, bounds: tuple[ArrayLike, ArrayLike] | None, dim: int) -> Bounds | None:
    """``bounds`` checked (:func:`~sketchanim.reducer.swing.check_bounds`), or a
    :class:`SampleError` naming the first sample of ``values`` (checked finite) outside
    them, by its index in the caller's input and its channel."""
    limits = check_bounds(bounds, dim)
    if limits is None:
        return None
    x = np.asarray(values, dtype=float).reshape(-1, dim)
    i = outside(x, limits)
    if i is not None:
        j = int(np.flatnonzero((x[i] < limits[0]) | (x[i] > limits[1]))[0])
        raise SampleError(f"value {float(x[i, j])!r} is outside the bounds [{float(limits[0][j])!r}, "
                          f"{float(limits[1][j])!r}]", index=i, field=f"channel {j}")
    return limits


def reduce(
    times: ArrayLike,
    values: ArrayLike,
    tol: float | ArrayLike,
    *,
    order: int = 4,
    method: str = "global",
    start: str = "paper",
    split: float = 0.1,
    minimax_iterations: int = 8,
    exhaustive_below: int = 32,
    coarse_samples: int | None = 8192,
    window: int = 20,
    constraints: str = "end",
    angle: float | None = None,
    features: bool | FeatureOptions = True,
    bounds: tuple[ArrayLike, ArrayLike] | None = None,
) -> Reduction:
    """Reduce sampled motion to a B-spline that keeps every sample's value and time.

    Time is the spline's parameter, so timing is kept: for every sample ``i`` and channel
    ``j``, ``|spline(times[i])[j] - values[i, j]| <= tol[j]``. This is checked on the
    result of every call and reported in ``max_error``. Between samples ``i`` and
    ``i + 1`` the curve stays within the range of samples ``i - 1 .. i + 2`` widened by
    the tolerance and cut to ``bounds`` (no swing; :mod:`sketchanim.reducer.gaps`).

    Parameters
    ----------
    times : array_like, shape (n,)
        Sample times in seconds, increasing (exact duplicate samples are dropped).
    values : array_like, shape (n,) or (n, d)
        Sample values, one column per channel.
    tol : float or array_like, shape (d,)
        Tolerance per channel, in the channel's units.
    order : int
        Spline order, degree + 1 (4: cubic).
    method : {"global", "incremental"}
        Lyche-Morken knot removal over the whole take, or the incremental method
        (windows of ``window`` knots, as :class:`StreamReducer` does while samples
        arrive, growing where the motion is smooth: ``grow=True``; with
        ``FeatureOptions(jumps=False)`` or ``features=False``, the same spline as
        streaming these samples so, the stream keeping the no-swing bound itself).
    start : {"paper", "lm"}
        Starting curve: the samples as control polygon, or LM's reduced
        piecewise-linear interpolant raised to ``order``.
    split : float
        With ``start="lm"``, the share of ``tol`` given to the linear pass.
    minimax_iterations : int
        Lawson re-weightings when testing single knots (0 for plain least squares).
    exhaustive_below : int
        Knot vectors this short try every removal count instead of bisecting.
    coarse_samples : int or None
        Takes longer than twice this are first reduced from about this many evenly
        spaced samples (then checked against all); ``None`` always uses all samples.
    window, constraints : int, str
        Window size and variant of the incremental method (see :class:`StreamReducer`).
    angle : float or None
        If given, the four channels are quaternions and each sample keeps its rotation
        instead: the spline's value, normalised, within ``angle`` radians of it;
        ``tol`` then only scales the fit, and the no-swing range of each component is
        widened by ``2 sin(angle / 4)`` (the distance between unit quaternions whose
        rotations are ``angle`` apart). :func:`sketchanim.reduce_rotations` is the
        front end for rotations.
    features : bool or FeatureOptions
        Find pauses (the curve then holds exactly still there) and velocity breaks
        (kept as corners) and cut the take there (:mod:`sketchanim.reducer.features`);
        True uses the default thresholds, False looks for none. The take is cut at
        its jumps (a value step over one interval; not with False or
        ``FeatureOptions(jumps=False)``) and, whatever this says, wherever the curve would swing out of its local range between samples (gaps; with
        ``FeatureOptions.gap``, also at every interval over that many median
        intervals): each side reduced on its own, the cut interval bridged, C1 where
        that stays within its range, else straight (:mod:`sketchanim.reducer.gaps`).
        The result's ``features`` lists what was found.
    bounds : (array_like, array_like) or None
        Least and greatest value of each channel (numbers or shape (d,); ±inf:
        unbounded): the curve stays within them everywhere. Not with ``angle``.

    Returns
    -------
    Reduction

    Raises
    ------
    sketchanim.errors.SampleError
        A NaN or infinite sample, time going backwards, fewer than 2 distinct samples,
        or a sample outside ``bounds`` (names the sample index and field).
    sketchanim.errors.ArgumentError
        A tolerance <= 0 or of the wrong length, a bad order, method or start.

    Examples
    --------
    >>> import numpy as np, sketchanim
    >>> t = np.linspace(0, 6 * np.pi, 1000)
    >>> r = sketchanim.reduce(t, np.c_[t * np.cos(t), t * np.sin(t)], 0.1)
    >>> r.n_coefficients <= 18, bool(np.all(r.max_error <= 0.1))
    (True, True)
    >>> colour = sketchanim.reduce(t, np.clip(np.sin(t), 0, 1), 0.05, bounds=(0, 1))
    >>> curve = colour.spline(np.linspace(0, 6 * np.pi, 5000))
    >>> bool(curve.min() >= 0 and curve.max() <= 1)
    True
    """
    clock = time.perf_counter()
    order = check_order(order)
    if method not in METHODS:
        raise ArgumentError("method", f"must be one of {', '.join(METHODS)}, got {method!r}")
    if start not in STARTS:
        raise ArgumentError("start", f"must be one of {', '.join(STARTS)}, got {start!r}")
    if not 0.0 <= split < 1.0:
        raise ArgumentError("split", f"must be in [0, 1), got {split!r}")
    for name, value, least in (("minimax_iterations", minimax_iterations, 0), ("exhaustive_below", exhaustive_below, 0),
                               ("coarse_samples", 2 * order if coarse_samples is None else coarse_samples, 2 * order)):
        check_count(name, value, least)
    samples = condition(times, values, tol)
    angle = check_angle(angle, samples.dim)
    if angle and bounds is not None:
        raise ArgumentError("bounds", "orientations (angle) have no bounds")
    limits = _checked_bounds(values, bounds, samples.dim)
    options = FeatureOptions.of(features)
    report: dict[str, object] = {"duplicates_dropped": samples.duplicates_dropped}
    if method != "incremental":
        report["start"] = start

    def run(t: np.ndarray, x: np.ndarray) -> tuple[BSpline, list[Feature]]:
        """Samples ``t``, ``x`` (all, or a run between cuts) in one go, by ``method``;
        the work done is added up in the report."""
        if method == "incremental":
            stream = StreamReducer(samples.dim, samples.tol, order=order, window=window, constraints=constraints,
                                   angle=angle or None, features=options, grow=True)
            for a in range(0, len(t), STREAM_CHUNK):        # in chunks: the same spline, bounded memory
                stream.extend(t[a : a + STREAM_CHUNK], x[a : a + STREAM_CHUNK])
            streamed = stream.finish()
            report.update((key, v) for key, v in streamed.report.items() if key != "duplicates_dropped")
            return streamed.columns, list(streamed.features)
        if len(t) < order:
            if len(t) == samples.n:
                report["note"] = f"{len(t)} samples < order {order}: the interpolating polynomial"
            return polynomial_through(t, x, order), []
        opts = GlobalOptions(start, split, minimax_iterations, exhaustive_below, coarse_samples)
        found: list[Feature] = []
        if options.enabled:
            spline, found, work = reduce_segmented(t, x, samples.tol, order, opts, angle, options)
        else:
            spline, work = reduce_global(t, x, samples.tol, order, opts, angle)
        done = {key: int(report.get(key, 0)) for key in ("iterations", "fits")}  # type: ignore[call-overload]
        report.update(iterations=done["iterations"] + work.iterations, fits=done["fits"] + work.fits,
                      coarse_pass=bool(report.get("coarse_pass")) or work.coarse_pass,
                      coarse_outcome=work.coarse_outcome or report.get("coarse_outcome"))
        return spline, found

    def part(t: np.ndarray, x: np.ndarray) -> tuple[BSpline, tuple[Feature, ...]]:
        """A run between cuts, reduced alone."""
        spline, found = run(t, x)
        return spline, tuple(found)

    widening = np.full(samples.dim, 2 * np.sin(angle / 4)) if angle else samples.tol
    lo, hi = local_ranges(samples.values, widening, limits)
    spline, found = without_swing(samples.times, samples.values, samples.tol, order, options.jumps, options.gap, lo,
                                  hi, lambda: run(samples.times, samples.values), part, normalised=bool(angle))
    for kind in ("gap", "jump"):
        if any(f.kind == kind for f in found):
            report[kind + "s"] = sum(f.kind == kind for f in found)
    spline, max_error, fell_back = _guaranteed(spline, samples, order, angle)
    if fell_back:
        report["note"] = "rounding broke the bound: kept the interpolant"
        found = []
    if samples.scalar:
        spline = BSpline(spline.t, spline.c[:, 0], spline.k)
    return Reduction(
        spline=spline,
        tol=np.array([angle]) if angle else samples.tol,
        max_error=max_error,
        n_samples=samples.n,
        method=method,
        timings={"total": time.perf_counter() - clock},
        report=report,
        metric="rotation" if angle else "channels",
        features=tuple(found),
    )
