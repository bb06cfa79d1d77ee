"""What a new studio project starts with: the default scene, and the shapes the page
draws for plain objects."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.scene import Scene, SceneObject

#: The mesh the page draws for an object of kind "object".
SHAPE = AttributeType.enum(["box", "sphere", "cone", "cylinder", "torus"])

#: Where a new chain's goal is from its base: in front of and below its reach (the default
#: lengths reach 1.65), so the chain starts bent toward it.
CHAIN_GOAL = np.array([0.5, 1.1, 0.0])


def _looking_at(position: list[float], target: list[float]) -> list[float]:
    """The orientation (x, y, z, w) of a camera or light at ``position`` looking at
    ``target`` along its -z axis, y up (three.js's convention)."""
    back = np.subtract(position, target)
    back /= np.linalg.norm(back)
    right = np.cross([0.0, 1.0, 0.0], back)
    right /= np.linalg.norm(right)
    return Rotation.from_matrix(np.c_[right, np.cross(back, right), back]).as_quat().tolist()


def new_object(name: str, kind: str, place: Sequence[float] | None = None) -> SceneObject:
    """An object as the studio adds it, at ``place`` if given: a plain object gets a
    ``shape`` (a box); a walker's goal is its place; a chain stands there with its goal
    in front of its tip, where the animator grabs it.

    >>> new_object("crate", "object").attributes["shape"].value
    'box'
    >>> arm = new_object("arm", "chain", [1.0, 0.0, 0.0])
    >>> arm.attributes["position"].value.tolist(), arm.attributes["goal"].value.tolist()
    ([1.0, 0.0, 0.0], [1.5, 1.1, 0.0])
    """
    obj = SceneObject(name, kind)
    if kind == "object":
        obj.add("shape", SHAPE)
    placed = "goal" if kind == "walker" else "position"
    if place is not None:
        at = obj.attributes[placed]
        at.value = at.type.check(place, f"{name}.{placed}")
    if kind == "chain":
        obj.attributes["goal"].value = obj.attributes["position"].value + CHAIN_GOAL
    return obj


def default_scene() -> Scene:
    """The scene a new studio project starts with: a box in the middle of the view, a
    ball and a cone beside it, a spot light and a camera looking at the box.

    >>> scene = default_scene()
    >>> list(scene.objects), scene.get("box.position").tolist(), scene.get("box.shape")
    (['box', 'ball', 'cone', 'lamp', 'cam'], [0.0, 0.5, 0.0], 'box')
    """
    scene = Scene()
    for name, shape, position in (("box", "box", [0.0, 0.5, 0.0]), ("ball", "sphere", [1.6, 0.5, 0.4]),
                                  ("cone", "cone", [-1.6, 0.5, -0.3])):
        scene.add(name).add("shape", SHAPE, shape)
        scene.set(f"{name}.position", position)
    scene.add("lamp", "light")
    scene.set("lamp.position", [2.0, 4.0, 3.0])
    scene.set("lamp.orientation", _looking_at([2.0, 4.0, 3.0], [0.0, 0.5, 0.0]))
    scene.set("lamp.color", [1.0, 0.95, 0.85])
    scene.set("lamp.intensity", [1.0])
    scene.add("cam", "camera")
    scene.set("cam.position", [0.0, 1.6, 6.0])
    scene.set("cam.orientation", _looking_at([0.0, 1.6, 6.0], [0.0, 0.5, 0.0]))
    return scene
