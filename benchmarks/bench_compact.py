"""Compact clip exports against the web's compressors, at equal max world error.

    .venv/bin/python benchmarks/bench_compact.py [--data ../shared/data] [--clips NAME ...]

For every BVH clip in ``DATA/bvh`` and the CMU ASF/AMC clip (unit guessed from the
figure's height), at two bounds on the max world error (0.5 cm and 1 cm):

- **raw**: every source channel at every frame as float32 (frames x channels x 4 bytes),
  what ACL's compression ratios are taken against;
- **source**: the clip's frames as a .glb (``web_peers.source_glb``: every joint a node,
  LINEAR keys at every frame, float32, no mesh), the peers' input;
- **gltfpack** (npm 1.x, -kn so every joint stays a node) at its best settings for the
  bound: the smallest file within it over ``-c``/``-cc``, the resampling rate ``-af`` (the
  source's keys, 60, 30, 24, 15 Hz) and for each rate the bits of rotations ``-ar`` and
  translations ``-at`` (the fewest rotation bits within the bound, then for each of a few
  rotation bits above it the fewest translation bits, by bisection). ``-as`` has nothing
  to act on (no scale tracks) and ``-ac`` only keeps tracks;
- **gltfpack feet kept**: the same search where a file also has to keep the clip's planted
  feet as ours promises to (their sliding at most the source's plus
  ``contacts.SLIDING_SLACK_M_S``);
- **glTF-Transform** (npm 4.x CLI): ``resample --tolerance T`` then ``meshopt --level L``
  (high: its quaternion filter, 16 bits, and exponential filter, 12 bits; medium: no
  filters), or ``resample`` alone; the smallest file within the bound over L and T (T by
  bisection on a log scale). ``quantize`` acts on mesh attributes only: with no mesh it
  leaves the animation as it is, so it is not run;
- **ours**: ``sketchanim.export.compact_clip.compact_clip(clip, tol, shell,
  mesh=False)`` at the bound, shell 3 cm, the planted feet held as the command line's
  default does ("ours: not available" when it cannot be imported);
- **ours, no contacts**: the same with no frame held (``--no-contacts``): the world bound
  alone, the guarantee gltfpack's best file is measured at.

Bytes are whole .glb files (skeleton nodes and animation only). Every file's max world
error is measured the same way (``world_metric``: three.js with its meshopt decoder plays
it at every source frame; the largest distance of a point 3 cm from each joint along each
of its local axes, ACL's metric, and of the joints themselves, both in cm), and a file
counts as within the bound by the first. Sliding (``world_metric.file_sliding``): the median
speed of the joints the source plants (``contacts.planted``) over the planted 60 Hz steps
``contacts.sliding`` measures, as three.js plays the file, cm/s.

CPU: for a peer, the user + system time of its command processes (``RUSAGE_CHILDREN``
deltas, node's start included; glTF-Transform's two commands summed), median of 3 runs at
the best settings; "node start" is the same commands on a one-joint, two-frame clip, what
of that is the process starting. For ours, the in-process CPU time (``time.process_time``)
of ``compact_clip`` and writing the file, median of 3 (no interpreter start).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from web_peers import gltf_transform, gltfpack, source_glb  # noqa: E402
from world_metric import SHELL_M, WorldError, file_sliding, file_world_error  # noqa: E402

from sketchanim.formats.clip_files import read_clip  # noqa: E402
from sketchanim.mocap.contacts import SLIDING_SLACK_M_S, planted, sliding  # noqa: E402
from sketchanim.motion.skeleton import Clip, Skeleton  # noqa: E402

BOUNDS_CM = (0.5, 1.0)
#: gltfpack's resampling rates tried (0: the source's keys, no resampling).
RATES = (0, 60, 30, 24, 15)
#: gltfpack's levels: the search runs with the first; the others are tried at its best settings.
LEVELS = ("-cc", "-c")
#: Rotation bits above the fewest within the bound that are tried with fewer translation bits.
ROTATION_STEPS = 4
#: glTF-Transform's resample tolerances tried (log10), then this many bisection steps.
TOLERANCE_GRID = tuple(np.arange(-6.0, -0.99, 0.5).round(2).tolist())
TOLERANCE_STEPS = 4
#: meshopt's levels ("none": resample alone).
TRANSFORM_LEVELS = ("high", "medium", "none")
RUNS = 3


@dataclass(frozen=True)
class Trial:
    """One peer file: its settings, size and measured world error."""

    settings: str
    path: Path
    size: int
    error: WorldError


class Peers:
    """Every peer file of one clip, made and measured once (cached by settings)."""

    def __init__(self, clip: Clip, source: Path, folder: Path) -> None:
        self.clip, self.source, self.folder = clip, source, folder
        self.trials: dict[tuple, Trial] = {}
        self.held = planted(clip)
        self.source_sliding = 100 * sliding(clip, contacts=self.held) * clip.unit_m if self.held.any() else math.nan
        self.slid: dict[Path, float] = {}

    def sliding(self, path: Path) -> float:
        """How much the clip's planted joints slide in the file ``path``, cm/s (cached)."""
        if path not in self.slid:
            self.slid[path] = file_sliding(self.clip, path, self.held)
        return self.slid[path]

    def feet_kept(self, trial: Trial) -> bool:
        """Whether ``trial``'s planted joints slide no more than the source's plus
        ``SLIDING_SLACK_M_S`` (true where nothing is planted)."""
        return not self.held.any() or self.sliding(trial.path) <= self.source_sliding + 100 * SLIDING_SLACK_M_S

    def _measure(self, key: tuple, settings: str, make: Callable[[Path], None]) -> Trial:
        if key not in self.trials:
            out = self.folder / f"t{len(self.trials)}.glb"
            make(out)
            self.trials[key] = Trial(settings, out, out.stat().st_size, file_world_error(self.clip, out))
        return self.trials[key]

    def gltfpack(self, level: str, rate: int, rot: int, trans: int) -> Trial:
        args = gltfpack_args(level, rate, rot, trans)
        return self._measure(("gltfpack", *args), " ".join(args), lambda out: gltfpack(self.source, out, *args))

    def transform(self, level: str, log_tol: float | None) -> Trial:
        """``resample --tolerance 10**log_tol`` (None: not run), then ``meshopt --level
        level`` (``"none"``: not run)."""
        steps = ([f"resample --tolerance {10 ** log_tol:.3g}"] if log_tol is not None else []) + (
            [f"meshopt --level {level}"] if level != "none" else [])
        settings = " + ".join(steps)

        def make(out: Path) -> None:
            into = self.source
            for i, (command, *options) in enumerate(transform_commands(settings)):
                step = out if i == len(steps) - 1 else out.with_suffix(f".{i}.glb")
                gltf_transform(command, into, step, *options)
                into = step

        return self._measure(("transform", settings), settings, make)


