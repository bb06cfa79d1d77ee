"""Warming the compiled kernels before the studio says it is ready.

The reducer's kernels are compiled with numba on first use (about 30 s, then cached in
``__pycache__``); the reducer processes are forked on first use. :func:`warm_model` runs
a throwaway take through the real recorder (a fresh take and a punch-in over it, a
position and an orientation) and plays it, so the first take of the animator is as
quick as the tenth.
"""

from __future__ import annotations

import numpy as np

from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene


def warm_model() -> float:
    """Run the throwaway takes; the seconds it took.

    >>> warm_model() >= 0
    True
    """
    import time

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
