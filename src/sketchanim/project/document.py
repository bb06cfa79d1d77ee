"""The project document: the scene, its tracks and the animator's take tolerances as
versioned JSON, validated with pydantic when loaded (a take's samples live in the
``takes`` table, referred to by index).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import DISCRETE, AttributeType
from sketchanim.anim.scene import KINDS, Scene
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.errors import FileFormatError, InputError
from sketchanim.project.database import FORMAT, FORMAT_VERSION

#: Bounds on what a file may hold (a hostile file cannot make a reader allocate more).
MAX_DOCUMENT_BYTES = 256 * 2**20
MAX_ITEMS = 10_000_000
TYPE_NAMES = ("position", "orientation", "scale", "color", "intensity", "fov", "float", "vector") + DISCRETE

_Number = Annotated[float, Field(allow_inf_nan=False)]
_Name = Annotated[str, Field(min_length=1, max_length=64)]
_Items = Field(max_length=MAX_ITEMS)
#: A project's frame rate until one is set (film's and Blender's).
DEFAULT_FPS = 24.0


class _Doc(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=False)


class TypeDoc(_Doc):
    name: Literal[TYPE_NAMES]  # type: ignore[valid-type]
    dim: int = Field(ge=0, le=64)
    tol: _Number = Field(ge=0)
    unit: str = Field(max_length=64)
    default: list[_Number | bool | str | None] = Field(max_length=64)
    choices: list[_Name] = Field(default_factory=list, max_length=1024)


class AttributeDoc(_Doc):
    name: _Name
    type: TypeDoc
    value: list[_Number] | bool | str | None


class ObjectDoc(_Doc):
    name: _Name
    kind: Literal[tuple(KINDS)]  # type: ignore[valid-type]
    attributes: list[AttributeDoc] = Field(max_length=4096)


class CurveDoc(_Doc):
    path: str = Field(max_length=200)
    tol: _Number = Field(gt=0)
    order: int = Field(ge=1, le=32)
    knots: list[_Number] = _Items
    coef: list[list[_Number]] = _Items
    takes: list[int] = Field(default_factory=list, max_length=100_000)
    edited: bool = False


class StepsDoc(_Doc):
    path: str = Field(max_length=200)
    times: list[_Number] = _Items
    values: list[bool | str | None] = _Items


class ToleranceDoc(_Doc):
    """The tolerance the animator set for an attribute's takes: ``amount`` steps of the
    input that performs it (``px``: pixels for a pointer), or ``amount`` in the
    attribute's units (``units``)."""

    amount: _Number = Field(gt=0)
    unit: Literal["px", "units"]


#: What a sound's file was found to be when the project was loaded or the sound imported:
#: as imported, gone from its place, or different (its checksum is not the one recorded).
SoundStatus = Literal["ok", "missing", "changed"]


class SoundDoc(_Doc):
    """A sound the project refers to (stored by reference, with its checksum): its
    ``name``, its file's ``path`` relative to the project's folder, the file's SHA-256,
    its ``duration`` in seconds, the ``offset`` in seconds where it starts on the
    timeline, and its ``status`` when last checked (:data:`SoundStatus`)."""

    name: Annotated[str, Field(min_length=1, max_length=255)]
    path: Annotated[str, Field(min_length=1, max_length=1024)]
    sha256: Annotated[str, Field(pattern=r"^[0-9a-f]{64}$")]
    duration: Annotated[float, Field(ge=0, allow_inf_nan=False)]
    offset: _Number = 0.0
    status: SoundStatus = "ok"


class ProjectDoc(_Doc):
    """The scene and its tracks (a take's samples live in the ``takes`` table and are
    referenced by id), the take tolerances by attribute path (none in a document
    from before them), and the smoothing of each smoothed take, in seconds by take id
    (:attr:`~sketchanim.anim.tracks.Take.smoothing`; a take not there, as in a
    document from before smoothing, is not smoothed); by take id too, the takes'
    names, which are muted, and the loop recording and pass each loop take is part of
    (none in a document from before them); the frame rate."""

    format: Literal["sketchanim-project"] = FORMAT
    version: Literal[1] = FORMAT_VERSION
    objects: list[ObjectDoc] = Field(max_length=100_000)
    curves: list[CurveDoc] = Field(max_length=100_000)
    steps: list[StepsDoc] = Field(max_length=100_000)
    tolerances: dict[Annotated[str, Field(max_length=200)], ToleranceDoc] = Field(default_factory=dict,
                                                                                  max_length=100_000)
    smoothing: dict[int, Annotated[float, Field(gt=0, allow_inf_nan=False)]] = Field(default_factory=dict,
                                                                                     max_length=100_000)
    names: dict[int, Annotated[str, Field(max_length=64)]] = Field(default_factory=dict, max_length=100_000)
    muted: list[int] = Field(default_factory=list, max_length=100_000)
    loops: dict[int, tuple[Annotated[str, Field(max_length=128)], Annotated[int, Field(ge=0)]]] = Field(
        default_factory=dict, max_length=100_000)
    fps: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)] = DEFAULT_FPS
    #: the sounds, by reference (none in a document from before them)
    sounds: list[SoundDoc] = Field(default_factory=list, max_length=10_000)


def load_document(text: str, source: str) -> ProjectDoc:
    """Validate a project document; :class:`FileFormatError` naming the first bad field."""
    try:
        return ProjectDoc.model_validate_json(text)
    except ValidationError as err:
        first = err.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        raise FileFormatError(source, f"{where}: {first['msg']} ({err.error_count()} problems)") from None


