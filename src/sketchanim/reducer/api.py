"""``reduce``: samples in, a B-spline within tolerance of every sample out."""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError, ToleranceUnreachableError
from sketchanim.reducer.conditioning import Samples, check_angle, check_count, check_order, condition
from sketchanim.reducer.features import Feature, FeatureOptions
from sketchanim.reducer.global_method import STARTS, GlobalOptions, reduce_global
from sketchanim.reducer.metric import max_errors
from sketchanim.reducer.result import Reduction
from sketchanim.reducer.segments import reduce_segmented
from sketchanim.reducer.starts import interpolant, polynomial_through
from sketchanim.reducer.stream import StreamReducer

METHODS = ("global", "incremental")


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
            f"{what} {float(bound[j])!r} is below what floating point can "
            f"resolve for these values (the interpolant misses by {float(err[j])!r})"
        )
    return exact, err, True


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
) -> Reduction:
    """Reduce sampled motion to a B-spline that keeps every sample's value and time.

    Time is the spline's parameter, so timing is kept: for every sample ``i`` and channel
    ``j``, ``|spline(times[i])[j] - values[i, j]| <= tol[j]``. This is checked on the
    result of every call and reported in ``max_error``.

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
        arrive; the same spline as streaming these samples with its defaults).
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
        ``tol`` then only scales the fit. :func:`sketchanim.reduce_rotations` is the
        front end for rotations.
    features : bool or FeatureOptions
        Find pauses (the curve then holds exactly still there) and velocity breaks
        (kept as corners) and cut the take there (:mod:`sketchanim.reducer.features`);
        True uses the default thresholds, False reduces the take in one piece. The
        result's ``features`` lists what was found.

    Returns
    -------
    Reduction

    Raises
    ------
    sketchanim.errors.SampleError
        A NaN or infinite sample, time going backwards, or fewer than 2 distinct samples
        (names the sample index and field).
    sketchanim.errors.ArgumentError
        A tolerance <= 0 or of the wrong length, a bad order, method or start.

    Examples
    --------
    >>> import numpy as np, sketchanim
    >>> t = np.linspace(0, 6 * np.pi, 1000)
    >>> r = sketchanim.reduce(t, np.c_[t * np.cos(t), t * np.sin(t)], 0.1)
    >>> r.n_coefficients <= 18, bool(np.all(r.max_error <= 0.1))
    (True, True)
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
    options = FeatureOptions.of(features)
    found: list[Feature] = []
    report: dict[str, object] = {"duplicates_dropped": samples.duplicates_dropped}
    if method != "incremental":
        report["start"] = start
    if method == "incremental":
        stream = StreamReducer(samples.dim, samples.tol, order=order, window=window, constraints=constraints,
                               angle=angle or None, features=options)
        stream.extend(samples.times, samples.values)
        streamed = stream.finish()
        found = list(streamed.features)
        spline = streamed.columns
        report.update((key, v) for key, v in streamed.report.items() if key != "duplicates_dropped")
    elif samples.n < order:
        spline = polynomial_through(samples.times, samples.values, order)
        report["note"] = f"{samples.n} samples < order {order}: the interpolating polynomial"
    else:
        opts = GlobalOptions(start, split, minimax_iterations, exhaustive_below, coarse_samples)
        if options.enabled:
            spline, found, log = reduce_segmented(samples.times, samples.values, samples.tol, order, opts, angle,
                                                  options)
        else:
            spline, log = reduce_global(samples.times, samples.values, samples.tol, order, opts, angle)
        report.update(iterations=log.iterations, fits=log.fits, coarse_pass=log.coarse_pass,
                      coarse_outcome=log.coarse_outcome)
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
