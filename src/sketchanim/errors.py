"""Errors raised on bad input, shared by every layer.

Each names what is wrong and where: the argument, the sample index, the channel, or the
file and line. All are :class:`ValueError` subclasses, so callers that only know numpy's
conventions still catch them.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad input: the message says what is wrong and where.

    Examples
    --------
    >>> try:
    ...     raise SampleError("time is NaN", index=3, field="time")
    ... except InputError as err:
    ...     print(err, err.index, err.field)
    sample 3, time: time is NaN 3 time
    """


class ArgumentError(InputError):
    """A bad argument (tolerance, order, method...), named in ``argument``."""

    def __init__(self, argument: str, message: str) -> None:
        self.argument = argument
        super().__init__(f"{argument}: {message}")


class SampleError(InputError):
    """A bad sample, at position ``index`` of the caller's input, in ``field``."""

    def __init__(self, message: str, *, index: int | None = None, field: str | None = None) -> None:
        self.index = index
        self.field = field
        where = []
        if index is not None:
            where.append(f"sample {index}")
        if field is not None:
            where.append(field)
        super().__init__(f"{', '.join(where)}: {message}" if where else message)


class FileFormatError(InputError):
    """A malformed file, at ``path`` and (where known) 1-based ``line``."""

    def __init__(self, path: str, message: str, *, line: int | None = None) -> None:
        self.path = path
        self.line = line
        where = f"{path}, line {line}" if line is not None else path
        super().__init__(f"{where}: {message}")


class ToleranceUnreachableError(InputError):
    """Not even the interpolating spline meets the tolerance (it is below rounding)."""