def gltfpack_args(level: str, rate: int, rot: int, trans: int) -> tuple[str, ...]:
    """gltfpack's options for one trial."""
    return (level, "-af", str(rate), "-ar", str(rot), "-at", str(trans))


def transform_commands(settings: str) -> list[tuple[str, ...]]:
    """The glTF-Transform commands of a trial's settings, each as (command, options...)."""
    out = []
    for part in settings.split(" + "):
        command, *options = part.split()
        out.append((command, *options))
    return out


def fewest(lo: int, hi: int, ok: Callable[[int], bool]) -> int | None:
    """The smallest ``b`` in [lo, hi] with ``ok(b)`` (bisection: ``ok`` taken as monotone),
    None when ``ok(hi)`` is false."""
    if not ok(hi):
        return None
    while lo < hi:
        mid = (lo + hi) // 2
        if ok(mid):
            hi = mid
        else:
            lo = mid + 1
    return hi


def best_gltfpack(peers: Peers, bound: float, feet: bool = False) -> Trial | None:
    """gltfpack's smallest file within ``bound`` (cm, ACL's metric), and with ``feet``
    whose planted joints slide no more than the source's plus the slack
    (:meth:`Peers.feet_kept`): its settings searched at the first of :data:`LEVELS` (for
    each rate in :data:`RATES`: the fewest rotation bits within the bound with 24
    translation bits, then for it and up to :data:`ROTATION_STEPS` more rotation bits the
    fewest translation bits), the other levels tried at the best settings found."""
    within: list[Trial] = []

    def ok(level: str, rate: int, rot: int, trans: int) -> bool:
        trial = peers.gltfpack(level, rate, rot, trans)
        good = trial.error.point_cm <= bound and (not feet or peers.feet_kept(trial))
        if good:
            within.append(trial)
        return good

    level = LEVELS[0]
    for rate in RATES:
        least = fewest(4, 16, lambda r: ok(level, rate, r, 24))
        if least is None:
            continue                              # not within the bound at this rate, whatever the bits
        for rot in range(least, min(least + ROTATION_STEPS, 16) + 1):
            fewest(1, 24, lambda t: ok(level, rate, rot, t))
    if within:
        _, _, rate, _, rot, _, trans = min(within, key=lambda t: t.size).settings.split()
        for other in LEVELS[1:]:
            ok(other, int(rate), int(rot), int(trans))
    return min(within, key=lambda t: t.size, default=None)


