"""Mutation fuzzing of every reader: seeds from ../shared/data (or generated), mutated
bytes and text, each read and then used as a user would (reduced, loaded), and every
outcome sorted into what may happen and what must not.

May happen: ``ok`` (read, reduced, every sample within tolerance; a project identical
to the one saved), ``named`` (an :class:`~sketchanim.errors.InputError`: a reader's
named refusal, or the reducer's input checks refusing a sample). Must not:
``traceback`` (any other exception), ``refused_valid`` (input that passed every input
check, refused later: an internal error reported as the user's), ``beyond_tolerance``
(a result that breaks its promise), ``silent_damage`` (a damaged project loaded with
different contents).

Used by tests/formats/test_fuzz.py (a few hundred mutations) and benchmarks/fuzz_readers.py
(as many as asked for).
"""

from __future__ import annotations

import re
import tempfile
import traceback
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline

import sketchanim
from sketchanim.anim.attributes import EVENT, POSITION
from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.mocap.markers import Markers, reduce_markers
from sketchanim.anim.scene import Scene
from sketchanim.motion.skeleton import Clip
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take
from sketchanim.errors import InputError
from sketchanim.formats.amc import read_amc, read_asf
from sketchanim.formats.bvh import read_bvh
from sketchanim.formats.c3d import read_c3d
from sketchanim.formats.csvio import read_samples_csv
from sketchanim.formats.jsonio import read_samples_json
from sketchanim.project.store import Project
from sketchanim.formats.recordings import read_svc, read_tum
from sketchanim.reducer import Reduction
from sketchanim.reducer.conditioning import condition

OUTCOMES = ("ok", "named", "traceback", "refused_valid", "beyond_tolerance", "silent_damage")
MUST_NOT = OUTCOMES[2:]

#: Numbers a careless or hostile file puts where a number goes.
HOSTILE_NUMBERS = ["1e308", "-1e308", "1e20", "-1e20", "nan", "inf", "-inf", "0", "-0", "1e-320", "5e-324",
                   "１２", "1_000", "9" * 400, "9" * 5000, "", "1e99999", "0x10", "1e", "--1", "12.5.3"]
_NUMBER = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?")


class NotKept(Exception):
    """A promise was broken (a sample beyond tolerance, a damaged project loaded)."""

    def __init__(self, outcome: str, message: str) -> None:
        self.outcome = outcome
        super().__init__(message)


def mutate(data: bytes, rng: np.random.Generator) -> bytes:
    """One random mutation of ``data``: a bit or byte changed, bytes deleted, inserted
    or repeated, lines swapped, the file cut short, deep nesting, a digit changed or a
    value scaled (input that stays valid), or numbers replaced by hostile ones."""
    b = bytearray(data)
    n = max(len(b), 1)
    at = int(rng.integers(0, n))
    kind = int(rng.integers(0, 13))
    if kind == 0 and b:
        b[at % len(b)] ^= 1 << int(rng.integers(0, 8))
    elif kind == 1 and b:
        b[at % len(b)] = int(rng.integers(0, 256))
    elif kind == 2:
        del b[at : at + int(rng.integers(1, 17))]
    elif kind == 3:
        b[at:at] = rng.integers(0, 256, int(rng.integers(1, 9))).astype(np.uint8).tobytes()
    elif kind == 4:
        span = bytes(b[at : at + int(rng.integers(1, 200))])
        b[at:at] = span * int(rng.integers(1, 4))
    elif kind == 5:
        lines = bytes(b).split(b"\n")
        if len(lines) > 2:
            i, j = rng.integers(0, len(lines), 2)
            lines[i], lines[j] = lines[j], lines[i]
        b = bytearray(b"\n".join(lines))
    elif kind == 6:
        del b[at:]
    elif kind == 7:
        depth = int(rng.choice([70, 5000, 100_000]))
        b[at:at] = b"[" * depth
    elif kind in (8, 9, 10):
        # plausible damage that leaves valid input: a digit changed, a value scaled
        numbers = list(_NUMBER.finditer(bytes(b)))
        for _ in range(int(rng.integers(1, 4))):
            if not numbers:
                break
            m = numbers[int(rng.integers(0, len(numbers)))]
            text = bytearray(m.group())
            if kind == 8:
                digits = [i for i, c in enumerate(text) if chr(c).isdigit()]
                text[digits[int(rng.integers(0, len(digits)))]] = ord(str(int(rng.integers(0, 10))))
            else:
                scale = 10.0 ** int(rng.integers(-3, 12)) * float(rng.choice([-1, 1]))
                text = bytearray(repr(float(m.group()) * scale).encode())
            b[m.start() : m.end()] = bytes(text)
            numbers = list(_NUMBER.finditer(bytes(b)))
    else:
        numbers = list(_NUMBER.finditer(bytes(b)))
        for _ in range(int(rng.integers(1, 4))):
            if numbers:
                m = numbers[int(rng.integers(0, len(numbers)))]
                b[m.start() : m.end()] = str(rng.choice(HOSTILE_NUMBERS)).encode("utf-8")
                numbers = list(_NUMBER.finditer(bytes(b)))
    return bytes(b)


