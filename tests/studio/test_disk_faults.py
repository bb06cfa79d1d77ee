"""Every write the studio makes, failing on demand: the project's save, the take's notes,
the journal, the journal's clearing, the project file or its folder vanishing, a stop
while saves fail. Nothing acked is lost, every page is told, and the studio records and
edits again as soon as the fault is gone."""

from __future__ import annotations

import errno
import shutil

import numpy as np
import pytest

from sketchanim.errors import StorageError
from sketchanim.project.journal import Journal
from sketchanim.project.recovery import notes_path
from sketchanim.project.store import Project
from sketchanim.studio import saving, session as session_module
from sketchanim.studio.session import Session

OWNER = 1
FULL = OSError(errno.ENOSPC, "No space left on device")


def types(out):
    return [m["type"] for _, m in out]


def perform(session, name, t0=0.0, n=30):
    t = t0 + np.arange(1, n + 1) / 60
    session.begin_take(OWNER, name, ["box.position"], "replace", 0.1, t0, 1.0, {}, None, 0.25)
    out = session.samples(OWNER, name, t, np.c_[np.sin(t), 0 * t + 0.5, t].tolist())
    return t, out


@pytest.fixture
def project(tmp_path):
    return tmp_path / "faults.sketchanim"


@pytest.fixture
def full(monkeypatch):
    """Make the project's saves fail like a full disk until ``full.off()``."""
    class Switch:
        def on(self):
            def refuse(*args, **kwargs):
                raise FULL
            monkeypatch.setattr(Project, "save", refuse)

        def off(self):
            monkeypatch.undo()
    return Switch()


