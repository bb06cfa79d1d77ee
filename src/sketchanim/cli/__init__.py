"""The ``sketchanim`` command line: it parses, hands the work to the library, maps the
library's errors (which name fields) to its flags, and prints."""

from __future__ import annotations

from typing import Annotated

import typer

from sketchanim.cli.commands import export_command, paper_command, studio_command
from sketchanim.cli.flags import console
from sketchanim.cli.reduce import REDUCE_HELP, reduce_command
from sketchanim.cli.salvage import salvage_command

app = typer.Typer(
    help="Sketch 3D animations: reduce performed motion to compact B-splines within tolerance.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _version(value: bool) -> None:
    if value:
        from importlib.metadata import version

        console.print(f"sketchanim {version('sketchanim')}")
        raise typer.Exit()


@app.callback()
def main(version: Annotated[bool, typer.Option("--version", metavar="", callback=_version, is_eager=True,
                                               help="Print the version and exit.")] = False) -> None:
    """sketchanim command line."""


app.command("reduce", help=REDUCE_HELP)(reduce_command)
app.command("export")(export_command)
app.command("paper")(paper_command)
app.command("studio")(studio_command)
app.command("salvage")(salvage_command)

__all__ = ["app"]
