"""BVH files: read a skeleton and its motion into a :class:`~sketchanim.motion.skeleton.Clip`,
write a clip back (any frame rate). Errors name the file and line.

A joint has 0 to 6 channels in any order: three rotations (an intrinsic Euler
sequence in the order listed, degrees) and three positions (the joint's local
translation, replacing its offset, as Blender and most readers take it). End Sites
become joints without channels, named ``<parent>_End`` (their offsets are kept).
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.motion.skeleton import JOINT_CHANNELS, ROOT_CHANNELS, Clip, Skeleton
from sketchanim.errors import FileFormatError
from sketchanim.formats.csvio import text_lines
from sketchanim.atomic import write_atomic
from sketchanim.formats.numbers import CLIP_RANGE, FRAME_TIME_RANGE, out_of_clip_range, plain_float, plain_floats
from sketchanim.motion import euler_angles

ROTATIONS = ("Xrotation", "Yrotation", "Zrotation")
POSITIONS = ("Xposition", "Yposition", "Zposition")



class _Tokens:
    """Whitespace-separated words with their line numbers, read one at a time."""

    def __init__(self, path: str, lines: list[str]) -> None:
        self.path = path
        self.words = [(w, i) for i, line in enumerate(lines, start=1) for w in line.split()]
        self.at = 0

    def line(self, at: int | None = None) -> int:
        at = self.at if at is None else at
        return self.words[min(at, len(self.words) - 1)][1] if self.words else 1

    def fail(self, message: str, *, at: int | None = None) -> FileFormatError:
        """An error at the current word, or at word index ``at``."""
        return FileFormatError(self.path, message, line=self.line(at))

    def next(self, what: str) -> str:
        if self.at >= len(self.words):
            raise self.fail(f"file ends where {what} was expected")
        word = self.words[self.at][0]
        self.at += 1
        return word

    def expect(self, word: str) -> None:
        got = self.next(repr(word))
        if got != word:
            self.at -= 1
            raise self.fail(f"expected {word!r}, got {got!r}")

    def number(self, what: str) -> float:
        text = self.next(what)
        value = plain_float(text)
        if value is None:
            self.at -= 1
            raise self.fail(f"{what}: not a number: {text!r}")
        if not abs(value) <= CLIP_RANGE:
            self.at -= 1
            raise self.fail(f"{what} is {value!r}, beyond the range of +/-{CLIP_RANGE:g}")
        return value


class _Joints:
    """The hierarchy as it is parsed."""

    def __init__(self) -> None:
        self.names: list[str] = []
        self.parents: list[int] = []
        self.offsets: list[list[float]] = []
        self.channels: list[tuple[str, ...]] = []


def _channels(tok: _Tokens, joint: str) -> tuple[str, ...]:
    first = tok.at
    count_text = tok.next("the channel count")
    if not (count_text.isascii() and count_text.isdigit() and len(count_text) == 1) or int(count_text) > 6:
        tok.at -= 1
        raise tok.fail(f"joint {joint!r}: channel count must be 0 to 6, got {count_text!r}")
    names = []
    for _ in range(int(count_text)):
        word = tok.next("a channel name")
        name = word[0].upper() + word[1:].lower()
        if name not in ROTATIONS + POSITIONS:
            tok.at -= 1
            raise tok.fail(f"joint {joint!r}: unknown channel {word!r} (expected X/Y/Z position or rotation)")
        if name in names:
            tok.at -= 1
            raise tok.fail(f"joint {joint!r}: channel {word!r} twice")
        names.append(name)
    for group in (ROTATIONS, POSITIONS):
        if 0 < sum(n in group for n in names) < 3:
            raise tok.fail(f"joint {joint!r}: needs all three {group[0][1:]} channels or none, got {' '.join(names)}",
                           at=first)
    return tuple(names)


def _open_joint(tok: _Tokens, joints: _Joints, name: str, parent: int) -> int:
    """Read a joint's head (name given, up to its channels); its index."""
    if name in joints.names:
        raise tok.fail(f"joint {name!r} appears twice", at=tok.at - 1)
    index = len(joints.names)
    joints.names.append(name)
    joints.parents.append(parent)
    tok.expect("{")
    tok.expect("OFFSET")
    joints.offsets.append([tok.number(f"joint {name!r} OFFSET") for _ in range(3)])
    tok.expect("CHANNELS")
    joints.channels.append(_channels(tok, name))
    return index


