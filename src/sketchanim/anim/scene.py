"""The scene: named objects with typed, named attributes, addressed by path strings.

A path is ``"object.attribute"`` (``"lamp.color"``), as three.js's PropertyBinding
addresses a property. An object's kind gives its standard attributes; any object can
take more (:meth:`SceneObject.add`). New kinds (articulated chains, walkers) are more
entries in :data:`KINDS`.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from sketchanim.anim.attributes import BOOL, COLOR, EVENT, FOV, INTENSITY, ORIENTATION, POSITION, SCALE, AttributeType
from sketchanim.errors import ArgumentError

#: Joint slots of an articulated chain: its ``lengths``, ``limits`` and ``hinges`` hold one
#: entry per slot, and the chain is its leading slots of positive length (2 to 8 of them).
CHAIN_SLOTS = 8

#: Standard attributes of each object kind; every kind has ``cue``, its events (what the
#: animator marks on it while performing: a hit, a cut, a line of dialogue). A cue object has
#: no place in space: it holds events alone (the beats baked from a sound, cues to trigger).
#: A chain and a walker are rigs: the animator performs their ``goal`` (an ordinary position
#: track) and their pose is derived from it (:mod:`sketchanim.anim.rigs`). A chain stands at
#: its ``position``, straight up at rest, its segment ``lengths`` in scene units, each joint's
#: ``limits`` in degrees from rest and ``hinges`` 1 for a hinge (about the joint's x axis) or 0
#: for a ball; a walker follows its goal on the ground, a humanoid ``height`` metres tall.
KINDS: dict[str, dict[str, AttributeType]] = {
    "object": {"position": POSITION, "orientation": ORIENTATION, "scale": SCALE, "visible": BOOL, "cue": EVENT},
    "light": {"position": POSITION, "orientation": ORIENTATION, "color": COLOR, "intensity": INTENSITY, "on": BOOL,
              "cue": EVENT},
    "camera": {"position": POSITION, "orientation": ORIENTATION, "fov": FOV, "cue": EVENT},
    "cue": {"cue": EVENT},
    "chain": {"position": POSITION, "goal": POSITION,
              "lengths": AttributeType("vector", CHAIN_SLOTS, 1e-3, "scene units", (0.5, 0.4, 0.3, 0.25, 0.2, 0.0, 0.0, 0.0)),
              "limits": AttributeType("vector", CHAIN_SLOTS, 0.1, "degrees", (150.0,) * CHAIN_SLOTS),
              "hinges": AttributeType("vector", CHAIN_SLOTS, 1e-3, "", (0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0)),
              "cue": EVENT},
    "walker": {"goal": POSITION, "height": AttributeType("float", 1, 1e-3, "scene units", (1.75,)), "cue": EVENT},
}

#: The kinds whose pose is derived from a performed goal.
RIGS = ("chain", "walker")

#: The attribute a joint object names its parent joint object in (an enum of that one name):
#: the hierarchy of an imported skeleton, which the page draws as bones and a BVH export keeps.
BONE_PARENT = "parent"

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_\-]{0,63}")


def check_name(name: object, what: str) -> str:
    """``name`` if it can be part of a path (a letter or _, then letters, digits, _ or
    -, at most 64 characters; no dots).

    >>> check_name("lamp_1", "object")
    'lamp_1'
    """
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise ArgumentError(what, f"{name!r} is not a valid name (a letter or _, then letters, digits, _ or -)")
    return name


@dataclass
class Attribute:
    """An attribute of an object: its type and current value."""

    type: AttributeType
    value: object


@dataclass
class SceneObject:
    """A named object of some kind with its attributes.

    >>> lamp = SceneObject("lamp", "light")
    >>> sorted(lamp.attributes)
    ['color', 'cue', 'intensity', 'on', 'orientation', 'position']
    """

    name: str
    kind: str
    attributes: dict[str, Attribute] = field(default_factory=dict)

    def __post_init__(self) -> None:
        check_name(self.name, "object")
        if self.kind not in KINDS:
            raise ArgumentError("kind", f"must be one of {sorted(KINDS)}, got {self.kind!r}")
        for name, kind_type in KINDS[self.kind].items():
            if name not in self.attributes:
                self.add(name, kind_type)

    def add(self, name: str, type: AttributeType, value: object = None) -> Attribute:
        """Add an attribute (its type's default value unless ``value`` is given).

        >>> SceneObject("box", "object").add("wobble", AttributeType.vector(2)).value.tolist()
        [0.0, 0.0]
        """
        check_name(name, "attribute")
        if name in self.attributes:
            raise ArgumentError("attribute", f"{self.name}.{name} exists already")
        start = type.initial if value is None else value
        attribute = Attribute(type, type.check(start, f"{self.name}.{name}"))
        self.attributes[name] = attribute
        return attribute


#: Told of every change made through a :class:`Scene`'s methods: (what, subject, detail)
#: with what = "add" (subject: the object), "remove" (the object), "rename" (the old
#: name; detail: the new one) or "set" (subject: the path). Playback writes values
#: without telling (the player owns them while it plays).
Watcher = Callable[[str, str, str | None], None]


class Scene:
    """Objects by name; attributes by path.

    >>> scene = Scene()
    >>> _ = scene.add("lamp", "light")
    >>> scene.set("lamp.color", [1.0, 0.5, 0.0])
    >>> scene.get("lamp.color").tolist(), scene.type("lamp.color").unit
    ([1.0, 0.5, 0.0], 'colour units')
    >>> changes = []; scene.watch(lambda *change: changes.append(change))
    >>> scene.rename("lamp", "sun"); scene.set("sun.intensity", [2.0]); _ = scene.remove("sun")
    >>> changes, scene.paths()
    ([('rename', 'lamp', 'sun'), ('set', 'sun.intensity', None), ('remove', 'sun', None)], [])
    """

    def __init__(self) -> None:
        self.objects: dict[str, SceneObject] = {}
        self._watchers: list[Watcher] = []

    def watch(self, watcher: Watcher) -> None:
        """Tell ``watcher`` of every change from now on (see :data:`Watcher`)."""
        self._watchers.append(watcher)

    def _tell(self, what: str, subject: str, detail: str | None = None) -> None:
        for watcher in self._watchers:
            watcher(what, subject, detail)

    def add(self, name: str, kind: str = "object") -> SceneObject:
        """Add an object of ``kind`` ("object", "light", "camera", ...)."""
        return self.insert(SceneObject(name, kind))

    def insert(self, obj: SceneObject, at: int | None = None) -> SceneObject:
        """Add ``obj`` as it is (e.g. one :meth:`remove` gave back, to undo that), at
        place ``at`` among the objects (last by default)."""
        if obj.name in self.objects:
            raise ArgumentError("object", f"{obj.name!r} exists already")
        items = list(self.objects.items())
        items.insert(len(items) if at is None else at, (obj.name, obj))
        self.objects = dict(items)
        self._tell("add", obj.name)
        return obj

    def index(self, name: str) -> int:
        """The place of object ``name`` among the objects."""
        if name not in self.objects:
            raise ArgumentError("object", f"no object {name!r}")
        return list(self.objects).index(name)

    def remove(self, name: str) -> SceneObject:
        """Take the object ``name`` out of the scene; it is returned, attributes and all."""
        if name not in self.objects:
            raise ArgumentError("object", f"no object {name!r}")
        obj = self.objects.pop(name)
        self._tell("remove", name)
        return obj

    def rename(self, name: str, to: str) -> None:
        """Call the object ``name`` ``to`` (its paths become ``to.attribute``), keeping
        its place among the objects."""
        if name not in self.objects:
            raise ArgumentError("object", f"no object {name!r}")
        check_name(to, "object")
        if to in self.objects:
            raise ArgumentError("object", f"{to!r} exists already")
        self.objects = {(to if k == name else k): v for k, v in self.objects.items()}
        self.objects[to].name = to
        self._tell("rename", name, to)

    def attribute(self, path: str) -> Attribute:
        """The attribute at ``path`` ("object.attribute"); :class:`ArgumentError` naming
        the part that is not there."""
        if not isinstance(path, str) or path.count(".") != 1:
            raise ArgumentError("path", f"must be 'object.attribute', got {path!r}")
        name, attr = path.split(".")
        if name not in self.objects:
            raise ArgumentError("path", f"{path!r}: no object {name!r}")
        obj = self.objects[name]
        if attr not in obj.attributes:
            raise ArgumentError("path", f"{path!r}: {obj.kind} {name!r} has no attribute {attr!r}")
        return obj.attributes[attr]

    def paths(self) -> list[str]:
        """Every attribute's path, object by object."""
        return [f"{o.name}.{a}" for o in self.objects.values() for a in o.attributes]

    def type(self, path: str) -> AttributeType:
        """The type of the attribute at ``path``."""
        return self.attribute(path).type

    def get(self, path: str) -> object:
        """The current value at ``path`` (a copy for a vector)."""
        value = self.attribute(path).value
        return value.copy() if isinstance(value, np.ndarray) else value

    def set(self, path: str, value: object) -> None:
        """Set the value at ``path``, checked against its type."""
        attribute = self.attribute(path)
        attribute.value = attribute.type.check(value, path)
        self._tell("set", path)
