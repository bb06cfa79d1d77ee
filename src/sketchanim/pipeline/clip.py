"""One clip (a skeleton's BVH or ASF/AMC, or C3D markers), reduced: read, its unit
settled, reduced by :mod:`sketchanim.mocap` and (on request) written, with the report
row that says how it went."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, replace
from pathlib import Path

from sketchanim.errors import InputError
from sketchanim.atomic import write_atomic
from sketchanim.export.compact_clip import CompactClip, compact_clip
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import read_clip
from sketchanim.mocap.clip_reduction import ReducedClip, reduce_clip
from sketchanim.mocap.markers import Markers, ReducedMarkers, reduce_markers
from sketchanim.mocap.world_reduction import reduce_clip_world
from sketchanim.mocap.tracks import FLOAT32
from sketchanim.motion.skeleton import UNITS_M, Clip
from sketchanim.pipeline.clip_options import ClipOptions


@dataclass(frozen=True)
class ClipOutcome:
    """One clip's result, a row of a folder's report."""

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


@dataclass(frozen=True)
class ClipReduction:
    """A reduced clip: the source (with its unit, where known or guessed), its curves,
    the position tolerance used, and the report row."""

    clip: Clip | Markers
    reduced: ReducedClip | ReducedMarkers | CompactClip
    tol: float
    outcome: ClipOutcome


def clip_outcome(source: Path, output: Path, clip: Clip | Markers,
                 reduced: ReducedClip | ReducedMarkers | CompactClip, tol: float, seconds: float) -> ClipOutcome:
    """The report row of a reduced clip (markers: one "joint" per marker, no rotation,
    and their position error is their world error; a compact clip: its keys as control
    points, its file as the reduced bytes)."""
    if isinstance(reduced, CompactClip):
        assert isinstance(clip, Clip)
        r = reduced.report
        raw = FLOAT32 * len(clip.times) * sum(len(c) for c in clip.channels)
        return ClipOutcome(str(source), str(output), "reduced", "", r.frames, len(clip.skeleton), r.keys, raw, r.bytes,
                           round(raw / max(r.bytes, 1), 3), r.max_rotation_error_deg, r.max_position_error,
                           r.max_world_error, tol, round(seconds, 3))
    if isinstance(reduced, ReducedMarkers):
        rows = reduced.reports()
        worst = max((r.max_distance for r in rows), default=0.0)
        return ClipOutcome(str(source), str(output), "reduced", "", len(reduced.times), len(rows),
                           sum(r.control_points for r in rows), reduced.raw_bytes(), reduced.reduced_bytes(),
                           round(reduced.compression(), 3), 0.0, worst, worst, tol, round(seconds, 3))
    assert isinstance(clip, Clip)
    joints = reduced.joint_reports()
    rot = [r.rotation_error_deg for r in joints if r.rotation_points]
    pos = [r.position_error for r in joints if r.position_points]
    return ClipOutcome(str(source), str(output), "reduced", "", len(clip.times), len(clip.skeleton),
                       sum(r.rotation_points + r.position_points for r in joints), reduced.raw_bytes(),
                       reduced.reduced_bytes(), round(reduced.compression(), 3), max(rot, default=0.0),
                       max(pos, default=0.0), float(reduced.world_errors(clip).max()), tol, round(seconds, 3))


def _reduced(clip: Clip | Markers, options: ClipOptions,
             name: str) -> tuple[ReducedClip | ReducedMarkers | CompactClip, float]:
    tol = options.distance(clip)
    if isinstance(clip, Markers):
        return reduce_markers(clip, tol), tol
    if options.world or options.keys == "compact":
        if clip.unit_m is None:
            raise InputError(f"{'world' if options.world else 'keys'}: cannot tell the clip's units, to put its "
                             f"{options.shell_cm:g} cm shell in them; give units=UNIT ({', '.join(UNITS_M)})")
        shell = options.shell_cm * 0.01 / clip.unit_m
        if options.keys == "compact":
            return compact_clip(clip, tol, shell, contacts=options.contacts_of(clip), name=name), tol
        return reduce_clip_world(clip, tol, shell, order=options.order, contacts=options.contacts_of(clip)), tol
    return reduce_clip(clip, tol, options.rot_tol_deg, order=options.order, contacts=options.contacts_of(clip)), tol


def reduce_clip_file(source: str | os.PathLike[str], options: ClipOptions,
                     output: str | os.PathLike[str] | None = None) -> ClipReduction:
    """Read and reduce one clip (or C3D markers) and, given ``output``, write it (.glb,
    .bvh, .usd(a/c) or .json, by the extension).

    Raises
    ------
    InputError
        A bad file, naming it and where; ``OSError`` if the output cannot be written.
    """
    start = time.perf_counter()
    clip = read_clip(Path(source), skeleton=options.skeleton)
    clip = replace(clip, unit_m=options.unit_m(clip))
    if output is not None and options.keys == "compact" and Path(output).suffix.lower() != ".glb":
        raise InputError(f"{output}: keys: compact files are .glb")
    reduced, tol = _reduced(clip, options, Path(output or source).stem)
    if isinstance(reduced, CompactClip) and output is not None:
        write_atomic(Path(output), reduced.glb)
    elif output is not None:
        write_reduced(Path(output), reduced, rate=options.rate, keys=options.keys)
    row = clip_outcome(Path(source), Path(output or ""), clip, reduced, tol, time.perf_counter() - start)
    return ClipReduction(clip, reduced, tol, row)


def convert_clip(source: Path, output: Path, options: ClipOptions) -> ClipOutcome:
    """Reduce ``source`` and write ``output``; a bad file gives a failed outcome naming
    what is wrong, never an exception (for a folder's workers)."""
    start = time.perf_counter()
    try:
        return reduce_clip_file(source, options, output).outcome
    except (InputError, OSError) as err:
        message = f"{err.filename}: {err.strerror}" if isinstance(err, OSError) and err.filename else str(err)
        return ClipOutcome(str(source), str(output), "failed", message, seconds=round(time.perf_counter() - start, 3))
