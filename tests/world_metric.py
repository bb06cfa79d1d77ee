"""A clip file's error in the world, measured the same way on every file (ours and the web
compressors'): three.js plays the .glb (:func:`threejs_client.three_play_world`, its meshopt
decoder on) at every source frame, and each joint's world transform is compared with the
source's (:func:`sketchanim.motion.kinematics.world_pose`), in metres.

Two numbers, the largest over frames and joints, in centimetres:

- ``joint_cm``: the distance of each joint's world position;
- ``point_cm``: the Animation Compression Library's metric, the distance of the points
  :data:`SHELL_M` from each joint along each of its local axes (x, y, z), which sees a
  joint's rotation error too (an end joint's included).

Nodes are matched with joints by name; the world includes every node above them (our files'
``to metres`` root, whatever a compressor made of it), so a file in any layout is measured
against the same source world, scaled to metres by the clip's unit.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.mocap.contacts import planted_steps
from sketchanim.motion.kinematics import world_pose
from sketchanim.motion.skeleton import Clip
from threejs_client import three_play_world

#: ACL's virtual vertex distance: a point this far (metres) from each joint on each local axis.
SHELL_M = 0.03


@dataclass(frozen=True)
class WorldError:
    """Largest world errors of a played file against its source clip, centimetres:
    ``joint_cm`` of the joints' positions, ``point_cm`` of the points :data:`SHELL_M` from
    each joint along its local axes (ACL's metric)."""

    joint_cm: float
    point_cm: float


def clip_unit_m(clip: Clip) -> float:
    """Metres per clip unit (the clip's own or guessed unit; metres when neither)."""
    return clip.guess_unit_m() or 1.0


def source_world(clip: Clip) -> tuple[np.ndarray, np.ndarray]:
    """The source's world quaternions (n, J, 4, scalar-last) and positions (n, J, 3,
    metres) at its frames."""
    turns, positions = world_pose(clip.skeleton, clip.rotations, clip.translations)
    return np.stack([r.as_quat() for r in turns], axis=1), positions * clip_unit_m(clip)


def shell_points(quaternions: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """The points :data:`SHELL_M` from each pose along its local x, y and z axes,
    (..., 3 axes, 3), metres, for world quaternions (..., 4) and positions (..., 3).

    >>> p = shell_points(np.array([[0.0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)]]), np.array([[1.0, 0, 0]]))
    >>> p.round(6).tolist()
    [[[1.0, 0.03, 0.0], [0.97, 0.0, 0.0], [1.0, 0.0, 0.03]]]
    """
    axes = Rotation.from_quat(quaternions.reshape(-1, 4)).as_matrix().reshape(*quaternions.shape[:-1], 3, 3)
    return positions[..., None, :] + SHELL_M * np.swapaxes(axes, -1, -2)   # rows: the rotated x, y, z axes


def world_error(clip: Clip, played: dict[str, dict[str, np.ndarray]], file_unit_m: float = 1.0) -> WorldError:
    """The world error of ``played`` (world ``position`` (n, 3) and ``quaternion`` (n, 4)
    per node name, at the clip's frames) against ``clip``; ``file_unit_m``: metres per unit
    of the file's world (1 for a file in metres, glTF's unit: ours when the clip's unit is
    set, under their ``to metres`` node).

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> clip = Clip.still(Skeleton(("hips", "head"), (-1, 0), np.array([[0.0, 1, 0], [0, 0.5, 0]])), [0.0, 0.1])
    >>> clip = Clip(clip.skeleton, clip.times, clip.rotations, clip.translations, clip.rotating, clip.translating,
    ...             clip.channels, unit_m=1.0)
    >>> q, p = source_world(clip)
    >>> played = {n: {"quaternion": q[:, j], "position": p[:, j] + [0.0, 0.002, 0]} for j, n in enumerate(("hips", "head"))}
    >>> e = world_error(clip, played)
    >>> round(e.joint_cm, 9), round(e.point_cm, 9)
    (0.2, 0.2)
    """
    names = clip.skeleton.names
    missing = [n for n in names if n not in played]
    if missing:
        raise ValueError(f"the played file has no node named {missing[0]!r} (joint of the clip; "
                         f"{len(missing)} of {len(names)} joints missing)")
    quaternions, positions = source_world(clip)
    got_q = np.stack([played[n]["quaternion"] for n in names], axis=1)
    got_p = np.stack([played[n]["position"] for n in names], axis=1) * file_unit_m
    joint = np.linalg.norm(got_p - positions, axis=-1).max()
    point = np.linalg.norm(shell_points(got_q, got_p) - shell_points(quaternions, positions), axis=-1).max()
    return WorldError(100 * float(joint), 100 * float(point))


def file_sliding(clip: Clip, glb: Path, held: np.ndarray, file_unit_m: float = 1.0) -> float:
    """How much the joints of ``clip`` planted at ``held`` (n, J) slide as three.js plays
    the .glb ``glb``, cm/s: their median speed over the steps
    :func:`sketchanim.mocap.contacts.sliding` measures (NaN where nothing is planted)."""
    at, first, joint = planted_steps(clip.times, held)
    if not len(first):
        return float("nan")
    played = three_play_world(glb, at)
    positions = np.stack([played[n]["position"] for n in clip.skeleton.names], axis=1) * file_unit_m
    speed = np.linalg.norm(positions[first + 1, joint] - positions[first, joint], axis=-1) / np.diff(at)[first]
    return 100 * float(np.median(speed))


def file_world_error(clip: Clip, glb: Path, file_unit_m: float = 1.0) -> WorldError:
    """The world error of the .glb ``glb`` as three.js plays it at the clip's frames
    (:func:`world_error`)."""
    return world_error(clip, three_play_world(glb, clip.times), file_unit_m)
