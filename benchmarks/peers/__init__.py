"""The peers our figures are measured against: SISL (Lyche-Morken's own routines) and
scipy's FITPACK. Each returns a :class:`PeerResult` checked against the samples."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline


@dataclass(frozen=True)
class PeerResult:
    """One peer's answer: its spline, its count and the seconds it took."""

    name: str
    spline: BSpline
    seconds: float

    @property
    def n_coefficients(self) -> int:
        return len(self.spline.c)

    def max_error(self, times: np.ndarray, values: np.ndarray) -> np.ndarray:
        """Largest |spline - sample| per channel, measured at the samples."""
        return np.abs(np.asarray(self.spline(times)).reshape(values.shape) - values).max(axis=0)
