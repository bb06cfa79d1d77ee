"""Project files: save/load and JSON round trips, the recording journal under kill -9,
and malformed or hostile files."""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.anim.attributes import EVENT, AttributeType
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.errors import FileFormatError
from sketchanim.project.store import Project

REPO = Path(__file__).resolve().parents[2]


def recorded(tmp: Path) -> tuple[Scene, dict]:
    """A scene with a base take and a punch-in on the box, a light, events, a custom enum."""
    scene = Scene()
    scene.add("box")
    scene.add("lamp", "light")
    scene.objects["box"].add("mood", AttributeType.enum(["calm", "wild"]), "wild")
    scene.objects["box"].add("hit", EVENT)
    rec = Recorder(scene)
    for path in ("box.position", "box.orientation", "lamp.color", "box.hit"):
        rec.arm(path)
    t = np.arange(0, 2, 1 / 120)
    rec.start()
    for ti in t:
        rec.push_frame(ti, np.r_[np.sin(ti), ti, 0, 0, 0, np.sin(ti / 2), np.cos(ti / 2), 0.5, 0.5, 0.2])
    rec.push("box.hit", 1.0, "bang")
    tracks = rec.stop()
    rec.disarm("lamp.color")
    rec.disarm("box.hit")
    rec.disarm("box.orientation")
    rec.arm("box.position", smoothing=0.03)
    rec.start(tracks)
    for ti in t[(t > 0.5) & (t < 1.5)]:
        rec.push("box.position", ti, [np.sin(ti) + 0.2 * np.sin(np.pi * (ti - 0.5)), ti, 0])
    tracks.update(rec.stop())
    return scene, tracks


def same(a: tuple[Scene, dict], b: tuple[Scene, dict]) -> None:
    (sa, ta), (sb, tb) = a, b
    assert sa.paths() == sb.paths()
    for p in sa.paths():
        assert sa.type(p) == sb.type(p)
        assert np.array_equal(np.asarray(sa.get(p), dtype=object), np.asarray(sb.get(p), dtype=object))
    assert ta.keys() == tb.keys()
    for p, x in ta.items():
        y = tb[p]
        if hasattr(x, "spline"):
            assert np.array_equal(x.spline.t, y.spline.t) and np.array_equal(x.spline.c, y.spline.c)
            assert x.tol == y.tol and len(x.takes) == len(y.takes)
            for u, v in zip(x.takes, y.takes):
                assert np.array_equal(u.times, v.times) and np.array_equal(u.values, v.values)
                assert (u.mode, u.blend, u.smoothing) == (v.mode, v.blend, v.smoothing)
        else:
            assert (x.times, x.values) == (y.times, y.values)


def test_save_load_and_json_round_trips(tmp_path) -> None:
    scene, tracks = recorded(tmp_path)
    assert [t.smoothing for t in tracks["box.position"].takes] == [0.0, 0.03]
    with Project(tmp_path / "a.sketchanim") as project:
        project.save(scene, tracks)
        project.export_json(tmp_path / "a.json")
    with Project(tmp_path / "a.sketchanim", create=False) as project:
        same((scene, tracks), project.load())
    with Project(tmp_path / "b.sketchanim") as project:
        project.import_json(tmp_path / "a.json")
        same((scene, tracks), project.load())
    with Project(tmp_path / "new.sketchanim") as project:
        empty_scene, empty = project.load()
        assert empty == {} and empty_scene.paths() == []


def test_a_document_from_before_smoothing_loads_its_takes_unsmoothed(tmp_path) -> None:
    scene, tracks = recorded(tmp_path)
    with Project(tmp_path / "a.sketchanim") as project:
        project.save(scene, tracks)
        project.export_json(tmp_path / "a.json")
    body = json.loads((tmp_path / "a.json").read_text())
    assert list(body.pop("smoothing").values()) == [0.03]
    (tmp_path / "old.json").write_text(json.dumps(body))
    with Project(tmp_path / "b.sketchanim") as project:
        project.import_json(tmp_path / "old.json")
        assert [t.smoothing for t in project.load()[1]["box.position"].takes] == [0.0, 0.0]


