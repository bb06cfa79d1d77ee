"""The timeline in a real browser (Debian's chromium through Playwright) against a real
server: a take's block dragged and stretched, a whole track moved, a range deleted and
undone, a range copied from one lane and pasted on another, a group folded, a strip drawn.
Every test checks the page drew something."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from sketchanim.anim.attributes import BOOL, POSITION
from sketchanim.anim.edits import without_range
from sketchanim.anim.layers import recorded_over
from sketchanim.anim.tracks import ContinuousTrack, DiscreteTrack, Take
from sketchanim.project.store import Project
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.takes import ORDER
from studio_browser import curve, drag, drew_something, project, studio_server

TOL = 0.005
SHOTS = Path(__file__).resolve().parents[2] / "out" / "screenshots"


def _timeline_project(folder: Path) -> Path:
    """The default scene with the box's position in two takes (a punch-in over 0..3 s, an
    additive bump over 1..2 s), the ball's position in one (0..3 s), the box's visibility
    switched off and on."""
    t = np.linspace(0, 3, 91)
    mid = t[30:61]
    box = recorded_over("box.position", POSITION, None, Take(t, np.c_[np.sin(t), 0.5 + 0 * t, np.cos(t)]), TOL, ORDER)
    box = recorded_over("box.position", POSITION, box,
                        Take(mid, np.c_[0 * mid, 0.3 * np.sin(np.pi * (mid - 1)), 0 * mid], "additive"), TOL, ORDER)
    ball = recorded_over("ball.position", POSITION, None, Take(t, np.c_[t - 1.5, 0.3 + 0 * t, 0.5 * t]), TOL, ORDER)
    path = folder / "timeline.sketchanim"
    Project(path).save(default_scene(), {"box.position": box, "ball.position": ball,
                                         "box.visible": DiscreteTrack("box.visible", BOOL, [0.0, 1.2, 2.2],
                                                                      [True, False, True])})
    return path


@pytest.fixture
def timeline_studio(tmp_path: Path):  # noqa: ANN201
    with studio_server(_timeline_project(tmp_path)) as url:
        yield url


def _open(_page, url: str):  # noqa: ANN001, ANN202
    """A page with snap on (24 fps), its timeline 170 px tall, and a log of what it sends."""
    page = _page(url)
    # the timeline grows with the window (60 px in this 600 px tall page): tall enough for every lane here
    page.evaluate("timeline.canvas.style.height = '170px'")
    page.keyboard.press("Shift+S")
    assert page.evaluate("studio.snap") is True and page.evaluate("studio.fps") == 24
    page.evaluate("""() => { window.sent = []; const send = studio.send.bind(studio);
        studio.send = (m) => { window.sent.push(m); send(m); }; }""")
    return page


def _at(page, path: str, t: float) -> dict:  # noqa: ANN001
    point = page.evaluate(f"timeline.where({path!r}, {t})")
    assert point is not None, f"{path} is not shown in the timeline"
    return point


def _steps(page) -> int:  # noqa: ANN001
    return page.evaluate("studio.history.undo.length")


def _wait_step(page, steps: int) -> None:  # noqa: ANN001
    page.wait_for_function(f"() => studio.history.undo.length === {steps}")


def _sent(page, kind: str) -> dict:  # noqa: ANN001
    return page.evaluate(f"window.sent.filter((m) => m.type === {kind!r}).at(-1)")


def _take_times(doc: dict, path: str, index: int) -> np.ndarray:
    entry = curve(doc, path)[1]
    return np.array(doc["takes"][entry["takes"][index]]["times"])


def _pixels_per_second(page) -> float:  # noqa: ANN001
    return 1 / page.evaluate("timeline.pixel()")


def _shot(page, name: str) -> float:  # noqa: ANN001
    """Save a screenshot of the timeline; the spread of its pixels."""
    from PIL import Image

    SHOTS.mkdir(parents=True, exist_ok=True)
    png = page.locator("[data-testid=timeline]").screenshot(path=str(SHOTS / name))
    return float(np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=float).std())


def test_dragging_a_take_block_shifts_it_by_whole_frames_and_its_handle_scales_it(_page, timeline_studio) -> None:  # noqa: ANN001
    page = _open(_page, timeline_studio)
    before = project(timeline_studio)
    steps = _steps(page)
    px = _pixels_per_second(page)
    drag(page, _at(page, "box.position", 1.5), [(0.1 * px, 0), (0.27 * px, 0), (0.53 * px, 0)])
    _wait_step(page, steps + 1)
    sent = _sent(page, "take.edit")
    assert sent["op"] == "shift" and sent["take"] == 1 and sent["path"] == "box.position"
    frames = sent["by"] * 24
    assert frames == round(frames) and abs(sent["by"] - 0.53) <= 1 / 48 + 1e-9, sent
    moved = project(timeline_studio)
    old = _take_times(before, "box.position", 1)
    new = _take_times(moved, "box.position", 1)
    assert np.array_equal(new, old + sent["by"]) and np.all(np.diff(new) > 0)
    assert np.array_equal(_take_times(moved, "box.position", 0), _take_times(before, "box.position", 0))
    assert _shot(page, "timeline-moved.png") > 5

    # its right edge (the retime handle) stretches it about its start
    end = float(new[-1])
    drag(page, _at(page, "box.position", end - 0.5 / px), [(0.2 * px, 0), (0.4 * px, 0)])
    _wait_step(page, steps + 2)
    sent = _sent(page, "take.edit")
    assert sent["op"] == "scale" and sent["pivot"] == new[0]
    stretched = _take_times(project(timeline_studio), "box.position", 1)
    assert np.array_equal(stretched, sent["pivot"] + sent["factor"] * (new - sent["pivot"]))
    new_end = sent["pivot"] + sent["factor"] * (end - sent["pivot"])
    assert abs(new_end * 24 - round(new_end * 24)) <= 1e-6 and sent["factor"] > 1       # its end on a frame
    assert drew_something(page) > 5 and not page.errors


def test_alt_drag_moves_a_whole_track_and_esc_drops_a_drag(_page, timeline_studio) -> None:  # noqa: ANN001
    page = _open(_page, timeline_studio)
    before = project(timeline_studio)
    steps = _steps(page)
    px = _pixels_per_second(page)
    start = _at(page, "ball.position", 1.0)
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    page.mouse.move(start["x"] + 0.5 * px, start["y"], steps=4)
    page.keyboard.press("Escape")                                   # dropped: nothing is sent
    page.mouse.up()
    assert page.evaluate("timeline.drag") is None and _steps(page) == steps
    page.keyboard.down("Alt")
    drag(page, start, [(0.2 * px, 0), (0.5 * px, 0)])
    page.keyboard.up("Alt")
    _wait_step(page, steps + 1)
    sent = _sent(page, "track.retime")
    assert sent["paths"] == ["ball.position"] and sent["shift"] * 24 == round(sent["shift"] * 24)
    after = project(timeline_studio)
    assert np.array_equal(curve(after, "ball.position")[1]["knots"],
                          np.array(curve(before, "ball.position")[1]["knots"]) + sent["shift"])
    assert np.array_equal(_take_times(after, "ball.position", 0), _take_times(before, "ball.position", 0) + sent["shift"])
    assert drew_something(page) > 5 and not page.errors


def test_a_range_deleted_is_bridged_and_undo_restores_the_project_bit_for_bit(_page, timeline_studio) -> None:  # noqa: ANN001
    page = _open(_page, timeline_studio)
    before = project(timeline_studio)
    steps = _steps(page)
    px = _pixels_per_second(page)
    page.keyboard.down("Shift")                                     # Shift-drag: a range, even over a take's block
    drag(page, _at(page, "box.position", 0.3), [(0.2 * px, 0), (0.5 * px, 0)])
    page.keyboard.up("Shift")
    chosen = page.evaluate("studio.timeRange")
    assert chosen["paths"] == ["box.position"] and chosen["t0"] == round(0.3 * 24) / 24
    assert _shot(page, "timeline-range.png") > 5
    page.keyboard.press("Delete")
    _wait_step(page, steps + 1)
    sent = _sent(page, "track.cut")
    spline, _ = curve(before, "box.position")
    track = ContinuousTrack("box.position", POSITION, spline, TOL)
    bridged = without_range(track, sent["t0"], sent["t1"])
    cut, _ = curve(project(timeline_studio), "box.position")
    assert np.allclose(cut.t, bridged.spline.t, atol=1e-12) and np.allclose(cut.c, bridged.spline.c, atol=1e-12)
    assert page.evaluate("studio.timeRange") is None
    page.keyboard.press("Control+z")
    _wait_step(page, steps)
    assert project(timeline_studio) == before, "undo did not restore the project bit for bit"
    assert drew_something(page) > 5 and not page.errors


def test_copy_a_range_from_one_lane_and_paste_it_on_another(_page, timeline_studio) -> None:  # noqa: ANN001
    page = _open(_page, timeline_studio)
    before = project(timeline_studio)
    steps = _steps(page)
    px = _pixels_per_second(page)
    page.keyboard.down("Shift")
    drag(page, _at(page, "box.position", 0.5), [(0.5 * px, 0), (1.0 * px, 0)])
    page.keyboard.up("Shift")
    page.keyboard.press("Control+c")
    page.wait_for_function("() => timeline.clipboard !== null")
    assert page.evaluate("timeline.clipboard.path") == "box.position"
    label = page.evaluate("(() => { const p = timeline.where('ball.position', 0); return {x: p.x - 100, y: p.y}; })()")
    page.mouse.click(label["x"], label["y"])                        # the ball's lane, by its label
    assert page.evaluate("timeline.lane") == "ball.position"
    ruler = page.evaluate("(() => { const r = timeline.canvas.getBoundingClientRect(); return r.top + 8; })()")
    page.mouse.click(_at(page, "ball.position", 1.75)["x"], ruler)  # the playhead to 1.75 s
    page.keyboard.press("Control+v")
    _wait_step(page, steps + 1)
    sent = _sent(page, "track.paste")
    assert sent["path"] == "ball.position" and sent["at"] * 24 == round(sent["at"] * 24)
    after = project(timeline_studio)
    entry = curve(after, "ball.position")[1]
    assert len(entry["takes"]) == 2 and after["names"][str(entry["takes"][1])] == "paste"
    pasted = after["takes"][entry["takes"][1]]
    times, values = np.array(pasted["times"]), np.array(pasted["values"])
    assert times[0] == sent["at"] and np.all(np.diff(times) > 0)
    box, _ = curve(before, "box.position")
    piece = page.evaluate("timeline.clipboard")
    t0 = _sent(page, "track.copy")["t0"]
    assert np.abs(values - box(times - sent["at"] + t0)).max() <= 1e-9 * 10     # the box's motion, moved
    ball, _ = curve(after, "ball.position")
    inner = (times > times[0] + 0.1) & (times < times[-1] - 0.1)
    assert np.abs(ball(times[inner]) - values[inner]).max() <= TOL + 1e-9
    assert piece["length"] == pytest.approx(times[-1] - times[0])
    page.keyboard.press("Control+z")
    _wait_step(page, steps)
    assert project(timeline_studio) == before
    assert drew_something(page) > 5 and not page.errors


def test_a_group_folds_and_a_strip_draws_above_the_lanes(_page, timeline_studio) -> None:  # noqa: ANN001
    page = _open(_page, timeline_studio)
    lanes = page.evaluate("timeline.rows.filter((r) => r.kind === 'lane').map((r) => r.path)")
    assert lanes == ["box.position", "box.visible", "ball.position"]
    page.evaluate("""() => { studio.strips.push({ id: 'dummy', label: 'sound', height: 26,
        draw: (g, a, t0, t1) => { g.fillStyle = '#6fcf7f';
          for (let i = 0; i < a.width; i += 2) { const h = a.height * (0.2 + 0.8 * Math.abs(Math.sin(i / 9)));
            g.fillRect(a.x + i, a.y + (a.height - h) / 2, 1, h); } } }); timeline.invalidate(); }""")
    page.wait_for_function("() => timeline.lanesTop() === 46")
    spread = _shot(page, "timeline-lanes.png")
    group = page.evaluate("(() => { const p = timeline.where('box', 0); return {x: p.x - 140, y: p.y}; })()")
    page.mouse.click(group["x"], group["y"])                        # the box's triangle
    page.wait_for_function("() => timeline.rows.filter((r) => r.kind === 'lane').length === 1")
    assert page.evaluate("timeline.where('box.position', 1)") is None
    assert page.evaluate("timeline.rows.find((r) => r.kind === 'group' && r.object === 'box').folded") is True
    assert _shot(page, "timeline-folded.png") > 5 and spread > 5
    page.mouse.click(group["x"], group["y"])
    page.wait_for_function("() => timeline.rows.filter((r) => r.kind === 'lane').length === 3")
    assert page.evaluate("timeline.drawMs") < 50
    assert drew_something(page) > 5 and not page.errors


def test_the_loop_range_selected_by_a_double_click_is_deleted_on_that_lane(_page, timeline_studio) -> None:  # noqa: ANN001
    page = _open(_page, timeline_studio)
    steps = _steps(page)
    ruler = page.evaluate("timeline.canvas.getBoundingClientRect().top + 8")
    a, b = _at(page, "ball.position", 1.0)["x"], _at(page, "ball.position", 2.0)["x"]
    page.keyboard.down("Shift")
    drag(page, {"x": a, "y": ruler}, [((b - a) / 2, 0), (b - a, 0)])     # Shift-drag on the ruler: the loop
    page.keyboard.up("Shift")
    loop = page.evaluate("studio.transport.clock.loop")
    assert loop[0] == pytest.approx(1.0, abs=0.02) and loop[1] == pytest.approx(2.0, abs=0.02)
    page.mouse.dblclick(**_at(page, "ball.position", 2.5))
    assert page.evaluate("studio.timeRange") == {"paths": ["ball.position"], "t0": loop[0], "t1": loop[1]}
    page.keyboard.press("Delete")
    _wait_step(page, steps + 1)
    sent = _sent(page, "track.cut")
    assert (sent["paths"], sent["t0"], sent["t1"]) == (["ball.position"], loop[0], loop[1])
    assert page.evaluate("studio.objects.some((o) => o.name === 'ball')")        # the range went, not the object
    assert drew_something(page) > 5 and not page.errors
