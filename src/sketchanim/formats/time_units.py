"""Time columns in seconds: units converted when asked, and columns that are clearly
not seconds recognised (wall-clock nanoseconds, microseconds or milliseconds since
1970; whole-number counters), so they are never reduced as seconds by mistake."""

from __future__ import annotations

import numpy as np

from sketchanim.errors import ArgumentError
from sketchanim.limits import LIMITS

#: Seconds per unit of a time column.
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}

#: Smallest magnitude of wall-clock times since 1970 in each unit (the year 2001 on).
_WALL_CLOCK = (("ns", 1e18), ("us", 1e15), ("ms", 1e12))

#: Whole-number times reaching this are taken for a counter, not seconds (16 minutes
#: of whole seconds is not how motion is sampled).
COUNTER = 1000.0

def to_seconds(times: np.ndarray, *, unit: str | None = None, rate: float | None = None) -> tuple[np.ndarray, str]:
    """``times`` in seconds, and a note saying how they were read.

    ``rate`` (Hz) reads them as frame numbers, ``unit`` (one of :data:`TIME_UNITS`) as
    that unit. Without either, times at wall-clock magnitudes in ns, us or ms since 1970
    are converted (the note says so), and whole numbers reaching :data:`COUNTER` (frame
    numbers, clock ticks, packet counters) are refused with an :class:`ArgumentError` that says what to pass.

    >>> t, note = to_seconds(np.array([1.7e18, 1.7e18 + 1e7]))
    >>> round(float(t[1] - t[0]), 6), note
    (0.01, 'time column read as nanoseconds since 1970 (from its magnitude; time_unit=UNIT to change)')
    >>> to_seconds(np.array([0.0, 1.0, 2.0, 3.0]), rate=30)[0].tolist()
    [0.0, 0.03333333333333333, 0.06666666666666667, 0.1]
    """
    if rate is not None and unit is not None:
        raise ArgumentError("rate", "give rate= (times are frame numbers) or time_unit=, not both")
    if rate is not None:
        rate = float(LIMITS["rate"].check(rate))
        return times / rate, f"time column read as frame numbers at {rate:g} Hz"
    if unit is not None:
        if unit not in TIME_UNITS:
            raise ArgumentError("time_unit", f"one of {', '.join(TIME_UNITS)}, got {unit!r}")
        return (times if unit == "s" else times * TIME_UNITS[unit]), f"time column read as {unit}"
    if not len(times):
        return times, "time column read as seconds"
    top = float(np.max(np.abs(times)))
    for name, least in _WALL_CLOCK:
        if top >= least:
            long_name = {"ns": "nanoseconds", "us": "microseconds", "ms": "milliseconds"}[name]
            origin = float(times[0])
            return (times - origin) * TIME_UNITS[name] + origin * TIME_UNITS[name], (f"time column read as {long_name} since 1970 (from its magnitude; "
                                             f"time_unit=UNIT to change)")
    if len(times) >= 3 and top >= COUNTER and np.all(times == np.round(times)) and top < 2.0**53:
        steps = np.diff(times)
        step = float(np.median(steps)) if len(steps) else 0.0
        raise ArgumentError("time", f"the time column holds whole numbers ({float(times[0]):g} to "
                                    f"{float(times[-1]):g}, steps of {step:g}): frame numbers or clock ticks, not "
                                    f"seconds? Pass rate=HZ for frame numbers, time_unit=ms|us|ns for ticks, or "
                                    f"time_unit=s if they are seconds")
    return times, "time column read as seconds"
