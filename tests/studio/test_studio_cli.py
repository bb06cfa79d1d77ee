"""``sketchanim studio`` refuses what it cannot serve with a clear error and status 2."""

from __future__ import annotations

import socket

from typer.testing import CliRunner

from sketchanim.cli import app


def test_a_file_that_is_not_a_project_is_refused(tmp_path):
    bad = tmp_path / "notes.sketchanim"
    bad.write_text("shopping list")
    result = CliRunner().invoke(app, ["studio", str(bad), "--no-browser", "--port", "0"])
    assert result.exit_code == 2 and "not a project file" in result.output and "Traceback" not in result.output
    assert bad.read_text() == "shopping list"


def test_a_busy_port_is_refused(tmp_path):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = CliRunner().invoke(app, ["studio", str(tmp_path / "p.sketchanim"), "--no-browser", "--port", str(port)])
    assert result.exit_code == 2 and str(port) in result.output and "Traceback" not in result.output
    assert not (tmp_path / "p.sketchanim").exists()            # nothing made for a server that did not start
