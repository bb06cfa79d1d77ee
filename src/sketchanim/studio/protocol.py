"""The studio's messages, both directions: one pydantic model per message, a union
keyed on ``type`` for each direction (docs/studio-protocol.md is their reference).

A message from the page is validated once, at the websocket (:func:`parse`), as the
project store validates documents. A message to the pages is built from its model and
sent as :func:`wire` makes it (JSON types: tuples become lists); ``preview`` and
``transport`` go both ways, relayed to the other pages by :func:`relay` (without the
sender's ``id``). Values are the attribute types' canonical forms as JSON: lists of
floats (orientations scalar-last x, y, z, w; a field of view in degrees), or a bool /
string for discrete attributes.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field, StrictBool, TypeAdapter, ValidationError

from sketchanim.anim.tracks import BLEND, MODES
from sketchanim.project.document import DEFAULT_FPS
from sketchanim.errors import load_json

#: Largest message the server reads, in bytes of UTF-8 (larger: ``too_large``).
MAX_MESSAGE_BYTES = 2**20
#: Largest websocket frame the server takes in at all, in bytes (uvicorn's ``ws_max_size``):
#: a frame up to it that is over :data:`MAX_MESSAGE_BYTES` is answered ``too_large`` on a
#: socket that stays open; a larger one closes the socket (code 1009).
MAX_FRAME_BYTES = 16 * 2**20
#: Longest text of an error's ``message``, in characters (what the page sent is never echoed whole).
MAX_ERROR_TEXT = 300
#: Most samples in one ``take.samples`` batch.
MAX_BATCH = 10_000
#: Most attributes armed in one take.
MAX_PATHS = 64
#: Widest smoothing of a take, in seconds (wider, a gesture's own shape is averaged away).
MAX_SMOOTHING = 0.5

Number = Annotated[float, Field(allow_inf_nan=False)]
#: An attribute's path, ``object.attribute``.
AttributePath = Annotated[str, Field(min_length=3, max_length=129)]
Name = Annotated[str, Field(min_length=1, max_length=64)]
Key = Annotated[str, Field(min_length=1, max_length=128)]
Id = Annotated[int, Field(ge=-(2**53), le=2**53)] | Annotated[str, Field(max_length=64)]
Value = Annotated[list[Number], Field(max_length=64)] | StrictBool | Annotated[str, Field(max_length=256)] | None


class _Message(BaseModel):
    model_config = ConfigDict(extra="forbid")

    id: Id | None = None


class Ping(_Message):
    type: Literal["ping"]


class StateRequest(_Message):
    type: Literal["state"]


class Set(_Message):
    """An undoable scene edit: ``path`` takes ``value``."""

    type: Literal["set"]
    path: AttributePath
    value: Value
    label: Annotated[str, Field(max_length=200)] | None = None
    merge: Key | None = None


class Preview(_Message):
    """A live value while the performer drags (not in History)."""

    type: Literal["preview"]
    key: Key
    path: AttributePath
    value: Value


Vector3 = tuple[Number, Number, Number]
#: Most control points moved in one ``curve.points``, knots inserted or removed in one ``curve.knots``.
MAX_EDITS = 10_000


class ObjectAdd(_Message):
    """Add an object (one History step), at ``position`` if given (the page places it in
    front of its camera), else at the kind's default place."""

    type: Literal["object.add"]
    name: Name
    kind: Literal["object", "light", "camera", "chain", "walker"] = "object"
    position: Vector3 | None = None


class ObjectDuplicate(_Message):
    """Copy the object ``name`` (its values and tracks) as ``to`` (one History step)."""

    type: Literal["object.duplicate"]
    name: Name
    to: Name


class ObjectRemove(_Message):
    type: Literal["object.remove"]
    name: Name


class ObjectRename(_Message):
    type: Literal["object.rename"]
    name: Name
    to: Name


