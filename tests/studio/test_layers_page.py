"""The layers panel (a track's takes), the outliner's object tools, the transport's frames and
frame rate, and the help overlay, in a real browser (Debian's chromium through Playwright)
against a real server. Every test checks the page drew something."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.layers import compose, recorded_over
from sketchanim.anim.tracks import Take
from sketchanim.project.store import Project
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.protocol import FRAME_RATES
from sketchanim.studio.takes import ORDER
from studio_browser import curve, drew_something, project, studio_server

ROOT = Path(__file__).resolve().parents[2]
PATH = "box.position"
TOL = 0.005


def _takes() -> list[Take]:
    """Three takes of the box's position: a punch-in over 0..3 s, an additive bump over
    1..2 s, a punch-in over 2.5..3.5 s."""
    t = np.linspace(0, 3, 91)
    mid = t[30:60]
    late = t[60:] + 0.5
    return [Take(t, np.c_[np.sin(t), 0.5 + 0 * t, np.cos(t)]),
            Take(mid, np.c_[0 * mid, 0.3 * np.sin(np.pi * (mid - 1)), 0 * mid], "additive"),
            Take(late, np.c_[-1 + 0 * late, 0.5 + 0 * late, late])]


def _takes_project(folder: Path) -> Path:
    """A project of the default scene with the box's position recorded in three takes."""
    track = None
    for take in _takes():
        track = recorded_over(PATH, POSITION, track, take, TOL, ORDER)
    path = folder / "takes.sketchanim"
    Project(path).save(default_scene(), {PATH: track})
    return path


@pytest.fixture
def takes_studio(tmp_path: Path):  # noqa: ANN201
    """A studio on :func:`_takes_project`."""
    with studio_server(_takes_project(tmp_path)) as url:
        yield url


def _composed_equal(doc: dict, takes: list[Take]) -> None:
    """The track in ``doc`` is ``compose`` of ``takes`` (knots and coefficients to 1e-9)."""
    spline, _ = curve(doc, PATH)
    expected = compose(POSITION, takes, TOL, ORDER)
    assert spline.k == expected.k and len(spline.t) == len(expected.t)
    assert np.abs(spline.t - expected.t).max() <= 1e-9
    assert np.abs(spline.c - expected.c).max() <= 1e-9


def _history(page) -> int:  # noqa: ANN001
    return page.evaluate("studio.history.undo.length")


def _edit(page, selector: str) -> None:  # noqa: ANN001
    """Click ``selector`` and wait for its History step."""
    steps = _history(page)
    page.click(selector)
    page.wait_for_function(f"() => studio.history.undo.length === {steps + 1}")


def _undo(page, button: str = "[data-testid=layers-undo]") -> None:  # noqa: ANN001
    steps = _history(page)
    page.click(button)
    page.wait_for_function(f"() => studio.history.undo.length === {steps - 1}")


def _show_box(page) -> None:  # noqa: ANN001
    page.click("[data-testid=outliner] li[data-object=box]")
    page.wait_for_selector("[data-testid=layers] [data-take='2']")


def test_muting_a_take_composes_the_track_without_it_and_undo_restores_it(_page, takes_studio: str) -> None:  # noqa: ANN001
    page = _page(takes_studio)
    _show_box(page)
    rows = page.locator("[data-testid=layers] [data-take]")
    assert rows.count() == 3
    assert "additive" in rows.nth(1).inner_text() and "punch-in" in rows.nth(0).inner_text()
    assert "f 24–47" in rows.nth(1).inner_text(), rows.nth(1).inner_text()       # frames at 24 fps
    before = project(takes_studio)
    takes = _takes()
    _edit(page, "[data-take='1'] [data-testid=take-mute]")
    doc = project(takes_studio)
    _composed_equal(doc, [takes[0], takes[2]])
    assert page.locator("[data-take='1']").get_attribute("class").split().count("muted") == 1
    assert page.locator("[data-take='1'] [data-testid=take-mute]").get_attribute("aria-pressed") == "true"
    _undo(page)
    assert project(takes_studio) == before, "undo did not restore the project bit for bit"
    assert page.locator("[data-take='1'] [data-testid=take-mute]").get_attribute("aria-pressed") == "false"
    assert drew_something(page) > 5 and not page.errors


