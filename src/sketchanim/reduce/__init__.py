"""Knot-removal reducers: samples in, compact B-splines within tolerance out."""

from sketchanim.reduce.api import METHODS, reduce
from sketchanim.reduce.result import Reduction

__all__ = ["METHODS", "Reduction", "reduce"]
