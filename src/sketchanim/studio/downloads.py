"""The scene or the project as a download (``GET /api/export``), and the export
dialog's choices (``GET /api/export/choices``): each format, the file it makes, and
what each client plays from it, within which tolerance (the largest tolerance of the
tracks the file animates; docs/clients.md says what each promise rests on).

Every format goes through the writers ``sketchanim export`` uses: glTF (exact
CUBICSPLINE keys, LINEAR keys at the takes' samples: ``--keys frames``, or the fewest of
those quantised and compressed: ``--keys compact``), USD, BVH (the
skeletons of imported clips, :mod:`sketchanim.export.scene_bvh`), and the project as JSON. Nothing is written beside the project: a file that has to be written
to be made (USD) is made in a temporary folder.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
import unicodedata
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import quote

import numpy as np
from pydantic import BaseModel

from sketchanim.anim.rigs import rigs
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.errors import ArgumentError
from sketchanim.export.scene_bvh import skeletons
from sketchanim.export.scene_gltf import left_out


@dataclass(frozen=True)
class Format:
    """One export format: its title, its file's ending and media type, and what its
    clients play (client, ``"tol"`` for within the tracks' tolerances, else the words)."""

    title: str
    ending: str
    media_type: str
    clients: tuple[tuple[str, str], ...]


#: What the dialog offers, by the name ``GET /api/export?format=`` takes.
FORMATS = {
    "glb": Format("glTF binary, exact B-spline curves (CUBICSPLINE keys)", ".glb", "model/gltf-binary", (
        ("three.js, Babylon.js (the glTF spec's cubic spline)", "tol"),
        ("Blender, through blender/sketchanim_import.py", "tol"),
        ("Blender's own glTF importer", "not within: it drops the tangents and overshoots; use glTF frames"))),
    "glb-frames": Format("glTF binary, LINEAR keys at the takes' samples (frame keys)", ".frames.glb",
                         "model/gltf-binary", (
        ("Blender's own glTF importer, any importer that drops tangents", "tol"),
        ("three.js, Babylon.js", "tol"))),
    "glb-compact": Format("glTF binary, compact: the fewest LINEAR keys, quantised and meshopt-compressed",
                          ".compact.glb", "model/gltf-binary", (
        ("three.js with its MeshoptDecoder, Babylon.js, any reader of EXT_meshopt_compression", "tol"),
        ("Blender, through blender/sketchanim_import.py (with the meshopt package)", "tol"),
        ("Blender's own glTF importer", "not at all: it cannot read EXT_meshopt_compression; use glTF frames"))),
    "usd": Format("USD, the curves as double-precision samples at the takes' times", ".usd",
                  "application/octet-stream", (
        ("usd-core, Omniverse: at every recorded sample (straight lines between)", "tol"),)),
    "bvh": Format("BVH, the imported skeletons as joint hierarchies at the project's frame rate", ".bvh",
                  "application/octet-stream", (
        ("Blender's BVH importer, MotionBuilder, any BVH reader",
         "at each frame: the joints' orientations as the scene's, positions over each bone's median length "
         "(its own where it moves)"),)),
    "json": Format("The whole project as JSON (curves, takes, tolerances)", ".json", "application/json", (
        ("sketchanim (sketchanim export, the studio's /api/project)", "exact: the float64 curves and raw takes"),)),
}


class ClientPlay(BaseModel):
    """What one client plays from an export."""

    client: str
    plays: str


class ExportChoice(BaseModel):
    """One choice of the export dialog."""

    format: str
    title: str
    file: str
    clients: list[ClientPlay]
    #: tracks the file leaves out (a scene file animates transforms only; BVH the skeletons only)
    left_out: list[str]


class ExportChoices(BaseModel):
    """``GET /api/export/choices``'s answer."""

    choices: list[ExportChoice]


def check_format(name: str) -> Format:
    """The format called ``name``, or an :class:`ArgumentError` naming the choices.

    >>> check_format("glb").ending
    '.glb'
    >>> check_format("fbx")
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: format: 'fbx' is not an export format; one of glb, glb-frames, glb-compact, usd, bvh, json
    """
    if name not in FORMATS:
        raise ArgumentError("format", f"{name!r} is not an export format; one of {', '.join(FORMATS)}")
    return FORMATS[name]


def within(tracks: dict[str, Track], scene: Scene) -> str:
    """The tolerances a scene file's clients play its animated tracks within: the
    largest of each kind (positions in mm, orientations in degrees, scales).

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import POSITION
    >>> scene = Scene(); _ = scene.add("box")
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> within({"box.position": ContinuousTrack("box.position", POSITION, s, 0.003)}, scene)
    'within 3 mm'
    >>> within({}, scene)
    'exact: nothing is animated, the current values are written'
    >>> _ = scene.add("arm", "chain")
    >>> within({"arm.goal": ContinuousTrack("arm.goal", POSITION, s, 0.005)}, scene)
    'within 5 mm'
    """
    skipped = set(left_out(scene, tracks))
    tols: dict[str, float] = {}
    for path, track in tracks.items():
        if path not in skipped and isinstance(track, ContinuousTrack):
            kind = path.split(".")[1]
            kind = "position" if kind == "goal" else kind          # a rig's figure keeps its goal's distance
            tols[kind] = max(tols.get(kind, 0.0), float(track.tol))
    if not tols:
        return "exact: nothing is animated, the current values are written"
    words = {"position": lambda v: f"{v * 1000:.3g} mm", "orientation": lambda v: f"{v:.3g}°",
             "scale": lambda v: f"{v:.3g} in scale"}
    return "within " + ", ".join(words[k](tols[k]) for k in ("position", "orientation", "scale") if k in tols)


def file_name(project: Path, fmt: Format) -> str:
    """The download's file name: the project's stem and the format's ending.

    >>> file_name(Path("/a/show.sketchanim"), FORMATS["glb-frames"])
    'show.frames.glb'
    """
    return project.stem + fmt.ending


def disposition(name: str) -> str:
    """A ``Content-Disposition`` header downloading as ``name`` (its ASCII form in
    ``filename``, the name itself, UTF-8, in ``filename*``).

    >>> disposition('séance "1".glb')
    'attachment; filename="seance _1_.glb"; filename*=UTF-8\\'\\'s%C3%A9ance%20%221%22.glb'
    """
    plain = unicodedata.normalize("NFKD", name).encode("ascii", "ignore").decode()
    plain = "".join(c if c.isprintable() and c not in '"\\' else "_" for c in plain) or "export"
    return f"attachment; filename=\"{plain}\"; filename*=UTF-8''{quote(name)}"


def choices(project: Path, scene: Scene, tracks: dict[str, Track]) -> ExportChoices:
    """Every format the dialog offers for this scene (BVH where it has a skeleton: an
    imported clip's joints, a chain, a walker), with what each client plays.

    >>> scene = Scene(); _ = scene.add("box")
    >>> c = choices(Path("show.sketchanim"), scene, {}).choices
    >>> [x.format for x in c], c[0].file, c[0].clients[0].plays
    (['glb', 'glb-frames', 'glb-compact', 'usd', 'json'], 'show.glb', 'exact: nothing is animated, the current values are written')
    """
    tol = within(tracks, scene)
    skipped = left_out(scene, tracks)
    joints = {name for skeleton in skeletons(scene) for name in skeleton}
    rigged = set(rigs(scene))
    outside = sorted(p for p in tracks if not (p.split(".")[0] in joints and p.split(".")[1] in ("position", "orientation")
                                              or p.split(".")[0] in rigged and p.split(".")[1] in ("position", "goal")))
    return ExportChoices(choices=[
        ExportChoice(format=name, title=fmt.title, file=file_name(project, fmt),
                     clients=[ClientPlay(client=c, plays=tol if plays == "tol" else plays) for c, plays in fmt.clients],
                     left_out=[] if name == "json" else outside if name == "bvh" else skipped)
        for name, fmt in FORMATS.items() if name != "bvh" or joints or rigged])


def build(name: str, project: Path, scene: Scene, tracks: dict[str, Track], fps: float,
          document: Callable[[], bytes]) -> bytes:
    """The export ``name`` (a key of :data:`FORMATS`) of the scene, or what ``document``
    makes (the project as JSON) for ``json``; :class:`ArgumentError` for an unknown format, an
    :class:`~sketchanim.errors.InputError` when USD's library is missing.

    >>> scene = Scene(); _ = scene.add("box")
    >>> build("glb", Path("show.sketchanim"), scene, {}, 30.0, lambda: b"{}")[:4]
    b'glTF'
    """
    from sketchanim.export.scene_bvh import skeleton_clip
    from sketchanim.export.scene_gltf import scene_glb
    from sketchanim.export.scene_usd import scene_usd
    from sketchanim.formats.bvh import bvh_text

    fmt = check_format(name)
    if name == "json":
        return document()
    if name == "bvh":
        return bvh_text(skeleton_clip(scene, tracks, fps)).encode()
    if name == "usd":
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / file_name(project, fmt)
            scene_usd(out, scene, tracks, fps)
            return out.read_bytes()
    keys = {"glb-frames": "frames", "glb-compact": "compact"}.get(name, "curves")
    return scene_glb(scene, tracks, name=project.stem, keys=keys)[0]