def test_deleting_and_moving_takes_recompose_and_undo_exactly(_page, takes_studio: str) -> None:  # noqa: ANN001
    page = _page(takes_studio)
    _show_box(page)
    before = project(takes_studio)
    takes = _takes()
    _edit(page, "[data-take='1'] [data-testid=take-delete]")
    assert page.locator("[data-testid=layers] [data-take]").count() == 2
    _composed_equal(project(takes_studio), [takes[0], takes[2]])
    _undo(page)
    assert project(takes_studio) == before
    _edit(page, "[data-take='2'] [data-testid=take-up]")            # the late punch-in before the additive bump
    _composed_equal(project(takes_studio), [takes[0], takes[2], takes[1]])
    assert "additive" in page.locator("[data-take='2']").inner_text()
    assert page.locator("[data-take='2'] [data-testid=take-down]").is_disabled()
    _undo(page, "[data-testid=undo]")
    assert project(takes_studio) == before
    assert drew_something(page) > 5 and not page.errors


def test_a_take_renamed_inline_keeps_its_name_after_a_reload(_page, takes_studio: str) -> None:  # noqa: ANN001
    page = _page(takes_studio)
    _show_box(page)
    before = project(takes_studio)
    page.dblclick("[data-take='0'] [data-testid=take-name]")
    page.keyboard.type("wobble")
    page.keyboard.press("Escape")                                     # dropped: nothing sent, the box stays selected
    assert page.locator("[data-take='0'] [data-testid=take-name]").inner_text() == "take 1"
    assert page.evaluate("studio.selected") == "box" and _history(page) == 0
    page.dblclick("[data-take='0'] [data-testid=take-name]")
    page.keyboard.type("stray")
    page.click("[data-testid=timeline]")                              # clicking away drops the field too
    page.wait_for_function("() => !document.querySelector('[data-testid=layers] input')")
    assert page.locator("[data-take='0'] [data-testid=take-name]").inner_text() == "take 1" and _history(page) == 0
    page.dblclick("[data-take='0'] [data-testid=take-name]")
    steps = _history(page)
    page.keyboard.type("base")
    page.keyboard.press("Enter")
    page.wait_for_function(f"() => studio.history.undo.length === {steps + 1}")
    page.reload()
    page.wait_for_selector("body[data-ready=true]", timeout=60_000)
    _show_box(page)
    assert page.locator("[data-take='0'] [data-testid=take-name]").inner_text() == "base"
    assert page.locator("[data-take='1'] [data-testid=take-name]").inner_text() == "take 2"
    _composed_equal(project(takes_studio), _takes())                 # a rename leaves the curve
    _undo(page)
    assert project(takes_studio) == before
    assert drew_something(page) > 5 and not page.errors


