"""The one-studio-per-project lock: beside the project, or, where nothing can be created
there (read-only media), in the user's temporary folder, and exclusive either way."""

from __future__ import annotations

import errno
import os
import tempfile

import pytest

from sketchanim.errors import ArgumentError
from sketchanim.project import lock as lock_module
from sketchanim.project.lock import ProjectLock, fallback_path


@pytest.fixture
def unwritable_beside(monkeypatch, tmp_path):
    """Creating a file beside the project fails as on read-only media (EROFS)."""
    real = os.open

    def refuse(path, flags, *args, **kwargs):
        if os.path.realpath(os.path.dirname(os.fspath(path))) == str(tmp_path.resolve()) and flags & os.O_CREAT:
            raise OSError(errno.EROFS, os.strerror(errno.EROFS), os.fspath(path))
        return real(path, flags, *args, **kwargs)

    monkeypatch.setattr(lock_module.os, "open", refuse)


def test_the_lock_goes_to_the_temporary_folder_and_still_excludes(tmp_path, unwritable_beside):
    path = tmp_path / "p.sketchanim"
    first = ProjectLock(path)
    try:
        assert first.path == fallback_path(path) and str(first.path.parent) == tempfile.gettempdir()
        assert not (tmp_path / "p.sketchanim.lock").exists()
        with pytest.raises(ArgumentError, match="open in another studio"):
            ProjectLock(tmp_path / ".." / tmp_path.name / "p.sketchanim")      # the same project, named otherwise
    finally:
        first.release()
    assert not fallback_path(path).exists()
    ProjectLock(path).release()                                                 # free again


def test_a_lock_file_left_on_read_only_media_still_locks(tmp_path, unwritable_beside):
    beside = tmp_path / "p.sketchanim.lock"
    beside.write_bytes(b"")             # (not os.open) a studio killed before the media became read-only left it
    first = ProjectLock(tmp_path / "p.sketchanim")
    try:
        assert first.path == beside
        with pytest.raises(ArgumentError, match="open in another studio"):
            ProjectLock(tmp_path / "p.sketchanim")
    finally:
        first.release()


def test_other_faults_are_not_hidden(tmp_path, monkeypatch):
    def vanished(path, flags, *args, **kwargs):
        raise OSError(errno.ENOENT, os.strerror(errno.ENOENT), os.fspath(path))

    monkeypatch.setattr(lock_module.os, "open", vanished)
    with pytest.raises(FileNotFoundError):
        ProjectLock(tmp_path / "gone" / "p.sketchanim")


def test_different_projects_have_different_fallbacks(tmp_path):
    assert fallback_path(tmp_path / "a.sketchanim") != fallback_path(tmp_path / "b.sketchanim")
    assert fallback_path(tmp_path / "a.sketchanim").name.startswith(f"sketchanim-{os.getuid()}-")