def _joint(tok: _Tokens, joints: _Joints, name: str, parent: int) -> None:
    """Read a joint and everything under it, with a stack of open joints (no
    recursion: a hierarchy of any depth)."""
    open_joints = [_open_joint(tok, joints, name, parent)]
    while open_joints:
        index = open_joints[-1]
        name = joints.names[index]
        word = tok.next("JOINT, End Site or '}'")
        if word == "}":
            open_joints.pop()
        elif word == "JOINT":
            open_joints.append(_open_joint(tok, joints, tok.next("a joint name"), index))
        elif word == "End":
            tok.expect("Site")
            tok.expect("{")
            tok.expect("OFFSET")
            end = f"{name}_End"
            if end in joints.names:
                raise tok.fail(f"joint {name!r} has two End Sites")
            joints.names.append(end)
            joints.parents.append(index)
            joints.offsets.append([tok.number(f"{name!r} End Site OFFSET") for _ in range(3)])
            joints.channels.append(())
            tok.expect("}")
        else:
            tok.at -= 1
            raise tok.fail(f"joint {name!r}: expected JOINT, End Site or '}}', got {word!r}")


def read_bvh(path: str | os.PathLike[str]) -> Clip:
    """Read a BVH file: hierarchy, offsets, channels in any order, frame time, frames.

    A truncated MOTION section (fewer frames than ``Frames:`` says, or a short row), a
    row that is not numbers, a missing or bad frame time: each raises
    :class:`~sketchanim.errors.FileFormatError` naming the line.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "m.bvh"
    >>> _ = p.write_text("HIERARCHY\\nROOT Hips\\n{\\n OFFSET 0 0 0\\n CHANNELS 6 Xposition Yposition Zposition"
    ...                  " Zrotation Xrotation Yrotation\\n End Site\\n {\\n  OFFSET 0 1 0\\n }\\n}\\n"
    ...                  "MOTION\\nFrames: 2\\nFrame Time: 0.5\\n0 1 2 90 0 0\\n3 4 5 0 0 0\\n")
    >>> clip = read_bvh(p)
    >>> clip.skeleton.names, clip.times.tolist(), clip.translations[1, 0].tolist()
    (('Hips', 'Hips_End'), [0.0, 0.5], [3.0, 4.0, 5.0])
    >>> clip.world_positions()[0, 1].round(9).tolist()    # Z turned 90 degrees: up becomes -x
    [-1.0, 1.0, 2.0]
    """
    where = str(path)
    lines = text_lines(path)
    motion_at = next((i for i, line in enumerate(lines) if line.strip() == "MOTION"), None)
    if motion_at is None:
        raise FileFormatError(where, "no MOTION section")
    tok = _Tokens(where, lines[:motion_at])
    tok.expect("HIERARCHY")
    joints = _Joints()
    while tok.at < len(tok.words):
        tok.expect("ROOT")
        _joint(tok, joints, tok.next("a joint name"), -1)
    if not joints.names:
        raise FileFormatError(where, "HIERARCHY has no ROOT", line=motion_at)
    skeleton = Skeleton(tuple(joints.names), tuple(joints.parents), np.array(joints.offsets, dtype=float))
    frame_time, frames = _motion(where, lines, motion_at, sum(len(c) for c in joints.channels))
    return _clip(skeleton, tuple(joints.channels), frame_time, frames)


