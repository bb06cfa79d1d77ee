"""three.js as a client of our .glb files (scripts/play-gltf.mjs: GLTFLoader with three's
meshopt decoder and an AnimationMixer in node, three from npm, pinned by package-lock.json)."""

from __future__ import annotations

import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _play(glb: Path, times: np.ndarray, *flags: str) -> dict[str, dict[str, np.ndarray]]:
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "t.json").write_text(json.dumps(np.asarray(times, dtype=float).tolist()))
        run = subprocess.run(["node", str(ROOT / "scripts" / "play-gltf.mjs"), str(glb), str(Path(tmp) / "t.json"),
                              *flags], capture_output=True, text=True, check=True, cwd=ROOT)
    return {name: {k: np.array(v, dtype=float) for k, v in node.items()} for name, node in json.loads(run.stdout).items()}


def three_play(glb: Path, times: np.ndarray) -> dict[str, dict[str, np.ndarray]]:
    """Every named node's local position, quaternion (x, y, z, w) and scale, (n, 3|4),
    as three.js plays the file's first animation at ``times`` (mixer.setTime)."""
    return _play(glb, times)


def three_play_world(glb: Path, times: np.ndarray) -> dict[str, dict[str, np.ndarray]]:
    """Every named node's world position, world quaternion (x, y, z, w) and world scale,
    (n, 3|4), from its ``matrixWorld`` as three.js plays the file at ``times``: every
    parent's transform applied, a root ``to metres`` node's scale included (so in metres
    for our files)."""
    return _play(glb, times, "--world")
