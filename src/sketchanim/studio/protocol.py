"""The studio's messages: one pydantic model per message, a union keyed on ``type``.

A message from the page is validated once, at the websocket (:func:`parse`), as
:mod:`sketchanim.project.store` validates documents; what the server sends is built by the
session as plain dictionaries of the shapes documented here. Values are the attribute
types' canonical forms as JSON: lists of floats (orientations scalar-last x, y, z, w; a
field of view in degrees), or a bool / string for discrete attributes.
"""

from __future__ import annotations

import json
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, StrictBool, TypeAdapter, ValidationError

from sketchanim.anim.tracks import BLEND, MODES

#: Largest message the server reads, in bytes.
MAX_MESSAGE_BYTES = 2**20
#: Most samples in one ``take.samples`` batch.
MAX_BATCH = 10_000
#: Most attributes armed in one take.
MAX_PATHS = 64

Number = Annotated[float, Field(allow_inf_nan=False)]
Path = Annotated[str, Field(min_length=3, max_length=129)]
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
    path: Path
    value: Value
    label: Annotated[str, Field(max_length=200)] | None = None
    merge: Key | None = None


class Preview(_Message):
    """A live value while the performer drags (not in History)."""

    type: Literal["preview"]
    key: Key
    path: Path
    value: Value


class ObjectAdd(_Message):
    type: Literal["object.add"]
    name: Name
    kind: Literal["object", "light", "camera"] = "object"


class ObjectRemove(_Message):
    type: Literal["object.remove"]
    name: Name


class ObjectRename(_Message):
    type: Literal["object.rename"]
    name: Name
    to: Name


class TakeBegin(_Message):
    """Start a take of ``paths`` at transport time ``time``."""

    type: Literal["take.begin"]
    take: Key
    paths: Annotated[list[Path], Field(min_length=1, max_length=MAX_PATHS)]
    mode: Literal[MODES] = "replace"  # type: ignore[valid-type]
    blend: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)] = BLEND
    time: Number = 0.0
    speed: Annotated[float, Field(gt=0, le=4, allow_inf_nan=False)] = 1.0
    tol: Annotated[dict[Path, Annotated[float, Field(gt=0, allow_inf_nan=False)]], Field(max_length=MAX_PATHS)] = {}
    loop: Key | None = None
    gap: Annotated[float, Field(gt=0, le=60, allow_inf_nan=False)] = 0.25


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
    """The page's transport, kept for a reload and relayed to the other pages."""

    type: Literal["transport"]
    time: Number = 0.0
    playing: bool = False
    speed: Annotated[float, Field(ge=-16, le=16, allow_inf_nan=False)] = 1.0
    loop: tuple[Number, Number] | None = None


class Export(_Message):
    """Write the scene (.glb) or the project (.json) into the project's folder."""

    type: Literal["export"]
    file: Annotated[str, Field(min_length=1, max_length=128)]


Message = Annotated[
    Ping | StateRequest | Set | Preview | ObjectAdd | ObjectRemove | ObjectRename | TakeBegin | TakeSamples
    | TakeEnd | TakeCancel | Undo | Redo | Transport | Export,
    Field(discriminator="type"),
]
_ADAPTER: TypeAdapter[Message] = TypeAdapter(Message)


class BadMessage(ValueError):
    """A message that does not parse; ``id`` and ``type`` are what could be read of it."""

    def __init__(self, message: str, id: object = None, type: object = None) -> None:
        super().__init__(message)
        self.id = id if isinstance(id, (int, str)) and not isinstance(id, bool) else None
        self.type = type if isinstance(type, str) and len(type) <= 64 else None


def parse(text: str | bytes) -> Message:
    """The message in ``text``; :class:`BadMessage` naming the first bad field.

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
    """
    if len(text) > MAX_MESSAGE_BYTES:
        raise BadMessage(f"message of {len(text)} bytes is over the limit of {MAX_MESSAGE_BYTES}")
    try:
        raw = json.loads(text)
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise BadMessage(f"not JSON: {err}") from None
    if not isinstance(raw, dict):
        raise BadMessage(f"a message is a JSON object with a type, got {type(raw).__name__}")
    try:
        return _ADAPTER.validate_python(raw)
    except ValidationError as err:
        first = err.errors()[0]
        where = ".".join(str(p) for p in first["loc"]) or "message"
        raise BadMessage(f"{where}: {first['msg']}", raw.get("id"), raw.get("type")) from None