def best_transform(peers: Peers, bound: float) -> Trial | None:
    """glTF-Transform's smallest file within ``bound`` over its meshopt level and the
    resample tolerance: none, a grid of :data:`TOLERANCE_GRID` (log10 T; the size is not
    monotone in T: fewer keys, but each track's own key times), and a bisection between
    the largest within the bound on the grid and the next."""
    within: list[Trial] = []
    for level in TRANSFORM_LEVELS:
        tried = [(t, peers.transform(level, t)) for t in ((None,) if level != "none" else ()) + TOLERANCE_GRID]
        ok = [t for t, trial in tried if trial.error.point_cm <= bound]
        within += [trial for _, trial in tried if trial.error.point_cm <= bound]
        lo = max((t for t in ok if t is not None), default=None)
        if lo is None or lo == TOLERANCE_GRID[-1]:
            continue
        hi = TOLERANCE_GRID[TOLERANCE_GRID.index(lo) + 1]
        for _ in range(TOLERANCE_STEPS):
            mid = (lo + hi) / 2
            trial = peers.transform(level, mid)
            if trial.error.point_cm <= bound:
                within.append(trial)
                lo = mid
            else:
                hi = mid
    return min(within, key=lambda t: t.size, default=None)


def median_cpu(run: Callable[[], float]) -> float:
    """The median of :data:`RUNS` CPU times that ``run`` returns."""
    return statistics.median(run() for _ in range(RUNS))


def gltfpack_cpu(source: Path, trial: Trial, folder: Path) -> float:
    return median_cpu(lambda: gltfpack(source, folder / "cpu.glb", *trial.settings.split()))


def transform_cpu(source: Path, trial: Trial, folder: Path) -> float:
    def run() -> float:
        total, into = 0.0, source
        for i, (command, *options) in enumerate(transform_commands(trial.settings)):
            out = folder / f"cpu{i}.glb"
            total += gltf_transform(command, into, out, *options)
            into = out
        return total

    return median_cpu(run)


def process_cpu(work: Callable[[], None]) -> float:
    """In-process CPU seconds of ``work``."""
    start = time.process_time()
    work()
    return time.process_time() - start


def raw_bytes(clip: Clip) -> int:
    """Every source channel at every frame as float32."""
    return len(clip.times) * sum(len(c) for c in clip.channels) * 4


def load_ours() -> Callable[..., bytes] | None:
    """Our compact .glb of a clip (``contacts``: False holds no frame), or None."""
    try:
        from sketchanim.export.compact_clip import compact_clip
    except ImportError:
        return None

    def ours(clip: Clip, tol: float, shell: float, contacts: bool = True) -> bytes:
        held = None if contacts else np.zeros((len(clip.times), len(clip.skeleton)), bool)
        return compact_clip(clip, tol, shell, contacts=held, mesh=False).glb
    return ours


@dataclass
class Row:
    """One clip at one bound."""

    name: str
    frames: int
    channels: int
    raw: int
    source: int
    source_cpu: float
    source_error: WorldError
    gltfpack: Trial | None = None
    gltfpack_feet: Trial | None = None
    gltfpack_cpu: float = math.nan
    transform: Trial | None = None
    transform_cpu: float = math.nan
    ours_size: int | None = None
    ours_cpu: float = math.nan
    ours_error: WorldError | None = None
    free_size: int | None = None                # ours, no contacts
    free_error: WorldError | None = None
    sliding: tuple[float, ...] = (math.nan,) * 5   # source, gltfpack, gltfpack feet kept, ours, ours no contacts
    trials: int = 0


