"""Hostile and careless input, generated here for every case of issue 19: through the
command line where one reads it (exit status 2, a message naming the file and what is
wrong, no output written), through the API elsewhere (a named InputError)."""

from __future__ import annotations

import json
import os
import sqlite3
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import sketchanim
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.cli import app
from sketchanim.errors import ArgumentError, FileFormatError, InputError, SampleError
from sketchanim.formats.amc import read_amc
from sketchanim.atomic import SUFFIX, write_atomic
from sketchanim.formats.bvh import bvh_text, read_bvh
from sketchanim.project.store import Project
from sketchanim.formats.recordings import read_svc, read_tum
from sketchanim.reducer import Reduction

runner = CliRunner()

#: Row count of the generated takes.
N = 40


def bvh(*, depth: int = 2, offset: str = "0 1 0", frame_time: str = "0.0333", position: str = "0") -> str:
    """A BVH chain ``depth`` joints deep, root translating, with N frames."""
    head = ["HIERARCHY"]
    for d in range(depth):
        head += [f"{'ROOT' if d == 0 else 'JOINT'} j{d}", "{", f"OFFSET {offset if d else '0 0 0'}",
                 "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation" if d == 0
                 else "CHANNELS 3 Zrotation Xrotation Yrotation"]
    head += ["}"] * depth
    rows = [" ".join([position if f == N // 2 else str(f * 0.1), "0", "0"] + [str(5.0 * np.sin(f / 5))] * 3 * depth)
            for f in range(N)]
    return "\n".join(head + ["MOTION", f"Frames: {N}", f"Frame Time: {frame_time}"] + rows) + "\n"


ASF = """:units
 length 0.45
 angle deg
:root
 order TX TY TZ RX RY RZ
 axis XYZ
:bonedata
 begin
  id 1
  name femur
  direction 0 {direction} 0
  length 7
  axis 0 0 20 XYZ
  dof rx
 end
:hierarchy
 begin
  root femur
 end
"""


def amc() -> str:
    return "\n".join(f"{f + 1}\nroot {f * 0.1} 0 0 0 0 0\nfemur {10 * np.sin(f / 5)}" for f in range(N)) + "\n"


def csv_rows(cells: dict[int, str] | None = None) -> str:
    t = np.arange(N) / 30
    rows = [[f"{float(ti)!r}", f"{float(np.sin(ti))!r}", f"{float(np.cos(ti))!r}"] for ti in t]
    for i, cell in (cells or {}).items():
        rows[i][1] = cell
    return "t,x,y\n" + "\n".join(",".join(r) for r in rows) + "\n"


def nested(depth: int) -> str:
    return '{"t": 0, "x": ' + "[" * depth + "1" + "]" * depth + "}\n"


#: name -> (file name, its text, extra CLI arguments, words the message must hold)
CLI_CASES = {
    "json stream nested 100000 deep": ("s.jsonl", nested(100_000), ["--tol", "0.1"], ["line 1", "nested 100001 deep"]),
    "json array nested 100000 deep": ("s.json", "[" * 100_000 + "]" * 100_000, ["--tol", "0.1"], ["nested"]),
    "json integer of 400 digits": ("s.jsonl", '{"t": 0, "x": 1}\n{"t": 1, "x": ' + "9" * 400 + "}\n",
                                   ["--tol", "0.1"], ["line 2", "400 digits"]),
    "json integer of 5000 digits": ("s.json", '{"t": [0, 1], "x": [1, ' + "9" * 5000 + "]}", ["--tol", "0.1"],
                                    ["5000 digits"]),
    "csv of +-1e308": ("s.csv", csv_rows({5: "1e308", 6: "-1e308"}), ["--tol", "0.01"],
                       ["line 7", "channel 0", "1e+308", "tolerances"]),
    "csv full-width digits": ("s.csv", csv_rows({3: "１２"}), ["--tol", "0.01"], ["line 5", "１２"]),
    "csv underscore digits": ("s.csv", csv_rows({3: "1_000"}), ["--tol", "0.01"], ["line 5", "1_000"]),
    "order 60": ("s.csv", csv_rows(), ["--tol", "0.01", "--order", "60"], ["--order", "2 to 8", "60"]),
    "window 100000000": ("s.csv", csv_rows(), ["--tol", "0.01", "--method", "incremental", "--window",
                                               "100000000"], ["--window", "4 to 1000", "100000000"]),
    "bvh frame time 1e300": ("c.bvh", bvh(frame_time="1e300"), [], ["line", "frame time", "1e300"]),
    "bvh offset 1e308": ("c.bvh", bvh(offset="0 1e308 0"), [], ["line 8", "OFFSET", "1e+308"]),
    "bvh position 1e308": ("c.bvh", bvh(position="1e308"), [], ["frame 20", "1e+308"]),
    "bvh full-width digits": ("c.bvh", bvh(position="１２"), [], ["frame 20", "not a number"]),
    "bvh rate 1e9": ("c.bvh", bvh(), ["--rate", "1e9"], ["--rate", "1 to 1000", "1e+09"]),
    "bvh rate 0": ("c.bvh", bvh(), ["--rate", "0"], ["--rate", "1 to 1000", "got 0"]),
}


@pytest.mark.parametrize("case", sorted(CLI_CASES))
def test_hostile_files_exit_2_naming_file_and_fault_and_write_nothing(tmp_path, case) -> None:
    name, text, extra, words = CLI_CASES[case]
    source = tmp_path / name
    source.write_text(text, encoding="utf-8")
    out = tmp_path / ("out.bvh" if name.endswith(".bvh") else "out.json")
    res = runner.invoke(app, ["reduce", str(source), "-o", str(out), *extra])
    assert res.exit_code == 2, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), res.exception
    message = " ".join(res.output.split())
    if "rate" not in case and "order" not in case and "window" not in case:
        assert str(source) in message, message
    for word in words:
        assert word in message, (word, message)
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_asf_direction_of_minus_1e308_is_named(tmp_path) -> None:
    (tmp_path / "s.asf").write_text(ASF.format(direction="-1e308"))
    (tmp_path / "m.amc").write_text(amc())
    out = tmp_path / "out.glb"
    res = runner.invoke(app, ["reduce", str(tmp_path / "m.amc"), "--skeleton", str(tmp_path / "s.asf"),
                              "-o", str(out)])
    message = " ".join(res.output.split())
    assert res.exit_code == 2 and "s.asf, line 11" in message and "direction" in message, message
    assert not out.exists()


def test_asf_dof_naming_an_axis_twice_is_named(tmp_path) -> None:
    # found by the fuzz: scipy refused the Euler sequence "yyz" with a bare ValueError
    (tmp_path / "s.asf").write_text(ASF.format(direction="-1").replace("dof rx", "dof ry ry rz"))
    (tmp_path / "m.amc").write_text(amc())
    res = runner.invoke(app, ["reduce", str(tmp_path / "m.amc"), "--skeleton", str(tmp_path / "s.asf"),
                              "-o", str(tmp_path / "out.glb")])
    message = " ".join(res.output.split())
    assert res.exit_code == 2 and "s.asf, line 14" in message and "names an axis twice" in message, message
    assert not (tmp_path / "out.glb").exists()


def test_export_refuses_what_is_not_a_project_and_leaves_it_alone(tmp_path) -> None:
    for name, data in (("zero.sketchanim", b""), ("text.sketchanim", b"hello"), ("db.sketchanim", None)):
        path = tmp_path / name
        if data is None:
            sqlite3.connect(path).execute("CREATE TABLE x (a)").connection.close()
        else:
            path.write_bytes(data)
        before = path.read_bytes()
        for out in (tmp_path / "o.glb", tmp_path / "o.json"):
            res = runner.invoke(app, ["export", str(path), "-o", str(out)])
            message = " ".join(res.output.split())
            assert res.exit_code == 2 and str(path) in message and "not a project" in message, message
            assert not out.exists()
        assert path.read_bytes() == before
        assert not Path(f"{path}-wal").exists()


def test_read_only_project_loads_and_exports_without_writing(tmp_path) -> None:
    path = tmp_path / "p.sketchanim"
    scene = Scene()
    scene.add("box")
    with Project(path) as project:
        project.save(scene, {})
    before = path.read_bytes()
    with Project(path, read_only=True) as project:
        assert project.read_only
        project.export_json(tmp_path / "p.json")
        with pytest.raises(FileFormatError, match="read-only"):
            project.save(scene, {})
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.json", "p.sketchanim"]


def test_project_whose_takes_table_was_tampered_with_is_refused(tmp_path) -> None:
    path = tmp_path / "p.sketchanim"
    with Project(path) as project:
        project.save(Scene(), {})
    db = sqlite3.connect(path)
    db.execute("DROP TABLE takes")
    db.execute("CREATE TABLE takes (id INTEGER PRIMARY KEY, evil TEXT)")
    db.commit()
    db.close()
    with pytest.raises(FileFormatError, match="table takes"):
        with Project(path) as project:
            project.save(Scene(), {})


def test_nested_and_long_json_is_named_in_every_json_reader(tmp_path) -> None:
    deep = "[" * 100_000 + "]" * 100_000
    with pytest.raises(InputError, match="nested"):
        Reduction.from_json('{"schema": "sketchanim.reduction", "version": 1, "x": ' + deep + "}", source="r.json")
    with pytest.raises(InputError, match="5000 digits"):
        Reduction.from_json('{"schema": "sketchanim.reduction", "version": 1, "x": ' + "7" * 5000 + "}")
    export = tmp_path / "p.json"
    export.write_text('{"takes": ' + deep + "}")
    with Project(tmp_path / "p.sketchanim") as project:
        with pytest.raises(FileFormatError, match=f"{export}: nested"):
            project.import_json(export)
        project.journal()([("box.hit", np.array([1.0]), ["x"])])
        db = sqlite3.connect(tmp_path / "p.sketchanim")
        db.execute("UPDATE journal SET vals = ?", (deep,))
        db.commit()
        db.close()
        with pytest.raises(FileFormatError, match="nested"):
            project.recovered()


def test_a_5000_deep_hierarchy_is_read_and_written(tmp_path) -> None:
    path = tmp_path / "deep.bvh"
    path.write_text(bvh(depth=5000))
    clip = read_bvh(path)
    assert len(clip.skeleton.names) == 5000 and clip.skeleton.parents[-1] == 4998
    assert bvh_text(clip).count("JOINT") == 4999


def test_tum_position_of_minus_1e308_is_named(tmp_path) -> None:
    rows = [f"{100 + i / 30} {np.sin(i)} 0 {'-1e308' if i == 9 else 1.5} 0 0 0 1" for i in range(N)]
    path = tmp_path / "gt.txt"
    path.write_text("\n".join(rows))
    t, p, _ = read_tum(path)
    with pytest.raises(SampleError) as err:
        sketchanim.reduce(t, p, 0.01)
    assert (err.value.index, err.value.field) == (9, "channel 2")


def test_api_arguments_are_named_errors(tmp_path) -> None:
    t = np.linspace(0, 1, N)
    with pytest.raises(ArgumentError, match="tol: must be numbers"):
        sketchanim.reduce(t, np.sin(t), tol=["a"])
    stream = sketchanim.StreamReducer(1, 0.1)
    stream.push(0.0, [1.0])
    with pytest.raises(SampleError, match="at least 2"):
        stream.finish()
    scene = Scene()
    scene.add("box")
    rec = Recorder(scene)
    rec.arm("box.position")
    rec.start()
    with pytest.raises(SampleError, match="time 'x' is not a number"):
        rec.push("box.position", "x", [1, 2, 3])
    rec.push("box.position", 0.0, [1, 2, 3])
    with pytest.raises(SampleError, match="tolerances"):
        rec.push("box.position", 0.1, [1e308, 2, 3])
    rec.push("box.position", 0.2, [1, 2, 3])
    assert len(rec.stop()["box.position"].takes[0].times) == 2          # nothing recorded was lost
    svc = tmp_path / "s.svc"
    svc.write_text("2\n5 7 1000 1\n6 8 1010 1\n")
    with pytest.raises(ArgumentError, match="columns"):
        read_svc(svc, columns=("y", "x", "time", "down"), time_scale=1e-3)
    with pytest.raises(ArgumentError, match="time_scale"):
        read_svc(svc, columns=("y", "x", "t", "down"), time_scale=float("nan"))
    with pytest.raises(ArgumentError, match="rate"):
        read_amc(svc, None, rate=float("nan"))
    svc.write_text("２\n5 7 1000 1\n6 8 1010 1\n")
    with pytest.raises(FileFormatError, match="sample count"):
        read_svc(svc, columns=("y", "x", "t", "down"), time_scale=1e-3)


def test_atomic_writes_clear_stale_temporaries_and_name_the_output(tmp_path) -> None:
    target = tmp_path / "out.json"
    # a writer SIGKILLed midway (no such process now) left its temporary file
    stale = tmp_path / f".out.json.{2**22 + 12345}.abc{SUFFIX}"
    stale.write_bytes(b"x" * 1000)
    other = tmp_path / f".other.json.{2**22 + 12345}.abc{SUFFIX}"
    other.write_bytes(b"y")
    mine = tmp_path / f".out.json.{os.getpid()}.abc{SUFFIX}"              # a live writer's: kept
    mine.write_bytes(b"z")
    write_atomic(target, json.dumps({"a": 1}))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([target.name, other.name, mine.name])
    blocked = tmp_path / "file"
    blocked.write_text("")
    with pytest.raises(OSError) as err:
        write_atomic(blocked / "x.json", "{}")
    assert err.value.filename == str(blocked / "x.json")
