"""Never lose a performance: the take a studio was recording when it stopped without
saving (killed, or the machine went down) comes back at the next start.

While a take runs, its samples stream into the project's journal (:mod:`.journal`) and
its settings (mode, fade, tolerances, capture speed, stall gap) are noted in
``<project>.take.json`` beside it (:func:`note_take`); :func:`recovered_tracks` makes the
tracks of such a take again, as the recorder would have: cut at its stalls, each part
recorded over what was there (:func:`~sketchanim.anim.layers.recorded_over`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from sketchanim.anim.layers import recorded_over
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import BLEND, ContinuousTrack, Take, Track
from sketchanim.atomic import write_atomic
from sketchanim.errors import ArgumentError
from sketchanim.project.store import Project

#: The stall gap (seconds of real time) of a take noted without one.
GAP = 0.25


def notes_path(project: str | os.PathLike[str]) -> Path:
    """Where the settings of the take in progress are noted, beside the project.

    >>> notes_path("show.sketchanim").name
    'show.sketchanim.take.json'
    """
    project = Path(project)
    return project.with_name(project.name + ".take.json")


def note_take(project: str | os.PathLike[str], settings: Mapping[str, object]) -> None:
    """Note the settings of the take starting (``paths``, ``mode``, ``blend``, ``tol``,
    ``speed``, ``gap``, ``loop``, ``smoothing``) for a recovery."""
    write_atomic(notes_path(project), json.dumps(dict(settings)))


def forget_take(project: str | os.PathLike[str]) -> None:
    """The take is saved (or dropped): nothing to recover."""
    notes_path(project).unlink(missing_ok=True)


def split_at_stalls(times: np.ndarray, stall: float) -> list[slice]:
    """The runs of ``times`` with no step longer than ``stall``.

    >>> split_at_stalls(np.array([0.0, 0.1, 0.2, 1.0, 1.1]), 0.5)
    [slice(0, 3, None), slice(3, 5, None)]
    """
    cuts = [0, *(np.flatnonzero(np.diff(times) > stall) + 1).tolist(), len(times)]
    return [slice(a, b) for a, b in zip(cuts, cuts[1:])]


def _notes(project: Path) -> dict:
    try:
        notes = json.loads(notes_path(project).read_text())
    except (OSError, ValueError):
        return {}
    return notes if isinstance(notes, dict) else {}


def _continuous(scene: Scene, path: str) -> bool:
    try:
        return scene.type(path).continuous
    except ArgumentError:
        return False


def recovered_tracks(project: Project, scene: Scene, tracks: Mapping[str, Track], order: int) -> dict[str, Track]:
    """The tracks of the take left in ``project``'s journal, recorded over ``tracks`` at
    spline ``order`` with the take's noted settings (defaults where none were noted):
    path -> track, or empty. Samples of an attribute the scene does not have, or not
    continuous, or fewer than two, are left out. A journal without the take's notes
    (a take cancelled: :func:`forget_take` went first) is not recovered."""
    if not notes_path(project.path).exists():
        return {}
    notes = _notes(project.path)
    tol, mode = notes.get("tol", {}), notes.get("mode", "replace")
    blend = float(notes.get("blend", BLEND))
    smoothing = float(notes.get("smoothing", 0.0))
    stall = float(notes.get("gap", GAP)) * float(notes.get("speed", 1.0))
    made: dict[str, Track] = {}
    for path, (times, values) in project.recovered().items():
        if not _continuous(scene, path) or len(times) < 2:
            continue
        kind = scene.type(path)
        old = tracks.get(path)
        track = old if isinstance(old, ContinuousTrack) else None
        for part in split_at_stalls(times, stall):
            if part.stop - part.start >= 2:
                take = Take(times[part], np.asarray(values[part], dtype=float), mode, blend, smoothing)
                track = recorded_over(path, kind, track, take, float(tol.get(path, kind.tol)), order)
        if track is not None and track is not old:
            made[path] = track
    return made
