"""Warming the compiled kernels ahead of use: ``python -m sketchanim.anim.warmup``.

The kernels (input checks, pause and break detection, the incremental method's windows,
the player's evaluation, forward kinematics down a skeleton, rotation angles and LINEAR
rotation keys as clients play them) compile on first use, about
20 s on a fresh machine, and are then cached beside their modules (``__pycache__``,
``cache=True``). ``scripts/setup``
runs :func:`warm_up`, so the first reduction, recording or playback a user starts runs
at the cached speed; running it again only loads the cache. The studio runs
:func:`warm_recorder` before it says it is ready: the reducer processes forked and their
kernels loaded, so the animator's first take is as quick as the tenth.
"""

from __future__ import annotations

import time

import numpy as np

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.motion import reduce_rotations
from sketchanim.motion.kinematics import world_matrices
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.reducer import reduce
from sketchanim.reducer.linear_keys import linear_keys


def warm_up() -> float:
    """Run every compiled path on a small take (both methods, with a pause and a break;
    an orientation, and its LINEAR keys; one playback step; a skeleton's forward
    kinematics); the seconds it took.

    >>> warm_up() >= 0
    True
    """
    clock = time.perf_counter()
    t = np.arange(0, 3, 1 / 120)
    x = np.c_[np.where(t < 1, np.abs(t - 0.5), 0.5), np.sin(t)]       # a break, then a pause
    for method in ("global", "incremental"):
        r = reduce(t, x, 1e-3, method=method)
    q = np.c_[np.sin(t / 4), 0 * t, 0 * t, np.cos(t / 4)]
    for method in ("global", "incremental"):
        reduce_rotations(t, q, 0.5, method=method)
    linear_keys(t, q[None], np.radians(0.5), rotation=True)
    scene = Scene()
    scene.add("box")
    spline = r.columns
    track = ContinuousTrack("box.position", POSITION, type(spline)(spline.t, np.c_[spline.c, spline.c[:, :1]],
                                                                   spline.k), 1e-3)
    player = Player(scene, [track])
    player.seek(1.0)
    player.apply()
    still = Clip.still(Skeleton(("hips", "knee"), (-1, 0), np.eye(2, 3)), t[:2])
    world_matrices(still.skeleton, still.rotations, still.translations)
    return time.perf_counter() - clock


def warm_recorder() -> float:
    """Run throwaway takes through the real recorder (a fresh take and a punch-in over
    it, a position and an orientation) and play them; the seconds it took.

    >>> warm_recorder() >= 0
    True
    """
    clock = time.perf_counter()
    scene = Scene()
    scene.add("box")
    tracks: dict = {}
    t = np.arange(180) / 60.0
    for start in (0.0, 1.0):                                # a fresh take, then a punch-in over it
        rec = Recorder(scene)
        rec.arm("box.position")
        rec.arm("box.orientation")
        rec.start(tracks)
        half = t[t >= start] / 2
        for ti, h in zip(t[t >= start], half):
            rec.push_frame(ti, [np.sin(ti), 0.5, ti, 0.0, np.sin(h), 0.0, np.cos(h)])
        tracks.update(rec.stop())
    player = Player(scene, tracks.values())
    player.seek(1.0)
    player.apply()
    return time.perf_counter() - clock


if __name__ == "__main__":
    print(f"sketchanim: compiled kernels ready ({warm_up():.1f} s)")
