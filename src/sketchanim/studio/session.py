"""One project's model, bound to the studio's clients.

:class:`Session` is the one facade over a project's Scene, Player, History, Recorder
and Project file (as three.js's ``Editor.js`` is over its scene): the commands call its
methods, and each method returns the messages that tell the clients what changed. The
model is not thread-safe: every call runs in one thread, in order (the app sees to it).

A take: the page sends its samples in batches, stamped in the page with the transport
time; each row goes to the :class:`~sketchanim.anim.recorder.Recorder` as a frame, so the
curves are reduced while the take goes on and the samples stream into the project's
journal. A stall (no frame for ``gap`` seconds of real time: a tab in the background)
cuts the take: the part before is stopped and joined to the track, the part after is
recorded over the result, so the curve never swings across the stall (it holds, or
keeps the motion below, and fades into the next part over ``blend``). A take is one
History step; the project is saved after every step, and a take found in the journal at
start (the server was killed) comes back as a step of its own.
"""

from __future__ import annotations

import json
import os
import tempfile
import time
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import IO

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import AttributeType
from sketchanim.anim.edits import History
from sketchanim.anim.layers import punch_in
from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take, Track
from sketchanim.anim.workers import shared_pool
from sketchanim.errors import ArgumentError, InputError
from sketchanim.atomic import write_atomic
from sketchanim.project.store import Project

#: The mesh the page draws for an object of kind "object".
SHAPE = AttributeType.enum(["box", "sphere", "cone", "cylinder", "torus"])
#: Spline order of recorded curves.
ORDER = 4

#: A message for the clients and who gets it: "all", "others" (not the sender) or "self".
Out = tuple[str, dict]


def _looking_at(position: list[float], target: list[float]) -> list[float]:
    """The orientation (x, y, z, w) of a camera or light at ``position`` looking at
    ``target`` along its -z axis, y up (three.js's convention)."""
    back = np.subtract(position, target)
    back /= np.linalg.norm(back)
    right = np.cross([0.0, 1.0, 0.0], back)
    right /= np.linalg.norm(right)
    return Rotation.from_matrix(np.c_[right, np.cross(back, right), back]).as_quat().tolist()


def default_scene() -> Scene:
    """The scene a new studio project starts with: a box in the middle of the view, a
    ball and a cone beside it, a spot light and a camera looking at the box.

    >>> scene = default_scene()
    >>> list(scene.objects), scene.get("box.position").tolist(), scene.get("box.shape")
    (['box', 'ball', 'cone', 'lamp', 'cam'], [0.0, 0.5, 0.0], 'box')
    """
    scene = Scene()
    for name, shape, position in (("box", "box", [0.0, 0.5, 0.0]), ("ball", "sphere", [1.6, 0.5, 0.4]),
                                  ("cone", "cone", [-1.6, 0.5, -0.3])):
        scene.add(name).add("shape", SHAPE, shape)
        scene.set(f"{name}.position", position)
    scene.add("lamp", "light")
    scene.set("lamp.position", [2.0, 4.0, 3.0])
    scene.set("lamp.orientation", _looking_at([2.0, 4.0, 3.0], [0.0, 0.5, 0.0]))
    scene.set("lamp.color", [1.0, 0.95, 0.85])
    scene.set("lamp.intensity", [1.0])
    scene.add("cam", "camera")
    scene.set("cam.position", [0.0, 1.6, 6.0])
    scene.set("cam.orientation", _looking_at([0.0, 1.6, 6.0], [0.0, 0.5, 0.0]))
    return scene


def _value(value: object) -> object:
    return value.tolist() if isinstance(value, np.ndarray) else value


def type_message(kind: AttributeType) -> dict:
    """An attribute type as the page sees it.

    >>> from sketchanim.anim.attributes import FOV
    >>> type_message(FOV)
    {'name': 'fov', 'dim': 1, 'tol': 0.1, 'unit': 'degrees', 'default': [50.0], 'choices': [], 'continuous': True}
    """
    return {"name": kind.name, "dim": kind.dim, "tol": kind.tol, "unit": kind.unit, "default": list(kind.default),
            "choices": list(kind.choices), "continuous": kind.continuous}


