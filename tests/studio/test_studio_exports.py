"""Studio exports: a bare file name in the exports folder, never the project's own files,
an existing file replaced only when asked to (a folder never), disk faults answered as
``failed`` with nothing left behind."""

from __future__ import annotations

import errno
import json
import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.atomic import SUFFIX
from sketchanim.errors import InputError
from sketchanim.studio import protocol as p
from sketchanim.studio.exports import MAX_NAME_BYTES
from sketchanim.studio.handlers import error_code, handle
from sketchanim.studio.session import Session


@pytest.fixture(scope="module")
def session():
    folder = Path(tempfile.mkdtemp())
    session = Session(folder / "p.sketchanim")
    yield session
    session.close()


def export(session: Session, file: str, overwrite: bool = False) -> tuple[str, str]:
    """The reply to an ``export`` message: ("exported", file) or (its error code, message)."""
    try:
        message = p.parse(json.dumps({"type": "export", "id": 1, "file": file, "overwrite": overwrite}))
    except p.BadMessage as err:
        return "bad_message", str(err)
    try:
        [(_, reply)] = handle(session, message, 0)
    except InputError as err:
        return error_code(message, err, session), str(err)
    return reply["type"], reply["file"]


def listing(folder: Path) -> set[str]:
    return set(os.listdir(folder))


HOSTILE = [
    ("a\x00b.glb", "refused", "control characters"),
    ("a\nb.json", "refused", "control characters"),
    ("a\ud800.glb", "bad_message", "valid string"),              # the protocol refuses it first
    ("あ" * 84 + ".glb", "refused", "bytes long"),              # 256 bytes in UTF-8, 88 characters
    ("a/b.glb", "refused", "not a path"),
    ("a\\b.glb", "refused", "not a path"),
    ("..", "refused", "hidden"),
    (".", "refused", "hidden"),
    (".x.glb", "refused", "hidden"),
    (f".p.glb.1.x{SUFFIX}", "refused", "hidden"),            # an atomic writer's temporary file
    ("", "bad_message", "at least 1 character"),                 # the protocol refuses it first
    ("x.txt", "refused", ".glb or .json"),
    ("p.sketchanim", "refused", ".glb or .json"),
    ("p.sketchanim-wal", "refused", ".glb or .json"),
    ("p.sketchanim.lock", "refused", ".glb or .json"),
    ("p.sketchanim.take.json", "refused", "own files"),
    ("P.SKETCHANIM.take.json", "refused", "own files"),          # the same file where names ignore case
    ("p.sketchanim.x.glb", "refused", "own files"),
    ("other.sketchanim.take.json", "refused", "own files"),      # another project's take notes
]


@pytest.mark.parametrize("name, code, why", HOSTILE)
def test_hostile_names_are_refused_by_name_and_the_session_goes_on(session, name, code, why):
    before = listing(session.folder)
    got, message = export(session, name)
    assert (got, why in message) == (code, True), message
    assert code == "bad_message" or repr(name)[:20] in message         # the protocol names the field
    assert listing(session.folder) == before
    assert export(session, "after.glb", overwrite=True) == ("exported", "after.glb")


def test_a_name_no_file_system_encodes_is_refused_by_the_session_too(session):
    with pytest.raises(InputError, match="lone surrogates"):
        session.export("a\ud800.glb")