class PointMove(BaseModel):
    """Control point ``index`` of the curve of ``path`` moved to ``value`` (its channels)."""

    model_config = ConfigDict(extra="forbid")

    path: AttributePath
    index: Annotated[int, Field(ge=0, le=10_000_000)]
    value: Annotated[list[Number], Field(min_length=1, max_length=64)]


class CurvePoints(_Message):
    """Move control points of one or more curves, as one History step (a drag in the
    curve editor or along a motion path: the curve changes only on the spans of the
    points moved)."""

    type: Literal["curve.points"]
    edits: Annotated[list[PointMove], Field(min_length=1, max_length=MAX_EDITS)]
    label: Annotated[str, Field(max_length=200)] | None = None


class CurveKey(_Message):
    """Set the value and / or the slope (per second) of the curve of ``path`` at ``time``
    (a key or its tangent handle dragged), as one History step: the least change of the
    control points active there, so the curve changes only on the spans around ``time``
    and keeps its knots (its continuity)."""

    type: Literal["curve.key"]
    path: AttributePath
    time: Number
    value: Annotated[list[Number], Field(min_length=1, max_length=64)] | None = None
    slope: Annotated[list[Number], Field(min_length=1, max_length=64)] | None = None
    label: Annotated[str, Field(max_length=200)] | None = None


class CurveKnots(_Message):
    """Insert knots at times ``insert`` (the curve unchanged, a control point more each)
    and remove the interior knots ``remove`` (indices into the curve's ``knots``: the
    nearest curve without them, changed only on their spans), as one History step."""

    type: Literal["curve.knots"]
    path: AttributePath
    insert: Annotated[list[Number], Field(max_length=MAX_EDITS)] = []
    remove: Annotated[list[Annotated[int, Field(ge=0, le=10_000_000)]], Field(max_length=MAX_EDITS)] = []


class TrackKey(_Message):
    """Key the discrete attribute ``path`` (a bool, an enum, an event) to ``value`` at
    transport time ``time`` (an event: a label or None), as one History step: what a page
    sends when the animator toggles or picks a value while the transport plays, or marks
    a cue."""

    type: Literal["track.key"]
    path: AttributePath
    time: Number
    value: StrictBool | Annotated[str, Field(max_length=64)] | None = None


class TrackReduce(_Message):
    """Re-reduce the tracks ``paths`` from their raw takes within ``tol`` (the attribute's
    units: degrees for an orientation): with ``preview``, only answered (``reduced`` with
    the would-be curves; no History step); otherwise one History step. Answered by
    ``reduced`` either way."""

    type: Literal["track.reduce"]
    paths: Annotated[list[AttributePath], Field(min_length=1, max_length=MAX_PATHS)]
    tol: Annotated[float, Field(gt=0, allow_inf_nan=False)]
    preview: bool = False


class TrackSamples(_Message):
    """Ask for the samples the curve of ``path`` keeps within its tolerance (each take's
    targets where no later take covers them), answered by ``samples``."""

    type: Literal["track.samples"]
    path: AttributePath


#: What ``take.edit`` does to a take: rename it, mute or unmute it, solo it (mute every
#: other), delete it, move it to another place in the track's order, or keep it as the
#: pass of its loop recording (the other passes muted), shift it in time (``by`` seconds),
#: or scale its times (by ``factor`` about ``pivot``, its start if None).
TakeOp = Literal["rename", "mute", "unmute", "solo", "delete", "move", "keep", "shift", "scale"]
Factor = Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)]


class TakeEdit(_Message):
    """Change take ``take`` (its index in the track's ``takes``) of the track at ``path``;
    the track is composed again from its takes (one History step)."""

    type: Literal["take.edit"]
    path: AttributePath
    take: Annotated[int, Field(ge=0, le=100_000)]
    op: TakeOp
    name: Annotated[str, Field(max_length=64)] | None = None
    to: Annotated[int, Field(ge=0, le=100_000)] | None = None
    by: Number | None = None
    factor: Factor | None = None
    pivot: Number | None = None


