"""Motion capture files by extension: read BVH or ASF/AMC clips and C3D markers; write a
reduced clip as glTF (.glb), BVH, USD or JSON, reduced markers as glTF or JSON."""

from __future__ import annotations

import os
from pathlib import Path

from sketchanim.mocap.clip_reduction import ReducedClip
from sketchanim.mocap.markers import Markers, ReducedMarkers
from sketchanim.motion.skeleton import Clip
from sketchanim.errors import FileFormatError, InputError
from sketchanim.formats.amc import read_amc, read_asf
from sketchanim.atomic import write_atomic
from sketchanim.formats.bvh import read_bvh, write_bvh
from sketchanim.formats.c3d import read_c3d

#: Extensions read as clips (.c3d: markers).
CLIP_INPUTS = (".bvh", ".amc", ".c3d")

#: Extensions a reduced clip is written as.
CLIP_OUTPUTS = (".glb", ".bvh", ".json", ".usd", ".usda", ".usdc")

#: Extensions reduced markers are written as.
MARKER_OUTPUTS = (".glb", ".json")


def find_asf(amc: Path) -> Path:
    """The ASF skeleton of an AMC file: in its folder, the .asf whose name starts its
    name (``11.asf`` for ``11_01.amc``, ``cmu_11.asf`` for ``cmu_11_01.amc``), or the
    only .asf there.

    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> for name in ("11.asf", "12.asf"): _ = (d / name).write_text("")
    >>> find_asf(d / "11_01.amc").name
    '11.asf'
    """
    candidates = sorted(amc.parent.glob("*.asf"))
    prefixed = [a for a in candidates if amc.stem.startswith(a.stem + "_") or amc.stem == a.stem]
    if prefixed:
        return max(prefixed, key=lambda a: len(a.stem))
    if len(candidates) == 1:
        return candidates[0]
    found = ", ".join(a.name for a in candidates) or "none"
    raise FileFormatError(str(amc), f"cannot tell which .asf skeleton it uses (found: {found}); give it with "
                                    "skeleton=PATH")


def read_clip(path: str | os.PathLike[str], *, skeleton: str | os.PathLike[str] | None = None) -> Clip | Markers:
    """A clip from a BVH file, or an AMC file with its ASF ``skeleton`` (found beside it
    when not given: :func:`find_asf`); the markers of a C3D file."""
    source = Path(path)
    suffix = source.suffix.lower()
    if suffix == ".bvh":
        return read_bvh(source)
    if suffix == ".amc":
        return read_amc(source, read_asf(Path(skeleton) if skeleton else find_asf(source)))
    if suffix == ".c3d":
        return read_c3d(source)
    raise FileFormatError(str(source), f"not a clip format this reads ({', '.join(CLIP_INPUTS)})")


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
        from sketchanim.formats.gltf_motion import clip_glb, markers_glb

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
