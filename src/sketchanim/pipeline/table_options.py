"""How a sample table is read and reduced: one frozen object, checked once against
:data:`sketchanim.limits.LIMITS` and the choices each field takes."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from sketchanim.formats.gltf_frames import KEYS
from sketchanim.formats.quirks import DUPLICATES, UNORDERED
from sketchanim.formats.tables import FORMATS
from sketchanim.formats.time_units import TIME_UNITS
from sketchanim.limits import LIMITS, one_of
from sketchanim.motion.rotations import ROTATION_MODES
from sketchanim.reducer import METHODS, FeatureOptions
from sketchanim.reducer.global_method import STARTS


def _names(value: Sequence[str] | str | None) -> tuple[str, ...] | None:
    """Names given as a sequence (or one comma-separated string), stripped."""
    if value is None:
        return None
    parts = value.split(",") if isinstance(value, str) else value
    return tuple(str(p).strip() for p in parts)


@dataclass(frozen=True)
class TableOptions:
    """How :func:`~sketchanim.pipeline.table.reduce_table` reads and reduces a table.

    Every field is checked when the object is made (an
    :class:`~sketchanim.errors.ArgumentError` naming the field); numeric ranges are
    :data:`~sketchanim.limits.LIMITS`.

    Attributes
    ----------
    tol : tuple of float or None
        Tolerance: one value, or one per channel (every channel but the rotation's);
        needed unless the table holds only an orientation.
    order, method, start, window
        The spline order, ``"global"`` or ``"incremental"``, the global method's
        starting curve (``"paper"`` or ``"lm"``), knots per incremental window
        (:func:`sketchanim.reduce`).
    rot_cols : tuple of str or None
        Rotation columns: 4 (a quaternion, x, y, z, w unless ``scalar_first``) or 3
        (Euler angles in degrees, in ``seq`` order); None: the format's (TUM, EuRoC,
        KITTI), else no rotation.
    rot_tol_deg, rot_mode, seq, scalar_first
        The rotation's tolerance in degrees, its curve (``"quaternion"`` or
        ``"euler"``), Euler sequence, and quaternion layout.
    pauses, breaks, min_pause, gap
        Features kept (:class:`~sketchanim.reducer.FeatureOptions`); ``gap`` 0 (the default): no long-interval cut.
    format, time_unit, time_col, cols, rate
        How the file is read (:func:`sketchanim.formats.tables.read_table`).
    groups : tuple of tuple of str, or None
        Channel groups reduced with their own knot vectors; channels not listed form
        one more group.
    duplicates, unordered
        Real-data quirks (:mod:`sketchanim.formats.quirks`).
    keys : {"curves", "frames", "compact"}
        How a .glb holds the path (:mod:`sketchanim.export.table_gltf`): the curves
        exactly; the curves as LINEAR keys at the sample times (for importers that
        ignore tangents); or ``"compact"``, the fewest LINEAR keys picked from the
        samples, quantised and meshopt-compressed. Either of the last two plays within
        the tolerance of every sample; they need a .glb output and the table read whole.

    ``cols``, ``rot_cols`` and ``groups`` also take text as the command line writes
    them (``"x,y"``, ``"x,y:pressure"``); ``tol`` one number for every channel.

    Examples
    --------
    >>> TableOptions(tol=0.01).tol
    (0.01,)
    >>> TableOptions(tol=0.01, window=2)
    Traceback (most recent call last):
    sketchanim.errors.ArgumentError: window: the incremental method's window must be 4 to 1000 knots, got 2
    >>> TableOptions(tol=0.01, keys="bezier")
    Traceback (most recent call last):
    sketchanim.errors.ArgumentError: keys: one of curves, frames, compact, got 'bezier'
    """

    tol: tuple[float, ...] | None = None
    order: int = 4
    method: str = "global"
    start: str = "paper"
    window: int = 20
    rot_cols: tuple[str, ...] | None = None
    rot_tol_deg: float = 0.5
    rot_mode: str = "quaternion"
    seq: str = "ZXY"
    scalar_first: bool = False
    pauses: bool = True
    breaks: bool = True
    min_pause: float = 0.5
    gap: float = 0.0
    format: str = "auto"
    time_unit: str | None = None
    time_col: str | None = None
    cols: tuple[str, ...] | None = None
    groups: tuple[tuple[str, ...], ...] | None = None
    duplicates: str = "error"
    unordered: str = "error"
    rate: float | None = None
    keys: str = "curves"

    def __post_init__(self) -> None:
        if self.tol is not None:
            tol = (self.tol,) if isinstance(self.tol, (int, float)) else tuple(self.tol)
            object.__setattr__(self, "tol", tuple(float(LIMITS["tol"].check(v)) for v in tol))
        for name in ("order", "window", "rot_tol_deg", "min_pause", "gap"):
            LIMITS[name].check(getattr(self, name))
        if self.rate is not None:
            LIMITS["rate"].check(self.rate)
        one_of("method", self.method, METHODS, either=True)
        one_of("start", self.start, STARTS, either=True)
        one_of("rot_mode", self.rot_mode, ROTATION_MODES, either=True)
        one_of("duplicates", self.duplicates, DUPLICATES)
        one_of("unordered", self.unordered, UNORDERED)
        one_of("format", self.format, FORMATS)
        one_of("keys", self.keys, KEYS)
        if self.time_unit is not None:
            one_of("time_unit", self.time_unit, tuple(TIME_UNITS))
        object.__setattr__(self, "cols", _names(self.cols))
        object.__setattr__(self, "rot_cols", _names(self.rot_cols))
        if self.groups is not None:
            groups = self.groups.split(":") if isinstance(self.groups, str) else self.groups
            object.__setattr__(self, "groups", tuple(_names(g) for g in groups))

    @property
    def features(self) -> FeatureOptions:
        """The features kept, as the reducer takes them."""
        return FeatureOptions(pauses=self.pauses, breaks=self.breaks, min_pause=self.min_pause, gap=self.gap or None)
