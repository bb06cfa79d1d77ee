"""After the setup step's warm-up, a fresh process's first reduction, recording and
playback compile nothing: every numba kernel is loaded from its cache."""

from __future__ import annotations

import json
import subprocess
import sys

CHECK = """
import json, numpy as np
from numba.core.registry import CPUDispatcher
from sketchanim.anim import player
from sketchanim.anim.warmup import warm_up
from sketchanim.reducer import conditioning, features, window_kernel
warm_up()                                           # the first reduction of a fresh process
compiled = [f"{m.__name__}.{name}" for m in (player, conditioning, features, window_kernel)
            for name, f in vars(m).items() if isinstance(f, CPUDispatcher) and f.stats.cache_misses]
print(json.dumps(compiled))
"""


def test_first_reduction_after_setup_does_not_compile():
    subprocess.run([sys.executable, "-m", "sketchanim.anim.warmup"], check=True, capture_output=True)  # setup's step
    out = subprocess.run([sys.executable, "-c", CHECK], check=True, capture_output=True, text=True)
    assert json.loads(out.stdout.strip().splitlines()[-1]) == []
