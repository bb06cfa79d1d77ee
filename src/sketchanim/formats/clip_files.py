"""Motion capture files by extension: read BVH or ASF/AMC clips and C3D markers (reduced
ones are written by :func:`sketchanim.export.files.write_reduced`)."""

from __future__ import annotations

import os
from pathlib import Path

from sketchanim.errors import FileFormatError
from sketchanim.formats.amc import read_amc, read_asf
from sketchanim.formats.bvh import read_bvh
from sketchanim.formats.c3d import read_c3d
from sketchanim.mocap.markers import Markers
from sketchanim.motion.skeleton import Clip

#: Extensions read as clips (.c3d: markers).
CLIP_INPUTS = (".bvh", ".amc", ".c3d")


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
