"""Every action in the studio does what it says, in a real browser (Debian's chromium,
driven by Playwright, against a real server): undo after a drag or a gizmo turn, the keys
whichever control has focus, two pages on one project while one records, the transport's
controls after a reload, a take over an attribute that had a value. Every test also checks
that the page drew something."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest

from studio_browser import drag, drew_something, last_take



#: Where the second page's screenshots go (to look at; not compared).
SHOTS = Path(tempfile.gettempdir()) / "sketchanim-screenshots"


def _served(page, path: str) -> list:  # noqa: ANN001
    """The scene's value at ``path`` as the server holds it (GET /api/state)."""
    state = page.evaluate("fetch('/api/state').then(r => r.json())")
    obj, attr = path.split(".")
    return next(a["value"] for o in state["objects"] if o["name"] == obj for a in o["attributes"] if a["name"] == attr)


def _gizmo_ring(page, centre: dict) -> tuple[float, float] | None:  # noqa: ANN001
    """A radius and angle around ``centre`` (page pixels) where the pointer hovers an axis of
    the transform controls, the pointer left there; None if there is none."""
    for r in range(30, 160, 6):
        for a in np.linspace(0, 2 * np.pi, 24, endpoint=False):
            page.mouse.move(centre["x"] + r * np.cos(a), centre["y"] + r * np.sin(a))
            if page.evaluate("viewport.transform.axis") is not None:
                return float(r), float(a)
    return None


