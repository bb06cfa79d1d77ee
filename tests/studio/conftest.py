"""The studio's shared fixtures: a session, and an app, on a fresh project (the app through FastAPI's TestClient);
for page tests, a headless chromium (one per module), a real server on a fresh project
(:func:`studio_browser.studio_server`) and an opener of pages on it."""

from __future__ import annotations

from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from sketchanim.studio.app import create_app
from sketchanim.studio.session import Session
from studio_browser import drew_something, launch, open_page, studio_server, viewport_drew


@pytest.fixture
def client(tmp_path):
    """A TestClient on the studio app for ``tmp_path / "p.sketchanim"`` (ready at once)."""
    app = create_app(tmp_path / "p.sketchanim", warm=False)
    with TestClient(app) as c:
        yield c
    app.state.hub.session.close()


@pytest.fixture
def session(tmp_path):
    """A :class:`Session` on a fresh project, ``tmp_path / "s.sketchanim"``, closed after."""
    s = Session(tmp_path / "s.sketchanim")
    yield s
    s.close()


@pytest.fixture(scope="module")
def browser():  # noqa: ANN201
    """Debian's chromium through Playwright (a dev dependency: scripts/setup installs it)."""
    playwright_api = pytest.importorskip("playwright.sync_api", reason="playwright is a dev dependency (scripts/setup)")
    with playwright_api.sync_playwright() as p:
        b = launch(p)
        yield b
        b.close()


@pytest.fixture
def studio(tmp_path: Path):  # noqa: ANN201
    """The URL of a studio server on a fresh project in ``tmp_path``."""
    with studio_server(tmp_path / "studio.sketchanim") as url:
        yield url


@pytest.fixture
def _page(browser):  # noqa: ANN001, ANN201
    """Opens pages on a studio (checking they drew something); closes them after the test,
    so no page reconnects to the next test's server."""
    pages = []

    def opener(url: str, init_script: str | None = None):  # noqa: ANN202
        page = open_page(browser, url, init_script)
        pages.append(page)
        assert drew_something(page) > 5 and viewport_drew(page) > 5, "the page drew nothing"
        return page

    yield opener
    for page in pages:
        page.close()
