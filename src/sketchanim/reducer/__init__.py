"""Knot-removal reducers: samples in, compact B-splines within tolerance out."""

from sketchanim.reducer.api import METHODS, reduce
from sketchanim.reducer.features import Feature, FeatureOptions
from sketchanim.reducer.result import Reduction
from sketchanim.reducer.stream import Piece, StreamReducer

__all__ = ["METHODS", "Feature", "FeatureOptions", "Piece", "Reduction", "StreamReducer", "reduce"]
