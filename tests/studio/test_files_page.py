"""Files from the page, in a real browser (Debian's chromium through Playwright) against a
real server: the export dialog (a take made, exported as .glb and .usd as browser
downloads: the Khronos validator finds no error, three.js and pxr play the take within
its tolerance), closed by Escape with the focus back, a refusal shown in it. Every test
checks the page drew something."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from clips import validate
from studio_browser import curve, drag, drew_something, last_take, project
from threejs_client import three_play

PATH = "box.position"
#: Where the dialog's screenshot goes (for a look with an image viewer).
SHOTS = Path(__file__).resolve().parents[2] / "out" / "screenshots"


def _make_take(page) -> None:  # noqa: ANN001
    """Record mode on, one drag of the box, record mode off."""
    page.click("[data-testid=record]")
    page.wait_for_timeout(100)
    start = page.evaluate("viewport.screenOf('box')")
    s = np.linspace(0, 1, 45)
    drag(page, start, list(zip(160 * s, -60 * np.sin(np.pi * s))))
    assert not last_take(page)["errors"]
    page.click("[data-testid=record]")


def _raw_take(url: str) -> tuple[np.ndarray, np.ndarray, float]:
    """The box position's take as the project keeps it: times, values, the tolerance."""
    doc = project(url)
    _, entry = curve(doc, PATH)
    (take,) = [doc["takes"][i] for i in entry["takes"]]
    return np.array(take["times"]), np.array(take["values"]), entry["tol"]


def _download(page, testid: str, folder: Path) -> Path:  # noqa: ANN001
    """Open the dialog, choose ``testid``, the browser's download saved in ``folder``."""
    page.click("[data-testid=export]")
    page.wait_for_selector(f"[data-testid={testid}]")
    with page.expect_download() as info:
        page.click(f"[data-testid={testid}]")
    download = info.value
    path = folder / download.suggested_filename
    download.save_as(path)
    page.wait_for_selector("[data-testid=export-dialog]", state="hidden")
    return path


def test_export_dialog_downloads_a_glb_three_js_plays_within_tolerance(_page, studio: str, tmp_path: Path) -> None:  # noqa: ANN001
    page = _page(studio)
    _make_take(page)
    page.click("[data-testid=export]")
    dialog = page.locator("[data-testid=export-dialog]")
    dialog.locator("[data-testid=export-glb]").wait_for()
    text = dialog.inner_text()
    times, values, tol = _raw_take(studio)
    assert "three.js" in text and f"within {tol * 1000:.3g} mm" in text and "Blender's own glTF importer" in text
    SHOTS.mkdir(parents=True, exist_ok=True)
    dialog.screenshot(path=str(SHOTS / "export-dialog.png"))
    recording = "document.querySelector('[data-testid=record]').classList.contains('on')"
    page.keyboard.press("r")                        # the record shortcut: not under the dialog
    assert page.evaluate(recording) is False, "a key in the dialog reached the shortcuts"
    page.keyboard.press("Escape")
    page.wait_for_selector("[data-testid=export-dialog]", state="hidden")
    assert page.evaluate("document.activeElement.dataset.testid") == "export", "the focus did not come back"
    page.keyboard.press("r")                        # the shortcuts are back
    assert page.evaluate(recording) is True
    page.keyboard.press("r")

    glb = _download(page, "export-glb", tmp_path)
    assert glb.name == "studio.glb"
    assert page.evaluate("document.activeElement.dataset.testid") == "export"
    (report,) = validate(glb)
    assert report["numErrors"] == 0, report["messages"][:3]
    played = three_play(glb, times)["box"]["position"]
    assert np.abs(played - values).max() <= tol, "three.js plays the take outside its tolerance"
    assert drew_something(page) > 5 and not page.errors


def test_export_dialog_downloads_usd_pxr_opens_and_shows_a_refusal(_page, studio: str, tmp_path: Path) -> None:  # noqa: ANN001
    from pxr import Usd

    page = _page(studio)
    _make_take(page)
    usd = _download(page, "export-usd", tmp_path)
    assert usd.name == "studio.usd"
    stage = Usd.Stage.Open(str(usd))
    rate = stage.GetTimeCodesPerSecond()
    translate = stage.GetPrimAtPath("/box").GetAttribute("xformOp:translate")
    times, values, tol = _raw_take(studio)
    played = np.array([translate.Get(float(t * rate)) for t in times])
    assert np.abs(played - values).max() <= tol
    # a refusal (as a server without usd-core answers) is shown in the dialog, which stays open
    detail = "USD export needs usd-core: pip install 'sketchanim[usd]'"
    page.route("**/api/export?format=usd", lambda route: route.fulfill(
        status=400, content_type="application/json", body=json.dumps({"detail": detail})))
    page.click("[data-testid=export]")
    page.click("[data-testid=export-usd]")
    error = page.locator("[data-testid=export-error]")
    error.wait_for()
    assert detail in error.inner_text() and "studio.usd" in error.inner_text()
    assert page.locator("[data-testid=export-dialog]").is_visible()
    page.click("[data-testid=export-close]")
    page.wait_for_selector("[data-testid=export-dialog]", state="hidden")
    assert drew_something(page) > 5 and not page.errors
