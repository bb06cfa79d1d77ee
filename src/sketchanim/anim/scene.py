"""The scene: named objects with typed, named attributes, addressed by path strings.

A path is ``"object.attribute"`` (``"lamp.color"``), as three.js's PropertyBinding
addresses a property. An object's kind gives its standard attributes; any object can
take more (:meth:`SceneObject.add`). New kinds (articulated chains, walkers) are more
entries in :data:`KINDS`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from sketchanim.anim.attributes import BOOL, COLOR, FOV, INTENSITY, ORIENTATION, POSITION, SCALE, AttributeType
from sketchanim.errors import ArgumentError

#: Standard attributes of each object kind.
KINDS: dict[str, dict[str, AttributeType]] = {
    "object": {"position": POSITION, "orientation": ORIENTATION, "scale": SCALE, "visible": BOOL},
    "light": {"position": POSITION, "orientation": ORIENTATION, "color": COLOR, "intensity": INTENSITY, "on": BOOL},
    "camera": {"position": POSITION, "orientation": ORIENTATION, "fov": FOV},
}

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
    ['color', 'intensity', 'on', 'orientation', 'position']
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


class Scene:
    """Objects by name; attributes by path.

    >>> scene = Scene()
    >>> _ = scene.add("lamp", "light")
    >>> scene.set("lamp.color", [1.0, 0.5, 0.0])
    >>> scene.get("lamp.color").tolist(), scene.type("lamp.color").unit
    ([1.0, 0.5, 0.0], 'colour units')
    """

    def __init__(self) -> None:
        self.objects: dict[str, SceneObject] = {}

    def add(self, name: str, kind: str = "object") -> SceneObject:
        """Add an object of ``kind`` ("object", "light", "camera", ...)."""
        if name in self.objects:
            raise ArgumentError("object", f"{name!r} exists already")
        obj = SceneObject(name, kind)
        self.objects[name] = obj
        return obj

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