def to_document(scene: Scene, tracks: dict[str, Track], tolerances: dict[str, ToleranceDoc] | None = None,
                fps: float = DEFAULT_FPS, sounds: list[SoundDoc] | None = None) -> tuple[ProjectDoc, list[Take]]:
    """The document of a scene, its tracks, take tolerances (those of attributes the
    scene holds), frame rate and sounds, and the takes it refers to by index.

    >>> scene = Scene(); _ = scene.add("box")
    >>> doc, _ = to_document(scene, {}, {"box.position": ToleranceDoc(amount=2, unit="px"),
    ...                                  "gone.position": ToleranceDoc(amount=1, unit="px")})
    >>> doc.tolerances
    {'box.position': ToleranceDoc(amount=2.0, unit='px')}
    """
    takes: list[Take] = []
    index: dict[int, int] = {}
    objects = [ObjectDoc(name=o.name, kind=o.kind, attributes=[
        AttributeDoc(name=n, type=TypeDoc(name=a.type.name, dim=a.type.dim, tol=a.type.tol, unit=a.type.unit,
                                          default=list(a.type.default), choices=list(a.type.choices)),
                     value=a.value.tolist() if isinstance(a.value, np.ndarray) else a.value)
        for n, a in o.attributes.items()]) for o in scene.objects.values()]
    curves, steps = [], []
    for track in tracks.values():
        if isinstance(track, DiscreteTrack):
            steps.append(StepsDoc(path=track.path, times=track.times, values=track.values))
            continue
        ids = []
        for take in track.takes:
            ids.append(index.setdefault(id(take), len(takes)))
            if ids[-1] == len(takes):
                takes.append(take)
        curves.append(CurveDoc(path=track.path, tol=track.tol, order=track.spline.k + 1,
                               knots=np.asarray(track.spline.t).tolist(), coef=np.asarray(track.spline.c).tolist(),
                               takes=ids, edited=track.edited))
    kept = {path: t for path, t in (tolerances or {}).items() if _holds(scene, path)}
    smoothing = {i: float(t.smoothing) for i, t in enumerate(takes) if t.smoothing > 0}
    return ProjectDoc(objects=objects, curves=curves, steps=steps, tolerances=kept, smoothing=smoothing,
                      names={i: t.name for i, t in enumerate(takes) if t.name},
                      muted=[i for i, t in enumerate(takes) if t.muted],
                      loops={i: (t.loop, t.loop_pass) for i, t in enumerate(takes) if t.loop is not None},
                      fps=fps, sounds=list(sounds or [])), takes


def _holds(scene: Scene, path: str) -> bool:
    """Whether ``scene`` has a continuous attribute at ``path``."""
    try:
        return scene.type(path).continuous
    except InputError:
        return False


def document_tolerances(doc: ProjectDoc, scene: Scene, source: str) -> dict[str, ToleranceDoc]:
    """The take tolerances of a validated document of ``scene``; :class:`FileFormatError`
    naming one for an attribute the scene does not have (or that is not performed)."""
    for path in doc.tolerances:
        if not _holds(scene, path):
            raise FileFormatError(source, f"tolerances.{path}: no continuous attribute {path!r} in the scene")
    return dict(doc.tolerances)


def from_document(doc: ProjectDoc, takes: dict[int, Take], source: str) -> tuple[Scene, dict[str, Track]]:
    """The scene and tracks of a validated document; :class:`FileFormatError` naming
    what does not fit (a value of the wrong type, a track for no attribute...). The
    takes get their smoothing, names, muting and loops from the document."""
    muted = set(doc.muted)
    takes = {i: replace(t, smoothing=doc.smoothing.get(i, t.smoothing), name=doc.names.get(i, t.name),
                        muted=i in muted, loop=doc.loops[i][0] if i in doc.loops else None,
                        loop_pass=doc.loops[i][1] if i in doc.loops else 0) for i, t in takes.items()}
    scene = Scene()
    tracks: dict[str, Track] = {}
    try:
        for o in doc.objects:
            obj = scene.add(o.name, o.kind)
            for a in o.attributes:
                kind = AttributeType(a.type.name, a.type.dim, a.type.tol, a.type.unit, tuple(a.type.default),
                                     tuple(a.type.choices))
                if a.name in obj.attributes and obj.attributes[a.name].type != kind:
                    raise FileFormatError(source, f"{o.name}.{a.name}: not the {o.kind}'s standard type")
                if a.name not in obj.attributes:
                    if kind.continuous and (kind.dim < 1 or kind.tol <= 0):
                        raise FileFormatError(source, f"{o.name}.{a.name}: a continuous type needs dim >= 1, tol > 0")
                    obj.add(a.name, kind)
                scene.set(f"{o.name}.{a.name}", a.value)
        for c in doc.curves:
            kind = scene.type(c.path)
            missing = [i for i in c.takes if i not in takes]
            if missing:
                raise FileFormatError(source, f"{c.path}: refers to missing takes {missing[:5]}")
            n = len(c.knots) - c.order
            if n < 1 or len(c.coef) != n or np.any(np.diff(c.knots) < 0):
                raise FileFormatError(source, f"{c.path}: {len(c.knots)} sorted knots for order {c.order} need "
                                              f"{max(n, 1)} coefficients, got {len(c.coef)}")
            coef = np.array(c.coef, dtype=float) if all(len(r) == kind.dim for r in c.coef) else None
            if coef is None:
                raise FileFormatError(source, f"{c.path}: coefficients need {kind.dim} numbers each")
            spline = BSpline(np.array(c.knots), coef, c.order - 1)
            tracks[c.path] = ContinuousTrack(c.path, kind, spline, c.tol, tuple(takes[i] for i in c.takes), c.edited)
        for s in doc.steps:
            tracks[s.path] = DiscreteTrack(s.path, scene.type(s.path), list(s.times), list(s.values))
    except FileFormatError:
        raise
    except InputError as err:
        raise FileFormatError(source, str(err)) from None
    return scene, tracks
