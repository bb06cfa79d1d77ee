"""``sketchanim salvage``: a damaged project's sound parts, into a new project."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer
from rich.table import Table

from sketchanim.cli.flags import console, fail, fail_to_write
from sketchanim.errors import InputError


def salvage_command(
    project: Annotated[Path, typer.Argument(help="The damaged project file (read, never written).")],
    output: Annotated[Optional[Path], typer.Option("-o", "--output", help="The new project (default: "
                                                   "<stem>.salvaged.sketchanim beside the damaged one).")] = None,
    force: Annotated[bool, typer.Option("--force", help="Replace the output (and its orphan takes file) if it "
                                        "exists.")] = False,
) -> None:
    """Keep what is sound in a damaged project: the scene and its tracks if the document
    is undamaged, each track with its undamaged takes, as a new project; undamaged takes
    of no track in OUT.orphan-takes.json. Prints what was kept and what was left out.

    Example: sketchanim salvage show.sketchanim -o show.salvaged.sketchanim"""
    from sketchanim.project.salvage import default_output, salvage_project

    out = default_output(project) if output is None else output
    try:
        report = salvage_project(project, out, force=force)
    except InputError as err:
        fail(str(err))
    except OSError as err:
        fail_to_write(err, out)
    table = Table(title=f"salvaged {project} into {report.out}")
    table.add_column("kept")
    table.add_column("left out, and why")
    for i in range(max(len(report.kept), len(report.left_out))):
        table.add_row(*(rows[i] if i < len(rows) else "" for rows in (report.kept, report.left_out)))
    console.print(table)
    console.print(f"wrote {report.out}" + (f" and {report.orphans}" if report.orphans else ""))