#: Frame rates the page's menu offers (frames per second; a project may have any in (0, 1000]).
FRAME_RATES = (12.0, 15.0, 23.976, 24.0, 25.0, 29.97, 30.0, 48.0, 50.0, 59.94, 60.0, 120.0)


class Settings(_Message):
    """The project's settings, kept by the project (not History) and sent to every page:
    the frame rate the transport counts frames in and edits snap to."""

    type: Literal["settings"]
    fps: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)]


class TakeBegin(_Message):
    """Start a take of ``paths`` at transport time ``time``, its samples smoothed over
    ``smoothing`` seconds before they are reduced (0: not smoothed; the raw samples are
    kept)."""

    type: Literal["take.begin"]
    take: Key
    paths: Annotated[list[AttributePath], Field(min_length=1, max_length=MAX_PATHS)]
    mode: Literal[MODES] = "replace"  # type: ignore[valid-type]
    blend: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)] = BLEND
    time: Number = 0.0
    speed: Annotated[float, Field(gt=0, le=4, allow_inf_nan=False)] = 1.0
    tol: Annotated[dict[AttributePath, Annotated[float, Field(gt=0, allow_inf_nan=False)]], Field(max_length=MAX_PATHS)] = {}
    loop: Key | None = None
    gap: Annotated[float, Field(gt=0, le=60, allow_inf_nan=False)] = 0.25
    smoothing: Annotated[float, Field(ge=0, le=MAX_SMOOTHING, allow_inf_nan=False)] = 0.0


class TakeSamples(_Message):
    """Samples of the running take: transport times (n,) and rows of its layout (n, width)."""

    type: Literal["take.samples"]
    take: Key
    t: Annotated[list[Number], Field(max_length=MAX_BATCH)]
    values: Annotated[list[Annotated[list[Number], Field(max_length=64 * MAX_PATHS)]], Field(max_length=MAX_BATCH)]


class TakeEnd(_Message):
    type: Literal["take.end"]
    take: Key
    label: Annotated[str, Field(max_length=200)] | None = None


class TakeCancel(_Message):
    type: Literal["take.cancel"]
    take: Key


class Undo(_Message):
    type: Literal["undo"]


class Redo(_Message):
    type: Literal["redo"]


class Transport(_Message):
    """The page's transport and record settings, kept for a reload and relayed to the
    other pages: the time, playing, the playback speed, the loop range; the count-in's
    seconds, the capture speed, the layer mode and loop recording."""

    type: Literal["transport"]
    time: Number = 0.0
    playing: bool = False
    speed: Annotated[float, Field(ge=-16, le=16, allow_inf_nan=False)] = 1.0
    loop: tuple[Number, Number] | None = None
    count_in: Annotated[float, Field(ge=0, le=60, allow_inf_nan=False)] = 0.0
    capture_speed: Annotated[float, Field(gt=0, le=4, allow_inf_nan=False)] = 1.0
    mode: Literal[MODES] = "replace"  # type: ignore[valid-type]
    loop_record: bool = False
    smoothing: Annotated[float, Field(ge=0, le=MAX_SMOOTHING, allow_inf_nan=False)] = 0.0


class ToleranceSet(_Message):
    """The tolerance takes of ``path`` are recorded within, kept by the project (not a
    History step): ``amount`` input steps (``unit`` px: pixels for a pointer) or the
    attribute's units; ``amount`` None: what the input resolves."""

    type: Literal["tolerance.set"]
    path: AttributePath
    amount: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = None
    unit: Literal["px", "units"] = "px"


class Export(_Message):
    """Write the scene (.glb) or the project (.json) into the studio's export folder (the
    project's, unless the studio was started with another); an existing file is replaced
    only with ``overwrite``, and the project's own files never."""

    type: Literal["export"]
    file: Annotated[str, Field(min_length=1, max_length=128)]
    overwrite: bool = False


# -- retiming and the clipboard (the timeline) ---------------------------------------------