def clip_rows(path: Path, folder: Path, ours: Callable[..., bytes] | None, console: Console) -> list[Row]:
    clip = read_clip(path)
    unit = clip.guess_unit_m()
    if unit is None:
        raise SystemExit(f"{path}: cannot guess the clip's unit from its figure's height")
    clip = replace(clip, unit_m=unit)             # every file in metres (under a "to metres" root)
    source = folder / "source.glb"
    source_cpu = process_cpu(lambda: source.write_bytes(source_glb(clip, unit)))
    source_error = file_world_error(clip, source)
    peers = Peers(clip, source, folder)
    rows = []
    for bound in BOUNDS_CM:
        start = time.perf_counter()
        row = Row(path.stem, len(clip.times), sum(len(c) for c in clip.channels), raw_bytes(clip), source.stat().st_size,
                  source_cpu, source_error)
        row.gltfpack = best_gltfpack(peers, bound)
        row.gltfpack_feet = best_gltfpack(peers, bound, feet=True)
        row.transform = best_transform(peers, bound)
        row.trials = len(peers.trials)
        if row.gltfpack:
            row.gltfpack_cpu = gltfpack_cpu(source, row.gltfpack, folder)
        if row.transform:
            row.transform_cpu = transform_cpu(source, row.transform, folder)
        if ours is not None:
            tol, shell = bound * 0.01 / unit, SHELL_M / unit
            out = folder / "ours.glb"
            row.ours_cpu = statistics.median(process_cpu(lambda: out.write_bytes(ours(clip, tol, shell)))
                                             for _ in range(RUNS))
            row.ours_size = out.stat().st_size
            row.ours_error = file_world_error(clip, out)
            free = folder / "ours_free.glb"
            free.write_bytes(ours(clip, tol, shell, contacts=False))
            row.free_size, row.free_error = free.stat().st_size, file_world_error(clip, free)
        if peers.held.any():
            row.sliding = (peers.source_sliding, *(peers.sliding(t.path) if t else math.nan
                                                   for t in (row.gltfpack, row.gltfpack_feet)),
                           *(file_sliding(clip, folder / f, peers.held) if ours is not None else math.nan
                             for f in ("ours.glb", "ours_free.glb")))
        console.log(f"{path.stem} at {bound} cm: {row.trials} peer files so far, {time.perf_counter() - start:.0f} s")
        rows.append(row)
    return rows


def startup_cpu(folder: Path) -> tuple[float, float]:
    """gltfpack's and glTF-Transform's (resample + meshopt) CPU on a one-joint, two-frame
    clip: the process starting, mostly."""
    tiny = folder / "tiny.glb"
    tiny.write_bytes(source_glb(Clip.still(Skeleton(("hips",), (-1,), np.zeros((1, 3))), [0.0, 1 / 30])))
    pack = median_cpu(lambda: gltfpack(tiny, folder / "tiny.p.glb", "-cc"))
    transform = median_cpu(lambda: gltf_transform("resample", tiny, folder / "tiny.r.glb")
                           + gltf_transform("meshopt", folder / "tiny.r.glb", folder / "tiny.m.glb"))
    return pack, transform


def _kb(n: int | None) -> str:
    return "-" if n is None else f"{n / 1000:.1f}"


def _ratio(a: float | None, b: float | None, digits: int = 2) -> str:
    if a is None or b is None or not (a == a and b == b) or b == 0:
        return "-"
    return f"{a / b:.{digits}f}"


def _err(e: WorldError | None) -> str:
    return "-" if e is None else f"{e.point_cm:.3f} / {e.joint_cm:.3f}"


def _sum(values: list) -> float | None:
    return None if any(v is None or v != v for v in values) else sum(values)


