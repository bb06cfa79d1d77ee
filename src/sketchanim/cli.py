"""The ``sketchanim`` command line."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated, Optional

import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from sketchanim.errors import InputError, SampleError
from sketchanim.io.atomic import write_atomic
from sketchanim.io.csvio import read_samples_csv
from sketchanim.reducer import METHODS, Reduction, reduce

app = typer.Typer(
    help="Sketch 3D animations: reduce performed motion to compact B-splines within tolerance.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
console = Console()
errors = Console(stderr=True)


@app.callback()
def main() -> None:
    """sketchanim command line."""


def _tolerances(text: str) -> list[float]:
    try:
        return [float(part) for part in text.split(",")]
    except ValueError:
        raise InputError(f"--tol: expected a number or comma-separated numbers, got {text!r}") from None


def summary_line(reduction: Reduction, seconds: float) -> str:
    """One line: samples, control points, ratio, order, time."""
    return (f"{reduction.n_samples} samples -> {reduction.n_coefficients} control points "
            f"(ratio {reduction.ratio:.1f}:1, order {reduction.order}, {seconds * 1e3:.1f} ms)")


def summary_table(reduction: Reduction, channels: list[str]) -> Table:
    """Per channel: tolerance, max error at the samples, and their ratio."""
    table = Table()
    table.add_column("channel")
    table.add_column("tolerance", justify="right")
    table.add_column("max error", justify="right")
    table.add_column("max error / tol", justify="right")
    for name, tol, err in zip(channels, reduction.tol, reduction.max_error):
        table.add_row(name, f"{tol:.6g}", f"{err:.6g}", f"{err / tol:.3f}")
    return table


@app.command("reduce")
def reduce_command(
    input: Annotated[Path, typer.Argument(help="CSV: time in seconds, then one column per channel.")],
    tol: Annotated[str, typer.Option("--tol", help="Tolerance: one value, or one per channel (comma-separated).")],
    output: Annotated[Optional[Path], typer.Option("-o", "--output", help="Write the spline JSON here.")] = None,
    order: Annotated[int, typer.Option(help="Spline order (4: cubic).")] = 4,
    method: Annotated[str, typer.Option(help=f"One of: {', '.join(METHODS)}.")] = "global",
    start: Annotated[str, typer.Option(help="Starting curve: paper or lm.")] = "paper",
    window: Annotated[int, typer.Option(help="Knots per window of the incremental method.")] = 20,
    plot: Annotated[Optional[Path], typer.Option(help="Draw components, control points and errors to this PNG.")] = None,
) -> None:
    """Reduce a CSV of samples to a B-spline; print the report, write JSON and plot."""
    try:
        table = read_samples_csv(input)
        clock = time.perf_counter()
        try:
            reduction = reduce(table.times, table.values, _tolerances(tol), order=order, method=method, start=start,
                               window=window)
        except SampleError as err:
            if err.index is None:
                raise
            raise InputError(f"{input}, line {table.lines[err.index]}: {err}") from None
        seconds = time.perf_counter() - clock
    except InputError as err:
        _fail(str(err))
    console.print(summary_line(reduction, seconds))
    console.print(summary_table(reduction, table.channels))
    if reduction.report.get("duplicates_dropped"):
        console.print(f"dropped {reduction.report['duplicates_dropped']} exact duplicate samples")
    try:
        if output is not None:
            write_atomic(output, reduction.to_json())
            console.print(f"wrote {output}")
        if plot is not None:
            from sketchanim.plot import plot_reduction

            plot_reduction(table.times, table.values, reduction, plot, table.channels, title=str(input))
            console.print(f"wrote {plot}")
    except OSError as err:
        _fail(f"{err.filename or output}: cannot write ({err.strerror})")


@app.command("paper")
def paper_command(
    output: Annotated[Path, typer.Option("-o", "--output", help="Folder for the PNG plots.")] = Path("out/paper"),
    data: Annotated[Path, typer.Option(help="Recordings folder; its camera path runs beside the synthetic takes.")]
    = Path("../shared/data"),
) -> None:
    """Re-run the paper's section 2.2 experiments; print tables 8 and 10 and write the figures."""
    from sketchanim.paper import run

    try:
        tables = run(output, data if data.is_dir() else None)
    except OSError as err:
        _fail(f"{err.filename or output}: cannot write ({err.strerror})")
    for name, rows in tables.items():
        table = Table(title=name if name != "spiral" else "spiral, window 10, tol (0.1, 0.1): figures 1 and 2")
        for column in rows[0]:
            table.add_column(column, justify="right")
        for row in rows:
            table.add_row(*(f"{v:.1f}" if isinstance(v, float) else str(v) for v in row.values()))
        console.print(table)
    console.print(f"wrote the figures to {output}/")


def _fail(message: str) -> None:
    errors.print(Text.assemble(("error: ", "red"), message), soft_wrap=True)
    raise typer.Exit(2)
