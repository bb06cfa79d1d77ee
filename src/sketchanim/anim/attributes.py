"""Attribute types: what an animatable attribute holds, and how it is checked.

A continuous attribute (position, orientation, colour...) is a float vector of fixed
size, recorded into a B-spline within a tolerance in its own units; a discrete one
(bool, enum, event) is recorded as time-stamped values with step semantics.
Orientations are unit quaternions, scalar-last (x, y, z, w) as scipy's ``Rotation``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sketchanim.errors import ArgumentError
from sketchanim.motion.rotations import MIN_NORM

#: Kinds of discrete attribute.
DISCRETE = ("bool", "enum", "event")

#: The closed range every channel of these attributes keeps (the others are unbounded):
#: a colour channel is a fraction; an intensity is no negative light; a field of view
#: is a perspective camera's only between 0 and 180 degrees (tan(fov / 2) is finite
#: and positive), and 1 to 179 keeps its zoom within 1/115 .. 115 of a 90-degree view;
#: a scale of 0 is a singular transform (no inverse, no normals), and 1e-3 (a
#: thousandth of the object, a fifth of the default tolerance) is the least that
#: keeps it invertible in float32 with room to spare.
BOUNDS: dict[str, tuple[float, float]] = {
    "color": (0.0, 1.0),
    "intensity": (0.0, np.inf),
    "fov": (1.0, 179.0),
    "scale": (1e-3, np.inf),
}


@dataclass(frozen=True)
class AttributeType:
    """The type of an attribute.

    Attributes
    ----------
    name : str
        "position", "orientation", "scale", "color", "intensity", "fov", "float",
        "vector", or a discrete kind: "bool", "enum", "event".
    dim : int
        Size of a continuous value (0 for a discrete one).
    tol : float
        Default recording tolerance, in ``unit``.
    unit : str
        "scene units", "degrees" (an orientation's geodesic angle, or a field of view),
        "colour units" (0..1 per channel), or "" for plain numbers.
    default : tuple
        The value a new attribute starts with (a discrete one: ``(value,)``).
    choices : tuple of str
        An enum's allowed values.

    >>> POSITION.dim, POSITION.tol, ORIENTATION.unit, ORIENTATION.is_rotation
    (3, 0.005, 'degrees', True)
    """

    name: str
    dim: int
    tol: float
    unit: str
    default: tuple
    choices: tuple[str, ...] = ()

    @property
    def continuous(self) -> bool:
        """Recorded into a spline (else into step events)."""
        return self.name not in DISCRETE

    @property
    def initial(self) -> object:
        """The value a new attribute of this type starts with.

        >>> SCALE.initial, BOOL.initial
        ((1.0, 1.0, 1.0), True)
        """
        return self.default if self.continuous else self.default[0]

    @property
    def bounds(self) -> tuple[float, float] | None:
        """The closed range of every channel (:data:`BOUNDS`), or None: unbounded.

        >>> COLOR.bounds, POSITION.bounds
        ((0.0, 1.0), None)
        """
        return BOUNDS.get(self.name)

    @property
    def is_rotation(self) -> bool:
        """A unit quaternion, bounded by the geodesic angle."""
        return self.name == "orientation"

    @staticmethod
    def vector(dim: int, tol: float = 1e-3) -> AttributeType:
        """A plain float vector of ``dim`` channels.

        >>> AttributeType.vector(2).default
        (0.0, 0.0)
        """
        if isinstance(dim, bool) or not isinstance(dim, (int, np.integer)) or not 1 <= dim <= 64:
            raise ArgumentError("dim", f"must be an integer from 1 to 64, got {dim!r}")
        return AttributeType("vector", int(dim), _positive("tol", tol), "", (0.0,) * int(dim))

    @staticmethod
    def enum(choices: tuple[str, ...] | list[str]) -> AttributeType:
        """A discrete attribute taking one of ``choices`` (the first by default).

        >>> AttributeType.enum(["walk", "run"]).default
        ('walk',)
        """
        names = tuple(choices)
        if not names or not all(isinstance(c, str) and c for c in names) or len(set(names)) != len(names):
            raise ArgumentError("choices", f"must be distinct non-empty strings, got {choices!r}")
        return AttributeType("enum", 0, 0.0, "", (names[0],), names)

    def check(self, value: object, where: str = "value", *, bounded: bool = True) -> object:
        """``value`` in this type's canonical form (a float array of shape (dim,), a
        unit quaternion, or a discrete value); :class:`ArgumentError` naming ``where``
        if it does not fit, or (with ``bounded``; an additive take's offsets are not)
        if it leaves the type's :attr:`bounds`.

        >>> ORIENTATION.check([0, 0, 0, 2]).tolist()
        [0.0, 0.0, 0.0, 1.0]
        >>> COLOR.check([1.0, 0.5, 1.2], "lamp.color")
        Traceback (most recent call last):
        ...
        sketchanim.errors.ArgumentError: lamp.color: a color keeps every channel in [0.0, 1.0], got [1.0, 0.5, 1.2]
        >>> BOOL.check(1)
        Traceback (most recent call last):
        ...
        sketchanim.errors.ArgumentError: value: a bool attribute takes True or False, got 1
        """
        if self.name == "bool":
            if not isinstance(value, (bool, np.bool_)):
                raise ArgumentError(where, f"a bool attribute takes True or False, got {value!r}")
            return bool(value)
        if self.name == "enum":
            if value not in self.choices:
                raise ArgumentError(where, f"must be one of {list(self.choices)}, got {value!r}")
            return value
        if self.name == "event":
            if value is not None and not isinstance(value, str):
                raise ArgumentError(where, f"an event carries a label (a string) or None, got {value!r}")
            return value
        try:
            v = np.asarray(value, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ArgumentError(where, f"must be {self.dim} numbers, got {value!r}") from None
        if v.shape != (self.dim,):
            raise ArgumentError(where, f"must be {self.dim} numbers, got {v.size}")
        if not np.all(np.isfinite(v)):
            raise ArgumentError(where, f"must be finite, got {v.tolist()}")
        if self.is_rotation:
            norm = float(np.linalg.norm(v))
            if norm < MIN_NORM:                          # what the rotation reducers refuse too
                raise ArgumentError(where, f"a zero quaternion is no orientation (norm {norm:.3g})")
            v = v / norm
        limits = self.bounds
        if bounded and limits is not None and (np.any(v < limits[0]) or np.any(v > limits[1])):
            raise ArgumentError(where, f"a {self.name} keeps every channel in [{limits[0]}, {limits[1]}], "
                                       f"got {v.tolist()}")
        return v


def _positive(name: str, value: float) -> float:
    if not (isinstance(value, (int, float, np.floating)) and np.isfinite(value) and value > 0):
        raise ArgumentError(name, f"must be a positive number, got {value!r}")
    return float(value)


POSITION = AttributeType("position", 3, 0.005, "scene units", (0.0, 0.0, 0.0))
ORIENTATION = AttributeType("orientation", 4, 0.5, "degrees", (0.0, 0.0, 0.0, 1.0))
SCALE = AttributeType("scale", 3, 0.005, "scene units", (1.0, 1.0, 1.0))
COLOR = AttributeType("color", 3, 0.005, "colour units", (1.0, 1.0, 1.0))
INTENSITY = AttributeType("intensity", 1, 0.01, "", (1.0,))
FOV = AttributeType("fov", 1, 0.1, "degrees", (50.0,))
FLOAT = AttributeType("float", 1, 1e-3, "", (0.0,))
BOOL = AttributeType("bool", 0, 0.0, "", (True,))
EVENT = AttributeType("event", 0, 0.0, "", (None,))

#: The named types (vectors and enums are made with :meth:`AttributeType.vector` and
#: :meth:`AttributeType.enum`).
TYPES = {t.name: t for t in (POSITION, ORIENTATION, SCALE, COLOR, INTENSITY, FOV, FLOAT, BOOL, EVENT)}
