"""Motion paths and onion skin in the studio's 3D view, in Debian's chromium against a real
server on a project with a recorded ``box.position`` track: the selected object's path has
a tick per frame of its range and handles for the control points acting on it; dragging a
handle with the mouse makes the edit the API makes (one History step, undone bit for bit);
Esc mid-drag sends nothing; onion skin ghosts sit at the track's values. Every test checks
the page drew something, and leaves screenshots in /tmp/shots-paths/ for a look."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.edits import moved_points
from sketchanim.anim.layers import recorded_over
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.project.store import Project
from sketchanim.studio.defaults import default_scene
from studio_browser import curve, drag, drew_something, held, project, studio_server

SHOTS = Path("/tmp/shots-paths")
PATH = "box.position"
#: The path's colour (motionpaths.js COLOURS.path).
CYAN = np.array([0x4D, 0xD0, 0xE1])
#: Keeps every message the page sends (before the page's own scripts run).
RECORD_SENT = """window.sentFrames = [];
const send = WebSocket.prototype.send;
WebSocket.prototype.send = function (data) { window.sentFrames.push(String(data)); return send.call(this, data); };"""


@pytest.fixture
def animated(tmp_path: Path):  # noqa: ANN201
    """A studio on the default scene with a recorded box.position track (two hops over 3 s)."""
    path = tmp_path / "paths.sketchanim"
    t = np.linspace(0, 3, 181)
    xyz = np.c_[t - 1.5, 0.5 + 0.8 * np.sin(np.pi * t / 1.5) ** 2, 0.4 * np.sin(2 * np.pi * t / 3)]   # two hops
    track = recorded_over(PATH, POSITION, None, Take(t, xyz), POSITION.tol, 4)
    with Project(path) as made:
        made.save(default_scene(), {PATH: track})
    with studio_server(path) as url:
        yield url


def _track(doc: dict) -> ContinuousTrack:
    spline, entry = curve(doc, PATH)
    return ContinuousTrack(PATH, POSITION, spline, entry["tol"])


def _shot(page, name: str) -> np.ndarray:  # noqa: ANN001
    """A screenshot of the 3D view (kept in SHOTS), as RGB pixels."""
    from PIL import Image

    SHOTS.mkdir(exist_ok=True)
    shot = page.locator("[data-testid=viewport]").screenshot(path=str(SHOTS / f"{name}.png"))
    return np.asarray(Image.open(io.BytesIO(shot)).convert("RGB"), dtype=int)


def _cyan(pixels: np.ndarray) -> int:
    return int((np.abs(pixels - CYAN).max(axis=2) <= 24).sum())


def _select_box(page, time: float) -> None:  # noqa: ANN001
    page.evaluate(f"studio.transport.seek({time})")
    page.click("[data-testid=outliner] li[data-object=box]")
    page.wait_for_function("viewport.paths.report().length === 1")


def _curve_points(page) -> list[dict]:  # noqa: ANN001
    return [m for m in map(json.loads, page.evaluate("window.sentFrames")) if m["type"] == "curve.points"]


def _free_handles(page) -> list[tuple[int, dict]]:  # noqa: ANN001
    """The shown handles well inside the view and clear (16 px) of the others and of the
    box, farthest from them first, with their page coordinates."""
    report = page.evaluate("viewport.paths.report()")[0]
    box = page.locator("[data-testid=viewport]").bounding_box()
    at = {i: page.evaluate(f"viewport.paths.handleScreen('{PATH}', {i})") for i in report["handles"]}
    at["box"] = page.evaluate("viewport.screenOf('box')")
    inside = [i for i in report["handles"] if box["x"] + 20 < at[i]["x"] < box["x"] + box["width"] - 20
              and box["y"] + 20 < at[i]["y"] < box["y"] + box["height"] - 20]
    room = {i: min(np.hypot(at[i]["x"] - p["x"], at[i]["y"] - p["y"]) for j, p in at.items() if j != i) for i in inside}
    clear = sorted((i for i in room if room[i] > 16), key=room.get, reverse=True)
    assert len(clear) >= 3, f"not three handles stand clear of the others: {room}"
    return [(i, at[i]) for i in clear]


def _colour_at(page, pixels: np.ndarray, at: dict) -> np.ndarray:  # noqa: ANN001
    """The colour of the view's screenshot ``pixels`` at page coordinates ``at``."""
    box = page.locator("[data-testid=viewport]").bounding_box()
    return pixels[round(at["y"] - box["y"]), round(at["x"] - box["x"])]


def _zoom_on_box(page) -> None:  # noqa: ANN001
    """The view closer to the path (as an animator would wheel in)."""
    page.evaluate("""() => { const v = viewport; v.camera.position.set(0.2, 3.2, 4.6); v.orbit.target.set(0.2, 0.7, 0);
        v.orbit.update(); }""")
    page.wait_for_timeout(100)


