"""A scene of the animation model as glTF: its objects, cameras and lights as nodes,
their position, orientation and scale tracks as animation channels (written by
:func:`~sketchanim.formats.gltf_tracks.tracks_glb`).

Conventions (three.js's, which the studio draws with): scene units are metres, a camera
looks down its local -Z with +Y up and ``fov`` is its vertical field of view in degrees;
a light is a KHR_lights_punctual spot light shining down its local -Z. Plain objects carry
a small octahedron so a viewer shows them.

A chain or walker is baked (:mod:`~sketchanim.export.rig_bake`): a group node named for
it, its joints under it with their curves within its goal's tolerance in the world, a
skinned bone mesh, and its goal as a node of its own, ``<object>.goal``, with the goal's
track.

Core glTF animates only translation, rotation and scale. The other tracks (colour,
intensity, field of view, visibility, events, custom attributes) are not written; their
values at the scene's current state are, where glTF has a place for them, and
:func:`scene_glb` lists the tracks it left out.

What a client plays is the written keys and key times in float32, computed in float32.
For a track of one take (recorded in ``replace`` mode), :func:`written_curve` keeps that
within the track's tolerance of every sample of the take: the curve may use only
:func:`~sketchanim.float32.position_budget` (or ``rotation_budget``) of the
tolerance, float32's share left out, as clip exports do; a tolerance float32 would take
more than half of is refused (:func:`take_budget`). A track whose curve already
is within the budget is written as it is; one the recorder's streaming reducer ran closer
to the tolerance is reduced again from its take, for the file only (the project keeps its
curve). An orientation's unit-quaternion keys (glTF requires them) are checked against
the take's samples within the same budget, knots inserted where one would miss. Tracks
of layered takes (punch-ins, additive takes) or without takes are written as their
curves, orientations' keys within ``KEY_SHARE`` of their own curve: there float32 may
add its rounding (about 1e-6 of the values' size) to the curve's error.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pygltflib as gl
from scipy.interpolate import BSpline

from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.scene import RIGS, Scene
from sketchanim.anim.tracks import ContinuousTrack, Track, held_values
from sketchanim.errors import ArgumentError
from sketchanim.export.rig_bake import bake, rig_nodes
from sketchanim.float32 import position_budget, rotation_budget
from sketchanim.formats.gltf import Node, octahedron
from sketchanim.formats.gltf_frames import FRAME_SHARE, KEYS, allowance, frame_times
from sketchanim.formats.gltf_tracks import GLTF_PATHS, CurvePiece, ExportTrack, tracks_glb
from sketchanim.motion.rotations import unit_keys
from sketchanim.reducer.metric import max_errors

#: Of an orientation track's tolerance, what making its keys unit quaternions may use.
KEY_SHARE = 0.1

#: Frames per second of ``keys="frames"`` for a track without takes, when no rate is given.
FRAME_RATE = 30.0

#: Size of a plain object's octahedron, scene units.
OBJECT_RADIUS = 0.1

#: Near clipping plane of exported cameras, scene units.
ZNEAR = 0.01

#: Cone of exported spot lights, radians (KHR_lights_punctual's default outer angle).
SPOT_OUTER = np.pi / 4


#: The attributes whose tracks a scene file writes: an object's transform; a rig's goal
#: (its own node) and base (baked into its joints).
_WRITTEN = {False: set(GLTF_PATHS), True: {"goal", "position"}}


def rotation_keys(track: ContinuousTrack) -> BSpline:
    """An orientation track's curve with unit-quaternion keys (as glTF requires),
    within ``KEY_SHARE`` of the track's tolerance of its own curve at every time it was
    sampled (its takes' times; without takes, eight times per knot span).

    >>> from sketchanim.anim.attributes import ORIENTATION
    >>> from scipy.spatial.transform import Rotation
    >>> from sketchanim.motion import reduce_rotations
    >>> t = np.linspace(0, 2, 121)
    >>> r = reduce_rotations(t, Rotation.from_rotvec(np.c_[np.sin(3 * t), t, 0 * t]).as_quat(), 0.5)
    >>> s = rotation_keys(ContinuousTrack("cam.orientation", ORIENTATION, r.columns, 0.5))
    >>> bool(np.allclose(np.linalg.norm(s(np.unique(s.t)), axis=1), 1.0))
    True
    """
    spline = track.spline
    times = np.unique(np.concatenate([t.times for t in track.takes])) if track.takes else np.array([])
    times = times[(times >= track.start) & (times <= track.end)]
    if not times.size:
        breaks = np.unique(spline.t)
        times = np.unique(np.concatenate([np.linspace(a, b, 9) for a, b in zip(breaks[:-1], breaks[1:])]))
    fixed, _ = unit_keys(spline, times, track.evaluate(times), np.radians(KEY_SHARE * track.tol))
    return fixed


def take_budget(track: ContinuousTrack, times: np.ndarray, values: np.ndarray) -> float:
    """What the file may use of a track's tolerance at its take's samples ``values`` at
    ``times``: :func:`~sketchanim.float32.position_budget`, or for an orientation
    :func:`~sketchanim.float32.rotation_budget` in degrees.

    Parameters
    ----------
    track : ContinuousTrack
        The track, its tolerance ``tol`` (degrees for an orientation).
    times, values : numpy.ndarray
        Its take's samples inside its span.

    Returns
    -------
    float
        The budget, in the tolerance's units.

    Raises
    ------
    ArgumentError
        Naming ``tolerance`` and the track, where float32 may move the track by more
        than half of its tolerance (a fine tolerance, values far from the origin, late
        times).

    Examples
    --------
    >>> from sketchanim.anim.attributes import POSITION
    >>> t = np.linspace(0, 1, 31)
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 0, 0]]), 1)
    >>> x = np.c_[t, 0 * t, 1000 + 0 * t]
    >>> bool(0.004 < take_budget(ContinuousTrack("a.position", POSITION, s, 0.005), t, x) < 0.005)  # 1 km out
    True
    >>> take_budget(ContinuousTrack("a.position", POSITION, s, 1e-4), t, x)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: tolerance: 0.0001 for track 'a.position' is less than twice what float32 ...
    """
    subject = f"for track {track.path!r}"
    if track.type.is_rotation:
        return rotation_budget(times, values, track.tol, field="tolerance", subject=subject)
    return position_budget(times, values, track.tol, field="tolerance", subject=subject)


def written_curve(track: ContinuousTrack) -> BSpline:
    """The curve :func:`scene_glb` writes for a track: for one ``replace`` take, within
    the float32 budget of the track's tolerance (:func:`take_budget`: ``position_budget``
    per axis, ``rotation_budget`` in degrees) of every sample of the take inside the track's span,
    reduced again from the take where the track's curve is not, orientations with unit
    keys (:func:`~sketchanim.motion.rotations.unit_keys`, checked against the take); for
    other tracks, the track's curve (orientations by :func:`rotation_keys`).

    >>> from sketchanim.anim.attributes import POSITION
    >>> from sketchanim.anim.tracks import Take
    >>> t = np.linspace(0, 1, 31)
    >>> x = np.c_[t, 0 * t, 1000 + 0 * t]
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 1000], [1.0, 0, 1000]]), 1)
    >>> take = Take(t, x + [0, 0.005, 0])                         # the curve at the tolerance
    >>> w = written_curve(ContinuousTrack("a.position", POSITION, s, 0.005, (take,)))
    >>> bool(np.abs(w(t) - take.values).max() <= position_budget(t, take.values, 0.005) < 0.005)
    True
    """
    if len(track.takes) != 1 or track.takes[0].mode != "replace":
        return rotation_keys(track) if track.type.is_rotation else track.spline
    take = track.takes[0]
    inside = (take.times >= track.start) & (take.times <= track.end)
    t, x = take.times[inside], take.values[inside]
    rotation = track.type.is_rotation
    budget = take_budget(track, t, x)
    error = max_errors(track.evaluate(t), x, 1.0 if rotation else 0.0).max()
    spline = track.spline
    if (np.degrees(error) if rotation else error) > budget:
        spline = reduce_samples(track.type, t, x, budget, track.spline.k + 1, "global")
    return unit_keys(spline, t, x, np.radians(budget))[0] if rotation else spline


def _rest(scene: Scene, name: str, attribute: str) -> list[float] | None:
    obj = scene.objects[name]
    return np.asarray(scene.get(f"{name}.{attribute}"), dtype=float).tolist() if attribute in obj.attributes else None


def frame_allowance(track: ContinuousTrack, spline: BSpline | None = None) -> float:
    """What dropping frame keys may add to a track (a distance, or radians): for a track
    of one take, what its float32 budget (:func:`written_curve`'s) leaves over the error
    of ``spline`` (by default the track's curve) at the take's samples (at most
    ``FRAME_SHARE`` of it), so the keys stay within the tolerance of the take; over
    layered takes, ``FRAME_SHARE`` of the tolerance.

    >>> from sketchanim.anim.attributes import POSITION
    >>> from sketchanim.anim.tracks import Take
    >>> t = np.linspace(0, 1, 11)
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 0, 0]]), 1)
    >>> take = Take(t, np.c_[t + 0.004, 0 * t, 0 * t])
    >>> round(frame_allowance(ContinuousTrack("a.position", POSITION, s, 0.005, (take,))), 5)
    0.0005
    """
    rotation = track.type.is_rotation
    tol = float(np.radians(track.tol)) if rotation else float(track.tol)
    if len(track.takes) != 1:
        return FRAME_SHARE * tol
    take = track.takes[0]
    inside = (take.times >= track.start) & (take.times <= track.end)
    t, x = take.times[inside], take.values[inside]
    curve = held_values(track.spline if spline is None else spline, t, rotation)
    error = float(max_errors(curve, x, 1.0 if rotation else 0.0).max())
    budget = float(np.radians(take_budget(track, t, x))) if rotation else take_budget(track, t, x)
    return allowance(budget, error)


def track_times(track: ContinuousTrack, rate: float | None = None) -> np.ndarray:
    """Where a track was sampled: its takes' times inside its span; or ``rate`` per
    second over its span (also where it has no takes: ``FRAME_RATE``).

    >>> from sketchanim.anim.attributes import POSITION
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> track_times(ContinuousTrack("a.position", POSITION, s, 0.005), 4).tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    times = np.unique(np.concatenate([t.times for t in track.takes])) if track.takes and rate is None else []
    times = times[(times >= track.start) & (times <= track.end)] if len(times) else times
    return times if len(times) else frame_times(track.start, track.end, rate or FRAME_RATE)