def test_a_failed_save_keeps_the_edit_tells_every_page_once_and_saves_later(project, full, caplog):
    session = Session(project)
    full.on()
    session.set("lamp.intensity", [3.0], None, None)
    out = session.save()
    assert types(out) == ["saved", "notice"]
    assert out[0][1]["ok"] is False and "No space left" in out[0][1]["error"] and out[0][0] == "all"
    assert session.state()["saved"]["ok"] is False
    assert session.tick(1e9) == [] and session.tick(1e9 + saving.RETRY) == []     # retried, not told again
    assert sum("cannot save" in r.getMessage() for r in caplog.records) == 1
    with pytest.raises(StorageError, match="cannot record"):                    # the unsaved edit comes first
        session.begin_take(OWNER, "k", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    assert session.take is None
    full.off()
    out = session.tick(1e9 + 2 * saving.RETRY)
    assert types(out) == ["saved", "notice"] and out[0][1]["ok"] is True
    perform(session, "k")                                                       # records again
    session.end_take(OWNER, "k", None)
    session.close()
    again = Session(project)
    assert again.scene.get("lamp.intensity").tolist() == [3.0] and "box.position" in again.player.tracks
    again.close()


def test_a_save_first_failing_at_a_take_begin_is_told_at_the_next_tick(project, full):
    session = Session(project)
    session.set("lamp.intensity", [3.0], None, None)
    full.on()
    with pytest.raises(StorageError, match="cannot record"):
        session.begin_take(OWNER, "k", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    out = session.tick(0.0)                                 # not yet due for a retry: the news all the same
    assert types(out) == ["saved", "notice"] and out[0][1]["ok"] is False
    full.off()
    session.close()


def test_a_take_ended_while_saves_fail_is_kept_and_saved_when_they_work(project, full):
    session = Session(project)
    t, _ = perform(session, "k")
    full.on()
    session.end_take(OWNER, "k", None)
    assert not session.save()[0][1]["ok"]
    full.off()
    session.tick(1e9)
    session.close()
    again = Session(project)
    track = again.player.tracks["box.position"]
    assert np.array_equal(track.takes[-1].times, t) and again.recovered is None
    again.close()


def test_notes_that_cannot_be_written_refuse_the_take_and_change_nothing(project, monkeypatch):
    session = Session(project)

    def refuse(*args):
        raise OSError(errno.EACCES, "Permission denied", str(notes_path(project)))
    monkeypatch.setattr(session_module, "note_take", refuse)
    with pytest.raises(StorageError, match="Permission denied"):
        session.begin_take(OWNER, "k", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    assert session.take is None and session.state()["take"] is None
    monkeypatch.undo()
    perform(session, "k2")                                      # the fault gone: records
    assert session.end_take(OWNER, "k2", None)[-1][1]["paths"] == ["box.position"]
    session.close()


def test_a_failing_journal_is_told_at_once_retried_and_the_take_kept(project, monkeypatch):
    session = Session(project)
    calls = {"n": 0}
    real = Journal.__call__

    def flaky(self, batches):
        calls["n"] += 1
        raise OSError(errno.ENOSPC, "No space left on device")
    monkeypatch.setattr(Journal, "__call__", flaky)
    t, _ = perform(session, "k")
    import time
    deadline = time.monotonic() + 10
    while calls["n"] == 0 and time.monotonic() < deadline:
        time.sleep(0.02)
    more = t[-1] + np.arange(1, 4) / 60
    out = session.samples(OWNER, "k", more, np.c_[np.sin(more), 0 * more + 0.5, more].tolist())
    told = [m for _, m in out if m["type"] == "notice"]
    assert len(told) == 1 and told[0]["level"] == "error" and "journal cannot be written" in told[0]["text"]
    monkeypatch.setattr(Journal, "__call__", real)
    deadline = time.monotonic() + 10
    while session.take.recorder.journal_error is not None and time.monotonic() < deadline:
        time.sleep(0.02)
    later = more[-1] + np.arange(1, 4) / 60
    out = session.samples(OWNER, "k", later, np.c_[np.sin(later), 0 * later + 0.5, later].tolist())
    assert [m["level"] for _, m in out if m["type"] == "notice"] == ["info"]
    rows = session.project.recovered()["box.position"][0]
    assert np.array_equal(rows[:len(t) + 3], np.r_[t, more])      # what failed was journalled when it could be
    session.end_take(OWNER, "k", None)
    session.close()


def test_a_cancelled_take_is_not_recovered_even_if_the_journal_cannot_be_cleared(project, monkeypatch):
    session = Session(project)
    perform(session, "k")
    monkeypatch.setattr(Project, "clear_journal", lambda self: (_ for _ in ()).throw(FULL))
    session.cancel_take(OWNER, "k")
    assert session.project.recovered()              # the rows are still there...
    session.project.close()                         # ...and the studio dies
    session.lock.release()
    monkeypatch.undo()
    again = Session(project)
    assert again.recovered is None and "box.position" not in again.player.tracks
    assert again.project.recovered() == {}          # cleared at the start's save
    again.close()


def test_a_deleted_project_file_is_written_anew(project):
    session = Session(project)
    session.set("lamp.intensity", [2.5], None, None)
    session.save()
    for name in (project.name, project.name + "-wal", project.name + "-shm"):
        (project.parent / name).unlink(missing_ok=True)
    session.set("lamp.intensity", [4.0], None, None)
    assert session.save() == [] and project.exists()
    session.close()
    again = Session(project)
    assert again.scene.get("lamp.intensity").tolist() == [4.0]
    again.close()


def test_a_vanished_folder_is_reported_and_written_when_it_is_back(tmp_path):
    folder = tmp_path / "usb"
    folder.mkdir()
    project = folder / "show.sketchanim"
    session = Session(project)
    session.set("lamp.intensity", [1.25], None, None)
    shutil.rmtree(folder)
    out = session.save()
    assert out[0][1]["ok"] is False and "folder is gone" in out[0][1]["error"]
    folder.mkdir()                                  # plugged in again
    assert session.tick(1e12)[0][1]["ok"] is True
    session.close()
    again = Session(project)
    assert again.scene.get("lamp.intensity").tolist() == [1.25]
    again.close()


def test_a_stop_while_saves_fail_rescues_the_model_as_a_new_project(project, full, caplog):
    real_save = Project.__dict__["save"]
    session = Session(project)
    session.set("lamp.intensity", [0.75], None, None)
    full.on()
    session.save()
    full.off()
    rescued_saves = []

    def only_copies(self, *args, **kwargs):         # the project's own file still refuses; a copy elsewhere not
        if self.path == project:
            raise FULL
        rescued_saves.append(self.path)
        return real_save(self, *args, **kwargs)
    Project.save = only_copies
    try:
        session.close()
    finally:
        Project.save = real_save
    assert len(rescued_saves) == 1 and rescued_saves[0].name.startswith("faults.rescued-")
    assert any(str(rescued_saves[0]) in r.getMessage() for r in caplog.records)
    rescued = Session(rescued_saves[0])
    assert rescued.scene.get("lamp.intensity").tolist() == [0.75]
    rescued.close()
