"""``sketchanim salvage``: a damaged project's sound scene, tracks and takes into a new
project, takes of no track beside it as JSON, the damaged file never written, an
existing output kept unless ``--force``."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline
from typer.testing import CliRunner

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.cli import app
from sketchanim.project.checksums import take_digest
from sketchanim.project.salvage import orphans_path
from sketchanim.project.store import Project

runner = CliRunner()


def made(path: Path) -> None:
    """A project of two objects, a track each with two takes (ids 0 1 and 2 3), and a
    sound take 9 of no track (as a project saved by another version might hold)."""
    scene = Scene()
    tracks = {}
    t = np.linspace(0, 1, 20)
    curve = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 1, 1]]), 1)
    for name in ("a", "b"):
        scene.add(name)
        takes = tuple(Take(t, np.c_[t, k * t, t * t]) for k in range(2))
        tracks[f"{name}.position"] = ContinuousTrack(f"{name}.position", POSITION, curve, 0.005, takes)
    with Project(path) as project:
        project.save(scene, tracks)
    row = (9, "additive", 0.25, 3, 3, np.r_[0.0, 0.5, 1.0].tobytes(), np.arange(9.0).tobytes())
    sql(path, ("INSERT INTO takes VALUES (?, ?, ?, ?, ?, ?, ?)", row),
        ("INSERT INTO checksums VALUES (?, ?)", ("take 9", take_digest(*row))))


def sql(path: Path, *statements: tuple[str, tuple] | str) -> None:
    db = sqlite3.connect(path)
    with db:
        for s in statements:
            db.execute(*(s if isinstance(s, tuple) else (s,)))
    db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    db.close()


def salvage(*args: str):  # noqa: ANN201
    return runner.invoke(app, ["salvage", *args])


def test_a_damaged_take_is_left_out_and_the_rest_kept(tmp_path):
    path = tmp_path / "show.sketchanim"
    made(path)
    sql(path, "UPDATE takes SET vals = zeroblob(length(vals)) WHERE id = 2")    # a flipped page
    before = path.read_bytes()
    result = salvage(str(path))
    assert result.exit_code == 0, result.output
    assert "take 2" in result.output and "checksum" in result.output and "Traceback" not in result.output
    assert path.read_bytes() == before                                           # never written
    out = tmp_path / "show.salvaged.sketchanim"
    with Project(out) as project:
        scene, tracks = project.load()                                           # sound: it loads
    assert list(scene.objects) == ["a", "b"]
    assert [len(tracks[p].takes) for p in ("a.position", "b.position")] == [2, 1]
    orphans = json.loads(orphans_path(out).read_text())
    assert [(o["id"], o["mode"], o["blend"], o["times"]) for o in orphans["takes"]] == \
        [(9, "additive", 0.25, [0.0, 0.5, 1.0])]
    assert orphans["takes"][0]["values"] == np.arange(9.0).reshape(3, 3).tolist()


def test_a_damaged_document_keeps_every_take_as_an_orphan(tmp_path):
    path = tmp_path / "show.sketchanim"
    made(path)
    sql(path, "UPDATE documents SET body = replace(body, '0.005', '0.006')")
    out = tmp_path / "kept.sketchanim"
    result = salvage(str(path), "-o", str(out))
    assert result.exit_code == 0, result.output
    assert "the document" in result.output
    with Project(out) as project:
        scene, tracks = project.load()
    assert not scene.objects and not tracks
    assert [o["id"] for o in json.loads(orphans_path(out).read_text())["takes"]] == [0, 1, 2, 3, 9]


def test_an_existing_output_is_kept_unless_forced(tmp_path):
    path = tmp_path / "show.sketchanim"
    made(path)
    out = tmp_path / "out.sketchanim"
    out.write_bytes(b"the animator's")
    result = salvage(str(path), "-o", str(out))
    assert result.exit_code == 2 and "--force" in result.output and "exists" in result.output
    assert out.read_bytes() == b"the animator's" and not orphans_path(out).exists()
    orphans_path(out).write_text("older")
    out.unlink()
    assert salvage(str(path), "-o", str(out)).exit_code == 2                   # its orphans file counts too
    assert orphans_path(out).read_text() == "older"
    result = salvage(str(path), "-o", str(out), "--force")
    assert result.exit_code == 0, result.output
    with Project(out) as project:
        assert list(project.load()[0].objects) == ["a", "b"]
    assert json.loads(orphans_path(out).read_text())["takes"][0]["id"] == 9
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.sketchanim", orphans_path(out).name, "show.sketchanim"]


def test_the_damaged_project_is_not_its_own_output(tmp_path):
    path = tmp_path / "show.sketchanim"
    made(path)
    before = path.read_bytes()
    result = salvage(str(path), "-o", str(path), "--force")
    assert result.exit_code == 2 and "damaged project itself" in result.output
    assert path.read_bytes() == before


def test_nothing_readable_fails_clearly_and_writes_nothing(tmp_path):
    path = tmp_path / "show.sketchanim"
    scene = Scene()
    scene.add("box")
    with Project(path) as project:
        project.save(scene, {})
    sql(path, "UPDATE checksums SET digest = 'x' WHERE name = 'document'")
    result = salvage(str(path))
    assert result.exit_code == 2 and "nothing could be read" in result.output and "the document" in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["show.sketchanim"]
    notes = tmp_path / "notes.sketchanim"
    notes.write_text("shopping list")
    result = salvage(str(notes))
    assert result.exit_code == 2 and "not a project file" in result.output and "Traceback" not in result.output


def test_the_studio_names_the_command_for_a_damaged_project(tmp_path):
    path = tmp_path / "show.sketchanim"
    made(path)
    sql(path, "UPDATE takes SET vals = zeroblob(length(vals)) WHERE id = 1")
    before = path.read_bytes()
    result = runner.invoke(app, ["studio", str(path), "--no-browser", "--port", "0"])
    assert result.exit_code == 2 and "Traceback" not in result.output
    flat = " ".join(result.output.split())
    assert "damaged: take 1" in flat and f"run `sketchanim salvage {path}`" in flat, flat
    assert path.read_bytes() == before and not (tmp_path / "show.sketchanim.lock").exists()
