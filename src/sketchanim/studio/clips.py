"""Motion clips into the scene from the page (``POST /api/clips?name=FILE.bvh`` or
``FILE.c3d``): the upload checked (its type by name, its size), read by the format's reader
(whose errors name the line and field, here under the uploaded file's name), its joints
made objects with world position and orientation tracks, or its markers objects with world
position tracks (:mod:`sketchanim.mocap.scene_clip`), added as one History step.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydantic import BaseModel

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.commands import Change
from sketchanim.anim.player import Player
from sketchanim.anim.scene import BONE_PARENT, SceneObject
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.errors import ArgumentError, InputError
from sketchanim.formats.clip_files import read_clip
from sketchanim.mocap.markers import Markers
from sketchanim.mocap.scene_clip import joint_tracks, marker_tracks, object_names, renamed
from sketchanim.motion.skeleton import Clip
from sketchanim.studio.defaults import new_object

#: Largest upload taken, bytes (a 10 min, 120 Hz, 60-joint BVH is about 60 MB).
MAX_CLIP_BYTES = 64 * 2**20
#: What the page may upload as a clip.
CLIP_UPLOADS = (".bvh", ".c3d")
#: The names a page may give an ASF/AMC pair's files.
AMC_PATTERN = r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,100}\.amc$"
ASF_PATTERN = r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,100}\.asf$"
#: The names a page may give an upload (as the OpenAPI spec says; anything else is
#: checked and refused with its reason).
NAME_PATTERN = r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,100}\.(bvh|c3d)$"
#: A joint sphere's scale (the page's sphere has a 0.45 m radius at scale 1: here 4.5 cm).
JOINT_SCALE = 0.1


class ClipImported(BaseModel):
    """``POST /api/clips``'s answer: the objects made (one per joint), their tracks, and
    the clip's frames and seconds."""

    objects: list[str]
    tracks: int
    frames: int
    seconds: float


class TooLarge(ArgumentError):
    """An upload over :data:`MAX_CLIP_BYTES`."""


def check_upload(name: str, size: int | None, kinds: tuple[str, ...] = CLIP_UPLOADS) -> None:
    """Refuse an upload by its name (one of ``kinds``) or its size (``size`` bytes, if known).

    >>> check_upload("walk.bvh", 1000)
    >>> check_upload("walk.mp3", 1000)
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: name: 'walk.mp3': a clip upload is a .bvh or a .c3d file
    """
    if Path(name).suffix.lower() not in kinds:
        raise ArgumentError("name", f"{name!r}: a clip upload is {' or '.join('a ' + s for s in kinds)} file")
    if size is not None and size > MAX_CLIP_BYTES:
        raise TooLarge("name", f"{name!r}: {size / 2**20:.1f} MB; a clip upload is at most {MAX_CLIP_BYTES // 2**20} MB")


def read_upload(name: str, data: bytes, skeleton: tuple[str, bytes] | None = None) -> Clip | Markers:
    """The clip (a .bvh; a .amc with its ``skeleton``, the .asf's name and bytes) or
    markers (a .c3d) in an upload named ``name``; the reader's error (naming the line and
    field) under the uploaded file's name, never the temporary file's.

    >>> read_upload("x.bvh", b"HIERARCHY\\nROOT")
    Traceback (most recent call last):
    ...
    sketchanim.errors.FileFormatError: x.bvh: no MOTION section
    """
    check_upload(name, len(data), (".amc",) if skeleton else CLIP_UPLOADS)
    if skeleton:
        check_upload(skeleton[0], len(skeleton[1]), (".asf",))
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp) / f"upload{Path(name).suffix.lower()}"
        scratch.write_bytes(data)
        sources = {str(scratch): name}
        if skeleton:
            asf = Path(tmp) / "upload.asf"
            asf.write_bytes(skeleton[1])
            sources[str(asf)] = skeleton[0]
        try:
            return read_clip(scratch, skeleton=asf if skeleton else None)
        except InputError as err:
            for path, shown in sources.items():
                err.args = tuple(str(a).replace(path, shown) for a in err.args)
            raise