class TrackRetime(_Message):
    """Retime the tracks ``paths`` as a whole: time ``t`` goes to
    ``pivot + factor * (t - pivot) + shift`` (their curves and takes with it), one History step."""

    type: Literal["track.retime"]
    paths: Annotated[list[AttributePath], Field(min_length=1, max_length=MAX_PATHS)]
    factor: Factor = 1.0
    pivot: Number = 0.0
    shift: Number = 0.0


class TrackCut(_Message):
    """Delete the motion of the tracks ``paths`` over ``(t0, t1)`` (a curve bridged
    smoothly across, a discrete track's values there removed), one History step."""

    type: Literal["track.cut"]
    paths: Annotated[list[AttributePath], Field(min_length=1, max_length=MAX_PATHS)]
    t0: Number
    t1: Number


class TrackCopy(_Message):
    """Copy the motion of the track at ``path`` over ``(t0, t1)``: answered by
    ``track.piece`` (the page keeps it as its clipboard; nothing changes)."""

    type: Literal["track.copy"]
    path: AttributePath
    t0: Number
    t1: Number


class TrackPaste(_Message):
    """Put a ``piece`` (as ``track.piece`` brought it) on the track at ``path`` from time
    ``at``: a curve gets it as a replacing take, a discrete track its values (those in
    ``(at, at + length)`` removed); the piece's attribute (its ``path``'s type) must be
    the track's. One History step."""

    type: Literal["track.paste"]
    path: AttributePath
    at: Number
    piece: TrackInfo
    length: Annotated[float, Field(ge=0, allow_inf_nan=False)]


# -- sounds (studio/sounds.py, studio/beats.py) ---------------------------------------------

#: A sound's name: its file's in the project's sounds folder.
SoundName = Annotated[str, Field(min_length=1, max_length=255)]


class SoundSet(_Message):
    """Start the sound ``name`` at ``offset`` seconds on the timeline (a project setting,
    not a History step)."""

    type: Literal["sound.set"]
    name: SoundName
    offset: Number


class SoundRemove(_Message):
    """Drop the sound ``name`` from the project (its file stays in the sounds folder)."""

    type: Literal["sound.remove"]
    name: SoundName


class SoundBeats(_Message):
    """Bake the onsets of the sound ``name`` into an event track at ``path`` (an event
    attribute, or ``<new object>.cue``: a cue object made for it; ``beats.cue`` if
    None), at the sound's offset plus each onset: one History step."""

    type: Literal["sound.beats"]
    name: SoundName
    path: AttributePath | None = None


Message = Annotated[
    Ping | StateRequest | Set | Preview | ObjectAdd | ObjectDuplicate | ObjectRemove | ObjectRename | TakeBegin
    | TakeSamples | TakeEnd | TakeCancel | Undo | Redo | Transport | Export | ToleranceSet | CurvePoints | CurveKey
    | CurveKnots | TrackKey | TrackReduce | TrackSamples | TakeEdit | Settings | TrackRetime | TrackCut | TrackCopy
    | TrackPaste | SoundSet | SoundRemove | SoundBeats,
    Field(discriminator="type"),
]
_ADAPTER: TypeAdapter[Message] = TypeAdapter(Message)


# -- from the server to the pages -----------------------------------------------------------


class _Outbound(BaseModel):
    model_config = ConfigDict(extra="forbid")


class TypeInfo(_Outbound):
    """An attribute type as the page sees it."""

    name: str
    dim: int
    tol: float
    unit: str
    default: list[Any]
    choices: list[str]
    continuous: bool


class AttributeInfo(_Outbound):
    name: str
    type: TypeInfo
    value: Any


class ObjectInfo(_Outbound):
    name: str
    kind: str
    attributes: list[AttributeInfo]


class TakeSpan(_Outbound):
    """One take of a curve: its span, mode, number of samples, the seconds they were
    smoothed over before the reduction (0: not smoothed), its name (empty: none given),
    whether it is muted (left out of the curve), and the loop recording it is part of
    (None: none) with the number of its pass (0, 1, ...; a pass may be several takes)."""

    start: float
    end: float
    mode: str
    n: int
    smoothing: float
    name: str = ""
    muted: bool = False
    loop: str | None = None
    loop_pass: int = 0