def test_a_plain_drag_and_a_gizmo_turn_are_undone_exactly(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    before = page.evaluate("studio.values.get('box.position')")
    start = page.evaluate("viewport.screenOf('box')")
    drag(page, start, [(4 * i, -2 * i) for i in range(1, 30)])
    page.wait_for_function("studio.history.undo.length === 1")
    moved = page.evaluate("studio.values.get('box.position')")
    assert np.linalg.norm(np.subtract(moved, before)) > 0.3 and _served(page, "box.position") == moved
    page.click("[data-testid=undo]")
    page.wait_for_function("studio.history.can_redo")
    page.wait_for_timeout(200)
    assert page.evaluate("studio.values.get('box.position')") == before
    assert _served(page, "box.position") == before, "undo did not restore the value before the drag"
    # a gizmo turn with the pointer: find a ring of the rotate gizmo (where the controls hover an
    # axis), press on it and drag along it
    turned0 = page.evaluate("studio.values.get('box.orientation')")
    page.click("[data-testid=outliner] li[data-object=box]")
    page.keyboard.press("e")
    centre = page.evaluate("viewport.screenOf('box')")
    ring = _gizmo_ring(page, centre)
    assert ring is not None, "no ring of the rotate gizmo under the pointer around the box"
    r, a = ring
    page.mouse.down()
    for k in range(1, 25):
        page.wait_for_timeout(16)
        page.mouse.move(centre["x"] + r * np.cos(a + 0.04 * k), centre["y"] + r * np.sin(a + 0.04 * k))
    page.wait_for_timeout(16)
    page.mouse.up()
    page.wait_for_function("studio.history.undo.length === 1 && studio.history.undo[0].startsWith('rotate')")
    assert _served(page, "box.orientation") != turned0
    page.keyboard.press("Control+z")
    page.wait_for_function("studio.history.undo.length === 0 && studio.history.can_redo")
    page.wait_for_timeout(200)
    assert _served(page, "box.orientation") == turned0, "undo did not restore the orientation before the turn"
    assert page.evaluate("studio.values.get('box.orientation')") == turned0
    assert drew_something(page) > 5 and not page.errors


def test_keys_do_the_same_whichever_control_has_focus(_page, studio: str) -> None:  # noqa: ANN001
    """Enter / Space / R after clicking each button, after using each menu and with the
    checkbox focused: the shortcut alone, never the focused control as well."""
    page = _page(studio)
    state = "({record: studio.transport.record, playing: studio.transport.clock.playing, undo: studio.history.undo.length, " \
            "loop: !!studio.transport.clock.loop, rec: document.querySelector('[data-testid=loop-record]').checked})"
    start = page.evaluate("viewport.screenOf('box')")
    drag(page, start, [(3 * i, 0) for i in range(1, 20)])
    drag(page, page.evaluate("viewport.screenOf('ball')"), [(0, -3 * i) for i in range(1, 20)])
    page.wait_for_function("studio.history.undo.length === 2")
    # undo: one step for the click; Enter then stops, it does not undo again
    page.click("[data-testid=undo]")
    page.wait_for_function("studio.history.undo.length === 1")
    page.keyboard.press("Space")
    page.wait_for_timeout(100)
    assert page.evaluate(state)["playing"] is True
    page.keyboard.press("Enter")
    page.wait_for_timeout(300)
    s = page.evaluate(state)
    assert s["undo"] == 1 and s["playing"] is False, f"Enter after clicking undo: {s}"
    # redo the same
    page.click("[data-testid=redo]")
    page.wait_for_function("studio.history.undo.length === 2")
    page.keyboard.press("Enter")
    page.wait_for_timeout(300)
    assert page.evaluate(state)["undo"] == 2
    # REC: Enter stops (record mode off), Space plays, R toggles record mode once
    page.click("[data-testid=record]")
    assert page.evaluate(state)["record"] is True
    page.keyboard.press("Enter")
    page.wait_for_timeout(100)
    assert page.evaluate(state)["record"] is False, "Enter after clicking REC left record mode on"
    page.keyboard.press("r")
    assert page.evaluate(state)["record"] is True
    page.keyboard.press("r")
    assert page.evaluate(state)["record"] is False
    # play / stop / loop buttons: Space toggles play once, R records, Enter stops
    for button in ("play", "stop", "loop"):
        page.click(f"[data-testid={button}]")
        before = page.evaluate(state)
        page.keyboard.press("Space")
        page.wait_for_timeout(100)
        after = page.evaluate(state)
        assert after["playing"] != before["playing"] and after["loop"] == before["loop"], f"Space after {button}"
        page.keyboard.press("Enter")
        page.wait_for_timeout(100)
        assert page.evaluate(state)["playing"] is False, f"Enter after {button}"
    # each menu: after a choice, Space plays and R records (the menu neither opens nor jumps)
    for menu, value in (("speed", "0.5"), ("mode", "additive"), ("count-in", "1"), ("capture-speed", "0.5")):
        page.select_option(f"[data-testid={menu}]", value)
        page.focus(f"[data-testid={menu}]")
        page.keyboard.press("Space")
        page.wait_for_timeout(100)
        assert page.evaluate(state)["playing"] is True, f"Space after the {menu} menu"
        page.keyboard.press("Space")
        page.keyboard.press("r")
        assert page.evaluate(state)["record"] is True, f"R after the {menu} menu"
        page.keyboard.press("r")
        assert page.evaluate(f"document.querySelector('[data-testid={menu}]').value") == value, f"a key changed {menu}"
        page.keyboard.press("Enter")
    # the checkbox focused: Space plays, the box does not toggle
    page.click("[data-testid=loop-record]")
    assert page.evaluate(state)["rec"] is True
    page.keyboard.press("Space")
    page.wait_for_timeout(100)
    s = page.evaluate(state)
    assert s["playing"] is True and s["rec"] is True, f"Space with the checkbox focused: {s}"
    page.keyboard.press("Enter")
    # typing into a number field: the keys are the field's
    page.click("[data-testid=outliner] li[data-object=box]")
    page.focus("[data-testid='edit-box.position-0']")
    page.keyboard.press("r")
    assert page.evaluate(state)["record"] is False
    assert drew_something(page) > 5 and not page.errors


def test_a_second_page_sees_the_take_read_only_and_cannot_record(_page, studio: str) -> None:  # noqa: ANN001
    SHOTS.mkdir(parents=True, exist_ok=True)
    a, b = _page(studio), _page(studio)
    b.click("[data-testid=record]")                         # b in record mode before a's take
    ball0 = b.evaluate("studio.values.get('ball.position')")
    a.click("[data-testid=record]")
    a.wait_for_timeout(100)
    start = a.evaluate("viewport.screenOf('box')")
    a.mouse.move(start["x"], start["y"])
    a.mouse.down()
    for i in range(1, 30):
        a.wait_for_timeout(16)
        a.mouse.move(start["x"] + 4 * i, start["y"] - 2 * i)
    a.wait_for_function("!!(studio.performer.grab && studio.performer.grab.take)")
    b.wait_for_function("studio.remoteTake !== null")
    box_b = b.evaluate("studio.values.get('box.position')")
    moved = lambda: b.evaluate(f"studio.pieces.size > 0 && studio.values.get('box.position')[0] !== {box_b[0]}")  # noqa: E731
    for i in range(30, 600):                       # a keeps dragging until b shows a piece of it
        if i % 10 == 0 and moved():
            break
        a.wait_for_timeout(16)
        a.mouse.move(start["x"] + 120 * np.sin(i / 20), start["y"] - 60 * np.sin(i / 30))
    assert moved(), "b shows none of a's take"
    status = b.locator("[data-testid=take-status]").inner_text()
    assert "recording in another tab" in status and "box.position" in status, status
    assert b.evaluate("document.body.classList.contains('remote-recording')")
    for shot in (SHOTS / "remote-1.png", SHOTS / "remote-2.png"):
        b.screenshot(path=str(shot))
        b.wait_for_timeout(150)
    # b grabs the ball in record mode meanwhile: no take, and it keeps the server's value
    drag(b, b.evaluate("viewport.screenOf('ball')"), [(0, -4 * i) for i in range(1, 20)])
    b.wait_for_timeout(200)
    assert b.evaluate("studio.takes.length") == 0 and not b.evaluate("studio.errors")
    assert b.evaluate("studio.values.get('ball.position')") == ball0 == _served(b, "ball.position")
    assert b.evaluate("document.querySelector('[data-testid=record]').disabled") is False   # b was in record mode
    b.click("[data-testid=record]")
    b.keyboard.press("r")
    assert b.evaluate("studio.transport.record") is False, "b turned record mode on while a records"
    assert b.evaluate("document.querySelector('[data-testid=record]').disabled") is True
    a.mouse.up()
    take = last_take(a)
    assert take["label"]
    b.wait_for_function("studio.remoteTake === null && studio.tracks.has('box.position')", timeout=30_000)
    b.wait_for_timeout(200)
    # what b shows is what the server holds: the track at b's time
    shown = np.array(b.evaluate("studio.values.get('box.position')"))
    track = np.array(b.evaluate("(() => { studio.writeTracks(studio.transport.time); "
                                "return studio.values.get('box.position'); })()"))
    assert np.allclose(shown, track) and "another tab" not in b.locator("[data-testid=take-status]").inner_text()
    b.keyboard.press("r")
    assert b.evaluate("studio.transport.record") is True, "b cannot record after a's take"
    assert drew_something(b) > 5 and drew_something(a) > 5 and not a.errors and not b.errors


def test_a_reload_shows_the_transport_as_it_is(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    page.select_option("[data-testid=speed]", "0.5")
    page.select_option("[data-testid=count-in]", "2")
    page.select_option("[data-testid=capture-speed]", "0.25")
    page.select_option("[data-testid=mode]", "additive")
    page.select_option("[data-testid=smoothing]", "0.05")
    page.click("[data-testid=loop-record]")
    page.click("[data-testid=loop]")
    page.click("[data-testid=play]")
    page.wait_for_timeout(300)
    page.reload()
    page.wait_for_selector("body[data-ready=true]", timeout=60_000)
    controls = page.evaluate("""() => Object.fromEntries(['speed', 'count-in', 'capture-speed', 'mode', 'smoothing'].map(
        (k) => [k, document.querySelector(`[data-testid=${k}]`).value]))""")
    assert controls == {"speed": "0.5", "count-in": "2", "capture-speed": "0.25", "mode": "additive", "smoothing": "0.05"}
    assert page.evaluate("document.querySelector('[data-testid=loop-record]').checked") is True
    assert page.evaluate("document.querySelector('[data-testid=loop]').classList.contains('on')") is True
    t = page.evaluate("[studio.transport.playSpeed, studio.transport.countIn, studio.transport.captureSpeed, "
                      "studio.performer.mode, studio.performer.loopRecord, studio.performer.smoothing]")
    assert t == [0.5, 2, 0.25, "additive", True, 0.05]
    # a reloaded page starts paused, and its play button says so
    assert page.evaluate("studio.transport.clock.playing") is False
    assert page.locator("[data-testid=play]").inner_text() == "▶"
    page.click("[data-testid=play]")
    assert page.locator("[data-testid=play]").inner_text() == "❚❚"
    # playback really runs at half speed: transport time over real time
    t0 = page.evaluate("[studio.transport.clock.raw(performance.now()), performance.now()]")
    page.wait_for_timeout(500)
    t1 = page.evaluate("[studio.transport.clock.raw(performance.now()), performance.now()]")
    loop = page.evaluate("studio.transport.clock.loop")
    rate = (t1[0] - t0[0]) / ((t1[1] - t0[1]) / 1000)
    assert loop is not None and (rate == pytest.approx(0.5, abs=0.02) or t1[0] < t0[0]), rate   # or it wrapped
    assert drew_something(page) > 5 and not page.errors


def test_a_colour_take_at_a_later_time_keeps_the_colour_before_it(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    page.click("[data-testid=outliner] li[data-object=lamp]")
    before = page.evaluate("studio.values.get('lamp.color')")
    page.evaluate("studio.transport.seek(1.0)")
    page.click("[data-testid=record]")
    page.wait_for_function("studio.transport.time > 1.2")
    picker = "[data-testid='color-lamp.color']"
    for colour in ("#ff2000", "#ee3010", "#dd4020", "#cc5030", "#bb6040", "#aa7050"):
        page.evaluate("([sel, c]) => { const p = document.querySelector(sel); p.value = c; "
                      "p.dispatchEvent(new Event('input')); }", [picker, colour])
        page.wait_for_timeout(60)
    page.evaluate("(sel) => document.querySelector(sel).dispatchEvent(new Event('change'))", picker)
    take = last_take(page)
    assert take["paths"] == ["lamp.color"] and take["times"][0] > 1.2
    page.click("[data-testid=record]")
    page.wait_for_function("studio.tracks.has('lamp.color')")
    # the page's evaluation of the track: the colour before the take (it eases onto the take's
    # first sample over the blend, 0.1 s, before it), the picked colours after
    shown = page.evaluate("""(ts) => ts.map((t) => { studio.transport.seek(t); return studio.values.get('lamp.color'); })""",
                          [0.0, 0.5, 1.0, take["times"][0] - 0.1 - 1e-3])
    assert np.abs(np.array(shown) - before).max() <= 0.005, f"the lamp's colour before the take changed: {shown}"
    end = page.evaluate("(t) => { studio.transport.seek(t); return studio.values.get('lamp.color'); }",
                        take["times"][-1])
    assert np.abs(np.array(end) - take["rows"][-1]).max() <= 0.005
    first = page.evaluate("(t) => { studio.transport.seek(t); return studio.values.get('lamp.color'); }",
                          take["times"][0])
    assert np.abs(np.array(first) - take["rows"][0]).max() <= 0.005, "the take's first sample was not kept"
    assert drew_something(page) > 5 and not page.errors