class AmcUpload(BaseModel):
    """``POST /api/clips/amc``'s body: an ASF skeleton's text and an AMC motion's text."""

    skeleton: str
    motion: str


@dataclass(frozen=True)
class SceneClip:
    """An upload as the scene takes it: tracks by joint or marker name (their attributes'
    tracks by attribute), each one's parent (index; -1: none), and the frames' times."""

    tracks: dict[str, dict[str, Track]]
    parents: tuple[int, ...]
    times: np.ndarray


def scene_clip(upload: Clip | Markers) -> SceneClip:
    """A clip's joints (parented as its skeleton is) or markers (none parented) as tracks
    (:func:`~sketchanim.mocap.scene_clip.joint_tracks`, :func:`~sketchanim.mocap.scene_clip.marker_tracks`).

    >>> p = np.zeros((30, 1, 3))
    >>> made = scene_clip(Markers(("toe",), np.arange(30) / 30, p))
    >>> list(made.tracks), made.parents
    (['toe'], (-1,))
    """
    if isinstance(upload, Markers):
        tracks = marker_tracks(upload)
        return SceneClip(tracks, (-1,) * len(tracks), upload.times)
    return SceneClip(dict(joint_tracks(upload)), upload.skeleton.parents, upload.times)


def joint_object(name: str, track: Track, parent: str | None = None) -> SceneObject:
    """A joint's (or marker's) object: a small sphere where its position track starts; a joint with a
    parent joint carries it as its ``parent`` attribute (an enum of that one object's
    name: the page draws a bone between the two; it persists and undoes with the object).

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import POSITION
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 1, 0], [1.0, 1, 0]]), 1)
    >>> obj = joint_object("walk_knee", ContinuousTrack("knee.position", POSITION, s, 0.005), "walk_hips")
    >>> obj.attributes["shape"].value, obj.attributes["parent"].value
    ('sphere', 'walk_hips')
    """
    obj = new_object(name, "object")
    obj.attributes["shape"].value = "sphere"
    if parent is not None:
        obj.add(BONE_PARENT, AttributeType.enum([parent]), parent)
    obj.attributes["scale"].value = np.full(3, JOINT_SCALE)
    if not isinstance(track, ContinuousTrack):
        raise ArgumentError("position", f"{name}: a position track is a continuous one")
    obj.attributes["position"].value = np.asarray(track.evaluate([track.start])[0], dtype=float)
    return obj


def clip_change(player: Player, prefix: str, joints: dict[str, dict[str, Track]],
                parents: tuple[int, ...], label: str) -> tuple[Change, list[str]]:
    """One History step adding a clip's joints or markers (:func:`scene_clip`)
    as objects named ``<prefix>_<joint>`` (numbered where taken), with their tracks, each
    joint's parent (``parents``: the index of each joint's, -1 for none) named by its
    ``parent`` attribute; and the objects' names.

    >>> from sketchanim.anim.scene import Scene
    >>> from sketchanim.mocap.scene_clip import joint_tracks
    >>> from sketchanim.motion.skeleton import Skeleton
    >>> clip = Clip.still(Skeleton(("hips",), (-1,), np.zeros((1, 3))), np.arange(30) / 30)
    >>> player = Player(Scene())
    >>> change, names = clip_change(player, "walk", joint_tracks(clip), (-1,), "import walk.bvh")
    >>> change.do(); names, sorted(player.tracks)
    (['walk_hips'], ['walk_hips.orientation', 'walk_hips.position'])
    """
    scene = player.scene
    names = object_names(prefix, tuple(joints), set(scene.objects))
    if len(parents) != len(names):
        raise ArgumentError("parents", f"{len(parents)} parents for {len(names)} joints")
    objects = [joint_object(n, joints[j]["position"], names[up] if up >= 0 else None)
               for n, j, up in zip(names, joints, parents)]
    tracks: dict[str, Track | None] = {t.path: t for n, j in zip(names, joints)
                                       for t in (renamed(track, n) for track in joints[j].values())}
    changes = tuple((lambda o=o: scene.insert(o), lambda o=o: scene.remove(o.name)) for o in objects)
    return Change(player, label, tracks, changes), names
