"""Reducing a folder of clips (skeletal clips or C3D markers): on local worker
processes or a Dask cluster; a bad file is reported and the rest go on; a rerun skips
clips already done. Each clip is :func:`sketchanim.pipeline.clip.convert_clip`."""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path

from sketchanim.atomic import write_atomic
from sketchanim.errors import ArgumentError, InputError
from sketchanim.export.files import CLIP_OUTPUTS
from sketchanim.formats.clip_files import CLIP_INPUTS
from sketchanim.limits import LIMITS, one_of
from sketchanim.pipeline.clip import ClipOutcome, convert_clip
from sketchanim.pipeline.clip_options import ClipOptions

REPORT = "report.csv"


@dataclass(frozen=True)
class FolderOptions:
    """How a folder of clips is reduced: each clip as ``clip`` says, written as
    ``format``, on ``workers`` local processes or the Dask scheduler at ``scheduler``
    (its workers must see the same paths).

    >>> FolderOptions(format="fbx")
    Traceback (most recent call last):
    sketchanim.errors.ArgumentError: format: one of glb, bvh, json, usd, usda, usdc, got 'fbx'
    """

    clip: ClipOptions = field(default_factory=ClipOptions)
    format: str = "glb"
    workers: int = 1
    scheduler: str | None = None

    def __post_init__(self) -> None:
        one_of("format", self.format.lower().lstrip("."), tuple(s[1:] for s in CLIP_OUTPUTS))
        LIMITS["workers"].check(self.workers)

    @property
    def suffix(self) -> str:
        """The outputs' extension."""
        return "." + self.format.lower().lstrip(".")


def plan_folder(folder: Path, out: Path, suffix: str) -> list[tuple[Path, Path]]:
    """Every clip under ``folder`` (recursively) and its output under ``out``, mirroring
    the folders, with extension ``suffix``."""
    sources = sorted(p for p in folder.rglob("*") if p.suffix.lower() in CLIP_INPUTS and p.is_file())
    return [(p, out / p.relative_to(folder).with_suffix(suffix)) for p in sources]


def _done(source: Path, output: Path) -> bool:
    return output.is_file() and output.stat().st_mtime >= source.stat().st_mtime


def previous_report(out: Path) -> dict[str, ClipOutcome]:
    """The rows of an earlier run's report in ``out``, by source (none if unreadable)."""
    try:
        with open(out / REPORT, newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle))
        kinds = {f.name: f.type for f in fields(ClipOutcome)}
        parse_value = {"int": int, "float": float, "str": str}
        return {r["source"]: ClipOutcome(**{k: parse_value[kinds[k]](v) for k, v in r.items()}) for r in rows}
    except (OSError, KeyError, TypeError, ValueError):
        return {}


@dataclass(frozen=True)
class FolderReduction:
    """A folder's clips, reduced: every outcome (in the order of the clips' paths) and
    the report written."""

    folder: Path
    outcomes: tuple[ClipOutcome, ...]
    report: Path

    def count(self, status: str) -> int:
        """How many clips ended with ``status`` ("reduced", "skipped", "failed")."""
        return sum(o.status == status for o in self.outcomes)


def reduce_folder(folder: Path, output: Path | None, options: FolderOptions, *,
                  on_planned: Callable[[int], None] = lambda n: None,
                  on_done: Callable[[ClipOutcome], None] = lambda o: None) -> FolderReduction:
    """Reduce every clip under ``folder`` not already done into ``output`` (mirroring
    the folders), and write the report (:data:`REPORT`) there; ``on_planned`` hears how
    many clips there are, ``on_done`` each outcome as it comes. A clip that fails is
    a failed outcome; a clip whose output is newer than it is skipped (its row kept
    from the earlier report).

    Raises
    ------
    InputError
        No output folder, no clips, or a scheduler that cannot be reached.
    """
    if output is None:
        raise ArgumentError("output", "a folder of clips needs an output folder")
    jobs = plan_folder(folder, output, options.suffix)
    if not jobs:
        raise InputError(f"{folder}: no clips ({', '.join(CLIP_INPUTS)}) in it")
    on_planned(len(jobs))
    previous = previous_report(output)
    results: dict[int, ClipOutcome] = {}
    todo = []
    for i, (source, target) in enumerate(jobs):
        if _done(source, target):
            old = previous.get(str(source))
            results[i] = (ClipOutcome(**{**asdict(old), "status": "skipped"}) if old
                          else ClipOutcome(str(source), str(target), "skipped", "output newer than the source"))
            on_done(results[i])
        else:
            todo.append(i)
    for i, result in _execute([jobs[i] for i in todo], options):
        results[todo[i]] = result
        on_done(result)
    outcomes = tuple(results[i] for i in range(len(jobs)))
    return FolderReduction(folder, outcomes, write_report(output / REPORT, list(outcomes)))


#: Seconds to wait for a Dask scheduler before saying it cannot be reached.
SCHEDULER_TIMEOUT = 5


def _execute(jobs: list[tuple[Path, Path]], folder: FolderOptions) -> Iterator[tuple[int, ClipOutcome]]:
    if not jobs:
        return
    options, workers, scheduler = folder.clip, folder.workers, folder.scheduler
    if scheduler:
        from distributed import Client, as_completed as dask_completed

        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as err:
            raise ArgumentError("scheduler", f"cannot reach a Dask scheduler at {scheduler} within "
                             f"{SCHEDULER_TIMEOUT} s ({type(err).__name__}: {str(err).splitlines()[0][:120]})") from None
        with client:
            futures = {client.submit(convert_clip, s, o, options, pure=False): i for i, (s, o) in enumerate(jobs)}
            for future in dask_completed(futures):
                yield futures[future], future.result()
    elif workers <= 1:
        for i, (s, o) in enumerate(jobs):
            yield i, convert_clip(s, o, options)
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            pending = {pool.submit(convert_clip, s, o, options): i for i, (s, o) in enumerate(jobs)}
            for future in as_completed(pending):
                yield pending[future], future.result()


def write_report(path: Path, outcomes: list[ClipOutcome]) -> Path:
    """The outcomes as CSV, atomically.

    >>> import tempfile, pathlib
    >>> p = write_report(pathlib.Path(tempfile.mkdtemp()) / "r.csv", [ClipOutcome("a.bvh", "a.glb", "failed", "bad")])
    >>> p.read_text().splitlines()[1][:24]
    'a.bvh,a.glb,failed,bad,0'
    """
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=[f.name for f in fields(ClipOutcome)], lineterminator="\n")
    writer.writeheader()
    for o in outcomes:
        writer.writerow(asdict(o))
    return write_atomic(path, text.getvalue())

