"""The command line's flags by option field, and library messages told in flags: the
library names fields (``cols: ...``, ``rate=HZ``), the command line prints ``--cols``
and ``--rate HZ``; errors end the command with exit status 2."""

from __future__ import annotations

import re
from typing import NoReturn

import typer
from rich.console import Console
from rich.text import Text

console = Console()
stderr = Console(stderr=True)

#: The flag of each option field the library's messages name.
FLAGS = {
    "output": "-o", "tol": "--tol", "order": "--order", "method": "--method", "start": "--start",
    "window": "--window", "plot": "--plot", "rot_cols": "--rot-cols", "rot_tol_deg": "--rot-tol-deg",
    "rot_mode": "--rot-mode", "seq": "--seq", "scalar_first": "--scalar-first", "pauses": "--pauses",
    "breaks": "--breaks", "min_pause": "--min-pause", "units": "--units", "skeleton": "--skeleton",
    "world": "--world", "shell_cm": "--shell", "rate": "--rate", "format": "--format", "workers": "--workers",
    "scheduler": "--scheduler", "time_unit": "--time-unit", "time_col": "--time-col", "cols": "--cols",
    "groups": "--groups", "duplicates": "--duplicates", "unordered": "--unordered", "gap": "--gap",
    "keys": "--keys", "contacts": "--contacts", "force": "--force",
}

_NAMES = "|".join(sorted(FLAGS, key=len, reverse=True))
#: A field heading a message or a part of one (``cols: ...``), or suggested with a
#: value (``rate=HZ``, ``time_unit=s``).
_FIELD = re.compile(rf"(?:(?<=^)|(?<=: )|(?<=, )|(?<=\()|(?<=; ))({_NAMES}):|(?<![\w./-])({_NAMES})=(?=(\S?))")


def _flag(match: re.Match[str]) -> str:
    if match.group(1):
        return FLAGS[match.group(1)] + ":"
    follows = match.group(3)
    return FLAGS[match.group(2)] + (" " if follows and follows not in ").,;" else "")


def in_flags(message: str) -> str:
    """A library message with the fields it names told as this command line's flags.

    >>> in_flags("f.csv: cols: 'z' is not a column")
    "f.csv: --cols: 'z' is not a column"
    >>> in_flags("whole numbers: pass rate=HZ for frame numbers, or time_unit=s")
    'whole numbers: pass --rate HZ for frame numbers, or --time-unit s'
    >>> in_flags("the frame rate: 30")
    'the frame rate: 30'
    """
    return _FIELD.sub(_flag, message)


def fail(message: str) -> NoReturn:
    """Print ``message`` (in flags) as an error and exit with status 2."""
    stderr.print(Text.assemble(("error: ", "red"), in_flags(message)), soft_wrap=True)
    raise typer.Exit(2)


def fail_to_write(err: OSError, output: object) -> NoReturn:
    """An output that could not be written, named."""
    fail(f"{err.filename or output}: cannot write ({err.strerror})")
