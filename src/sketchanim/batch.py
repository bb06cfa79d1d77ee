"""Reducing clips (skeletal clips or C3D markers), one or a whole library: on local
worker processes or a Dask cluster; a bad file is reported and the rest go on; a rerun
skips clips already done."""

from __future__ import annotations

import csv
import io
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path

import numpy as np

from sketchanim.mocap.clip_reduction import ReducedClip, reduce_clip
from sketchanim.mocap.markers import Markers, ReducedMarkers, reduce_markers
from sketchanim.motion.skeleton import UNITS_M, Clip
from sketchanim.mocap.world_reduction import reduce_clip_world
from sketchanim.errors import ArgumentError, InputError
from sketchanim.atomic import write_atomic
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import CLIP_INPUTS, read_clip

REPORT = "report.csv"


#: Highest frame rate clips are written at (BVH, USD), frames per second.
MAX_RATE = 10_000.0

@dataclass(frozen=True)
class Options:
    """How clips are reduced and written.

    Attributes
    ----------
    tol : float or None
        Position tolerance in the clip's units; None: ``tol_cm`` converted with the
        clip's unit.
    tol_cm : float
        Position tolerance in centimetres, used when ``tol`` is None.
    rot_tol_deg : float
        Rotation tolerance, degrees.
    units : str or None
        The clip's unit (a key of :data:`~sketchanim.motion.skeleton.UNITS_M`); None: the
        file's, else guessed from the figure's height.
    rate : float or None
        Frames per second of BVH / USD output (up to :data:`MAX_RATE`); None: the
        source's.
    skeleton : str or None
        ASF file for AMC input; None: found beside it.
    world : bool
        Skeletal clips: keep every joint, and every point ``shell_cm`` from a joint,
        within the distance in the world (:func:`~sketchanim.mocap.world_reduction.reduce_clip_world`),
        instead of every joint's rotation within ``rot_tol_deg``.
    shell_cm : float
        The shell's distance from each joint, centimetres.
    keys : {"curves", "frames"}
        glTF output: the curves exactly, or LINEAR keys at frames (``rate``) for
        importers that ignore tangents (:mod:`sketchanim.formats.gltf_frames`).
    """

    tol: float | None = None
    tol_cm: float = 0.5
    rot_tol_deg: float = 0.5
    units: str | None = None
    rate: float | None = None
    skeleton: str | None = None
    world: bool = False
    shell_cm: float = 3.0
    keys: str = "curves"

    def __post_init__(self) -> None:
        if self.rate is not None and not (isinstance(self.rate, (int, float)) and 0 < self.rate <= MAX_RATE):
            raise ArgumentError("rate", f"must be frames per second from 0 to {MAX_RATE:g} (not 0), got {self.rate!r}")

    def unit_m(self, clip: Clip | Markers) -> float | None:
        """Metres per unit of ``clip``: ``units`` if given, else the file's, else (a
        skeleton) guessed from the figure's height."""
        if self.units:
            return UNITS_M[self.units]
        return clip.unit_m if isinstance(clip, Markers) else clip.guess_unit_m()

    def distance(self, clip: Clip | Markers) -> float:
        """The position tolerance for ``clip``, in its units (``clip.unit_m``, as
        :func:`reduce_file` sets it with :meth:`unit_m`)."""
        if self.tol is not None:
            return self.tol
        unit = clip.unit_m
        if unit is None:
            why = ("the file does not say" if isinstance(clip, Markers) else
                   f"its figure is {float(np.ptp(clip.skeleton.rest_positions(), axis=0).max()):.4g} units tall")
            raise InputError(f"cannot tell the clip's units ({why}); give --tol in its units or --units "
                             f"({', '.join(UNITS_M)})")
        return self.tol_cm * 0.01 / unit


@dataclass(frozen=True)
class Outcome:
    """One clip's result, a row of the report."""

    source: str
    output: str
    status: str                  # "reduced", "skipped" (done before) or "failed"
    message: str = ""
    frames: int = 0
    joints: int = 0              # markers, for C3D
    control_points: int = 0
    raw_bytes: int = 0
    reduced_bytes: int = 0
    compression: float = 0.0
    max_rotation_error_deg: float = 0.0
    max_position_error: float = 0.0
    max_world_error: float = 0.0
    tol: float = 0.0
    seconds: float = 0.0


def reduce_file(source: Path, options: Options) -> tuple[Clip | Markers, ReducedClip | ReducedMarkers, float]:
    """Read and reduce one clip (or C3D markers): the source (with its unit, where
    known or guessed), its curves and the position tolerance used."""
    clip = read_clip(source, skeleton=options.skeleton)
    clip = replace(clip, unit_m=options.unit_m(clip))
    tol = options.distance(clip)
    if isinstance(clip, Markers):
        return clip, reduce_markers(clip, tol), tol
    if options.world:
        if clip.unit_m is None:
            raise InputError(f"--world: cannot tell the clip's units, to put its {options.shell_cm:g} cm shell in "
                             f"them; give --units ({', '.join(UNITS_M)})")
        return clip, reduce_clip_world(clip, tol, options.shell_cm * 0.01 / clip.unit_m), tol
    return clip, reduce_clip(clip, tol, options.rot_tol_deg), tol


