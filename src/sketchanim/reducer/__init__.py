"""Knot-removal reducers: samples in, compact B-splines within tolerance out."""

from sketchanim.reducer.api import METHODS, reduce
from sketchanim.reducer.result import Reduction

__all__ = ["METHODS", "Reduction", "reduce"]
