"""Reduced clips and markers written in the format a file's extension names."""

from __future__ import annotations

import os
from pathlib import Path

from sketchanim.atomic import write_atomic
from sketchanim.errors import InputError
from sketchanim.formats.bvh import write_bvh
from sketchanim.mocap.clip_reduction import ReducedClip
from sketchanim.mocap.markers import ReducedMarkers

#: Extensions a reduced clip is written as.
CLIP_OUTPUTS = (".glb", ".bvh", ".json", ".usd", ".usda", ".usdc")

#: Extensions reduced markers are written as.
MARKER_OUTPUTS = (".glb", ".json")


def write_reduced(path: str | os.PathLike[str], clip: ReducedClip | ReducedMarkers, *, rate: float | None = None,
                  keys: str = "curves") -> Path:
    """Write ``clip`` in the format its extension names: .glb (the curves, exactly; with
    ``keys="frames"`` as LINEAR keys at the source's frames, or at ``rate``, for
    importers that ignore tangents), .json (the curves), .bvh or .usd/.usda/.usdc
    (frames at ``rate`` per second, the source's rate by default; clips only, markers
    have no skeleton)."""
    target = Path(path)
    suffix = target.suffix.lower()
    if suffix == ".glb":
        from sketchanim.export.mocap_gltf import clip_glb, markers_glb     # pygltflib only when needed

        return write_atomic(target, markers_glb(clip, name=target.stem, keys=keys) if isinstance(clip, ReducedMarkers)
                            else clip_glb(clip, name=target.stem, keys=keys, rate=rate))
    if suffix == ".json":
        return write_atomic(target, clip.to_json())
    if isinstance(clip, ReducedMarkers):
        raise InputError(f"{target}: markers are written as {' or '.join(MARKER_OUTPUTS)}, not "
                         f"{suffix or 'files without an extension'}")
    frames = clip.resample(1.0 / clip.frame_time if rate is None else rate)
    if suffix == ".bvh":
        return write_bvh(target, frames)
    if suffix in (".usd", ".usda", ".usdc"):
        from sketchanim.formats.usd import write_usd

        return write_usd(target, frames)
    raise InputError(f"{target}: cannot write {suffix or 'files without an extension'}; use one of "
                     f"{', '.join(CLIP_OUTPUTS)}")