def test_the_selected_objects_path_has_a_tick_per_frame_and_handles_that_select(_page, animated: str) -> None:  # noqa: ANN001
    page = _page(animated, RECORD_SENT)
    _zoom_on_box(page)
    assert page.evaluate("viewport.paths.report()") == [], "a path before anything is selected"
    _select_box(page, 1.0)
    doc = project(animated)
    spline = curve(doc, PATH)[0]
    start, end = spline.t[spline.k], spline.t[-spline.k - 1]
    fps = page.evaluate("studio.fps")
    (shown,) = page.evaluate("viewport.paths.report()")
    # the range: two seconds either side of the playhead's frame, cut to the track's span
    frame = round(1.0 * fps)
    t0, t1 = max(start, (frame - 2 * fps) / fps), min(end, (frame + 2 * fps) / fps)
    assert (shown["path"], shown["frame"]) == (PATH, frame)
    assert shown["t0"] == pytest.approx(t0, abs=1e-12) and shown["t1"] == pytest.approx(t1, abs=1e-12)
    frames = np.arange(np.ceil(t0 * fps - 1e-9), np.floor(t1 * fps + 1e-9) + 1)
    assert shown["ticks"] == len(frames) == 73
    k, knots = spline.k + 1, spline.t
    assert shown["handles"] == [i for i in range(len(spline.c)) if knots[i] < t1 and knots[i + k] > t0]
    on = _shot(page, "path-on")
    assert _cyan(on) > 300, "the path's colour is not in the view"
    # the playhead moves a frame: the path follows (its frame), the range cut to the span stays
    page.keyboard.press("ArrowRight")
    page.wait_for_function(f"viewport.paths.report()[0].frame === {frame + 1}")
    # a click on a handle selects its point; Shift-click adds one; the handles are coloured so
    index, at = _free_handles(page)[0]
    page.mouse.move(at["x"], at["y"])
    page.wait_for_function(f"viewport.paths.hover && viewport.paths.hover.index === {index}")
    page.mouse.click(at["x"], at["y"])
    assert page.evaluate("studio.points") == [{"path": PATH, "kind": "point", "index": index}]
    (other, there), (plain, elsewhere) = _free_handles(page)[1:3]
    page.keyboard.down("Shift")
    page.mouse.click(there["x"], there["y"])
    page.keyboard.up("Shift")
    assert sorted(p["index"] for p in page.evaluate("studio.points")) == sorted([index, other])
    page.mouse.move(5, 5)                               # off the view: no handle hovered
    selected = _shot(page, "path-points-selected")
    for point in (at, there):
        assert np.abs(_colour_at(page, selected, point) - [0xFF, 0xC6, 0x40]).max() <= 24, "a selected handle is not so coloured"
    assert np.abs(_colour_at(page, selected, elsewhere) - CYAN).max() <= 24, "a handle not selected is coloured as selected"
    assert _curve_points(page) == [], "a click sent an edit"
    # P hides the paths (and the toggle shows it); P again shows them
    page.keyboard.press("p")
    page.wait_for_function("viewport.paths.report().length === 0")
    assert page.get_attribute("[data-testid=motion-paths]", "aria-pressed") == "false"
    assert _cyan(_shot(page, "path-off")) < 20
    page.click("[data-testid=motion-paths]")
    page.wait_for_function("viewport.paths.report().length === 1")
    assert drew_something(page) > 5 and not page.errors


def test_dragging_a_handle_makes_the_apis_edit_in_one_step_and_undo_restores_it(_page, animated: str) -> None:  # noqa: ANN001
    page = _page(animated, RECORD_SENT)
    _zoom_on_box(page)
    _select_box(page, 1.0)
    before = project(animated)
    steps = page.evaluate("studio.history.undo.length")
    index, at = _free_handles(page)[0]
    drag(page, at, [(0, -6 * s) for s in range(1, 9)] + [(4 * s, -48) for s in range(1, 6)])
    page.wait_for_function(f"studio.history.undo.length === {steps + 1}", timeout=10_000)
    (sent,) = _curve_points(page)
    (edit,) = sent["edits"]
    assert (edit["path"], edit["index"]) == (PATH, index)
    old = np.array(curve(before, PATH)[1]["coef"][index])
    moved = np.array(edit["value"]) - old
    view = np.array(page.evaluate("viewport.orbit.target.clone().sub(viewport.camera.position).normalize().toArray()"))
    assert np.linalg.norm(moved) > 0.2 and abs(moved @ view) < 1e-9, "the point did not move in the plane facing the view"
    after = project(animated)
    want = moved_points(_track(before), {index: edit["value"]}).spline
    got, entry = curve(after, PATH)
    assert np.array_equal(got.t, want.t) and np.abs(got.c - want.c).max() <= 1e-9
    assert entry["edited"] is True
    # the box, the playhead inside the changed span, plays the new curve
    page.wait_for_timeout(100)
    box = np.array(page.evaluate("viewport.nodes.get('box').root.position.toArray()"))
    assert np.abs(box - held(got, np.array([page.evaluate("studio.transport.time")]))[0]).max() <= 1e-6
    page.mouse.move(at["x"] + 200, at["y"] + 150)
    _shot(page, "path-dragged")
    page.keyboard.press("Control+z")
    page.wait_for_function(f"studio.history.undo.length === {steps}", timeout=10_000)
    page.wait_for_function(f"studio.tracks.get('{PATH}').coef[{index}][1] === {json.dumps(float(old[1]))}")
    assert curve(project(animated), PATH)[1]["coef"] == curve(before, PATH)[1]["coef"], "undo did not restore the curve"
    assert drew_something(page) > 5 and not page.errors


