"""The animator's take tolerances: set through the protocol, checked by the server, kept
by the project across a restart, an export and an import, carried by a rename."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.errors import ArgumentError, FileFormatError
from sketchanim.project.store import Project
from sketchanim.studio import protocol as p
from sketchanim.studio.session import Session

AMOUNTS = st.floats(min_value=1e-9, max_value=1e9, allow_nan=False, allow_infinity=False)


@settings(max_examples=25, deadline=None)
@given(amount=AMOUNTS, unit=st.sampled_from(["px", "units"]), other=AMOUNTS)
def test_a_tolerance_is_kept_across_a_restart(amount: float, unit: str, other: float) -> None:
    path = Path(tempfile.mkdtemp()) / "tol.sketchanim"
    session = Session(path)
    out = session.set_tolerance("box.position", amount, unit)
    assert out == [("all", {"type": "tolerances", "tolerances": {"box.position": {"amount": amount, "unit": unit}}})]
    session.set_tolerance("lamp.color", other, "px")
    session.set_tolerance("lamp.color", None, "px")            # back to what the input resolves
    session.close()
    again = Session(path)
    try:
        assert again.state()["tolerances"] == {"box.position": {"amount": amount, "unit": unit}}
    finally:
        again.close()


def test_an_export_and_an_import_keep_the_tolerances(tmp_path: Path) -> None:
    session = Session(tmp_path / "a.sketchanim")
    session.set_tolerance("box.position", 3.0, "px")
    session.set_tolerance("cam.fov", 0.2, "units")
    session.save()
    exported = session.project.export_json(tmp_path / "a.json")
    session.close()
    with Project(tmp_path / "b.sketchanim") as project:
        project.import_json(exported)
        kept = project.tolerances(project.load()[0])
    assert {k: (t.amount, t.unit) for k, t in kept.items()} == {"box.position": (3.0, "px"), "cam.fov": (0.2, "units")}


def test_a_rename_carries_the_tolerance_and_a_removed_object_leaves_none(tmp_path: Path) -> None:
    session = Session(tmp_path / "a.sketchanim")
    session.set_tolerance("ball.position", 4.0, "px")
    session.set_tolerance("cone.position", 5.0, "px")
    session.rename_object("ball", "sphere")
    session.remove_object("cone")
    session.close()
    again = Session(tmp_path / "a.sketchanim")
    try:
        assert again.state()["tolerances"] == {"sphere.position": {"amount": 4.0, "unit": "px"}}
    finally:
        again.close()


@pytest.mark.parametrize("text", ['{"type": "tolerance.set", "path": "box.position", "amount": 0}',
                                  '{"type": "tolerance.set", "path": "box.position", "amount": -1}',
                                  '{"type": "tolerance.set", "path": "box.position", "amount": 1e999}',
                                  '{"type": "tolerance.set", "path": "box.position", "amount": 1, "unit": "mm"}'])
def test_the_server_refuses_a_tolerance_that_is_not_positive_and_finite(text: str) -> None:
    with pytest.raises(p.BadMessage, match="tolerance.set"):
        p.parse(text)


def test_the_server_refuses_a_tolerance_for_what_is_not_performed(tmp_path: Path) -> None:
    session = Session(tmp_path / "a.sketchanim")
    try:
        with pytest.raises(ArgumentError, match="box.visible: a bool attribute is set, not performed"):
            session.set_tolerance("box.visible", 1.0, "px")
        with pytest.raises(ArgumentError, match="no object 'nothing'"):
            session.set_tolerance("nothing.position", 1.0, "px")
    finally:
        session.close()


def test_a_document_with_a_tolerance_for_no_attribute_is_refused_by_name(tmp_path: Path) -> None:
    session = Session(tmp_path / "a.sketchanim")
    session.set_tolerance("box.position", 2.0, "px")
    session.save()
    exported = session.project.export_json(tmp_path / "a.json")
    session.close()
    exported.write_text(exported.read_text().replace('"box.position": {', '"box.nothing": {'))
    with Project(tmp_path / "c.sketchanim") as project, pytest.raises(FileFormatError, match="tolerances.box.nothing"):
        project.import_json(exported)
