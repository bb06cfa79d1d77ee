"""Project checksums: damage to a take or the document is refused by name, salvage
keeps what is sound, and projects saved before checksums load and gain them on save."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.errors import FileFormatError
from sketchanim.project.store import Project


def saved(path: Path) -> tuple[Scene, dict]:
    scene = Scene()
    tracks = {}
    for name in ("a", "b"):
        scene.add(name)
        t = np.linspace(0, 1, 20)
        takes = tuple(Take(t, np.c_[t, k * t, t * t]) for k in range(2))
        curve = BSpline(np.r_[[0.0] * 2, [1.0] * 2], np.array([[0.0, 0, 0], [1.0, 1, 1]]), 1)
        tracks[f"{name}.position"] = ContinuousTrack(f"{name}.position", POSITION, curve, 0.005, takes)
    with Project(path) as project:
        project.save(scene, tracks)
    return scene, tracks


def _sql(path: Path, *statements: str) -> None:
    db = sqlite3.connect(path)
    with db:
        for s in statements:
            db.execute(s)
    db.close()


def test_a_damaged_take_is_named_and_salvage_keeps_the_rest(tmp_path) -> None:
    path = tmp_path / "p.sketchanim"
    saved(path)
    # the value of one sample of take 2 changes (as a flipped bit in its page would)
    _sql(path, "UPDATE takes SET vals = zeroblob(length(vals)) WHERE id = 2")
    with pytest.raises(FileFormatError, match=r"damaged: take 2 \(its checksum does not match\)"):
        with Project(path) as project:
            project.load()
    with Project(path) as project:
        kept = project.salvage()
    assert sorted(kept.takes) == [0, 1, 3]
    assert [len(kept.tracks[p].takes) for p in ("a.position", "b.position")] == [2, 1]
    assert any("take 2" in d for d in kept.damaged)


def test_a_damaged_document_is_named_and_the_takes_survive(tmp_path) -> None:
    path = tmp_path / "p.sketchanim"
    saved(path)
    _sql(path, "UPDATE documents SET body = replace(body, '0.005', '0.006')")
    with pytest.raises(FileFormatError, match="the document"):
        with Project(path) as project:
            project.load()
    with Project(path) as project:
        kept = project.salvage()
    assert kept.tracks == {} and sorted(kept.takes) == [0, 1, 2, 3]


def test_a_project_from_before_checksums_loads_and_gains_them_on_save(tmp_path) -> None:
    path = tmp_path / "p.sketchanim"
    scene, tracks = saved(path)
    _sql(path, "DELETE FROM meta WHERE key = 'checksums'", "DROP TABLE checksums")
    with Project(path) as project:
        assert not project.checksummed
        loaded = project.load()
        project.save(*loaded)
        assert project.checksummed
    _sql(path, "UPDATE takes SET vals = zeroblob(length(vals)) WHERE id = 0")
    with pytest.raises(FileFormatError, match="take 0"):
        with Project(path) as project:
            project.load()


def test_altered_meta_is_refused(tmp_path) -> None:
    path = tmp_path / "p.sketchanim"
    saved(path)
    _sql(path, "UPDATE meta SET value = 'blake2b-928' WHERE key = 'checksums'")
    with pytest.raises(FileFormatError, match="damaged: meta"):
        Project(path)
    _sql(path, "UPDATE meta SET key = 'checksumz' WHERE key = 'checksums'")
    with pytest.raises(FileFormatError, match="damaged: meta"):
        Project(path)