class CurveInfo(_Outbound):
    """A continuous track: a B-spline the page evaluates as the player does."""

    path: str
    kind: Literal["curve"] = "curve"
    dim: int
    order: int
    rotation: bool
    tol: float
    knots: list[float]
    coef: list[list[float]]
    start: float
    end: float
    takes: list[TakeSpan]
    #: the attribute's bounds (low, high; None: that side unbounded), or None: unbounded
    bounds: list[float | None] | None = None
    #: its control points or keys were edited by hand since it was composed from its takes
    #: (composing it again, at another tolerance or with a take muted, drops those edits)
    edited: bool = False


class StepsInfo(_Outbound):
    """A discrete track: values that hold from their time to the next."""

    path: str
    kind: Literal["steps"] = "steps"
    times: list[float]
    values: list[Any]


TrackInfo = Annotated[CurveInfo | StepsInfo, Field(discriminator="kind")]


class TransportInfo(_Outbound):
    """The transport and record settings as the server keeps them (see :class:`Transport`)."""

    time: float = 0.0
    playing: bool = False
    speed: float = 1.0
    loop: tuple[float, float] | None = None
    count_in: float = 0.0
    capture_speed: float = 1.0
    mode: str = "replace"
    loop_record: bool = False
    smoothing: float = 0.0


class TakeInfo(_Outbound):
    """The take being recorded, in a ``state``."""

    take: str
    paths: list[str]
    mode: str
    time: float
    layout: list[tuple[str, int, int]]


class ToleranceInfo(_Outbound):
    """The animator's tolerance for an attribute's takes: ``amount`` input steps (px) or
    the attribute's units."""

    amount: float
    unit: Literal["px", "units"]


class Tolerances(_Outbound):
    """The animator's take tolerances changed: all of them, by path."""

    type: Literal["tolerances"] = "tolerances"
    tolerances: dict[str, ToleranceInfo]


class HistoryInfo(_Outbound):
    """The labels of the steps to undo (oldest first) and to redo (the next redo last)."""

    type: Literal["history"] = "history"
    undo: list[str]
    redo: list[str]
    can_undo: bool
    can_redo: bool


class Saved(_Outbound):
    """Whether everything the pages were told is on disk: ``ok``; otherwise ``error``
    says why the last save failed (the disk is full, the folder cannot be written) and
    ``since`` when (epoch seconds) saves began to fail. What is not
    saved is kept by the server and saved at the next chance; sent to every page when
    this changes, and in every ``state``."""

    type: Literal["saved"] = "saved"
    ok: bool = True
    error: str | None = None
    since: float | None = None


class SettingsInfo(_Outbound):
    """The project's settings (see :class:`Settings`), sent to every page when they change."""

    type: Literal["settings"] = "settings"
    fps: float = DEFAULT_FPS


class Reduction(_Outbound):
    """A track re-reduced within ``tol``: its control points and the largest distance of
    the curve from the samples it keeps (in the attribute's units; degrees for an
    orientation)."""

    path: str
    tol: float
    n: int
    error: float


class Reduced(_Outbound):
    """The answer to ``track.reduce``: each track's reduction; for a preview, the would-be
    curves too (nothing changed)."""

    type: Literal["reduced"] = "reduced"
    preview: bool
    results: list[Reduction]
    curves: list[CurveInfo] = []


class Samples(_Outbound):
    """The answer to ``track.samples``: the times (n,) and values (n, dim) the curve of
    ``path`` keeps within ``tol`` (each take's targets where no later take covers them;
    none for a curve without takes)."""

    type: Literal["samples"] = "samples"
    path: str
    tol: float
    times: list[float]
    values: list[list[float]]