def test_objects_deleted_renamed_and_duplicated_from_the_outliner_undo_exactly(_page, takes_studio: str) -> None:  # noqa: ANN001
    page = _page(takes_studio)
    before = project(takes_studio)
    row = "[data-testid=outliner] li[data-object=box]"
    for how in ("mouse", "keys"):
        page.click(row)
        steps = _history(page)
        if how == "mouse":
            page.click("[data-testid=object-delete]")
        else:
            page.keyboard.press("Delete")
        page.wait_for_function(f"() => studio.history.undo.length === {steps + 1}")
        assert page.locator(row).count() == 0 and curve(project(takes_studio), PATH) is None
        page.keyboard.press("Control+z")
        page.wait_for_function(f"() => studio.history.undo.length === {steps}")
        assert project(takes_studio) == before, f"deleting by {how} was not undone exactly"

        page.click(row)
        if how == "mouse":
            page.click("[data-testid=object-rename]")
        else:
            page.keyboard.press("F2")
        field = page.locator("[data-testid=object-name]")
        assert field.evaluate("(e) => e === document.activeElement")
        page.keyboard.type("bad name")
        page.keyboard.press("Enter")
        assert "letters, digits" in page.locator("[data-testid=rename-problem]").inner_text()
        assert _history(page) == steps, "a bad name was sent"
        field.fill(f"crate_{how}")
        page.keyboard.press("Enter")
        page.wait_for_function(f"() => studio.history.undo.length === {steps + 1}")
        assert curve(project(takes_studio), f"crate_{how}.position") is not None
        page.wait_for_function(f"() => studio.selected === 'crate_{how}'")
        page.keyboard.press("Control+z")
        page.wait_for_function(f"() => studio.history.undo.length === {steps}")
        assert project(takes_studio) == before, f"renaming by {how} was not undone exactly"
        page.wait_for_function("() => studio.selected === 'box'")        # the undone rename keeps it selected

        page.click(row)
        if how == "mouse":
            page.click("[data-testid=object-duplicate]")
        else:
            page.keyboard.press("Shift+D")
        page.wait_for_function(f"() => studio.history.undo.length === {steps + 1}")
        copy = page.evaluate("studio.objects.map((o) => o.name).filter((n) => n.startsWith('box') && n !== 'box')")
        assert len(copy) == 1
        assert curve(project(takes_studio), f"{copy[0]}.position")[1]["coef"] == curve(before, PATH)[1]["coef"]
        page.keyboard.press("Control+z")
        page.wait_for_function(f"() => studio.history.undo.length === {steps}")
        assert project(takes_studio) == before, f"duplicating by {how} was not undone exactly"
    assert drew_something(page) > 5 and not page.errors


def test_a_new_object_goes_where_the_camera_looks_clear_of_the_others(_page, takes_studio: str) -> None:  # noqa: ANN001
    page = _page(takes_studio)
    # the view looks at the box: where its line of sight meets the floor's height is taken (the box and the
    # ball and cone beside it): the new object goes sideways, to the right, till it is clear of all three
    page.evaluate("viewport.camera.position.set(0, 2.5, 8); viewport.orbit.target.set(0, 0.5, 0); viewport.orbit.update()")
    steps = _history(page)
    page.click("[data-testid=add-object]")
    page.wait_for_function(f"() => studio.history.undo.length === {steps + 1}")
    added = page.evaluate("studio.objects.at(-1).name")
    position = np.array(page.evaluate(f"studio.values.get('{added}.position')"))
    assert position[1] == pytest.approx(0.5) and abs(position[2]) < 1e-6, position   # moved sideways only
    assert position[0] > 1.25, "not moved to the right of the box"
    for name in ("box", "ball", "cone"):
        other = np.array(page.evaluate(f"studio.values.get('{name}.position')"))
        assert np.linalg.norm(position - other) >= 0.75 + 0.5 - 1e-9, f"{added} at {position} is inside {name}"
    page.wait_for_timeout(100)
    seen = page.evaluate(f"viewport.screenOf('{added}')")
    box = page.locator("#viewport canvas").first.bounding_box()
    assert box["x"] < seen["x"] < box["x"] + box["width"] and box["y"] < seen["y"] < box["y"] + box["height"], "not in view"
    assert drew_something(page) > 5 and not page.errors


def _frame_shown(page, frame: int) -> None:  # noqa: ANN001
    """The transport is on ``frame`` and the bar shows it (the bar's text follows at the next frame)."""
    assert page.evaluate("studio.transport.frame") == frame
    page.wait_for_function(f"() => document.querySelector('[data-testid=frame]').textContent === '{frame}'")


def test_frames_show_step_and_follow_the_frame_rate_in_every_tab(_page, takes_studio: str) -> None:  # noqa: ANN001
    page = _page(takes_studio)
    other = _page(takes_studio)
    page.click("[data-testid=frame-on]")
    page.keyboard.press("ArrowRight")
    page.keyboard.press("ArrowRight")
    _frame_shown(page, 3)
    assert page.evaluate("studio.transport.time * 24") == pytest.approx(3, abs=1e-9)
    page.keyboard.press("ArrowLeft")
    page.click("[data-testid=frame-back]")
    _frame_shown(page, 1)
    page.select_option("[data-testid=fps]", "30")
    other.wait_for_function("() => studio.fps === 30")
    assert other.locator("[data-testid=fps]").input_value() == "30"
    page.wait_for_function("() => studio.fps === 30")
    page.keyboard.press("ArrowRight")                                  # 1/24 s is frame 1 at 30 fps; one on: frame 2
    _frame_shown(page, 2)
    assert page.evaluate("studio.transport.time * 30") == pytest.approx(2, abs=1e-9)
    page.keyboard.press("Shift+S")
    assert page.locator("[data-testid=snap]").get_attribute("aria-pressed") == "true"
    page.click("[data-testid=snap]")
    assert page.evaluate("studio.snap") is False
    assert drew_something(page) > 5 and drew_something(other) > 5 and not page.errors and not other.errors