# -- uses: read a file as a user would, and check the promises ---------------------------


def _reduce_table(times: np.ndarray, values: np.ndarray, tol: float) -> None:
    """Reduce samples that pass the input checks; they must be reduced within tolerance."""
    try:
        condition(times, values, tol)
    except InputError:
        raise                                       # a named refusal of bad samples
    try:
        r = sketchanim.reduce(times, values, tol)
    except InputError as err:
        raise NotKept("refused_valid", f"passed the input checks, then: {type(err).__name__}: {err}") from None
    err = np.abs(np.asarray(r.spline(times)).reshape(len(times), -1) - values.reshape(len(times), -1)).max()
    if not err <= tol:
        raise NotKept("beyond_tolerance", f"a sample misses by {err!r} > {tol!r}")


def _reduce_clip(clip: Clip) -> None:
    """Reduce a clip read without error; every frame within its tolerances."""
    tol, deg = 0.5, 0.5
    try:
        reduced = reduce_clip(clip, tol, deg)
    except InputError as err:
        raise NotKept("refused_valid", f"read, then: {err}") from None
    rotations = {i: reduced.joint_track(i, "orientation") for i in np.flatnonzero(clip.rotating)}
    translations = {i: reduced.joint_track(i, "position") for i in np.flatnonzero(clip.translating)}
    for i, r in rotations.items():
        q = np.asarray(r.spline(clip.times))
        q = q / np.linalg.norm(q, axis=1, keepdims=True)
        dot = np.minimum(np.abs(np.sum(q * clip.rotations[:, i], axis=1)), 1.0)
        worst = float(np.degrees(2 * np.arccos(dot)).max())
        if not worst <= deg * (1 + 1e-6):
            raise NotKept("beyond_tolerance", f"joint {i}: rotation misses by {worst} degrees")
    for i, r in translations.items():
        worst = float(np.linalg.norm(r.spline(clip.times) - clip.translations[:, i], axis=1).max())
        if not worst <= tol * (1 + 1e-9):
            raise NotKept("beyond_tolerance", f"joint {i}: position misses by {worst}")


def use_csv(path: Path) -> None:
    t = read_samples_csv(path)
    _reduce_table(t.times, t.values, 0.01)


def use_json(path: Path) -> None:
    t = read_samples_json(path)
    _reduce_table(t.times, t.values, 0.01)


def use_tum(path: Path) -> None:
    t, p, _ = read_tum(path)
    _reduce_table(t, p, 0.005)


def use_svc(path: Path) -> None:
    d = read_svc(path, columns=("y", "x", "t", "down", "az", "al", "p"), time_scale=1e-3)
    _reduce_table(d["t"], np.c_[d["x"], d["y"]], 1.0)


def use_bvh(path: Path) -> None:
    _reduce_clip(read_bvh(path))


def use_asf(path: Path) -> None:
    """A mutated ASF with the AMC beside it (``motion.amc``)."""
    _reduce_clip(read_amc(path.parent / "motion.amc", read_asf(path)))


def use_amc(path: Path) -> None:
    """A mutated AMC with the ASF beside it (``skeleton.asf``)."""
    _reduce_clip(read_amc(path, read_asf(path.parent / "skeleton.asf")))


