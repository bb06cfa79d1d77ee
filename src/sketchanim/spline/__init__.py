"""B-splines of any order and dimension, built on :class:`scipy.interpolate.BSpline`."""

from sketchanim.spline.hermite import BezierSegments, HermiteKeys, from_hermite, to_bezier, to_hermite
from sketchanim.spline.knots import derivative, elevate_degree, greville, insert_knots, insertion_matrix

__all__ = [
    "BezierSegments",
    "HermiteKeys",
    "derivative",
    "elevate_degree",
    "from_hermite",
    "greville",
    "insert_knots",
    "insertion_matrix",
    "to_bezier",
    "to_hermite",
]
