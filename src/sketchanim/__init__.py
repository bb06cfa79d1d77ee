"""sketchanim: sketch 3D animations; every performed channel becomes a compact B-spline.

>>> import numpy as np, sketchanim
>>> t = np.linspace(0, 2, 200)
>>> r = sketchanim.reduce(t, np.c_[np.sin(t), np.cos(t)], tol=0.01)
>>> bool(np.all(r.max_error <= 0.01)), r.n_coefficients < 200
(True, True)
"""

from sketchanim.errors import ArgumentError, FileFormatError, InputError, SampleError, ToleranceUnreachableError
from sketchanim.motion import RotationStream, reduce_rotations
from sketchanim.reducer import Feature, FeatureOptions, Piece, Reduction, StreamReducer, reduce

__all__ = [
    "ArgumentError",
    "Feature",
    "FeatureOptions",
    "FileFormatError",
    "InputError",
    "Piece",
    "Reduction",
    "RotationStream",
    "SampleError",
    "StreamReducer",
    "ToleranceUnreachableError",
    "reduce",
    "reduce_rotations",
]
__version__ = "0.1.0"