def scene_glb(scene: Scene, tracks: dict[str, Track], *, name: str = "scene", keys: str = "curves",
              rate: float | None = None) -> tuple[bytes, list[str]]:
    """The scene as a .glb: one node per object in space (its current position, orientation and
    scale at rest; a cue object has none), a perspective camera for each camera, a spot light for each light,
    and one animation of every position, orientation and scale track
    (:func:`export_track`: its curve, written by :func:`written_curve` to play in
    float32 within the tolerance of its take; or with ``keys="frames"``, LINEAR keys at
    :func:`track_times`, dropping those within :func:`frame_allowance`). Also returns
    the paths of the tracks glTF cannot animate, which are left out.

    Raises
    ------
    ArgumentError
        Naming ``keys`` (not a choice), or ``tolerance`` and a track whose tolerance
        float32 would take more than half of (:func:`take_budget`): no file keeps it.

    >>> from sketchanim.anim.attributes import POSITION
    >>> scene = Scene(); _ = scene.add("cam", "camera"); _ = scene.add("lamp", "light")
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> glb, left_out = scene_glb(scene, {"cam.position": ContinuousTrack("cam.position", POSITION, s, 0.005)})
    >>> doc = gl.GLTF2.load_from_bytes(glb)
    >>> [n.name for n in doc.nodes], bool(doc.cameras[0].perspective.yfov == np.radians(50)), left_out
    (['cam', 'lamp'], True, [])
    """
    if keys not in KEYS:
        raise ArgumentError("keys", f"one of {', '.join(KEYS)}, got {keys!r}")
    nodes, cameras, lights, meshes, skins, rigged = [], [], [], [], [], []
    octahedron_at = None
    for obj in scene.objects.values():
        if obj.kind in RIGS:
            made = rig_nodes(bake(scene, tracks, obj.name), len(nodes), rate)
            made.nodes[-1].mesh, made.nodes[-1].skin = len(meshes), len(skins)
            nodes += made.nodes
            meshes.append(made.mesh)
            skins.append(made.skin)
            rigged += made.tracks
            nodes.append(Node(f"{obj.name}.goal", translation=_rest(scene, obj.name, "goal")))
            goal = tracks.get(f"{obj.name}.goal")
            if isinstance(goal, ContinuousTrack):
                rigged.append(export_track(replace(goal, path=f"{obj.name}.goal.position"), rate))
            continue
        if "position" not in obj.attributes:          # a cue object: events, no place in space (left out)
            continue
        node = Node(obj.name, translation=_rest(scene, obj.name, "position"),
                    rotation=_rest(scene, obj.name, "orientation"), scale=_rest(scene, obj.name, "scale"))
        if obj.kind == "camera":
            node.camera = len(cameras)
            cameras.append(gl.Camera(name=obj.name, type="perspective", perspective=gl.Perspective(
                yfov=float(np.radians(scene.get(f"{obj.name}.fov")[0])), znear=ZNEAR)))
        elif obj.kind == "light":
            node.light = len(lights)
            on = bool(scene.get(f"{obj.name}.on"))
            lights.append({"name": obj.name, "type": "spot", "color": _rest(scene, obj.name, "color"),
                           "intensity": float(scene.get(f"{obj.name}.intensity")[0]) if on else 0.0,
                           "spot": {"outerConeAngle": SPOT_OUTER}})
        else:
            if octahedron_at is None:
                octahedron_at = len(meshes)
                meshes.append(octahedron("object", OBJECT_RADIUS))
            node.mesh = octahedron_at
        nodes.append(node)
    skipped = left_out(scene, tracks)
    written = [export_track(track, rate) for path, track in sorted(tracks.items())
               if path not in skipped and scene.objects[path.split(".")[0]].kind not in RIGS]
    return tracks_glb(nodes, written + rigged, name=name, keys=keys, meshes=meshes, skins=skins, cameras=cameras,
                      lights=lights), skipped