def test_a_name_of_the_longest_length_is_written(session):
    name = "あ" * ((MAX_NAME_BYTES - 4) // 3) + "x" * ((MAX_NAME_BYTES - 4) % 3) + ".glb"
    assert len(os.fsencode(name)) == MAX_NAME_BYTES
    assert export(session, name) == ("exported", name)
    assert export(session, "y" + name)[0] == "refused"
    (session.folder / name).unlink()


def test_a_folder_is_never_replaced(session):
    (session.folder / "dir.glb").mkdir()
    for overwrite in (False, True):
        code, message = export(session, "dir.glb", overwrite)
        assert code == "exists" and "'dir.glb' is a folder" in message
    assert (session.folder / "dir.glb").is_dir() and not os.listdir(session.folder / "dir.glb")


def test_an_existing_file_is_kept_unless_overwrite(session):
    for name, magic in (("shot.glb", b"glTF"), ("shot.json", b"{")):
        mine = session.folder / name
        mine.write_bytes(b"the animator's own file")
        code, message = export(session, name)
        assert code == "exists" and repr(name) in message and "overwrite" in message
        assert mine.read_bytes() == b"the animator's own file"
        assert export(session, name, overwrite=True) == ("exported", name)
        assert mine.read_bytes().startswith(magic)


def test_a_link_of_the_name_is_not_followed(session, tmp_path):
    outside = tmp_path / "outside.glb"
    outside.write_bytes(b"outside")
    link = session.folder / "link.glb"
    link.symlink_to(outside)
    assert export(session, "link.glb")[0] == "exists"
    assert export(session, "link.glb", overwrite=True) == ("exported", "link.glb")
    assert outside.read_bytes() == b"outside" and not link.is_symlink()         # the link was replaced


@pytest.mark.parametrize("fault, where", [(errno.ENOSPC, "fsync"), (errno.EACCES, "mkstemp"), (errno.EROFS, "replace")])
@pytest.mark.parametrize("name", ["fault.glb", "fault.json"])
def test_a_disk_fault_fails_by_name_and_leaves_nothing(session, monkeypatch, fault, where, name):
    old = session.folder / name
    old.write_bytes(b"old")
    before = listing(session.folder)

    def refuse(*args, **kwargs):
        raise OSError(fault, os.strerror(fault))

    monkeypatch.setattr(tempfile if where == "mkstemp" else os, where, refuse)
    code, message = export(session, name, overwrite=True)
    monkeypatch.undo()
    assert code == "failed" and repr(name) in message and os.strerror(fault) in message, message
    assert listing(session.folder) == before and old.read_bytes() == b"old"
    assert not [f for f in os.listdir(session.folder) if f.endswith(SUFFIX)]
    assert export(session, name, overwrite=True) == ("exported", name)        # the fault gone, it works


def test_a_fault_writing_a_new_export_leaves_no_file(session, monkeypatch):
    before = listing(session.folder)
    monkeypatch.setattr(os, "fsync", lambda fd: (_ for _ in ()).throw(OSError(errno.ENOSPC, "No space")))
    assert export(session, "new.glb")[0] == "failed"
    monkeypatch.undo()
    assert listing(session.folder) == before


def test_exports_go_to_the_exports_folder(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    session = Session(tmp_path / "p.sketchanim", exports=out)
    try:
        before = listing(tmp_path)
        assert export(session, "a.glb") == ("exported", "a.glb")
        assert listing(out) == {"a.glb"} and listing(tmp_path) == before
    finally:
        session.close()
    with pytest.raises(InputError, match="exports: .*missing is not a folder"):
        Session(tmp_path / "q.sketchanim", exports=tmp_path / "missing")


NAMES = st.one_of(
    st.text(max_size=300),
    st.builds(lambda stem, suffix: stem + suffix,
              st.text(st.characters(codec="utf-8"), min_size=0, max_size=90),
              st.sampled_from([".glb", ".json", ".GLB", ".txt", "", ".sketchanim", ".take.json"])),
    st.builds(lambda end: "p.sketchanim" + end, st.sampled_from(["", "-wal", "-shm", ".lock", ".take.json", ".a.glb"])),
)


@settings(max_examples=80, deadline=None)
@given(name=NAMES, overwrite=st.booleans())
def test_any_name_is_refused_or_written_in_the_exports_folder_only(session, name, overwrite):
    with tempfile.TemporaryDirectory() as home:
        out = Path(home)
        (out / "existing.glb").write_bytes(b"keep")
        session.exports = out
        try:
            before, project_before = listing(out), listing(session.folder)
            code, what = export(session, name, overwrite)
            after = listing(out)
        finally:
            session.exports = session.folder
        assert listing(session.folder) == project_before
        if code == "exported":
            assert what == name and (after - before == {name} or (overwrite and name in before and after == before))
            assert not name.startswith(".") and Path(name).suffix.lower() in (".glb", ".json")
            assert (out / name).stat().st_size > 0
        else:
            assert code in ("bad_message", "refused", "exists") and after == before, (code, what)
        assert (out / "existing.glb").read_bytes() == b"keep" or (overwrite and name == "existing.glb")