class SoundInfo(_Outbound):
    """A sound of the project: its name, its file's path relative to the project's folder,
    its SHA-256, its duration (s), where it starts on the timeline (s), whether its file is
    as imported (``ok``, ``missing``, ``changed``), and the URL that serves it."""

    name: str
    path: str
    sha256: str
    duration: float
    offset: float
    status: Literal["ok", "missing", "changed"]
    url: str


class Sounds(_Outbound):
    """The project's sounds changed (one imported, moved, removed): all of them."""

    type: Literal["sounds"] = "sounds"
    sounds: list[SoundInfo]


class BeatsBaked(_Outbound):
    """The answer to ``sound.beats``: how many beats of sound ``name`` went on ``path``."""

    type: Literal["beats"] = "beats"
    name: str
    path: str
    count: int


class State(_Outbound):
    """Everything a page needs to show the project: sent on connect, on ``state``, and
    when objects come or go."""

    type: Literal["state"] = "state"
    ready: bool
    project: str
    objects: list[ObjectInfo]
    tracks: list[TrackInfo]
    span: tuple[float, float]
    history: HistoryInfo
    transport: TransportInfo
    take: TakeInfo | None
    tolerances: dict[str, ToleranceInfo]
    saved: Saved = Saved()
    #: the project cannot be written (read-only media or file): it plays and exports, edits are refused
    read_only: bool = False
    settings: SettingsInfo = SettingsInfo()
    sounds: list[SoundInfo] = []


class Values(_Outbound):
    """Scene values that changed (path -> value)."""

    type: Literal["values"] = "values"
    values: dict[str, Any]


class Tracks(_Outbound):
    """Tracks that changed or went, and the player's span after."""

    type: Literal["tracks"] = "tracks"
    changed: list[TrackInfo]
    removed: list[str]
    span: tuple[float, float]


class TakeStarted(_Outbound):
    """To the page that began the take: where each path's columns are in a row."""

    type: Literal["take.started"] = "take.started"
    take: str
    layout: list[tuple[str, int, int]]
    width: int


class TakeRunning(TakeInfo):
    """To the other pages: another page began a take (``take.ended`` says when it is over)."""

    type: Literal["take.running"] = "take.running"


class TakePiece(_Outbound):
    """A finished piece of a take's curve (a B-spline over part of the take)."""

    type: Literal["take.piece"] = "take.piece"
    take: str
    path: str
    order: int
    rotation: bool
    knots: list[float]
    coef: list[list[float]]


#: Why a take ended: its page ended it, cancelled it, went away, fell silent (no message
#: for :data:`~sketchanim.studio.takes.SILENCE` seconds), or the server stopped.
EndReason = Literal["end", "cancel", "gone", "silent", "shutdown"]


class TakeEnded(_Outbound):
    """The take is over (``reason``): the History step it made (``label`` None if
    none), the paths it changed, the milliseconds the end took, the stalls that cut it,
    and the seconds its samples were smoothed over (0: not smoothed; the curve is within
    tolerance of the smoothed samples)."""

    type: Literal["take.ended"] = "take.ended"
    take: str
    label: str | None
    paths: list[str]
    ms: float
    gaps: list[tuple[float, float]]
    smoothing: float = 0.0
    reason: EndReason = "end"


class Pong(_Outbound):
    type: Literal["pong"] = "pong"
    id: Id | None
    server_time: float


class Ack(_Outbound):
    """A message with an ``id`` was carried out."""

    type: Literal["ack"] = "ack"
    id: Id
    ref: str


#: Why a message was not carried out: it was over the rate limit, over the size limit, did
#: not parse, began a take while one runs, the model refused it, it would edit a
#: read-only project, its file exists (export without ``overwrite``), or the disk failed.
ErrorCode = Literal["rate", "too_large", "bad_message", "busy", "refused", "read_only", "exists", "failed"]


class Error(_Outbound):
    """A message was not carried out (``ref``: its type; ``id``: its id, if readable)."""

    type: Literal["error"] = "error"
    id: Id | None
    ref: str | None
    code: ErrorCode
    message: str