def test_the_page_offers_the_servers_frame_rates() -> None:
    text = (ROOT / "src/sketchanim/studio/web/js/transportbar.js").read_text()
    rates = json.loads(re.search(r"export const FRAME_RATES = (\[[^\]]*\])", text).group(1))
    assert tuple(float(r) for r in rates) == FRAME_RATES


def test_the_help_overlay_opens_from_every_transport_control_and_lists_every_shortcut(_page, takes_studio: str) -> None:  # noqa: ANN001
    page = _page(takes_studio)
    shortcuts = page.evaluate("import('/js/keyboard.js').then((m) => m.SHORTCUTS)")
    help_ = page.locator("[data-testid=help]")
    listed = help_.locator("tr[data-action]").evaluate_all("(rows) => rows.map((r) => [r.dataset.action, r.textContent])")
    assert [action for action, _ in listed] == [s["action"] for s in shortcuts]
    for (_, text), s in zip(listed, shortcuts):
        assert s["does"] in text and all(k in text for k in s["keys"]), text
    gestures = page.evaluate("import('/js/keyboard.js').then((m) => m.GESTURES)")
    shown = help_.locator("[data-testid=help-gestures] tr").all_text_contents()
    assert len(shown) == len(gestures) and all(g["does"] in row for g, row in zip(gestures, shown))
    controls = page.locator("[data-testid=transport] button:enabled, [data-testid=transport] select, "
                            "[data-testid=transport] input:visible")         # not the sound's file input (its button opens it)
    count = controls.count()
    assert count >= 14
    for i in range(count):
        control = controls.nth(i)
        if control.evaluate("(e) => e.tagName") == "SELECT":
            control.focus()                     # a click opens the menu's own popup
        else:
            control.click()
        assert control.evaluate("(e) => e === document.activeElement")
        page.keyboard.press("?")
        assert help_.is_visible(), f"? after {control.get_attribute('data-testid')} did not open the help"
        page.keyboard.press("?")
        assert help_.is_hidden()
    page.keyboard.press("Escape")
    page.click("[data-testid=outliner] li[data-object=ball]")
    page.click("[data-testid=help-button]")
    assert help_.is_visible()
    page.keyboard.press("Escape")
    assert help_.is_hidden() and page.evaluate("studio.selected") == "ball", "Escape closing the help also deselected"
    page.keyboard.press("?")
    page.mouse.click(5, 300)                                           # outside the card
    assert help_.is_hidden() and page.evaluate("studio.selected") == "ball"
    assert drew_something(page) > 5 and not page.errors


def test_a_read_only_project_offers_no_take_or_object_edits(_page, tmp_path: Path) -> None:  # noqa: ANN001
    with studio_server(_takes_project(tmp_path), "--read-only") as url:
        page = _page(url)
        _show_box(page)
        buttons = page.locator("[data-testid=layers] button, [data-testid=layers-undo], [data-testid=layers-redo]")
        assert buttons.count() >= 15
        assert buttons.evaluate_all("(bs) => bs.filter((b) => !b.disabled).map((b) => b.dataset.testid)") == []
        for tool in ("object-rename", "object-duplicate", "object-delete", "add-object", "fps"):
            assert page.locator(f"[data-testid={tool}]").is_disabled(), tool
        page.dblclick("[data-take='0'] [data-testid=take-name]")
        page.keyboard.press("F2")
        assert page.locator("[data-testid=layers] input, [data-testid=outliner] input").count() == 0
        assert drew_something(page) > 5 and not page.errors
