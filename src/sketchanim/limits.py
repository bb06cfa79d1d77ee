"""Every numeric range an option of the file pipelines takes, in one table: its name, its
bounds and its unit. The options objects (:mod:`sketchanim.pipeline`,
:mod:`sketchanim.batch`) check their fields against it once, the command line shows the
ranges in ``--help`` and maps the errors to its flags, and ``docs/input-limits.md`` lists
every entry (a test checks that they agree).

>>> LIMITS["order"].check(4)
4
>>> LIMITS["order"].check(60)
Traceback (most recent call last):
sketchanim.errors.ArgumentError: order: the spline order must be 2 to 8, got 60
>>> LIMITS["tol"].describe()
'above 0 and at most 1e12'
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from sketchanim.errors import ArgumentError


def number_text(value: float) -> str:
    """A bound as the docs and messages write it: whole numbers below 1e7 in full,
    others in ``g`` notation without the exponent's ``+``.

    >>> number_text(1000000.0), number_text(1e12), number_text(0.5)
    ('1000000', '1e12', '0.5')
    """
    if math.isfinite(value) and value == int(value) and abs(value) < 1e7:
        return str(int(value))
    return f"{value:g}".replace("e+0", "e").replace("e+", "e")


@dataclass(frozen=True)
class Limit:
    """The range of one numeric option field.

    Attributes
    ----------
    field : str
        The options field it checks (errors name it).
    what : str
        What the value is, as an error says it ("the spline order").
    low, high : float
        Bounds; ``high`` may be ``inf`` (no upper bound).
    unit : str
        The value's unit ("" for counts and the channels' own units).
    above : bool
        ``low`` itself is refused (the value must be above it).
    zero : bool
        0 is accepted too (it turns the feature off).
    whole : bool
        Only whole numbers.
    """

    field: str
    what: str
    low: float
    high: float
    unit: str = ""
    above: bool = False
    zero: bool = False
    whole: bool = False

    def describe(self) -> str:
        """The range in words, as ``--help``, errors and the docs give it.

        >>> LIMITS["gap"].describe(), LIMITS["window"].describe()
        ('0 (off) or above 1', '4 to 1000 knots')
        """
        unit = f" {self.unit}" if self.unit else ""
        low, high = number_text(self.low), number_text(self.high)
        if math.isinf(self.high):
            text = f"above {low}{unit}" if self.above else f"{low}{unit} or more"
        elif self.above:
            text = f"above {low} and at most {high}{unit}"
        else:
            text = f"{low} to {high}{unit}"
        return f"0 (off) or {text}" if self.zero else text

    def admits(self, value: float) -> bool:
        """Whether ``value`` is in range.

        >>> LIMITS["gap"].admits(0), LIMITS["gap"].admits(0.5)
        (True, False)
        """
        try:
            number = float(value)
        except (TypeError, ValueError):
            return False
        if isinstance(value, bool) or math.isnan(number) or (self.whole and number != int(number)):
            return False
        if self.zero and number == 0:
            return True
        return (number > self.low if self.above else number >= self.low) and number <= self.high

    def check(self, value: float, field: str | None = None) -> float:
        """``value`` if in range, else an :class:`~sketchanim.errors.ArgumentError`
        naming ``field`` (default: :attr:`field`)."""
        if not self.admits(value):
            got = value if isinstance(value, (int, str)) else f"{value:g}" if isinstance(value, float) else repr(value)
            raise ArgumentError(field or self.field, f"{self.what} must be {self.describe()}, got {got}")
        return value


#: Every numeric option range, by name (the name is the field's, but for the rates
#: that share the field ``rate``).
LIMITS: dict[str, Limit] = {limit_name: limit for limit_name, limit in (
    ("tol", Limit("tol", "each tolerance", 0, 1e12, above=True)),
    ("rot_tol_deg", Limit("rot_tol_deg", "the rotation tolerance", 0, 180, "degrees", above=True)),
    ("order", Limit("order", "the spline order", 2, 8, whole=True)),
    ("window", Limit("window", "the incremental method's window", 4, 1000, "knots", whole=True)),
    ("min_pause", Limit("min_pause", "the shortest pause", 0, math.inf, "seconds", above=True)),
    ("gap", Limit("gap", "the gap, in median sampling intervals,", 1, math.inf, above=True, zero=True)),
    ("rate", Limit("rate", "a rate in Hz", 0, 1e6, "Hz", above=True)),
    ("clip_rate", Limit("rate", "a clip's frame rate", 1, 1000, "frames per second")),
    ("shell_cm", Limit("shell_cm", "the shell's distance from each joint", 0, math.inf, "cm")),
    ("workers", Limit("workers", "the number of worker processes", 1, 256, whole=True)),
)}


def one_of(field: str, value: object, choices: Sequence[str], *, either: bool = False) -> None:
    """Refuse ``value`` unless it is one of ``choices``, with an
    :class:`~sketchanim.errors.ArgumentError` naming ``field``.

    >>> one_of("keys", "bezier", ("curves", "frames"))
    Traceback (most recent call last):
    sketchanim.errors.ArgumentError: keys: one of curves, frames, got 'bezier'
    """
    if value not in choices:
        listed = " or ".join(choices) if either else "one of " + ", ".join(choices)
        raise ArgumentError(field, f"{listed}, got {value!r}")