def use_c3d(path: Path) -> None:
    m = read_c3d(path)
    few = Markers(m.names[:3], m.times, m.positions[:, :3], m.unit_m)
    try:
        reduced = reduce_markers(few, 5.0)
    except InputError as err:
        raise NotKept("refused_valid", f"read, then: {err}") from None
    worst = max((r.max_distance for r in reduced.reports()), default=0.0)
    if not worst <= 5.0 * (1 + 1e-9):
        raise NotKept("beyond_tolerance", f"a marker misses by {worst}")


def use_reduction(path: Path) -> None:
    r = Reduction.from_json(path.read_text(encoding="utf-8", errors="replace"), source=str(path))
    r.spline(np.linspace(r.spline.t[0], r.spline.t[-1], 50))


def project_contents(path: Path) -> tuple:
    """Everything a project holds, in comparable form."""
    with Project(path, create=False) as project:
        scene, tracks = project.load()
    values = tuple((p, repr(scene.get(p)), repr(scene.type(p))) for p in scene.paths())
    curves = []
    for name, track in sorted(tracks.items()):
        if isinstance(track, ContinuousTrack):
            curves.append((name, track.tol, track.spline.t.tobytes(), np.asarray(track.spline.c).tobytes(),
                           tuple((k.times.tobytes(), k.values.tobytes(), k.mode, k.blend) for k in track.takes)))
        else:
            curves.append((name, tuple(track.times), tuple(map(repr, track.values))))
    return values, tuple(curves)


def use_project(path: Path, original: tuple) -> None:
    if project_contents(path) != original:
        raise NotKept("silent_damage", "a damaged project loaded with different contents")


# -- seeds ------------------------------------------------------------------------------


def _head(path: Path, lines: int) -> bytes:
    return b"\n".join(path.read_bytes().split(b"\n")[:lines]) + b"\n"


def real_project(folder: Path, data: Path | None) -> Path:
    """A project holding a real recording (the TUM camera path, if ``data`` has it) as a
    take with its reduced curve, and an event track."""
    if data is not None and (data / "camera" / "freiburg1_xyz-groundtruth.txt").is_file():
        t, p, _ = read_tum(data / "camera" / "freiburg1_xyz-groundtruth.txt")
        t, p = t[:600], p[:600]
    else:
        t = np.arange(600) / 100.0
        p = np.c_[np.sin(t), np.cos(2 * t), 0.1 * t]
    scene = Scene()
    scene.add("cam", "camera")
    scene.objects["cam"].add("cut", EVENT)
    curve = sketchanim.reduce(t, p, 0.005).spline
    tracks = {"cam.position": ContinuousTrack("cam.position", POSITION, curve, 0.005, (Take(t, p),)),
              "cam.cut": DiscreteTrack("cam.cut", EVENT, [1.0, 2.5], ["a", "b"])}
    path = folder / "real.sketchanim"
    with Project(path) as project:
        project.save(scene, tracks)
    return path


@dataclass
class Reader:
    """A reader to fuzz: its seed file's name and bytes, and how a user uses it."""

    name: str
    file: str
    seed: bytes
    use: Callable[[Path], None]
    beside: dict[str, bytes] = field(default_factory=dict)      # files next to it, unmutated