def _header(where: str, lines: list[str], i: int, label: str) -> str:
    text = lines[i] if i < len(lines) else ""
    name, _, value = text.partition(":")
    if " ".join(name.split()).lower() != label.lower():
        raise FileFormatError(where, f"expected '{label}: ...', got {text.strip()!r}", line=i + 1)
    return value.strip()


def _motion(where: str, lines: list[str], motion_at: int, width: int) -> tuple[float, np.ndarray]:
    count_text = _header(where, lines, motion_at + 1, "Frames")
    if not (count_text.isascii() and count_text.isdigit() and len(count_text) <= 12):
        raise FileFormatError(where, f"frame count must be a whole number, got {count_text!r}", line=motion_at + 2)
    time_text = _header(where, lines, motion_at + 2, "Frame Time")
    frame_time = plain_float(time_text)
    low, high = FRAME_TIME_RANGE
    if frame_time is None or not low <= frame_time <= high:
        raise FileFormatError(where, f"frame time must be a positive number of seconds ({low:g} to {high:g}), got "
                                     f"{time_text!r}", line=motion_at + 3)
    n = int(count_text)
    rows = [(i, line) for i, line in enumerate(lines[motion_at + 3 :], start=motion_at + 4) if line.strip()]
    if len(rows) < n:
        last = rows[-1][0] if rows else motion_at + 3
        raise FileFormatError(where, f"MOTION is truncated: 'Frames: {n}' but {len(rows)} frames", line=last)
    if len(rows) > n:
        raise FileFormatError(where, f"more frame rows than 'Frames: {n}'", line=rows[n][0])
    frames = np.empty((n, width))
    for f, (i, line) in enumerate(rows):
        words = line.split()
        if len(words) != width:
            raise FileFormatError(where, f"frame {f} has {len(words)} values, the hierarchy has {width} channels"
                                  + (" (truncated?)" if f == n - 1 and len(words) < width else ""), line=i)
        row = plain_floats(words)
        if row is None:
            bad = next(w for w in words if plain_float(w) is None)
            raise FileFormatError(where, f"frame {f}: not a number: {bad!r}", line=i)
        far = out_of_clip_range(row)
        if far is not None:
            what = f"value {far!r} is beyond the range of +/-{CLIP_RANGE:g}" if np.isfinite(far) else "value is not finite"
            raise FileFormatError(where, f"frame {f}: {what}", line=i)
        frames[f] = row
    if n < 2:
        raise FileFormatError(where, f"needs at least 2 frames, has {n}", line=motion_at + 2)
    return frame_time, frames


def _clip(skeleton: Skeleton, channels: tuple[tuple[str, ...], ...], frame_time: float, frames: np.ndarray) -> Clip:
    n, j = len(frames), len(skeleton)
    rotations, translations = skeleton.rest_pose(n)
    rotating, translating = np.zeros(j, bool), np.zeros(j, bool)
    col = 0
    for i, names in enumerate(channels):
        block = frames[:, col : col + len(names)]
        col += len(names)
        rot = [k for k, c in enumerate(names) if c in ROTATIONS]
        if rot:
            seq = "".join(names[k][0] for k in rot)
            rotations[:, i] = Rotation.from_euler(seq, block[:, rot], degrees=True).as_quat()
            rotating[i] = True
        if any(c in POSITIONS for c in names):
            translations[:, i] = block[:, [names.index(p) for p in POSITIONS]]
            translating[i] = True
    return Clip(skeleton, np.arange(n) * frame_time, rotations, translations, rotating, translating, channels)


def _layout(clip: Clip, i: int) -> tuple[str, ...]:
    """The channels written for joint ``i``: the source's where they are BVH's (three
    rotations and / or three positions, as the joint moves), else a default for its role
    (an ASF bone with one or two degrees of freedom)."""
    names = clip.channels[i]
    if (sum(c in ROTATIONS for c in names) == 3 * bool(clip.rotating[i])
            and sum(c in POSITIONS for c in names) == 3 * bool(clip.translating[i])):
        return names
    return ROOT_CHANNELS if clip.translating[i] else JOINT_CHANNELS


