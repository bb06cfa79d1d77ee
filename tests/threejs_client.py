"""three.js as a client of our .glb files (scripts/play-gltf.mjs: GLTFLoader and an
AnimationMixer in node, three from npm, pinned by package-lock.json)."""

from __future__ import annotations

import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def three_play(glb: Path, times: np.ndarray) -> dict[str, dict[str, np.ndarray]]:
    """Every named node's local position, quaternion (x, y, z, w) and scale, (n, 3|4),
    as three.js plays the file's first animation at ``times`` (mixer.setTime)."""
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "t.json").write_text(json.dumps(np.asarray(times, dtype=float).tolist()))
        run = subprocess.run(["node", str(ROOT / "scripts" / "play-gltf.mjs"), str(glb), str(Path(tmp) / "t.json")],
                             capture_output=True, text=True, check=True, cwd=ROOT)
    return {name: {k: np.array(v, dtype=float) for k, v in node.items()} for name, node in json.loads(run.stdout).items()}
