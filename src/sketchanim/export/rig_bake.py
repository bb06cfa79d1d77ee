"""Rigs baked for export: a chain's or walker's derived pose
(:func:`~sketchanim.anim.rigs.rig_clip`, at the solver's ticks) reduced to one curve per
joint within a distance in the world (:func:`~sketchanim.mocap.world_reduction.reduce_clip_world`:
every joint, and every point :data:`SHELL` from one, within the tolerance at every tick),
and laid out as glTF nodes: a group node named for the object, its joints under it named
``<object>.<joint>``, and a skinned bone mesh so a viewer shows the figure.

The tolerance is the goal's: the figure keeps the distance its goal was recorded within
(the goal track's tolerance, :data:`~sketchanim.anim.attributes.POSITION`'s without one);
a walker keeps :data:`WALKER_SHARE` of it, so its planted feet stay planted.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.rigs import rig_clip
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Track
from sketchanim.export.mocap_gltf import clip_export_tracks
from sketchanim.formats.gltf import Mesh, Node, Skin, bone_mesh
from sketchanim.formats.gltf_tracks import ExportTrack
from sketchanim.mocap.clip_reduction import ReducedClip
from sketchanim.mocap.world_reduction import reduce_clip_world
from sketchanim.motion.skeleton import Clip

#: Metres from each joint of a baked rig that the world tolerance also holds at (a point
#: its skin could carry), as the clip exporter's world mode keeps.
SHELL = 0.03

#: Of its goal's tolerance, what a walker is baked within. A planted toe's error wobbles at
#: the pace of the steps and reads as sliding: within the whole 5 mm, a planted toe of a
#: brisk walk slides 5 to 7 cm/s (median); within a fifth, about 1 cm/s, under the 2 cm/s a
#: walker promises (tests/export/test_rig_export.py measures it in the file).
WALKER_SHARE = 0.2

#: The reducer's method for a bake: the incremental one, about 10 times faster than the
#: global one on a walk for a quarter more bytes (benchmarks/bench_bake.py), since an
#: export from the studio waits on it.
METHOD = "incremental"

#: A bake's curves are cubic, as the studio's other tracks are: a rig's pose follows the
#: animator's smooth curves, and on the 10 s chain of ``benchmarks/bench_bake.py`` cubic
#: pieces take 56% of the bytes of straight ones (its walker 9% more). Motion capture,
#: whose noise a cubic cannot smooth, is reduced to straight pieces instead.
ORDER = 4


@dataclass(frozen=True)
class BakedRig:
    """A rig's pose and its curves.

    Attributes
    ----------
    name : str
        The object's.
    clip : Clip
        The pose at the solver's ticks, world space, metres.
    reduced : ReducedClip
        Its curves, every joint and shell point within ``tol`` of ``clip`` at every tick.
    tol : float
        Metres.
    """

    name: str
    clip: Clip
    reduced: ReducedClip
    tol: float

    def node_name(self, joint: str) -> str:
        """The file's name of ``joint``: ``<object>.<joint>``."""
        return f"{self.name}.{joint}"


def bake(scene: Scene, tracks: dict[str, Track], name: str, tol: float | None = None) -> BakedRig:
    """Bake the rig ``name`` within ``tol`` metres (the goal track's tolerance by default).

    >>> from scipy.interpolate import BSpline
    >>> scene = Scene(); _ = scene.add("arm", "chain")
    >>> reach = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.5, 1.1, 0], [0.3, 0.6, 0.4]]), 1)
    >>> baked = bake(scene, {"arm.goal": ContinuousTrack("arm.goal", POSITION, reach, 0.005)}, "arm")
    >>> bool(baked.reduced.world_errors(baked.clip, SHELL).max() <= 0.005)
    True
    """
    if tol is None:
        goal = tracks.get(f"{name}.goal")
        tol = float(goal.tol) if isinstance(goal, ContinuousTrack) else POSITION.tol
        if scene.objects[name].kind == "walker":
            tol *= WALKER_SHARE
    clip = rig_clip(scene, tracks, name)
    return BakedRig(name, clip, reduce_clip_world(clip, tol, SHELL, method=METHOD, order=ORDER), tol)


@dataclass(frozen=True)
class RigNodes:
    """What a baked rig adds to a glTF file: its nodes (parents as indices into the
    file's node list), its tracks, its bone mesh and that mesh's skin (joints as file
    node indices)."""

    nodes: list[Node]
    tracks: list[ExportTrack]
    mesh: Mesh
    skin: Skin


def rig_nodes(baked: BakedRig, first: int, rate: float | None = None) -> RigNodes:
    """``baked`` as glTF nodes numbered from ``first``: the object's group node (at the
    origin), its joints under it, and the bone mesh's node (the mesh and skin indices are
    the caller's: it sets them on ``nodes[-1]``). ``rate`` keys ``keys="frames"`` files
    (the ticks by default).

    >>> scene = Scene(); _ = scene.add("arm", "chain")
    >>> made = rig_nodes(bake(scene, {}, "arm"), 0)
    >>> [n.name for n in made.nodes][:3], made.nodes[2].parent, made.tracks[0].path
    (['arm', 'arm.j1', 'arm.j2'], 1, 'arm.j1.orientation')
    """
    sk = baked.clip.skeleton
    nodes = [Node(baked.name)]
    nodes += [Node(baked.node_name(n), first + (p + 1 if p >= 0 else 0), translation=o.tolist())
              for n, p, o in zip(sk.names, sk.parents, sk.offsets)]
    tracks = [replace(t, path=f"{baked.name}.{t.path}") for t in clip_export_tracks(baked.reduced, rate)]
    rest = sk.rest_positions()
    inverse = np.tile(np.eye(4), (len(sk), 1, 1))
    inverse[:, :3, 3] = -rest
    nodes.append(Node(baked.node_name("bones")))
    return RigNodes(nodes, tracks, bone_mesh(rest, sk.parents), Skin([first + 1 + j for j in range(len(sk))], inverse))
