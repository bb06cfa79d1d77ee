"""An attribute's samples smoothed before they are reduced (:mod:`sketchanim.reducer.smoothing`).

A vector attribute's channels are smoothed as they are. An orientation's quaternions
are first put on one hemisphere (``q`` and ``-q`` are one rotation), smoothed component
by component, and normalised again. :func:`smoothed_samples` smooths a whole take;
:class:`SampleSmoother` the samples of a take while it is recorded, with the same result.
"""

from __future__ import annotations

import numpy as np

from sketchanim.anim.attributes import AttributeType
from sketchanim.motion.rotations import continuous_quaternions
from sketchanim.reducer.smoothing import StreamSmoother


class SampleSmoother:
    """Smooth the samples of one attribute of ``type`` as they arrive, over ``sigma``
    seconds (0: unchanged): :meth:`push` and :meth:`close` as
    :class:`~sketchanim.reducer.smoothing.StreamSmoother`'s.

    >>> from sketchanim.anim.attributes import ORIENTATION
    >>> s = SampleSmoother(ORIENTATION, 0.05)
    >>> q = np.array([[0, 0, 0, 1.0], [0, 0, 0, -1.0], [0, 0, 0, 1.0]])   # one rotation, signs flipping
    >>> t, x = s.push([0.0, 0.1, 0.2], q)
    >>> t2, x2 = s.close()
    >>> np.vstack([x, x2])[:, 3].round(12).tolist()      # not averaged to zero
    [1.0, 1.0, 1.0]
    """

    def __init__(self, type: AttributeType, sigma: float) -> None:
        self.rotation = type.is_rotation
        self.stream = StreamSmoother(type.dim, sigma)
        self._last: np.ndarray | None = None        # the last quaternion taken, on its hemisphere

    def push(self, times: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Take samples in time order; return those now smoothed (times, values)."""
        if self.rotation and len(values):
            values = continuous_quaternions(values, previous=self._last)
            self._last = values[-1]
        return self._unit(self.stream.push(times, values))

    def close(self) -> tuple[np.ndarray, np.ndarray]:
        """The samples still held back, smoothed."""
        return self._unit(self.stream.close())

    def _unit(self, out: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        t, x = out
        return (t, x / np.linalg.norm(x, axis=1, keepdims=True)) if self.rotation and len(x) else (t, x)


def smoothed_samples(type: AttributeType, times: np.ndarray, values: np.ndarray, sigma: float) -> np.ndarray:
    """The samples of a take of an attribute of ``type``, smoothed over ``sigma``
    seconds (0: ``values`` as they are).

    >>> from sketchanim.anim.attributes import FLOAT
    >>> t = np.linspace(0, 1, 11)
    >>> smoothed_samples(FLOAT, t, np.c_[t + 0.1 * (-1) ** np.arange(11)], 0.1)[5:7, 0].round(3).tolist()
    [0.499, 0.601]
    """
    if not sigma:
        return np.asarray(values, dtype=float)
    s = SampleSmoother(type, sigma)
    first, rest = s.push(times, values)[1], s.close()[1]
    return np.vstack([first, rest])
