"""The result of a reduction and its JSON form."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.interpolate import BSpline

from sketchanim.errors import InputError, load_json
from sketchanim.reducer.features import FEATURE_KINDS, Feature

SCHEMA = "sketchanim.reduction"
VERSION = 1


def load_versioned(text: str, source: str, schema: str, version: int) -> dict[str, Any]:
    """The JSON object in ``text``, checked to be a ``schema`` document of ``version``;
    :class:`InputError` naming ``source`` (and the line, for text that is not JSON).

    >>> load_versioned('{"schema": "s", "version": 2}', "f.json", "s", 1)
    Traceback (most recent call last):
    sketchanim.errors.InputError: f.json: version 2, this reader knows 1
    """
    try:
        doc = load_json(text, source)
    except json.JSONDecodeError as err:
        raise InputError(f"{source}, line {err.lineno}: not JSON ({err.msg})") from None
    if not isinstance(doc, dict) or doc.get("schema") != schema:
        raise InputError(f"{source}: not a {schema} document")
    if doc.get("version") != version:
        raise InputError(f"{source}: version {doc.get('version')!r}, this reader knows {version}")
    return doc


@dataclass(frozen=True)
class Reduction:
    """A reduced curve and what it promises.

    Attributes
    ----------
    spline : scipy.interpolate.BSpline
        The curve; evaluates to shape (m,) for a scalar channel, (m, d) otherwise.
    tol : ndarray, shape (d,) or (1,)
        Tolerance per channel; with ``metric == "rotation"`` one angle in radians.
    max_error : ndarray, shape (d,) or (1,)
        Largest |spline(t_i) - x_i| over the samples, per channel: at most ``tol``;
        with ``metric == "rotation"`` the largest rotation angle between the spline's
        normalised value and the sample quaternion.
    n_samples : int
        Samples reduced (after exact duplicates were dropped).
    method : str
        ``"global"`` or ``"incremental"``.
    timings : dict
        Seconds spent, by phase (``total`` at least).
    report : dict
        What happened: duplicates dropped, iterations, least-squares fits, ...
    metric : {"channels", "rotation"}
        What the tolerance bounds (see :mod:`sketchanim.reducer.metric`).
    features : tuple of Feature
        The pauses (the curve holds still over their span) and breaks (a corner at
        their time) found and kept, in time order.

    Examples
    --------
    >>> import sketchanim
    >>> t = np.linspace(0, 1, 50)
    >>> r = sketchanim.reduce(t, np.sin(t), 1e-3)
    >>> r2 = Reduction.from_json(r.to_json())
    >>> r2.n_coefficients == r.n_coefficients, bool(np.allclose(r2.spline(t), r.spline(t)))
    (True, True)
    """

    spline: BSpline
    tol: np.ndarray
    max_error: np.ndarray
    n_samples: int
    method: str
    timings: dict[str, float] = field(default_factory=dict)
    report: dict[str, Any] = field(default_factory=dict)
    metric: str = "channels"
    features: tuple[Feature, ...] = ()

    @property
    def order(self) -> int:
        """Spline order (degree + 1)."""
        return int(self.spline.k) + 1

    @property
    def columns(self) -> BSpline:
        """The curve with coefficients of shape (n, d), a scalar channel's too: it then
        evaluates to (m, 1) like any other.

        >>> import sketchanim
        >>> sketchanim.reduce(np.linspace(0, 1, 20), np.linspace(0, 1, 20), 1e-3).columns.c.shape
        (4, 1)
        """
        c = np.asarray(self.spline.c)
        return self.spline if c.ndim == 2 else BSpline(self.spline.t, c.reshape(len(c), -1), self.spline.k)

    @property
    def n_coefficients(self) -> int:
        """Number of control points."""
        return len(self.spline.c)

    @property
    def ratio(self) -> float:
        """Samples per control point."""
        return self.n_samples / self.n_coefficients

    def to_json(self) -> str:
        """The reduction as a JSON document (schema ``sketchanim.reduction``, version 1)."""
        c = np.asarray(self.spline.c)
        doc = {
            "schema": SCHEMA,
            "version": VERSION,
            "order": self.order,
            "knots": np.asarray(self.spline.t).tolist(),
            "coefficients": c.tolist(),
            "scalar": c.ndim == 1,
            "metric": self.metric,
            "tol": self.tol.tolist(),
            "max_error": self.max_error.tolist(),
            "n_samples": self.n_samples,
            "method": self.method,
            "timings": self.timings,
            "report": self.report,
            "features": [f.to_dict() for f in self.features],
        }
        return json.dumps(doc, indent=1)

    @classmethod
    def from_json(cls, text: str, *, source: str = "<json>") -> Reduction:
        """Read a document written by :meth:`to_json`; errors name ``source`` and the field."""
        doc = load_versioned(text, source, SCHEMA, VERSION)

        def field_array(name: str, ndim: tuple[int, ...]) -> np.ndarray:
            try:
                arr = np.asarray(doc[name], dtype=float)
            except KeyError:
                raise InputError(f"{source}: field {name!r} is missing") from None
            except (TypeError, ValueError):
                raise InputError(f"{source}: field {name!r} must be numbers") from None
            if arr.ndim not in ndim or not np.all(np.isfinite(arr)):
                raise InputError(f"{source}: field {name!r} must be a finite array of {ndim[0]}-D")
            return arr

        knots = field_array("knots", (1,))
        coef = field_array("coefficients", (1, 2))
        tol = field_array("tol", (1,))
        max_error = field_array("max_error", (1,))
        order = doc.get("order")
        if not isinstance(order, int) or order < 2:
            raise InputError(f"{source}: field 'order' must be an integer >= 2")
        if len(knots) != len(coef) + order or np.any(np.diff(knots) < 0):
            raise InputError(f"{source}: field 'knots' must be non-decreasing, {len(coef) + order} long")
        dim = 1 if coef.ndim == 1 else coef.shape[1]
        metric = doc.get("metric", "channels")
        if metric not in ("channels", "rotation") or (metric == "rotation" and dim != 4):
            raise InputError(f"{source}: field 'metric' must be 'channels', or 'rotation' with 4 channels")
        bounds = 1 if metric == "rotation" else dim
        if len(tol) != bounds or len(max_error) != bounds:
            raise InputError(f"{source}: fields 'tol' and 'max_error' need {bounds} value(s) for metric {metric!r}")
        n_samples = doc.get("n_samples")
        if not isinstance(n_samples, int) or n_samples < 1:
            raise InputError(f"{source}: field 'n_samples' must be a positive integer")
        features = doc.get("features", [])
        if not isinstance(features, list):
            raise InputError(f"{source}: field 'features' must be a list")
        found = []
        for i, f in enumerate(features):
            ok = isinstance(f, dict) and f.get("kind") in FEATURE_KINDS and all(
                isinstance(f.get(key), (int, float)) and not isinstance(f.get(key), bool) and np.isfinite(f[key])
                for key in ("start", "end"))
            if not ok or f["start"] > f["end"]:
                raise InputError(f"{source}: field 'features', item {i}: needs kind ({' or '.join(FEATURE_KINDS)}) "
                                 "and finite start <= end")
            found.append(Feature(f["kind"], float(f["start"]), float(f["end"])))
        return cls(
            spline=BSpline(knots, coef, order - 1),
            tol=tol,
            max_error=max_error,
            n_samples=n_samples,
            method=str(doc.get("method", "global")),
            timings=dict(doc.get("timings") or {}),
            report=dict(doc.get("report") or {}),
            metric=metric,
            features=tuple(found),
        )