def track_message(track: Track) -> dict:
    """A track as the page needs it to evaluate it as the player does (see
    docs/studio-protocol.md for the rule).

    >>> from scipy.interpolate import BSpline
    >>> from sketchanim.anim.attributes import INTENSITY
    >>> line = BSpline(np.r_[[0.0] * 2, [2.0] * 2], np.c_[[1.0, 3.0]], 1)
    >>> m = track_message(ContinuousTrack("lamp.intensity", INTENSITY, line, 0.01))
    >>> m["order"], m["knots"], m["coef"], m["rotation"], m["start"], m["end"]
    (2, [0.0, 0.0, 2.0, 2.0], [[1.0], [3.0]], False, 0.0, 2.0)
    """
    if isinstance(track, DiscreteTrack):
        return {"path": track.path, "kind": "steps", "times": list(track.times), "values": list(track.values)}
    s = track.spline
    return {"path": track.path, "kind": "curve", "dim": track.type.dim, "order": s.k + 1,
            "rotation": track.type.is_rotation, "tol": track.tol, "knots": np.asarray(s.t).tolist(),
            "coef": np.asarray(s.c).tolist(), "start": track.start, "end": track.end,
            "takes": [{"start": t.start, "end": t.end, "mode": t.mode, "n": len(t.times)} for t in track.takes]}


def split_at_stalls(times: np.ndarray, stall: float) -> list[slice]:
    """The runs of ``times`` with no step longer than ``stall``.

    >>> split_at_stalls(np.array([0.0, 0.1, 0.2, 1.0, 1.1]), 0.5)
    [slice(0, 3, None), slice(3, 5, None)]
    """
    cuts = [0, *(np.flatnonzero(np.diff(times) > stall) + 1).tolist(), len(times)]
    return [slice(a, b) for a, b in zip(cuts, cuts[1:])]


def _locked(path: Path) -> IO | None:
    """An exclusive lock on the project ``path`` (the file ``<path>.lock`` beside it,
    held while open; the system lets go of it when the process ends, however it ends),
    or :class:`ArgumentError` if another studio holds it. None where locks are not
    available.

    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "p.sketchanim"
    >>> lock = _locked(path)
    >>> _locked(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: project: ...p.sketchanim is open in another studio (one server per project)
    >>> lock.close()
    """
    try:
        import fcntl
    except ImportError:                                 # not a POSIX system
        return None
    handle = open(path.with_name(path.name + ".lock"), "a+")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        handle.close()
        raise ArgumentError("project", f"{path} is open in another studio (one server per project)") from None
    return handle


@dataclass
class _Take:
    """The take in progress."""

    id: str
    owner: int
    paths: list[str]
    mode: str
    blend: float
    speed: float
    gap: float
    tol: dict[str, float]
    loop: str | None
    time: float                                # the transport's time at the press
    over: dict[str, Track]                     # what the take is recorded over
    recorder: Recorder | None = None
    result: dict[str, Track] = field(default_factory=dict)   # parts before the last stall
    last: float = -np.inf
    samples: int = 0
    gaps: list[tuple[float, float]] = field(default_factory=list)