def left_out(scene: Scene, tracks: dict[str, Track]) -> list[str]:
    """The paths of the tracks a scene file leaves out, sorted: all but the position,
    orientation and scale tracks of the scene's objects (what glTF and USD transforms
    animate), and a rig's goal and base (its pose is baked from them).

    >>> from sketchanim.anim.attributes import BOOL
    >>> from sketchanim.anim.tracks import DiscreteTrack
    >>> scene = Scene(); _ = scene.add("box")
    >>> left_out(scene, {"box.visible": DiscreteTrack("box.visible", BOOL, [0.0], [False])})
    ['box.visible']
    """
    return sorted(path for path, track in tracks.items()
                  if not isinstance(track, ContinuousTrack) or path.split(".")[0] not in scene.objects
                  or path.split(".")[1] not in _WRITTEN[scene.objects[path.split(".")[0]].kind in RIGS])


def export_track(track: ContinuousTrack, rate: float | None = None) -> ExportTrack:
    """A position, orientation or scale track as the writer takes it: its
    :func:`written_curve`, keyed with ``keys="frames"`` at :func:`track_times`,
    dropping keys within :func:`frame_allowance`.

    >>> from sketchanim.anim.attributes import POSITION
    >>> s = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 2, 3]]), 1)
    >>> export_track(ContinuousTrack("a.position", POSITION, s, 0.005), 2).pieces[0].frames.tolist()
    [0.0, 0.5, 1.0]
    """
    spline = written_curve(track)
    return ExportTrack(track.path, (CurvePiece(track.start, track.end, spline, track_times(track, rate),
                                               frame_allowance(track, spline)),))