CHILD = textwrap.dedent("""
    import sys, time, numpy as np
    from sketchanim.anim.recorder import Recorder
    from sketchanim.anim.scene import Scene
    from sketchanim.project.store import Project
    scene = Scene(); scene.add("box")
    project = Project(sys.argv[1])
    project.save(scene, {})
    rec = Recorder(scene, journal=project.journal())
    rec.arm("box.position")
    rec.start()
    for i in range(100000):
        t = i / 120
        rec.push("box.position", t, [np.sin(t), np.cos(t), i])
        print(i, flush=True)
        time.sleep(1 / 120)
""")


def test_a_take_killed_mid_recording_is_recovered_from_the_journal(tmp_path) -> None:
    path = tmp_path / "crash.sketchanim"
    env = dict(os.environ, PYTHONPATH=str(REPO / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(path)], stdout=subprocess.PIPE, text=True, env=env)
    try:
        last = -1
        while last < 240:                       # two seconds into the take
            last = int(child.stdout.readline())
        time.sleep(0.1)                         # everything pushed up to `last` is now 100 ms old
        child.send_signal(signal.SIGKILL)
        child.wait(10)
    finally:
        child.kill()
    with Project(path) as project:
        found = project.recovered()
    times, values = found["box.position"]
    n = len(times)
    assert n >= last + 1                         # at most the last 100 ms may be missing
    i = np.arange(n)
    assert np.array_equal(times, i / 120) and np.array_equal(values[:, 2], i)
    assert np.array_equal(values[:, 0], np.sin(i / 120))


BAD = {
    "random bytes": lambda p: p.write_bytes(os.urandom(3000)),
    "empty text": lambda p: p.write_text("hello"),
    "truncated database": None,
    "another database": lambda p: sqlite3.connect(p).execute("CREATE TABLE x (a)"),
    "wrong version": lambda p: _sql(p, "UPDATE meta SET value = '9' WHERE key = 'version'"),
    "document not json": lambda p: _sql(p, "UPDATE documents SET body = '{oops'"),
    "nan in document": lambda p: _sql(p, "UPDATE documents SET body = replace(body, '\"tol\":0.005', '\"tol\":NaN')"),
    "huge take": lambda p: _sql(p, "UPDATE takes SET n = 900000000000"),
    "short blob": lambda p: _sql(p, "UPDATE takes SET times = x'0000'"),
    "missing take": lambda p: _sql(p, "DELETE FROM takes"),
    "bad mode": lambda p: _sql(p, "UPDATE takes SET mode = 'pickle'"),
    "unknown object kind": lambda p: _sql(p, "UPDATE documents SET body = replace(body, '\"kind\":\"light\"', "
                                             "'\"kind\":\"dragon\"')"),
    "extra field": lambda p: _sql(p, "UPDATE documents SET body = replace(body, '\"format\"', '\"evil\":1,\"format\"')"),
    "track for no attribute": lambda p: _sql(p, "UPDATE documents SET body = replace(body, 'lamp.color', "
                                                "'lamp.smell')"),
}


def _sql(path: Path, statement: str) -> None:
    db = sqlite3.connect(path)
    with db:
        db.execute(statement)
    db.close()


@pytest.mark.parametrize("case", sorted(BAD))
def test_malformed_projects_fail_with_the_file_and_the_reason(tmp_path, case) -> None:
    path = tmp_path / "bad.sketchanim"
    with Project(path) as project:
        project.save(*recorded(tmp_path))
    if case == "truncated database":
        data = path.read_bytes()
        (tmp_path / "bad.sketchanim-wal").unlink(missing_ok=True)
        path.write_bytes(data[: len(data) // 3])
    else:
        if case in ("random bytes", "empty text", "another database"):
            path.unlink()
        BAD[case](path)
    with pytest.raises(FileFormatError, match=str(path)):
        with Project(path) as project:
            project.load()


@given(st.binary(max_size=2000), st.integers(0, 1 << 16))
@settings(max_examples=40)
def test_fuzzed_project_bytes_never_escape_as_anything_but_a_format_error(blob, at) -> None:
    import tempfile
    folder = Path(tempfile.mkdtemp())
    path = folder / "f.sketchanim"
    with Project(path) as project:
        project.save(Scene(), {})
    data = bytearray(path.read_bytes())
    at %= len(data)
    data[at : at + len(blob)] = blob
    path.write_bytes(bytes(data))
    try:
        with Project(path) as project:
            project.load()
    except FileFormatError as err:
        assert str(path) in str(err)
