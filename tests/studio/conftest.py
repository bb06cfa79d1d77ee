"""The studio's shared fixtures: an app on a fresh project through FastAPI's TestClient
(the server in a process of its own is :func:`studio_browser.start_studio`)."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient

from sketchanim.studio.app import create_app


@pytest.fixture
def client(tmp_path):
    """A TestClient on the studio app for ``tmp_path / "p.sketchanim"`` (ready at once)."""
    app = create_app(tmp_path / "p.sketchanim", warm=False)
    with TestClient(app) as c:
        yield c
    app.state.hub.session.close()