class Ready(_Outbound):
    """The compiled kernels are warm: takes reduce at full speed."""

    type: Literal["ready"] = "ready"


class Exported(_Outbound):
    """The ``export`` was written: the file's name in the project's folder."""

    type: Literal["exported"] = "exported"
    file: str


class TrackPiece(_Outbound):
    """A copied range of the track at ``path`` (``track.copy``): ``piece`` starts at 0
    and is ``length`` seconds long; ``track.paste`` puts it back."""

    type: Literal["track.piece"] = "track.piece"
    path: str
    piece: TrackInfo
    length: float


class Notice(_Outbound):
    """Something the animator should know (a reducer process died, the journal failed),
    shown on the page and kept in the server's log."""

    type: Literal["notice"] = "notice"
    level: Literal["info", "warning", "error"]
    text: str
    source: str


ServerMessage = (State | Values | Tracks | HistoryInfo | TakeStarted | TakePiece | TakeEnded | Pong | Ack | Error
                 | Ready | Exported | Notice | Preview | Transport | Tolerances | TakeRunning | Saved | SettingsInfo
                 | Reduced | Samples | TrackPiece | Sounds | BeatsBaked)
#: Every model of a message, both directions (``preview`` and ``transport`` go both ways).
MESSAGES: tuple[type[BaseModel], ...] = (
    Ping, StateRequest, Set, Preview, ObjectAdd, ObjectDuplicate, ObjectRemove, ObjectRename, TakeBegin, TakeSamples,
    TakeEnd, TakeCancel, Undo, Redo, Transport, Export, ToleranceSet, CurvePoints, CurveKey, CurveKnots, TrackKey, TrackReduce,
    TrackSamples, TakeEdit, Settings, TrackRetime, TrackCut, TrackCopy, TrackPaste, SoundSet, SoundRemove, SoundBeats,
    State, Values, Tracks, HistoryInfo, TakeStarted, TakePiece, TakeEnded, Pong, Ack, Error, Ready, Exported, Notice,
    Tolerances, TakeRunning, Saved, SettingsInfo, Reduced, Samples, TrackPiece, Sounds, BeatsBaked)


#: Who gets a message: every page, every page but the sender's, or the sender's alone.
Audience = Literal["all", "others", "self"]
#: A message (as :func:`wire` or :func:`relay` made it) and who gets it.
Out = tuple[Audience, dict]


def wire(message: _Outbound) -> dict:
    """``message`` as it is sent: a JSON object.

    >>> wire(Notice(level="warning", text="a reducer process died", source="recorder"))
    {'type': 'notice', 'level': 'warning', 'text': 'a reducer process died', 'source': 'recorder'}
    """
    return message.model_dump(mode="json")


def relay(message: Preview | Transport) -> dict:
    """A page's ``preview`` or ``transport`` as the other pages get it (without its ``id``).

    >>> relay(parse('{"type": "preview", "id": 1, "key": "drag", "path": "box.position", "value": [0, 1, 2]}'))
    {'type': 'preview', 'key': 'drag', 'path': 'box.position', 'value': [0.0, 1.0, 2.0]}
    """
    return message.model_dump(mode="json", exclude={"id"})


def message_fields(model: type[BaseModel]) -> tuple[str, frozenset[str]]:
    """A message model's ``type`` literal and its field names (``type`` among them).

    >>> kind, fields = message_fields(Ack)
    >>> kind, sorted(fields)
    ('ack', ['id', 'ref', 'type'])
    """
    return model.model_fields["type"].annotation.__args__[0], frozenset(model.model_fields)


#: The ``type`` of every message a page may send (an error's ``ref`` is one of these, or None).
TYPES = frozenset(message_fields(model)[0] for model in get_args(get_args(Message)[0]))
_ID: TypeAdapter = TypeAdapter(Id)