def outcome(source: Path, output: Path, clip: Clip | Markers, reduced: ReducedClip | ReducedMarkers, tol: float,
            seconds: float) -> Outcome:
    """The report row of a reduced clip (markers: one "joint" per marker, no rotation,
    and their position error is their world error)."""
    if isinstance(reduced, ReducedMarkers):
        rows = reduced.reports()
        worst = max((r.max_distance for r in rows), default=0.0)
        return Outcome(str(source), str(output), "reduced", "", len(reduced.times), len(rows),
                       sum(r.control_points for r in rows), reduced.raw_bytes(), reduced.reduced_bytes(),
                       round(reduced.compression(), 3), 0.0, worst, worst, tol, round(seconds, 3))
    assert isinstance(clip, Clip)
    joints = reduced.joint_reports()
    rot = [r.rotation_error_deg for r in joints if r.rotation_points]
    pos = [r.position_error for r in joints if r.position_points]
    return Outcome(str(source), str(output), "reduced", "", len(clip.times), len(clip.skeleton),
                   sum(r.rotation_points + r.position_points for r in joints), reduced.raw_bytes(),
                   reduced.reduced_bytes(), round(reduced.compression(), 3), max(rot, default=0.0),
                   max(pos, default=0.0), float(reduced.world_errors(clip).max()), tol, round(seconds, 3))


def convert(source: Path, output: Path, options: Options) -> Outcome:
    """Reduce ``source`` and write ``output``; a bad file gives a failed outcome naming
    what is wrong, never an exception."""
    start = time.perf_counter()
    try:
        clip, reduced, tol = reduce_file(source, options)
        write_reduced(output, reduced, rate=options.rate, keys=options.keys)
    except (InputError, OSError) as err:
        message = f"{err.filename}: {err.strerror}" if isinstance(err, OSError) and err.filename else str(err)
        return Outcome(str(source), str(output), "failed", message, seconds=round(time.perf_counter() - start, 3))
    return outcome(source, output, clip, reduced, tol, time.perf_counter() - start)


def plan(folder: Path, out: Path, suffix: str) -> list[tuple[Path, Path]]:
    """Every clip under ``folder`` (recursively) and its output under ``out``, mirroring
    the folders, with extension ``suffix``."""
    sources = sorted(p for p in folder.rglob("*") if p.suffix.lower() in CLIP_INPUTS and p.is_file())
    return [(p, out / p.relative_to(folder).with_suffix(suffix)) for p in sources]


def _done(source: Path, output: Path) -> bool:
    return output.is_file() and output.stat().st_mtime >= source.stat().st_mtime


def previous_report(out: Path) -> dict[str, Outcome]:
    """The rows of an earlier run's report in ``out``, by source (none if unreadable)."""
    try:
        with open(out / REPORT, newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle))
        kinds = {f.name: f.type for f in fields(Outcome)}
        convert_value = {"int": int, "float": float, "str": str}
        return {r["source"]: Outcome(**{k: convert_value[kinds[k]](v) for k, v in r.items()}) for r in rows}
    except (OSError, KeyError, TypeError, ValueError):
        return {}


def run(jobs: list[tuple[Path, Path]], options: Options, *, workers: int = 1, scheduler: str | None = None,
        on_done: Callable[[Outcome], None] = lambda o: None, previous: dict[str, Outcome] | None = None
        ) -> list[Outcome]:
    """Reduce every job not already done, ``workers`` processes at a time, or on the Dask
    scheduler at ``scheduler`` (its workers must see the same paths); ``on_done`` hears
    each outcome as it comes. Outcomes are returned in the order of ``jobs``."""
    previous = previous or {}
    results: dict[int, Outcome] = {}
    todo = []
    for i, (source, output) in enumerate(jobs):
        if _done(source, output):
            old = previous.get(str(source))
            results[i] = (Outcome(**{**asdict(old), "status": "skipped"}) if old
                          else Outcome(str(source), str(output), "skipped", "output newer than the source"))
            on_done(results[i])
        else:
            todo.append(i)
    for i, result in _execute([jobs[i] for i in todo], options, workers, scheduler):
        results[todo[i]] = result
        on_done(result)
    return [results[i] for i in range(len(jobs))]


#: Seconds to wait for a Dask scheduler before saying it cannot be reached.
SCHEDULER_TIMEOUT = 5


def _execute(jobs: list[tuple[Path, Path]], options: Options, workers: int, scheduler: str | None
             ) -> Iterator[tuple[int, Outcome]]:
    if not jobs:
        return
    if scheduler:
        from distributed import Client, as_completed as dask_completed

        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as err:
            raise InputError(f"--scheduler: cannot reach a Dask scheduler at {scheduler} within "
                             f"{SCHEDULER_TIMEOUT} s ({type(err).__name__}: {str(err).splitlines()[0][:120]})") from None
        with client:
            futures = {client.submit(convert, s, o, options, pure=False): i for i, (s, o) in enumerate(jobs)}
            for future in dask_completed(futures):
                yield futures[future], future.result()
    elif workers <= 1:
        for i, (s, o) in enumerate(jobs):
            yield i, convert(s, o, options)
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            pending = {pool.submit(convert, s, o, options): i for i, (s, o) in enumerate(jobs)}
            for future in as_completed(pending):
                yield pending[future], future.result()


def write_report(path: Path, outcomes: list[Outcome]) -> Path:
    """The outcomes as CSV, atomically.

    >>> import tempfile, pathlib
    >>> p = write_report(pathlib.Path(tempfile.mkdtemp()) / "r.csv", [Outcome("a.bvh", "a.glb", "failed", "bad")])
    >>> p.read_text().splitlines()[1][:24]
    'a.bvh,a.glb,failed,bad,0'
    """
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=[f.name for f in fields(Outcome)], lineterminator="\n")
    writer.writeheader()
    for o in outcomes:
        writer.writerow(asdict(o))
    return write_atomic(path, text.getvalue())

