"""The curve editor in a real browser against a real server: a control point, a key and a box
of points dragged with the mouse (one History step each, undone bit for bit), the tolerance
after the take (the track re-reduced as the model's ``compose`` does it), and the frame time
while dragging on 10 tracks of 2,000 keys. Every test checks that the page drew something."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import BSpline

from sketchanim.anim.attributes import POSITION
from sketchanim.anim.layers import compose, recorded_over
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.project.store import Project
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.takes import ORDER
from studio_browser import curve, drag, drew_something, open_page, project, studio_server

TOP, BOTTOM = 8, 16          # the editor's plot margins (curveeditor.js)
TOL = 0.01


def recorded_project(path: Path) -> list[Take]:
    """A project whose box has a recorded position track (3 s at 60 Hz, one take); its takes."""
    t = np.arange(0, 3, 1 / 60)
    rng = np.random.default_rng(3)
    x = np.c_[np.sin(2 * t), 0.5 + 0.3 * np.cos(3 * t), 0.2 * t] + rng.normal(0, 0.002, (len(t), 3))
    take = Take(t, x)
    track = recorded_over("box.position", POSITION, None, take, TOL, ORDER)
    with Project(path) as p:
        p.save(default_scene(), {"box.position": track}, {})
    return [take]


def many_keys_project(path: Path, tracks: int = 10, keys: int = 2000) -> None:
    """An object ``rig`` with ``tracks`` position-like tracks of ``keys`` keys each (60 s)."""
    scene = Scene()
    scene.add("rig")
    rng = np.random.default_rng(5)
    knots = np.r_[[0.0] * 3, np.linspace(0, 60, keys), [60.0] * 3]
    found = {}
    for j in range(tracks):
        name = f"rig.p{j}"
        scene.objects["rig"].add(f"p{j}", POSITION)
        coef = np.cumsum(rng.normal(0, 0.05, (len(knots) - 4, 3)), axis=0)
        found[name] = ContinuousTrack(name, POSITION, BSpline(knots, coef, 3), 0.005)
    scene.add("cam", "camera").attributes["position"].value = np.array([0.0, 2.0, 9.0])
    with Project(path) as p:
        p.save(scene, found, {})


@pytest.fixture(scope="module")
def recorded(tmp_path_factory, browser):  # noqa: ANN001, ANN201
    """One server on the recorded project and a page on it with the box shown (each test
    leaves the track as it found it: it undoes what it did)."""
    path = tmp_path_factory.mktemp("curves") / "curves.sketchanim"
    takes = recorded_project(path)
    with studio_server(path) as url:
        page = open_page(browser, url, size=(1280, 800))
        page.evaluate("studio.select('box'); studio.showAttribute('position')")
        page.wait_for_function("() => curveEditor.lanes.length === 1")
        page.wait_for_timeout(200)
        yield page, url, takes
        page.close()


def _canvas(page) -> dict:  # noqa: ANN001
    return page.locator("[data-testid=curve-editor]").bounding_box()


def _screen(page, kind: str, i: int, ch: int) -> dict:  # noqa: ANN001
    """Where a control point ('p') or key ('k') of the first lane is, in page pixels."""
    box = _canvas(page)
    xy = page.evaluate(f"() => {{ const l = curveEditor.lanes[0]; return [l.{kind}x[{i}], l.{kind}y[{ch}][{i}]]; }}")
    return {"x": box["x"] + xy[0], "y": box["y"] + xy[1]}


def _view(page) -> dict:  # noqa: ANN001
    return page.evaluate("() => { const c = curveEditor.canvas; return {...curveEditor.currentView(c.clientWidth, c.clientHeight), h: c.clientHeight}; }")


def _steps(page) -> int:  # noqa: ANN001
    return page.evaluate("studio.history.undo.length")


def _wait_steps(page, n: int) -> None:  # noqa: ANN001
    page.wait_for_function(f"() => studio.history.undo.length === {n}", timeout=20_000)


def _undo(page, n: int) -> None:  # noqa: ANN001
    page.locator("[data-testid=curve-editor]").focus()
    page.keyboard.press("Control+z")
    _wait_steps(page, n)
    page.wait_for_timeout(100)


def _entry(url: str) -> tuple[BSpline, dict]:
    found = curve(project(url), "box.position")
    assert found is not None
    return found


def _valid(spline: BSpline, entry: dict) -> None:
    assert len(entry["coef"]) == len(entry["knots"]) - entry["order"]
    assert np.all(np.diff(entry["knots"]) >= 0) and np.all(np.isfinite(entry["coef"]))


def test_dragging_a_control_point_changes_only_its_spans_and_undoes_bit_for_bit(recorded) -> None:  # noqa: ANN001
    page, url, _ = recorded
    before, entry0 = _entry(url)
    i = len(entry0["coef"]) // 2
    steps = _steps(page)
    start = _screen(page, "p", i, 1)
    drag(page, start, [(0, -10), (0, -25), (0, -40)])
    _wait_steps(page, steps + 1)
    assert page.evaluate("studio.history.undo.at(-1)").startswith("move 1 control point")
    after, entry1 = _entry(url)
    _valid(after, entry1)
    assert entry1["knots"] == entry0["knots"]
    changed = [j for j in range(len(entry0["coef"])) if entry0["coef"][j] != entry1["coef"][j]]
    assert changed == [i]
    assert entry1["coef"][i][1] > entry0["coef"][i][1] and entry1["coef"][i][0] == entry0["coef"][i][0]
    knots = np.array(entry0["knots"])
    lo, hi = knots[i], knots[i + entry0["order"]]
    t = np.linspace(knots[0], knots[-1], 4001)
    outside = (t <= lo) | (t >= hi)
    assert np.array_equal(before(t[outside]), after(t[outside]))
    assert np.abs(before(t[~outside]) - after(t[~outside])).max() > 1e-4
    _undo(page, steps)
    back, entry2 = _entry(url)
    assert entry2["coef"] == entry0["coef"] and entry2["knots"] == entry0["knots"]
    assert drew_something(page) > 5 and not page.errors


def test_dragging_a_key_puts_the_curve_where_it_was_dropped(recorded) -> None:  # noqa: ANN001
    page, url, _ = recorded
    _, entry0 = _entry(url)
    keys = page.evaluate("() => Array.from(curveEditor.lanes[0].kt)")
    i = len(keys) // 2
    steps = _steps(page)
    start = _screen(page, "k", i, 0)
    view = _view(page)
    drag(page, start, [(0, 8), (0, 20), (0, 30)])
    _wait_steps(page, steps + 1)
    spline, entry1 = _entry(url)
    _valid(spline, entry1)
    ph = view["h"] - TOP - BOTTOM
    per_pixel = (view["v1"] - view["v0"]) / ph
    y = start["y"] + 30 - _canvas(page)["y"]
    dropped = view["v1"] - (y - TOP) * per_pixel
    assert abs(spline(keys[i])[0] - dropped) <= per_pixel
    assert abs(spline(keys[i])[0] - BSpline(np.array(entry0["knots"]), np.array(entry0["coef"]), 3)(keys[i])[0]) > 10 * per_pixel
    _undo(page, steps)
    _, entry2 = _entry(url)
    assert entry2["coef"] == entry0["coef"]
    assert drew_something(page) > 5 and not page.errors


def test_the_tolerance_after_the_take_re_reduces_as_compose_does(recorded) -> None:  # noqa: ANN001
    page, url, takes = recorded
    _, entry0 = _entry(url)
    steps = _steps(page)
    tol = 0.05
    page.evaluate("(tol) => { const i = document.querySelector('[data-testid=tolerance]'); i.value = String(tol);"
                  " i.dispatchEvent(new Event('change')); }", tol)
    _wait_steps(page, steps + 1)
    spline, entry1 = _entry(url)
    _valid(spline, entry1)
    expected = compose(POSITION, takes, tol, ORDER)
    assert len(entry1["coef"]) == len(expected.c) < len(entry0["coef"])
    for take in takes:
        assert np.abs(spline(take.times) - take.values).max() <= tol * (1 + 1e-9)
    page.wait_for_function("() => document.querySelector('[data-testid=tolerance-info]').textContent.includes('control points')")
    _undo(page, steps)
    _, entry2 = _entry(url)
    assert entry2["coef"] == entry0["coef"]
    assert drew_something(page) > 5 and not page.errors


def test_box_selecting_two_points_and_dragging_them_is_one_step(recorded) -> None:  # noqa: ANN001
    page, url, _ = recorded
    _, entry0 = _entry(url)
    # two neighbouring control points of y whose box holds no other control point (of any channel), from an empty corner
    pair = page.evaluate("""() => { const l = curveEditor.lanes[0];
        const all = []; for (let ch = 0; ch < l.dims; ch++) l.px.forEach((x, i) => all.push([x, l.py[ch][i], i]));
        for (let i = 1; i < l.px.length - 2; i++) {
          const a = [l.px[i], l.py[1][i]], b = [l.px[i + 1], l.py[1][i + 1]];
          const box = [Math.min(a[0], b[0]) - 9, Math.min(a[1], b[1]) - 9, Math.max(a[0], b[0]) + 9, Math.max(a[1], b[1]) + 9];
          const inside = new Set(all.filter(([x, y]) => x >= box[0] && x <= box[2] && y >= box[1] && y <= box[3]).map((p) => p[2]));
          if (inside.size === 2 && box[1] > 10 && !curveEditor.hitTest(box[0], box[1])) return {i, box};
        } return null; }""")
    assert pair is not None, "no two control points apart from the others"
    i, (x0, y0, x1, y1) = pair["i"], pair["box"]
    c = _canvas(page)
    drag(page, {"x": c["x"] + x0, "y": c["y"] + y0}, [((x1 - x0) / 2, (y1 - y0) / 2), (x1 - x0, y1 - y0)])
    selected = page.evaluate("studio.points")
    assert sorted(q["index"] for q in selected if q["kind"] == "point") == [i, i + 1]      # (keys in the box are selected too)
    steps = _steps(page)
    start = _screen(page, "p", i, 1)
    drag(page, start, [(0, -10), (0, -20), (0, -30)])
    _wait_steps(page, steps + 1)
    assert page.evaluate("studio.history.undo.at(-1)") == "move 2 control points"
    _, entry1 = _entry(url)
    changed = [j for j in range(len(entry0["coef"])) if entry0["coef"][j] != entry1["coef"][j]]
    assert changed == [i, i + 1]
    moved = [entry1["coef"][j][1] - entry0["coef"][j][1] for j in changed]
    assert moved[0] > 0 and moved[0] == pytest.approx(moved[1], rel=1e-9)
    _undo(page, steps)
    _, entry2 = _entry(url)
    assert entry2["coef"] == entry0["coef"]
    page.evaluate("studio.selectPoints([])")
    assert drew_something(page) > 5 and not page.errors


def test_escape_cancels_a_drag_and_sends_nothing(recorded) -> None:  # noqa: ANN001
    page, url, _ = recorded
    _, entry0 = _entry(url)
    steps = _steps(page)
    start = _screen(page, "p", 5, 0)
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    page.mouse.move(start["x"], start["y"] - 30, steps=4)
    page.keyboard.press("Escape")
    page.mouse.up()
    page.wait_for_timeout(300)
    assert _steps(page) == steps and _entry(url)[1]["coef"] == entry0["coef"]
    assert page.evaluate("studio.selected") == "box"          # Escape cancelled the drag, not the selection
    assert drew_something(page) > 5 and not page.errors


def test_dragging_on_10_tracks_of_2000_keys_previews_every_move_and_lands_one_step(tmp_path: Path, browser) -> None:  # noqa: ANN001
    path = tmp_path / "keys.sketchanim"
    many_keys_project(path)
    with studio_server(path) as url:
        page = open_page(browser, url, size=(1280, 800))
        page.evaluate("studio.select('rig')")
        page.locator("[data-testid=curve-all]").check()
        page.wait_for_function("() => curveEditor.lanes.length === 10", timeout=30_000)
        tolerance = page.locator("[data-testid=tolerance]")          # tracks without takes: nothing to re-reduce
        assert tolerance.is_disabled() and "no takes" in tolerance.get_attribute("title")
        page.keyboard.press("Home")
        page.wait_for_timeout(300)
        start = _screen(page, "p", 1000, 1)
        page.evaluate("for (const k of Object.keys(studioStats)) studioStats[k].length = 0;"
                      " curveEditor.stats.draw.length = 0; curveEditor.stats.move.length = 0")
        steps = _steps(page)
        drag(page, start, [(0, -2 * k) for k in range(1, 31)])
        _wait_steps(page, steps + 1)
        drawn = page.evaluate("curveEditor.stats.draw")
        moves = page.evaluate("curveEditor.stats.move")
        # the preview kept up with the pointer (its time per frame is benchmarks/bench_studio.py's to measure)
        assert len(drawn) >= 10 and len(moves) >= 20, "the editor did not preview the drag"
        assert drew_something(page) > 5 and not page.errors
        page.close()


def test_i_inserts_a_knot_at_the_playhead_and_delete_removes_it(recorded) -> None:  # noqa: ANN001
    page, url, _ = recorded
    before, entry0 = _entry(url)
    steps = _steps(page)
    page.evaluate("studio.transport.seek(1.37)")
    page.keyboard.press("i")
    _wait_steps(page, steps + 1)
    after, entry1 = _entry(url)
    assert len(entry1["knots"]) == len(entry0["knots"]) + 1 and 1.37 in entry1["knots"]
    t = np.linspace(0, 3, 1001)
    assert np.abs(after(t) - before(t)).max() < 1e-9                  # inserting a knot keeps the curve
    page.wait_for_function("() => Array.from(curveEditor.lanes[0].kt).some((t) => Math.abs(t - 1.37) < 1e-12)")
    i = page.evaluate("Array.from(curveEditor.lanes[0].kt).findIndex((t) => Math.abs(t - 1.37) < 1e-12)")
    key = _screen(page, "k", i, 0)
    page.mouse.click(key["x"], key["y"])
    assert page.evaluate("studio.points") == [{"path": "box.position", "kind": "key", "index": entry1["knots"].index(1.37)}]
    page.keyboard.press("Delete")
    _wait_steps(page, steps + 2)
    _, entry2 = _entry(url)
    assert len(entry2["knots"]) == len(entry0["knots"]) and 1.37 not in entry2["knots"]
    assert page.evaluate("studio.selected") == "box"                  # Delete took the key, not the object
    _undo(page, steps + 1)
    _undo(page, steps)
    _, entry3 = _entry(url)
    assert entry3["coef"] == entry0["coef"] and entry3["knots"] == entry0["knots"]
    assert drew_something(page) > 5 and not page.errors
