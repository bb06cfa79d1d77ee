"""The web's glTF compressors, run from npm as a pipeline runs them (pinned by
package-lock.json, installed by scripts/setup): gltfpack (meshoptimizer's, its npm build in
WebAssembly) and the glTF-Transform command line. Each run returns the CPU time (user +
system) of the command's process, node's start included (:func:`run_cpu`). What they are
given: :func:`source_glb`, a clip's frames as they are."""

from __future__ import annotations

import resource
import subprocess
from pathlib import Path

from sketchanim.formats.gltf import Channel, Node, glb_bytes
from sketchanim.motion.rotations import continuous_quaternions
from sketchanim.motion.skeleton import Clip

ROOT = Path(__file__).resolve().parents[1]
GLTFPACK = ROOT / "node_modules" / "gltfpack" / "cli.js"
GLTF_TRANSFORM = ROOT / "node_modules" / "@gltf-transform" / "cli" / "bin" / "cli.js"


def run_cpu(command: list[str]) -> float:
    """Run ``command`` (failing with its output when it fails) and return the user +
    system CPU seconds its process and children spent (``RUSAGE_CHILDREN`` before and
    after; only one command at a time from this process, so the difference is its own)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if run.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({run.returncode}): {(run.stderr or run.stdout).strip()}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _tool(script: Path) -> str:
    if not script.is_file():
        raise FileNotFoundError(f"{script.relative_to(ROOT)} is missing: run scripts/setup (npm ci)")
    return str(script)


def gltfpack(source: Path, out: Path, *options: str) -> float:
    """``gltfpack -i source -o out options...`` (``-kn`` always: every named node, so every
    joint, stays in the file); CPU seconds."""
    return run_cpu(["node", _tool(GLTFPACK), "-i", str(source), "-o", str(out), "-kn", *options])


def gltf_transform(command: str, source: Path, out: Path, *options: str) -> float:
    """``gltf-transform command source out options...``; CPU seconds."""
    return run_cpu(["node", _tool(GLTF_TRANSFORM), command, str(source), str(out), *options])


def source_glb(clip: Clip, unit_m: float | None = None) -> bytes:
    """The clip's frames as a .glb, the compressors' input: every joint a node at its rest
    offset, LINEAR keys at every frame (float32) for the rotations and translations the
    source has (each quaternion on the side of the previous one), no mesh; under a root
    scaling ``unit_m`` metres per clip unit to metres.

    >>> import numpy as np
    >>> from sketchanim.motion.skeleton import Skeleton
    >>> glb = source_glb(Clip.still(Skeleton(("hips",), (-1,), np.zeros((1, 3))), np.arange(4) / 30), 0.01)
    >>> import pygltflib as gl
    >>> doc = gl.GLTF2.load_from_bytes(glb)
    >>> [n.name for n in doc.nodes], [(c.target.path, doc.accessors[s.input].count) for c, s in
    ...                               zip(doc.animations[0].channels, doc.animations[0].samplers)]
    (['hips', 'to metres'], [('rotation', 4)])
    """
    sk = clip.skeleton
    nodes = [Node(n, p, translation=o.tolist()) for n, p, o in zip(sk.names, sk.parents, sk.offsets)]
    channels = []
    for j in range(len(sk)):
        if clip.rotating[j]:
            channels.append(Channel(j, "rotation", "LINEAR", clip.times, continuous_quaternions(clip.rotations[:, j])))
        if clip.translating[j]:
            channels.append(Channel(j, "translation", "LINEAR", clip.times, clip.translations[:, j]))
    return glb_bytes(nodes, channels, animation="source", unit_m=unit_m)
