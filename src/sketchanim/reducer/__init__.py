"""Knot-removal reducers: samples in, compact B-splines within tolerance out."""

from sketchanim.reducer.api import METHODS, reduce
from sketchanim.reducer.result import Reduction
from sketchanim.reducer.stream import Piece, StreamReducer

__all__ = ["METHODS", "Piece", "Reduction", "StreamReducer", "reduce"]
