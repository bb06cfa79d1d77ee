"""The web's glTF compressors, run from npm as a pipeline runs them (pinned by
package-lock.json, installed by scripts/setup): gltfpack (meshoptimizer's, its npm build in
WebAssembly) and the glTF-Transform command line. Each run returns the CPU time (user +
system) of the command's process, node's start included (:func:`run_cpu`)."""

from __future__ import annotations

import resource
import subprocess
from pathlib import Path

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
