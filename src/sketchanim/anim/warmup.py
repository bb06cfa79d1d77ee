"""Compile the numba kernels once, ahead of use: ``python -m sketchanim.anim.warmup``.

The kernels (input checks, pause and break detection, the incremental method's windows,
the player's evaluation) compile on first use, about 20 s on a fresh machine, and are
then cached beside their modules (``__pycache__``, ``cache=True``). ``scripts/setup``
runs this, so the first reduction, recording or playback a user starts runs at the
cached speed. Running it again only loads the cache.
"""

from __future__ import annotations

import time

import numpy as np

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.player import Player
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.motion import reduce_rotations
from sketchanim.reducer import reduce


def warm_up() -> float:
    """Run every compiled path on a small take (both methods, with a pause and a break;
    an orientation; one playback step); the seconds it took.

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
    scene = Scene()
    scene.add("box")
    spline = r.columns
    track = ContinuousTrack("box.position", POSITION, type(spline)(spline.t, np.c_[spline.c, spline.c[:, :1]],
                                                                   spline.k), 1e-3)
    player = Player(scene, [track])
    player.seek(1.0)
    player.apply()
    return time.perf_counter() - clock


if __name__ == "__main__":
    print(f"sketchanim: compiled kernels ready ({warm_up():.1f} s)")