def _frames(clip: Clip, layouts: list[tuple[str, ...]], order: list[int]) -> np.ndarray:
    """The MOTION rows: the channels of the joints in ``order`` (the hierarchy's, depth first)."""
    columns = []
    for i in order:
        names = layouts[i]
        rot = [c for c in names if c in ROTATIONS]
        angles = None
        if rot:
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", message="Gimbal lock")
                angles = np.degrees(euler_angles(clip.rotations[:, i], "".join(c[0] for c in rot)))
        for c in names:
            if c in ROTATIONS:
                columns.append(angles[:, rot.index(c)])  # type: ignore[index]
            else:
                columns.append(clip.translations[:, i, POSITIONS.index(c)])
    return np.column_stack(columns) if columns else np.zeros((len(clip.times), 0))


def bvh_text(clip: Clip) -> str:
    """The BVH text of ``clip`` (its frames as they are, at ``clip.frame_time``): its
    joints depth first, whatever their order in the clip (a parent before its children),
    and each frame's channels in that order.

    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("hips", "left", "right", "toe"), (-1, 0, 0, 1), np.eye(4, 3))
    >>> clip = Clip.still(s, [0.0, 0.1])
    >>> [line.split()[1] for line in bvh_text(clip).splitlines() if line.split()[0] in ("ROOT", "JOINT")]
    ['hips', 'left', 'toe', 'right']
    """
    sk = clip.skeleton
    layouts = [_layout(clip, i) for i in range(len(sk))]
    children: dict[int, list[int]] = {i: [] for i in range(-1, len(sk))}
    for i, p in enumerate(sk.parents):
        children[p].append(i)
    out = ["HIERARCHY"]
    order: list[int] = []                       # the joints as written: their channels' order in MOTION
    # depth first with a stack (no recursion); ("close", depth) ends a joint's block
    stack: list[tuple[int | str, int]] = [(root, 0) for root in reversed(children[-1])]
    while stack:
        i, depth = stack.pop()
        pad = "  " * depth
        if i == "close":
            out.append(f"{pad}}}")
            continue
        assert isinstance(i, int)
        off = " ".join(f"{v:.10g}" for v in sk.offsets[i])
        if not layouts[i] and not children[i] and sk.parents[i] >= 0:
            out.extend([f"{pad}End Site", f"{pad}{{", f"{pad}  OFFSET {off}", f"{pad}}}"])
            continue
        order.append(i)
        out.extend([f"{pad}{'ROOT' if sk.parents[i] < 0 else 'JOINT'} {sk.names[i]}", f"{pad}{{",
                    f"{pad}  OFFSET {off}", f"{pad}  CHANNELS {len(layouts[i])} {' '.join(layouts[i])}".rstrip()])
        stack.append(("close", depth))
        stack += [(c, depth + 1) for c in reversed(children[i])]
    frames = _frames(clip, layouts, order)
    out += ["MOTION", f"Frames: {len(frames)}", f"Frame Time: {clip.frame_time:.10g}"]
    out += [" ".join(f"{v:.10g}" for v in row) for row in frames]
    return "\n".join(out) + "\n"


def write_bvh(path: str | os.PathLike[str], clip: Clip) -> Path:
    """Write ``clip`` as BVH, atomically; rotations as each joint's source Euler order.

    >>> import tempfile, pathlib
    >>> from sketchanim.motion.skeleton import Skeleton
    >>> s = Skeleton(("root", "tip"), (-1, 0), np.array([[0.0, 0, 0], [0, 1.0, 0]]))
    >>> p = write_bvh(pathlib.Path(tempfile.mkdtemp()) / "still.bvh", Clip.still(s, np.arange(4) / 30))
    >>> read_bvh(p).skeleton.names
    ('root', 'tip')
    """
    return write_atomic(path, bvh_text(clip))

