"""``sketchanim export``, ``paper`` and ``studio``: each parses, hands the work to the
library and prints what came back."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer
from rich.table import Table

from sketchanim.cli.flags import console, stderr, fail, fail_to_write
from sketchanim.errors import InputError
from sketchanim.formats.gltf_frames import KEYS
from sketchanim.limits import LIMITS, one_of

#: What ``export -o`` writes as USD.
USD_SUFFIXES = (".usd", ".usda", ".usdc")


def export_command(
    project: Annotated[Path, typer.Argument(help="A project file (.sketchanim).")],
    output: Annotated[Path, typer.Option("-o", "--output", help="The scene as glTF (.glb) or USD (.usd, .usda, "
                                         ".usdc), its skeletons as BVH (.bvh), or the whole project as JSON (.json).")],
    keys: Annotated[str, typer.Option("--keys", help="glTF: 'curves' (exact) or 'frames' (LINEAR keys at the "
                                      "takes' samples or --rate, for importers that ignore tangents).")] = "curves",
    rate: Annotated[Optional[float], typer.Option(help=f"With --keys frames: keys per second, "
                                                  f"{LIMITS['rate'].describe()}.")] = None,
) -> None:
    """Export a project: its scene as glTF (objects, cameras, lights, and their
    position, orientation and scale tracks) or USD (the same tracks as samples at the
    takes' times), its imported clips' skeletons as BVH (at the project's frame rate), or
    everything as JSON.

    Examples: sketchanim export show.sketchanim -o show.glb; sketchanim export show.sketchanim -o show.usda;
    sketchanim export show.sketchanim -o show.bvh; sketchanim export show.sketchanim -o show.json"""
    from sketchanim.atomic import write_atomic
    from sketchanim.export.scene_bvh import skeleton_clip
    from sketchanim.export.scene_gltf import scene_glb
    from sketchanim.export.scene_usd import scene_usd
    from sketchanim.formats.bvh import write_bvh
    from sketchanim.project.store import Project

    suffix = output.suffix.lower()
    try:
        one_of("keys", keys, KEYS)
        if rate is not None:
            LIMITS["rate"].check(rate)
        if suffix not in (".glb", ".json", ".bvh", *USD_SUFFIXES):
            fail(f"-o: a project exports to .glb, .json, .bvh or {', '.join(USD_SUFFIXES)}, "
                 f"not {suffix or 'a file without an extension'}")
        with Project(project, create=False) as opened:
            if suffix == ".json":
                opened.export_json(output)
                left_out: list[str] = []
            elif suffix == ".bvh":
                scene, tracks = opened.load()
                write_bvh(output, skeleton_clip(scene, tracks, opened.fps()))
                left_out = []
            elif suffix in USD_SUFFIXES:
                scene, tracks = opened.load()
                left_out = scene_usd(output, scene, tracks, opened.fps())
            else:
                scene, tracks = opened.load()
                glb, left_out = scene_glb(scene, tracks, name=output.stem, keys=keys, rate=rate)
                write_atomic(output, glb)
    except InputError as err:
        fail(str(err))
    except OSError as err:
        fail_to_write(err, output)
    console.print(f"wrote {output}")
    if left_out:
        stderr.print(f"not in the {'USD' if suffix in USD_SUFFIXES else 'glTF'} (a scene file animates only "
                     f"position, orientation and scale): "
                     f"{', '.join(left_out)}", soft_wrap=True)


def paper_command(
    output: Annotated[Path, typer.Option("-o", "--output", help="Folder for the PNG plots.")] = Path("out/paper"),
    data: Annotated[Path, typer.Option(help="Recordings folder; its camera path runs beside the synthetic takes.")]
    = Path("../shared/data"),
) -> None:
    """Re-run the paper's section 2.2 experiments; print tables 8 and 10 and write the figures.

    Example: sketchanim paper -o out/paper --data ../shared/data"""
    from sketchanim.paper import run_experiments

    try:
        tables = run_experiments(output, data if data.is_dir() else None)
    except OSError as err:
        fail_to_write(err, output)
    for name, rows in tables.items():
        table = Table(title=name if name != "spiral" else "spiral, window 10, tol (0.1, 0.1): figures 1 and 2")
        for column in rows[0]:
            table.add_column(column, justify="right")
        for row in rows:
            table.add_row(*(f"{v:.1f}" if isinstance(v, float) else str(v) for v in row.values()))
        console.print(table)
    console.print(f"wrote the figures to {output}/")


def studio_command(
    project: Annotated[Path, typer.Argument(help="The project file (created with a default scene if missing).")]
    = Path("studio.sketchanim"),
    host: Annotated[str, typer.Option(help="Address to serve on (127.0.0.1: this machine only).")] = "127.0.0.1",
    port: Annotated[int, typer.Option(help="Port to serve on.")] = 8000,
    browser: Annotated[bool, typer.Option("--browser/--no-browser", help="Open the page in a browser.")] = True,
    read_only: Annotated[bool, typer.Option("--read-only", help="Open the project read-only: it plays and exports, "
                                            "edits are refused (a project that cannot be written opens so "
                                            "anyway).")] = False,
    exports: Annotated[Optional[Path], typer.Option("--exports", help="The folder the page's exports go to "
                                                    "(default: the project's).")] = None,
    files: Annotated[Optional[Path], typer.Option("--files", help="The folder the page saves copies into and "
                                                  "opens projects from (default: the project's).")] = None,
    show_recent: Annotated[bool, typer.Option("--recent", help="List the projects opened lately, newest first, "
                                              "and exit.")] = False,
) -> None:
    """Start the studio: perform, record, play back and layer animation in the browser.

    Examples: sketchanim studio show.sketchanim; sketchanim studio show.sketchanim --read-only --exports out/;
    sketchanim studio --recent"""
    from sketchanim.studio.serve import serve

    if show_recent:
        print_recent()
        return
    try:
        serve(project, host, port, browser, console.print, read_only=read_only or None, exports=exports, files=files)
    except InputError as err:
        fail(str(err))
    except OSError as err:
        fail(f"{err.filename or f'{host}:{port}'}: {err.strerror or err}")


def print_recent() -> None:
    """The recent projects' list, newest first: when each was opened, and its path
    (marked when it is gone)."""
    import time

    from sketchanim.project.recent import recent, recent_file

    projects = recent()
    if not projects:
        console.print(f"no recent projects ({recent_file()})")
        return
    for r in projects:
        gone = "" if Path(r.path).is_file() else "  (gone)"
        console.print(f"{time.strftime('%Y-%m-%d %H:%M', time.localtime(r.opened))}  {r.path}{gone}",
                      soft_wrap=True, highlight=False)
