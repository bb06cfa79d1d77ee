"""What the studio page shows when the project cannot be written: a read-only project
(a banner, REC disabled, a drag sends nothing) and saves failing on a full disk (a red
indicator in the header until a save succeeds again). In Debian's chromium against a real
server; each test checks that the page drew something, and leaves screenshots in
/tmp/walk/ for a look."""

from __future__ import annotations

import errno
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from sketchanim.anim.workers import shared_pool
from sketchanim.project.store import Project
from sketchanim.studio.app import create_app
from sketchanim.studio.defaults import default_scene
from studio_browser import drag, free_port, project, studio_server

WALK = Path("/tmp/walk")


def _box_position(doc: dict) -> list[float]:
    """The box's position in a project document."""
    box = next(o for o in doc["objects"] if o["name"] == "box")
    return next(a["value"] for a in box["attributes"] if a["name"] == "position")


@pytest.fixture(scope="module", autouse=True)
def _reducers() -> None:
    """The reducer processes forked before the browser starts (the in-process app's
    Session would fork them later, and a child holding Playwright's pipes keeps its driver
    from ever exiting)."""
    shared_pool()


@pytest.fixture
def read_only_studio(tmp_path: Path) -> Iterator[str]:
    """The URL of ``sketchanim studio PROJECT --read-only`` on a project of the default scene."""
    path = tmp_path / "shown.sketchanim"
    with Project(path) as made:
        made.save(default_scene(), {})
    with studio_server(path, "--read-only") as url:
        yield url


@pytest.fixture
def in_process(tmp_path: Path) -> Iterator[str]:
    """The URL of the studio app on uvicorn in a thread of this process (so a test can
    monkeypatch what it calls); stopped, and its project closed, after."""
    import uvicorn

    app = create_app(tmp_path / "full.sketchanim", warm=False)
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=free_port(), log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        assert thread.is_alive() and time.monotonic() < deadline, "the in-process studio did not start"
        time.sleep(0.05)
    try:
        yield f"http://127.0.0.1:{server.config.port}/"
    finally:
        server.should_exit = True
        thread.join(30)
        app.state.hub.session.close()


def test_a_read_only_project_shows_a_banner_disables_rec_and_a_drag_sends_nothing(read_only_studio, _page) -> None:  # noqa: ANN001
    page = _page(read_only_studio)
    before = project(read_only_studio)
    banner = page.locator("[data-testid=read-only]")
    banner.wait_for(state="visible")
    assert banner.inner_text() == "read-only project: plays and exports; edits are refused"
    assert page.locator("[data-testid=record]").is_disabled()
    assert page.locator("[data-testid=undo]").is_disabled() and page.locator("[data-testid=redo]").is_disabled()
    page.keyboard.press("r")
    assert not page.evaluate("studio.transport.record"), "R turned record mode on"
    page.evaluate("""() => { window.sent = []; const send = studio.send.bind(studio);
        studio.send = (m) => { sent.push(m.type); send(m); }; }""")
    start = page.evaluate("viewport.screenOf('box')")
    drag(page, start, [(6 * i, -3 * i) for i in range(1, 25)])
    page.locator("[data-object=box]").click()
    assert page.locator("[data-testid='edit-box.position-0']").is_disabled()
    sent = page.evaluate("sent")
    assert not {"set", "preview", "take.begin"} & set(sent), f"the page sent edits to a read-only project: {sent}"
    assert project(read_only_studio) == before, "the drag changed the project"
    assert page.evaluate("studio.errors") == [], "the server refused something the page sent"
    shown = page.evaluate("studio.values.get('box.position')")
    assert shown == _box_position(before), "the box did not go back to where the project has it"
    WALK.mkdir(exist_ok=True)
    page.screenshot(path=str(WALK / "read-only.png"))
    assert not page.errors, page.errors


def test_a_failed_save_shows_in_the_header_until_a_save_succeeds(in_process, _page, monkeypatch) -> None:  # noqa: ANN001
    url = in_process
    page = _page(url)
    indicator = page.locator("[data-testid=save-status]")
    assert indicator.is_hidden()

    def full(self, *args, **kwargs) -> None:  # noqa: ANN001, ANN002, ANN003
        raise OSError(errno.ENOSPC, "No space left on device")

    saves = Project.save
    monkeypatch.setattr(Project, "save", full)
    page.locator("[data-object=box]").click()
    field = page.locator("[data-testid='edit-box.position-0']")
    field.fill("1.25")
    field.press("Tab")
    indicator.wait_for(state="visible", timeout=20_000)
    text = indicator.inner_text()
    assert "not saved" in text and "No space left" in text and "kept in memory, retrying (since " in text, text
    assert indicator.get_attribute("role") == "alert"
    WALK.mkdir(exist_ok=True)
    page.screenshot(path=str(WALK / "save-status.png"))
    record, transport = (page.locator(f"[data-testid={t}]").bounding_box() for t in ("record", "transport"))
    box = indicator.bounding_box()
    assert box["y"] + box["height"] <= min(record["y"], transport["y"]), "the indicator covers REC or the transport"

    monkeypatch.setattr(Project, "save", saves)                  # the disk has room again
    indicator.wait_for(state="hidden", timeout=30_000)           # the server's next retry saved it
    page.locator("[data-testid=notice][data-level=info]", has_text="saved full.sketchanim again").wait_for()
    assert _box_position(project(url))[0] == pytest.approx(1.25), "the edit was not saved"
    assert not page.errors, page.errors