def short(text: str, limit: int = MAX_ERROR_TEXT) -> str:
    """``text`` cut to ``limit`` characters (an ellipsis says it was cut).

    >>> short("x" * 1000, 10), short("ok")
    ('xxxxxxxxx…', 'ok')
    """
    return text if len(text) <= limit else text[:limit - 1] + "…"


def readable_id(value: object) -> Id | None:
    """``value`` if it is a valid ``id`` (an int within ±2**53, a string of up to 64), else None.

    >>> readable_id(7), readable_id("x" * 65), readable_id(2**60), readable_id(True)
    (7, None, None, None)
    """
    if isinstance(value, bool) or not isinstance(value, (int, str)):
        return None
    try:
        return _ID.validate_python(value, strict=True)
    except ValidationError:
        return None


class BadMessage(ValueError):
    """A message that does not parse; ``id`` and ``type`` are what could be read of it
    (None unless a valid id and a known type), ``code`` the error's (``too_large`` or
    ``bad_message``), the text at most :data:`MAX_ERROR_TEXT` characters."""

    def __init__(self, message: str, id: object = None, type: object = None,
                 code: ErrorCode = "bad_message") -> None:
        super().__init__(short(message))
        self.id = readable_id(id)
        self.type = type if isinstance(type, str) and type in TYPES else None
        self.code = code


def utf8_size(text: str) -> int:
    """How many bytes ``text`` is in UTF-8 (a lone surrogate counted as its 3 bytes).

    >>> utf8_size("abc"), utf8_size("é"), utf8_size(chr(0xD800))
    (3, 2, 3)
    """
    return len(text.encode("utf-8", "surrogatepass"))


def parse(text: str | bytes) -> Message:
    """The message in ``text`` (a text frame, or a binary one: UTF-8); :class:`BadMessage`
    naming the first bad field, and never another exception: over
    :data:`MAX_MESSAGE_BYTES` bytes it is ``too_large``; bytes that are not UTF-8, JSON
    that is not an object, nested deeper or with longer integers than
    :func:`~sketchanim.errors.load_json` reads are ``bad_message``.

    >>> parse('{"type": "ping", "id": 3}')
    Ping(id=3, type='ping')
    >>> parse('{"type": "set", "path": "box.visible", "value": 1}').value    # a number is not a bool
    Traceback (most recent call last):
    ...
    sketchanim.studio.protocol.BadMessage: set.value.list[...]: Input should be a valid list
    >>> parse('{"type": "set", "path": "box.position", "value": "x", "id": 4, "extra": 1}')
    Traceback (most recent call last):
    ...
    sketchanim.studio.protocol.BadMessage: set.extra: Extra inputs are not permitted
    >>> parse('{"type": "ping", "id": ' + "9" * 5000 + '}')
    Traceback (most recent call last):
    ...
    sketchanim.studio.protocol.BadMessage: not JSON: message: an integer of 5000 digits (at most 300)
    >>> parse("é" * 600_000)
    Traceback (most recent call last):
    ...
    sketchanim.studio.protocol.BadMessage: message of 1200000 bytes is over the limit of 1048576
    """
    size = len(text) if isinstance(text, bytes) or len(text) > MAX_MESSAGE_BYTES else utf8_size(text)
    if size > MAX_MESSAGE_BYTES:
        raise BadMessage(f"message of {size} bytes is over the limit of {MAX_MESSAGE_BYTES}", code="too_large")
    try:
        raw = load_json(text, "message")
    except (ValueError, RecursionError) as err:      # not UTF-8, not JSON, too deep, too long an integer
        raise BadMessage(f"not JSON: {err}") from None
    if not isinstance(raw, dict):
        raise BadMessage(f"a message is a JSON object with a type, got {type(raw).__name__}")
    try:
        return _ADAPTER.validate_python(raw)
    except ValidationError as err:
        first = err.errors(include_url=False, include_input=False)[0]
        where = ".".join(short(str(p), 64) for p in first["loc"]) or "message"
        raise BadMessage(f"{where}: {first['msg']}", raw.get("id"), raw.get("type")) from None