def test_escape_mid_drag_cancels_and_sends_nothing(_page, animated: str) -> None:  # noqa: ANN001
    page = _page(animated, RECORD_SENT)
    _zoom_on_box(page)
    _select_box(page, 1.0)
    before = project(animated)
    index, at = _free_handles(page)[0]
    path_before = page.evaluate("viewport.paths.report()")
    box0 = page.evaluate("viewport.nodes.get('box').root.position.toArray()")
    page.mouse.move(at["x"], at["y"])
    page.mouse.down()
    for s in range(1, 10):
        page.mouse.move(at["x"] + 5 * s, at["y"] - 5 * s)
        page.wait_for_timeout(16)
    assert page.evaluate(f"viewport.paths.preview.has('{PATH}')"), "no preview while dragging"
    moved = page.evaluate(f"viewport.paths.handleScreen('{PATH}', {index})")
    assert np.hypot(moved["x"] - at["x"] - 45, moved["y"] - at["y"] + 45) < 2, "the handle did not follow the pointer"
    _shot(page, "path-mid-drag")
    page.keyboard.press("Escape")
    page.mouse.move(at["x"] + 80, at["y"] - 80)
    page.mouse.up()
    page.wait_for_timeout(300)
    assert _curve_points(page) == [], "a cancelled drag sent an edit"
    assert project(animated)["curves"] == before["curves"]
    assert page.evaluate("studio.selected") == "box", "Esc in the drag also deselected"
    assert page.evaluate("viewport.paths.report()") == path_before
    assert page.evaluate(f"viewport.paths.handleScreen('{PATH}', {index})") == at
    assert page.evaluate("viewport.nodes.get('box').root.position.toArray()") == box0
    assert drew_something(page) > 5 and not page.errors


def test_onion_skin_is_off_then_o_shows_ghosts_at_the_tracks_values(_page, animated: str) -> None:  # noqa: ANN001
    page = _page(animated)
    _zoom_on_box(page)
    _select_box(page, 1.5)
    page.wait_for_timeout(100)
    assert page.evaluate("viewport.onion.report()") == [] and not page.evaluate("viewport.toggles.on.onion")
    assert page.get_attribute("[data-testid=onion-skin]", "aria-pressed") == "false"
    page.keyboard.press("o")
    page.wait_for_function("viewport.onion.report().length > 0")
    ghosts = page.evaluate("viewport.onion.report()")
    count, every, fps = page.evaluate("[viewport.onion.count, viewport.onion.every, studio.fps]")
    assert (count, every) == (3, 4)
    frame = round(1.5 * fps)
    want = [("before", (frame - every * j) / fps) for j in range(1, count + 1)] + \
           [("after", (frame + every * j) / fps) for j in range(1, count + 1)]
    assert [(g["name"], g["side"]) for g in ghosts] == [("box", side) for side, _ in want]
    assert np.allclose([g["time"] for g in ghosts], [t for _, t in want], atol=1e-12, rtol=0)
    spline = curve(project(animated), PATH)[0]
    values = held(spline, np.array([t for _, t in want]))
    assert np.abs(np.array([g["position"] for g in ghosts]) - values).max() <= 1e-9
    shot = _shot(page, "onion-on")
    warm = int((np.abs(shot - [0xFF, 0x7A, 0x6B]).max(axis=2) <= 60).sum())
    assert warm > 200, "no warm ghosts in the view"
    # the ghosts follow the playhead
    page.keyboard.press("ArrowRight")
    page.wait_for_function(f"viewport.onion.report()[0].time > {want[0][1] + 1e-6}")
    # the toggle in the view switches it off
    page.click("[data-testid=onion-skin]")
    page.wait_for_function("viewport.onion.report().length === 0")
    assert drew_something(page) > 5 and not page.errors