def print_tables(rows: list[Row], have_ours: bool, startup: tuple[float, float], console: Console) -> None:
    for bound in BOUNDS_CM:
        at = rows[BOUNDS_CM.index(bound)::len(BOUNDS_CM)]
        size = Table(title=f"bytes (kB) within {bound} cm max world error (ACL's metric: points 3 cm from each joint)")
        for col in ("clip", "frames x ch", "raw f32", "source", "gltfpack", "gltfpack feet kept", "glTF-T", "ours",
                    "ours no contacts", "ours / gltfpack feet kept", "ours no contacts / gltfpack", "ours / gltfpack",
                    "ours / glTF-T", "raw / gltfpack", "raw / glTF-T", "raw / ours"):
            size.add_column(col, justify="left" if col == "clip" else "right")
        sizes = {k: _sum([getattr(r, k).size if getattr(r, k) else None for r in at])
                 for k in ("gltfpack", "gltfpack_feet", "transform")}
        ours, free = _sum([r.ours_size for r in at]), _sum([r.free_size for r in at])
        for r in [*at, None]:
            name, frames, raw, source = (r.name, f"{r.frames} x {r.channels}", r.raw, r.source) if r else (
                "total", "", sum(r.raw for r in at), sum(r.source for r in at))
            pack = (r.gltfpack.size if r.gltfpack else None) if r else sizes["gltfpack"]
            feet = (r.gltfpack_feet.size if r.gltfpack_feet else None) if r else sizes["gltfpack_feet"]
            trans = (r.transform.size if r.transform else None) if r else sizes["transform"]
            mine, loose = (r.ours_size, r.free_size) if r else (ours, free)
            size.add_row(name, frames, _kb(raw), _kb(source), _kb(pack), _kb(feet), _kb(trans), _kb(mine), _kb(loose),
                         _ratio(mine, feet), _ratio(loose, pack), _ratio(mine, pack), _ratio(mine, trans),
                         _ratio(raw, pack, 1), _ratio(raw, trans, 1), _ratio(raw, mine, 1))
        console.print(size)
        cpu = Table(title=f"CPU seconds within {bound} cm (peers: their processes, node's start included, "
                          f"median of {RUNS}; ours: in-process)")
        for col in ("clip", "gltfpack", "glTF-T", "ours", "ours / gltfpack", "ours / glTF-T"):
            cpu.add_column(col, justify="left" if col == "clip" else "right")
        for r in at:
            cpu.add_row(r.name, f"{r.gltfpack_cpu:.3f}", f"{r.transform_cpu:.3f}", f"{r.ours_cpu:.3f}",
                        _ratio(r.ours_cpu, r.gltfpack_cpu), _ratio(r.ours_cpu, r.transform_cpu))
        sums = [_sum([getattr(r, k) for r in at]) for k in ("gltfpack_cpu", "transform_cpu", "ours_cpu")]
        cpu.add_row("total", *(f"{s:.3f}" if s is not None else "-" for s in sums), _ratio(sums[2], sums[0]),
                    _ratio(sums[2], sums[1]))
        cpu.add_row("node start", f"{startup[0]:.3f}", f"{startup[1]:.3f}", "", "", "")
        console.print(cpu)
        err = Table(title=f"max world error, cm (point 3 cm from each joint / joint), asked {bound} cm")
        for col in ("clip", "source", "gltfpack", "glTF-T", "ours", "ours no contacts"):
            err.add_column(col, justify="left" if col == "clip" else "right")
        for r in at:
            err.add_row(r.name, _err(r.source_error), _err(r.gltfpack.error if r.gltfpack else None),
                        _err(r.transform.error if r.transform else None), _err(r.ours_error), _err(r.free_error))
        console.print(err)
        slide = Table(title=f"planted joints' sliding, cm/s (median speed over planted 60 Hz steps, as three.js plays "
                            f"each file), within {bound} cm; feet kept: at most the source's + "
                            f"{100 * SLIDING_SLACK_M_S:g}")
        for col in ("clip", "source", "gltfpack", "gltfpack feet kept", "ours", "ours no contacts"):
            slide.add_column(col, justify="left" if col == "clip" else "right")
        for r in at:
            slide.add_row(r.name, *(f"{v:.2f}" if v == v else "-" for v in r.sliding))
        console.print(slide)
    best = Table(title="the peers' best settings (smallest file within the bound); files: peer files made and measured "
                       "for the clip by then (shared by the bounds)")
    for col in ("clip", "bound cm", "gltfpack", "gltfpack feet kept", "glTF-Transform", "files"):
        best.add_column(col)
    for r, bound in zip(rows, BOUNDS_CM * (len(rows) // len(BOUNDS_CM))):
        best.add_row(r.name, f"{bound}", *(t.settings if t else "none within"
                                           for t in (r.gltfpack, r.gltfpack_feet, r.transform)), str(r.trials))
    console.print(best)
    if not have_ours:
        console.print("ours: not available (sketchanim.export.compact_clip.compact_clip cannot be imported)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--clips", nargs="*", default=None, help="only the clips whose file stem contains one of these")
    args = parser.parse_args()
    sources = sorted((args.data / "bvh").glob("*.bvh")) + sorted((args.data / "amc").glob("*.amc"))
    if args.clips:
        sources = [s for s in sources if any(c in s.stem for c in args.clips)]
    if not sources:
        raise SystemExit(f"no clips under {args.data}")
    console = Console(width=200)
    ours = load_ours()
    rows: list[Row] = []
    with tempfile.TemporaryDirectory() as tmp:
        startup = startup_cpu(Path(tmp))
        for source in sources:
            folder = Path(tmp) / source.stem
            folder.mkdir()
            rows += clip_rows(source, folder, ours, console)
    print_tables(rows, ours is not None, startup, console)


if __name__ == "__main__":
    main()
