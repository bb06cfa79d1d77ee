"""CMU ASF/AMC: a skeleton file (.asf) and a motion file (.amc) into a
:class:`~sketchanim.motion.skeleton.Clip`. Errors name the file and line.

Each ASF bone becomes a joint at the bone's start (its parent's end), offset from its
parent joint by the parent bone's ``length * direction``; a bone with no children gets
an end joint ``<bone>_End`` at its tip. A bone's local rotation is ``C R C^-1``: ``C``
its ``axis`` (Euler angles in the stated order, fixed axes) and ``R`` the AMC values of
its ``dof`` (about fixed x, y, z, missing ones zero), as the CMU viewer plays them.
AMC files carry no frame rate: CMU's is 120 frames per second.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.errors import ArgumentError, FileFormatError
from sketchanim.formats.csvio import text_lines
from sketchanim.formats.numbers import CLIP_RANGE, FRAME_TIME_RANGE, out_of_clip_range, plain_floats

#: Frames per second of CMU's captures (AMC files do not say).
CMU_RATE = 120.0

_DOF_CHANNELS = {"rx": "Xrotation", "ry": "Yrotation", "rz": "Zrotation",
                 "tx": "Xposition", "ty": "Yposition", "tz": "Zposition"}


@dataclass
class _Bone:
    name: str
    line: int
    direction: np.ndarray = field(default_factory=lambda: np.zeros(3))
    length: float = 0.0
    axis: Rotation = field(default_factory=Rotation.identity)
    dof: tuple[str, ...] = ()
    parent: str | None = None


@dataclass(frozen=True)
class AsfSkeleton:
    """What an ASF file defines: the joints, and how AMC values become rotations."""

    skeleton: Skeleton
    dofs: dict[str, tuple[str, ...]]
    axes: dict[str, Rotation]
    degrees: bool
    unit_m: float | None
    source: str


def _floats(where: str, line: int, words: list[str], count: int, what: str) -> np.ndarray:
    values = plain_floats(words[:count])
    if values is None:
        raise FileFormatError(where, f"{what}: expected {count} numbers, got {' '.join(words)!r}", line=line)
    if len(values) != count or not np.all(np.isfinite(values)):
        raise FileFormatError(where, f"{what}: expected {count} finite numbers, got {' '.join(words)!r}", line=line)
    far = out_of_clip_range(values)
    if far is not None:
        raise FileFormatError(where, f"{what}: {far!r} is beyond the range of +/-{CLIP_RANGE:g}", line=line)
    return values


def read_asf(path: str | os.PathLike[str]) -> AsfSkeleton:
    """Read an ASF skeleton.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "s.asf"
    >>> _ = p.write_text(":units\\n length 0.45\\n angle deg\\n:root\\n order TX TY TZ RX RY RZ\\n axis XYZ\\n"
    ...                  ":bonedata\\n begin\\n  id 1\\n  name femur\\n  direction 0 -1 0\\n  length 7\\n"
    ...                  "  axis 0 0 20 XYZ\\n  dof rx\\n end\\n:hierarchy\\n begin\\n  root femur\\n end\\n")
    >>> asf = read_asf(p)
    >>> asf.skeleton.names, asf.skeleton.offsets[-1].tolist(), asf.dofs["femur"]
    (('root', 'femur', 'femur_End'), [0.0, -7.0, 0.0], ('rx',))
    """
    where = str(path)
    lines = text_lines(path)
    section, bones, bone = "", {}, None
    root_order: tuple[str, ...] = ()
    degrees, length_scale = True, None
    children: dict[str, list[str]] = {}
    for i, raw in enumerate(lines, start=1):
        words = raw.split("#")[0].split()
        if not words:
            continue
        if words[0].startswith(":"):
            section = words[0][1:].lower()
            continue
        key = words[0].lower()
        if section == "units":
            if key == "length":
                length_scale = float(_floats(where, i, words[1:], 1, "length unit")[0])
            elif key == "angle":
                degrees = words[1:2] != ["rad"]
        elif section == "root":
            if key == "order":
                root_order = tuple(w.lower() for w in words[1:])
                if any(w not in _DOF_CHANNELS for w in root_order) or len(set(root_order)) != len(root_order):
                    raise FileFormatError(where, f"root order {' '.join(words[1:])!r}: expected distinct TX TY TZ "
                                                 "RX RY RZ", line=i)
        elif section == "bonedata":
            if key == "begin":
                bone = _Bone("", i)
            elif bone is None:
                raise FileFormatError(where, f"{words[0]!r} outside a begin/end block", line=i)
            elif key == "end":
                if not bone.name:
                    raise FileFormatError(where, "bone without a name", line=bone.line)
                bones[bone.name] = bone
                bone = None
            elif key == "name":
                bone.name = words[1] if len(words) > 1 else ""
            elif key == "direction":
                bone.direction = _floats(where, i, words[1:], 3, "direction")
            elif key == "length":
                bone.length = float(_floats(where, i, words[1:], 1, "length")[0])
            elif key == "axis":
                angles = _floats(where, i, words[1:], 3, "axis")
                order = words[4].lower() if len(words) > 4 else "xyz"
                try:
                    bone.axis = Rotation.from_euler(order, angles, degrees=degrees)
                except ValueError:
                    raise FileFormatError(where, f"axis order {words[4]!r} is not an Euler order", line=i) from None
            elif key == "dof":
                bad = [w for w in words[1:] if w.lower() not in ("rx", "ry", "rz")]
                if bad:
                    raise FileFormatError(where, f"bone {bone.name!r}: dof {bad[0]!r} is not supported (only rx, "
                                                 "ry, rz)", line=i)
                bone.dof = tuple(w.lower() for w in words[1:])
                if len(set(bone.dof)) != len(bone.dof):
                    raise FileFormatError(where, f"bone {bone.name!r}: dof {' '.join(words[1:])!r} names an axis "
                                                 "twice", line=i)
        elif section == "hierarchy" and key not in ("begin", "end"):
            children.setdefault(words[0], []).extend(words[1:])
            for child in words[1:]:
                if child not in bones:
                    raise FileFormatError(where, f"hierarchy names bone {child!r}, which :bonedata does not define",
                                          line=i)
                bones[child].parent = words[0]
    if bone is not None:
        raise FileFormatError(where, "file ends inside a bone's begin/end block", line=bone.line)
    if "root" not in children:
        raise FileFormatError(where, "no :hierarchy with a root line")
    names, parents, offsets, dofs, axes = ["root"], [-1], [np.zeros(3)], {"root": root_order}, {}
    axes["root"] = Rotation.identity()
    stack = [(c, 0) for c in reversed(children["root"])]
    while stack:
        name, parent = stack.pop()
        b = bones[name]
        if name in names:
            raise FileFormatError(where, f"bone {name!r} appears twice in :hierarchy")
        up = bones.get(names[parent])
        names.append(name)
        parents.append(parent)
        offsets.append(up.length * up.direction if up else np.zeros(3))
        dofs[name], axes[name] = b.dof, b.axis
        index = len(names) - 1
        if name in children:
            stack += [(c, index) for c in reversed(children[name])]
        else:
            names.append(f"{name}_End")
            parents.append(index)
            offsets.append(b.length * b.direction)
    skeleton = Skeleton(tuple(names), tuple(parents), np.array(offsets))
    unit = 0.0254 / length_scale if length_scale else None
    return AsfSkeleton(skeleton, dofs, axes, degrees, unit, where)


def read_amc(path: str | os.PathLike[str], asf: AsfSkeleton, *, rate: float = CMU_RATE) -> Clip:
    """Read an AMC motion for the skeleton ``asf`` at ``rate`` frames per second.

    A bone line with the wrong number of values, an unknown bone, a frame missing a
    bone, or a file that ends inside a frame raise :class:`FileFormatError` with the line.
    """
    low, high = FRAME_TIME_RANGE
    if not (isinstance(rate, (int, float)) and 1 / high <= rate <= 1 / low):
        raise ArgumentError("rate", f"must be {1 / high:.3g} to {1 / low:g} frames per second, got {rate!r}")
    where = str(path)
    lines = text_lines(path)
    sk = asf.skeleton
    moving = [n for n in sk.names if asf.dofs.get(n)]
    frames: list[dict[str, np.ndarray]] = []
    frame_lines: list[int] = []
    for i, raw in enumerate(lines, start=1):
        words = raw.split()
        if not words or raw.startswith("#") or raw.startswith(":"):
            continue
        if len(words) == 1 and words[0].isdigit():
            frames.append({})
            frame_lines.append(i)
            continue
        if not frames:
            raise FileFormatError(where, f"expected a frame number, got {raw.strip()!r}", line=i)
        name = words[0]
        if name not in asf.dofs or not asf.dofs[name]:
            raise FileFormatError(where, f"frame {len(frames)}: no bone {name!r} with degrees of freedom in "
                                         f"{asf.source}", line=i)
        frames[-1][name] = _floats(where, i, words[1:], len(asf.dofs[name]), f"bone {name!r}")
        if len(words) - 1 != len(asf.dofs[name]):
            raise FileFormatError(where, f"bone {name!r}: {len(words) - 1} values, its dof has "
                                         f"{len(asf.dofs[name])}", line=i)
    if len(frames) < 2:
        raise FileFormatError(where, f"needs at least 2 frames, has {len(frames)}")
    for f, (frame, line) in enumerate(zip(frames, frame_lines)):
        missing = [n for n in moving if n not in frame]
        if missing:
            raise FileFormatError(where, f"frame {f} lacks bone {missing[0]!r} (truncated?)", line=line)
    return _clip(asf, frames, rate)


def _clip(asf: AsfSkeleton, frames: list[dict[str, np.ndarray]], rate: float) -> Clip:
    sk = asf.skeleton
    n, j = len(frames), len(sk)
    rotations, translations = sk.rest_pose(n)
    rotating, translating = np.zeros(j, bool), np.zeros(j, bool)
    channels: list[tuple[str, ...]] = []
    for i, name in enumerate(sk.names):
        dof = asf.dofs.get(name, ())
        channels.append(tuple(_DOF_CHANNELS[d] for d in dof))
        if not dof:
            continue
        values = np.array([f[name] for f in frames])
        rot = [k for k, d in enumerate(dof) if d.startswith("r")]
        if rot:
            seq = "".join(dof[k][1] for k in rot)
            local = Rotation.from_euler(seq, values[:, rot], degrees=asf.degrees)
            c = asf.axes[name]
            rotations[:, i] = (c * local * c.inv()).as_quat()
            rotating[i] = True
        pos = [dof.index(t) for t in ("tx", "ty", "tz") if t in dof]
        if len(pos) == 3:
            translations[:, i] = values[:, pos]
            translating[i] = True
    return Clip(sk, np.arange(n) / rate, rotations, translations, rotating, translating, tuple(channels),
                asf.unit_m)