class Session:
    """A project opened for the studio.

    Parameters
    ----------
    path : path-like
        The project file; created with :func:`default_scene` if it does not exist (or
        holds no objects).

    Examples
    --------
    >>> import tempfile
    >>> session = Session(Path(tempfile.mkdtemp()) / "show.sketchanim")
    >>> _ = session.begin_take(1, "t1", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    >>> t = np.arange(120) / 60
    >>> _ = session.samples(1, "t1", t, np.c_[np.sin(t), 0 * t + 0.5, t])
    >>> out = session.end_take(1, "t1", None)
    >>> track = session.player.tracks["box.position"]
    >>> bool(np.abs(track.evaluate(t) - np.c_[np.sin(t), 0 * t + 0.5, t]).max() <= track.tol), session.history.labels
    (True, (['take box.position'], []))
    >>> session.close()
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        shared_pool()                   # the reducer processes forked now, before the app's threads exist
        self.path = Path(path).resolve()
        self.folder = self.path.parent
        self._lock = _locked(self.path)
        try:
            self.project = Project(self.path)
        except BaseException:
            self._unlock()
            raise
        scene, tracks = self.project.load()
        fresh = not scene.objects
        self.scene = default_scene() if fresh else scene
        self.player = Player(self.scene, tracks.values())
        self._history_changed = False
        self.history = History(self.player, on_change=lambda _: setattr(self, "_history_changed", True))
        self.transport = {"time": 0.0, "playing": False, "speed": 1.0, "loop": None}
        self.take: _Take | None = None
        self.dirty = fresh
        self._changes: list[tuple[str, str, str | None]] = []
        self.scene.watch(lambda *change: self._changes.append(change))
        self.recovered = self._recover()
        self.save()

    @property
    def meta_path(self) -> Path:
        """Where the take in progress is described, for a recovery after a crash."""
        return self.path.with_name(self.path.name + ".take.json")

    # -- what the clients see --------------------------------------------------------------

    def state(self, ready: bool) -> dict:
        """Everything a page needs to show the project (see the protocol)."""
        return {"type": "state", "ready": ready, "project": self.path.name,
                "objects": [{"name": o.name, "kind": o.kind,
                             "attributes": [{"name": n, "type": type_message(a.type), "value": _value(a.value)}
                                            for n, a in o.attributes.items()]} for o in self.scene.objects.values()],
                "tracks": [track_message(t) for t in self.player.tracks.values()],
                "span": list(self.player.span), "history": self.history_message(),
                "transport": dict(self.transport),
                "take": None if self.take is None else {"take": self.take.id, "paths": self.take.paths,
                                                         "mode": self.take.mode, "time": self.take.time,
                                                         "layout": [list(x) for x in self.layout(self.take.paths)]}}

    def history_message(self) -> dict:
        undo, redo = self.history.labels
        return {"type": "history", "undo": undo, "redo": redo, "can_undo": bool(undo), "can_redo": bool(redo)}

    def layout(self, paths: list[str]) -> list[tuple[str, int, int]]:
        at, layout = 0, []
        for p in paths:
            dim = self.scene.type(p).dim
            layout.append((p, at, at + dim))
            at += dim
        return layout

    def _told(self, ready: bool, tracks: dict[str, Track | None] | None = None) -> list[Out]:
        """The messages for what changed since the last call: the scene (as values, or
        the whole state if objects came or went), the tracks given, the history if it
        changed (the History's change callback says so)."""
        changes, self._changes = self._changes, []
        history, self._history_changed = self._history_changed, False
        out: list[Out] = []
        if any(what != "set" for what, _, _ in changes):
            return [("all", self.state(ready))]
        if changes:
            out.append(("all", {"type": "values", "values": {p: _value(self.scene.get(p))
                                                             for p in dict.fromkeys(s for _, s, _ in changes)
                                                             if self._exists(p)}}))
        if tracks:
            out.append(("all", {"type": "tracks", "changed": [track_message(t) for t in tracks.values() if t is not None],
                                "removed": [p for p, t in tracks.items() if t is None], "span": list(self.player.span)}))
        if history:
            out.append(("all", self.history_message()))
        return out

    def _exists(self, path: str) -> bool:
        try:
            self.scene.attribute(path)
        except ArgumentError:
            return False
        return True

    # -- scene edits -----------------------------------------------------------------------

    def set(self, path: str, value: object, label: str | None, merge: str | None, ready: bool = True) -> list[Out]:
        """Set ``path`` to ``value`` as one History step."""
        self.history.set(path, value, label, merge)
        self.dirty = True
        return self._told(ready)

    def preview(self, path: str, value: object) -> None:
        """A live value (not a History step): the scene's current value until the next."""
        self.scene.attribute(path).value = self.scene.type(path).check(value, path)

    def add_object(self, name: str, kind: str, ready: bool = True) -> list[Out]:
        """Add an object (with a ``shape`` if it is a plain object) as one step."""
        from sketchanim.anim.scene import SceneObject

        obj = SceneObject(name, kind)
        if kind == "object":
            obj.add("shape", SHAPE)
        if name in self.scene.objects:
            raise ArgumentError("object", f"{name!r} exists already")
        self.history.apply(f"add {name}", {}, ((lambda: self.scene.insert(obj), lambda: self.scene.remove(name)),))
        self.dirty = True
        return self._told(ready)

    def _still(self, what: str) -> None:
        if self.take is not None:
            raise ArgumentError(what, f"not while take {self.take.id!r} is being recorded")

    def remove_object(self, name: str, ready: bool = True) -> list[Out]:
        """Remove an object and its tracks as one step."""
        self._still("object.remove")
        obj = self.scene.objects.get(name)
        if obj is None:
            raise ArgumentError("object", f"no object {name!r}")
        tracks = {p: None for p in self.player.tracks if p.split(".")[0] == name}
        at = self.scene.index(name)
        self.history.apply(f"remove {name}", tracks,
                           ((lambda: self.scene.remove(name), lambda: self.scene.insert(obj, at)),))
        self.dirty = True
        return self._told(ready)

    def rename_object(self, name: str, to: str, ready: bool = True) -> list[Out]:
        """Rename an object, its tracks with it, as one step."""
        self._still("object.rename")
        if name not in self.scene.objects:
            raise ArgumentError("object", f"no object {name!r}")
        if to in self.scene.objects:
            raise ArgumentError("object", f"{to!r} exists already")
        from sketchanim.anim.scene import check_name

        check_name(to, "object")
        tracks: dict[str, Track | None] = {}
        for p, t in self.player.tracks.items():
            if p.split(".")[0] == name:
                moved = f"{to}.{p.split('.')[1]}"
                tracks[p], tracks[moved] = None, replace(t, path=moved)
        self.history.apply(f"rename {name} to {to}", tracks,
                           ((lambda: self.scene.rename(name, to), lambda: self.scene.rename(to, name)),))
        self.dirty = True
        return self._told(ready)

    def undo(self, ready: bool = True) -> list[Out]:
        return self._step(self.history.done, self.history.undo, "before", ready)

    def redo(self, ready: bool = True) -> list[Out]:
        return self._step(self.history.undone, self.history.redo, "after", ready)

    def _step(self, stack: list, move, side: str, ready: bool) -> list[Out]:
        self._still("undo")
        if not stack:
            return [("self", self.history_message())]
        tracks = dict(getattr(stack[-1], side))
        move()
        self.dirty = True
        return self._told(ready, tracks)

    # -- takes -----------------------------------------------------------------------------

    def begin_take(self, owner: int, take: str, paths: list[str], mode: str, blend: float, time: float,
                   speed: float, tol: dict[str, float], loop: str | None, gap: float) -> list[Out]:
        """Start a take of ``paths`` (continuous attributes) for client ``owner``."""
        if self.take is not None:
            raise ArgumentError("take", f"take {self.take.id!r} is being recorded")
        self.save()                     # the last take leaves the journal before this one streams into it
        if len(set(paths)) != len(paths):
            raise ArgumentError("paths", "a path is armed twice")
        for p in paths:
            if not self.scene.type(p).continuous:
                raise ArgumentError("paths", f"{p}: a {self.scene.type(p).name} attribute is set, not performed")
        for p in tol:
            if p not in paths:
                raise ArgumentError("tol", f"{p} is not armed")
        over = dict(self.player.tracks)
        last = self.history.done[-1] if self.history.done else None
        if loop is not None and last is not None and last.merge == loop:      # the next pass of a loop
            over.update(last.before)
            over = {p: t for p, t in over.items() if t is not None}
        self.take = _Take(take, owner, list(paths), mode, blend, speed, gap, dict(tol), loop, time, over)
        write_atomic(self.meta_path, json.dumps({"paths": paths, "mode": mode, "blend": blend, "tol": tol,
                                                 "speed": speed, "gap": gap, "loop": loop}))
        self._start_part()
        return [("self", {"type": "take.started", "take": take, "layout": [list(x) for x in self.layout(paths)],
                          "width": self.layout(paths)[-1][2]})]

    def _start_part(self) -> None:
        take = self.take
        rec = Recorder(self.scene, order=ORDER, journal=self.project.journal())
        for p in take.paths:
            rec.arm(p, tol=take.tol.get(p), mode=take.mode, blend=take.blend)
        rec.start({**take.over, **take.result})
        take.recorder = rec

    def _own(self, owner: int, take: str) -> _Take:
        if self.take is None or self.take.id != take:
            raise ArgumentError("take", f"no take {take!r} is being recorded")
        if self.take.owner != owner:
            raise ArgumentError("take", f"take {take!r} belongs to another page")
        return self.take

    def samples(self, owner: int, take: str, times: np.ndarray, values: np.ndarray) -> list[Out]:
        """Push a batch of frames (transport times (n,), rows (n, width)); a stall cuts
        the take (see the module's description)."""
        tk = self._own(owner, take)
        times = np.asarray(times, dtype=float)
        if len(values) != len(times):
            raise ArgumentError("values", f"{len(values)} rows for {len(times)} times")
        stall = tk.gap * tk.speed
        for i, (t, row) in enumerate(zip(times, values)):
            if tk.samples and t - tk.last > stall:
                self._cut(tk)
                tk.gaps.append((tk.last, float(t)))
                self._start_part()
            try:
                tk.recorder.push_frame(t, row)
            except InputError as err:
                raise ArgumentError(f"values[{i}]", f"sample {i} of the batch (take sample {tk.samples}): {err}") \
                    from None
            tk.last = float(t)
            tk.samples += 1
        return [("all", {"type": "take.piece", "take": take, "path": path, "order": piece.order,
                         "rotation": self.scene.type(path).is_rotation, "knots": piece.knots.tolist(),
                         "coef": piece.coef.tolist()}) for path, piece in tk.recorder.pieces()]

    def _cut(self, tk: _Take) -> None:
        """End the part recorded so far, keeping what it made."""
        rec, tk.recorder = tk.recorder, None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")                 # a one-sample part (left out) is no news
            tk.result.update(rec.stop())
        rec.journal.close()

    def end_take(self, owner: int, take: str, label: str | None, ready: bool = True) -> list[Out]:
        """End the take: its tracks as one History step (merged with the last pass of a
        loop recording); the project is saved by the next :meth:`save`."""
        clock = time.perf_counter()
        tk = self._own(owner, take)
        self._cut(tk)
        self.take = None
        made = dict(tk.result)
        if made:
            last = self.history.done[-1] if self.history.done else None
            if tk.loop is not None and last is not None and last.merge == tk.loop:
                made = {**{p: last.before[p] for p in last.after if p not in made}, **made}
            self.history.apply(label or f"take {', '.join(tk.result)}", made, merge=tk.loop)
        self.dirty = True               # saved soon after (the journal holds the take until then)
        out = self._told(ready, made)
        ms = 1000 * (time.perf_counter() - clock)
        out.append(("all", {"type": "take.ended", "take": take, "label": self.history.done[-1].label if made else None,
                            "paths": list(made), "ms": ms, "gaps": [list(g) for g in tk.gaps]}))
        return out

    def cancel_take(self, owner: int, take: str) -> list[Out]:
        """Drop the take: nothing changes."""
        tk = self._own(owner, take)
        self.take = None
        if tk.recorder is not None:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                tk.recorder.stop()
            tk.recorder.journal.close()
        self.save()
        return [("all", {"type": "take.ended", "take": take, "label": None, "paths": [], "ms": 0.0, "gaps": []})]

    def _recover(self) -> str | None:
        """A take left in the journal by a server that did not stop cleanly, made one
        History step (labelled "recovered take"); what was recovered, or None."""
        samples = self.project.recovered()
        meta = {}
        if self.meta_path.exists():
            try:
                meta = json.loads(self.meta_path.read_text())
            except (OSError, ValueError):
                meta = {}
        made: dict[str, Track] = {}
        for path, (times, values) in samples.items():
            if not self._exists(path) or not self.scene.type(path).continuous or len(times) < 2:
                continue
            kind = self.scene.type(path)
            tol = float(meta.get("tol", {}).get(path, kind.tol))
            old = self.player.tracks.get(path)
            spline = old.spline if isinstance(old, ContinuousTrack) else None
            takes = old.takes if isinstance(old, ContinuousTrack) else ()
            stall = float(meta.get("gap", 0.25)) * float(meta.get("speed", 1.0))
            for part in split_at_stalls(times, stall):
                if part.stop - part.start < 2:
                    continue
                piece = Take(times[part], np.asarray(values[part], dtype=float), meta.get("mode", "replace"),
                             float(meta.get("blend", 0.1)))
                spline = punch_in(kind, spline, piece, tol, ORDER)
                takes += (piece,)
            if takes:
                made[path] = ContinuousTrack(path, kind, spline, tol, takes)
        if made:
            self.history.apply("recovered take", made)
            self.dirty = True
        return ", ".join(made) or None

    # -- files -----------------------------------------------------------------------------

    def save(self) -> None:
        """Save the project if anything changed (not while a take runs: saving clears
        the journal the take is streaming into)."""
        if self.dirty and self.take is None:
            self.project.save(self.scene, dict(self.player.tracks))
            self.meta_path.unlink(missing_ok=True)
            self.dirty = False

    def export_document(self) -> bytes:
        """The project as ``sketchanim export PROJECT -o X.json`` writes it (saved first)."""
        self.save()
        with tempfile.TemporaryDirectory() as folder:
            out = Path(folder) / "project.json"
            self.project.export_json(out)
            return out.read_bytes()

    def export(self, name: str) -> Path:
        """Write the scene (``.glb``) or the project (``.json``) to ``name`` in the
        project's folder; a name that would leave the folder is refused."""
        from sketchanim.export.scene_gltf import scene_glb

        if os.sep in name or "/" in name or "\\" in name or name in (".", "..") or name.startswith("."):
            raise ArgumentError("file", f"{name!r}: a file name in the project's folder, not a path")
        target = (self.folder / name).resolve()
        if target.parent != self.folder or target == self.path:
            raise ArgumentError("file", f"{name!r} is not a new file in the project's folder")
        suffix = target.suffix.lower()
        if suffix == ".json":
            self.save()
            return self.project.export_json(target)
        if suffix == ".glb":
            glb, _ = scene_glb(self.scene, dict(self.player.tracks), name=target.stem)
            return write_atomic(target, glb)
        raise ArgumentError("file", f"{name!r}: exports are .glb or .json")

    def flush(self) -> None:
        """End a take still running (kept) and save."""
        if self.take is not None:
            self.end_take(self.take.owner, self.take.id, None)
        self.save()

    def close(self) -> None:
        """Flush, then close the file (and let another studio open it)."""
        self.flush()
        self.project.close()
        self._unlock()

    def _unlock(self) -> None:
        if self._lock is not None:
            Path(self._lock.name).unlink(missing_ok=True)
            self._lock.close()
            self._lock = None