def readers(data: Path | None, folder: Path) -> list[Reader]:
    """Every reader with its seed: from ``data`` (../shared/data) where present, else
    generated."""
    t = np.arange(300) / 50.0
    x = np.c_[np.sin(t), np.cos(1.3 * t)]
    csv = ("t,x,y\n" + "\n".join(f"{a!r},{b!r},{c!r}" for a, b, c in np.c_[t, x].tolist()) + "\n").encode()
    jsonl = "\n".join(f'{{"t": {a!r}, "p": [{b!r}, {c!r}]}}' for a, b, c in np.c_[t, x].tolist()).encode()
    reduction = sketchanim.reduce(t, x, 0.01).to_json().encode()
    found = []
    if data is not None and data.is_dir():
        found = [
            Reader("csv", "s.csv", _head(data / "imu" / "ngimu_quaternion.csv", 300), use_csv),
            Reader("tum", "gt.txt", _head(data / "camera" / "freiburg1_xyz-groundtruth.txt", 400), use_tum),
            Reader("svc", "s.svc", (data / "pen" / "HC-female__00026_w.cz.fnusa.10_1.svc").read_bytes(), use_svc),
            Reader("bvh", "c.bvh", (data / "bvh" / "bandai1_dash_normal_001.bvh").read_bytes(), use_bvh),
            Reader("asf", "s.asf", (data / "amc" / "cmu_11.asf").read_bytes(), use_asf,
                   {"motion.amc": _head(data / "amc" / "cmu_11_01.amc", 4 + 30 * 30)}),
            Reader("amc", "m.amc", _head(data / "amc" / "cmu_11_01.amc", 4 + 30 * 30), use_amc,
                   {"skeleton.asf": (data / "amc" / "cmu_11.asf").read_bytes()}),
            Reader("c3d", "m.c3d", (data / "c3d" / "pyomeca_markers_analogs.c3d").read_bytes(), use_c3d),
        ]
    else:
        found = [Reader("csv", "s.csv", csv, use_csv)]
    found += [
        Reader("jsonl", "s.jsonl", jsonl, use_json),
        Reader("json", "s.json", b"[" + jsonl.replace(b"\n", b",\n") + b"]", use_json),
        Reader("reduction", "r.json", reduction, use_reduction),
    ]
    project = real_project(folder, data if data is not None and data.is_dir() else None)
    original = project_contents(project)
    found.append(Reader("project", "p.sketchanim", project.read_bytes(), lambda p: use_project(p, original)))
    return found


@dataclass
class Tally:
    """Outcomes per reader, and the first few cases of each outcome that must not happen."""

    counts: dict[str, Counter] = field(default_factory=dict)
    examples: list[str] = field(default_factory=list)

    def add(self, reader: str, outcome: str, note: str = "") -> None:
        self.counts.setdefault(reader, Counter())[outcome] += 1
        if outcome in MUST_NOT and len(self.examples) < 20:
            self.examples.append(f"{reader}: {outcome}: {note}")

    def total(self, outcome: str) -> int:
        return sum(c[outcome] for c in self.counts.values())


def run_one(reader: Reader, data: bytes, folder: Path) -> tuple[str, str]:
    """Write ``data`` as the reader's file in a fresh folder and use it: (outcome, note)."""
    work = Path(tempfile.mkdtemp(dir=folder))
    for name, blob in reader.beside.items():
        (work / name).write_bytes(blob)
    path = work / reader.file
    path.write_bytes(data)
    try:
        reader.use(path)
    except NotKept as err:
        return err.outcome, str(err)
    except InputError as err:
        return "named", str(err)
    except Exception:                                    # noqa: BLE001 - what the fuzz is for
        return "traceback", traceback.format_exc(limit=-3)
    return "ok", ""


def fuzz(data: Path | None, per_reader: int, seed: int, *, only: set[str] | None = None) -> Tally:
    """``per_reader`` seeded mutations of every reader's seed (after the seed itself,
    which must come out ``ok``)."""
    tally = Tally()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for number, reader in enumerate(readers(data, folder)):
            if only and reader.name not in only:
                continue
            outcome, note = run_one(reader, reader.seed, folder)
            tally.add(reader.name, "ok" if outcome == "ok" else "refused_valid", f"the unmutated seed: {note}")
            rng = np.random.default_rng([seed, number])
            for _ in range(per_reader):
                outcome, note = run_one(reader, mutate(reader.seed, rng), folder)
                tally.add(reader.name, outcome, note)
    return tally


def flip_bytes(path: Path, original: tuple, flips: int, seed: int) -> Counter:
    """Flip one byte in a random place of the project at ``path`` (a fresh copy each
    time); count the loads refused (``named``), identical (``ok``) and otherwise."""
    rng = np.random.default_rng(seed)
    blob = path.read_bytes()
    counts: Counter = Counter()
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(flips):
            copy = Path(tmp) / f"{i}.sketchanim"
            damaged = bytearray(blob)
            at = int(rng.integers(0, len(blob)))
            damaged[at] ^= int(rng.integers(1, 256))
            copy.write_bytes(bytes(damaged))
            try:
                counts["ok" if project_contents(copy) == original else "silent_damage"] += 1
            except InputError:
                counts["named"] += 1
            except Exception:                            # noqa: BLE001
                counts["traceback"] += 1
    return counts
