"""The studio page in a real browser (Debian's chromium, headless, WebGL through
SwiftShader, driven by Playwright) against a real server on a fresh project. Every test
also checks that the page drew something (a screenshot that is not uniform), so a page
without a WebGL context cannot pass."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from studio_browser import curve, drag, drew_something, held, last_take, project, studio_server
from studio_browser import GAMEPAD, viewport_drew



def _record_drag(page, name: str, offsets: list[tuple[float, float]]) -> dict:  # noqa: ANN001
    """Drag an object in record mode; the take as the page sent it."""
    page.wait_for_timeout(100)
    start = page.evaluate(f"viewport.screenOf('{name}')")
    drag(page, start, offsets)
    return last_take(page)


def _record_once(page, name: str, offsets: list[tuple[float, float]]) -> dict:  # noqa: ANN001
    """Record mode on, one drag of ``name``, record mode off; the take."""
    page.click("[data-testid=record]")
    take = _record_drag(page, name, offsets)
    page.click("[data-testid=record]")
    return take


def _sweep(n: int = 45, dx: float = 160, dy: float = -60) -> list[tuple[float, float]]:
    s = np.linspace(0, 1, n)
    return list(zip(dx * s, dy * np.sin(np.pi * s)))


#: The seconds of fade after a stall (a step between samples longer than the take's ``gap``:
#: the server fades the part after it in over the blend).
BLEND = 0.1


def _smoothstep(u: np.ndarray) -> np.ndarray:
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3 - 2 * u)


def _check_within(take: dict, doc: dict, path: str, below=None) -> np.ndarray:  # noqa: ANN001
    """The track at ``path`` plays every sample the page sent within its tolerance
    (except within the blend after a stall, where the curve fades in from its hold); the
    sample times (transport seconds from the browser's clock) are the raw takes'. A take
    punched in over the curve ``below`` is checked against its documented targets: the
    samples faded in and out of ``below`` over the blend (smoothstep) at its seams."""
    assert take["label"] and not take["errors"], f"the take was refused: {take['errors']}"
    found = curve(doc, path)
    assert found is not None, f"no track for {path}"
    spline, entry = found
    j = take["paths"].index(path)
    lo = sum(take["dims"][:j])
    rows = np.array(take["rows"])[:, lo : lo + take["dims"][j]]
    times = np.array(take["times"])
    cuts = np.r_[0, np.flatnonzero(np.diff(times) > take["gap"]) + 1, len(times)]
    parts = [slice(i, j) for i, j in zip(cuts[:-1], cuts[1:]) if j - i >= 2]   # a lone sample is no take
    kept = np.zeros(len(times), dtype=bool)
    for part in parts:
        kept[part] = True
    resumed = times[1:][np.diff(times) > take["gap"]]
    fading = np.zeros(len(times), dtype=bool)
    for t in resumed:
        fading |= (times >= t) & (times < t + BLEND)
    played = held(spline, times)
    if below is not None:                   # each part (between stalls) is punched in on its own
        w = np.ones(len(times))
        for part in parts:
            i, j = part.start, part.stop
            t = times[i:j]
            blend = min(BLEND, (t[-1] - t[0]) / 2)
            w[i:j] = _smoothstep((t - t[0]) / blend) * _smoothstep((t[-1] - t) / blend) if blend > 0 else 0
        old = held(below, times)
        rows = old + w[:, None] * (rows - old)
        fading[:] = False
    if path.endswith(".orientation"):
        played /= np.linalg.norm(played, axis=1, keepdims=True)
        error = np.degrees((Rotation.from_quat(played).inv() * Rotation.from_quat(rows)).magnitude())
    else:
        error = np.abs(played - rows).max(axis=1)
    fading |= ~kept
    worst = int(np.argmax(np.where(fading, 0, error)))
    assert error[~fading].max() <= entry["tol"] * (1 + 1e-6), (
        f"{path}: sample {worst} of {len(times)} at t={times[worst]:.4f} is {error[worst]:.4g} off; "
        f"steps around it {np.diff(times)[max(worst - 3, 0):worst + 3].round(4).tolist()}")
    raw = [np.array(doc["takes"][i]["times"]) for i in entry["takes"]]
    ours = [r for r in raw if r[0] >= times[0] and r[-1] <= times[-1]]
    assert np.array_equal(np.concatenate(ours), times[kept]), "the raw takes are not the page's samples"
    return times


#: Records every pointermove's timeStamp (coalesced events included) before the page's own listeners.
RECORD_MOVES = """window.pointerMoves = [];
window.addEventListener('pointermove', (e) => {
  const all = e.getCoalescedEvents ? e.getCoalescedEvents() : [];
  for (const c of all.length ? all : [e]) window.pointerMoves.push(c.timeStamp);
}, true);"""


def test_drag_in_record_mode_records_the_track_at_the_pointer_events_times(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio, RECORD_MOVES)
    page.click("[data-testid=record]")
    take = _record_drag(page, "box", _sweep())
    assert take["paths"] == ["box.position"] and take["label"]
    times = _check_within(take, project(studio), "box.position")
    # timed by the browser's clock: transport time follows the clock (performance.now()) of each sample
    stamps = np.array(take["stamps"])
    assert np.allclose(times - times[0], (stamps - stamps[0]) / 1000, atol=1e-9)
    assert np.all(np.diff(times) > 0)
    # each sample is a pointer event at its own time, or the pointer at rest on a frame (or at its start)
    moves = np.array(page.evaluate("window.pointerMoves"))
    frames = np.array(page.evaluate("studioStats.stamps"))
    rest = stamps[~np.isin(stamps, moves)]
    from_frames = np.isin(rest, frames)
    rest_starts = rest[~from_frames]
    last_move = moves[np.searchsorted(moves, rest_starts) - 1]
    assert np.all(rest_starts - last_move >= 25 - 1e-9), "a sample neither an event's, a frame's nor a rest's start"
    assert np.isin(stamps, moves).sum() >= len(_sweep()) - 3, "the pointer's events are not the samples"
    # the box moved with the pointer: the track spans the drag
    rows = np.array(take["rows"])
    assert np.linalg.norm(rows[-1] - rows[0]) > 0.5
    assert drew_something(page) > 5 and not page.errors


def test_a_layer_during_playback_changes_only_the_grabbed_span(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    for name, sweep in (("box", _sweep(90)), ("ball", _sweep(150, dx=-120, dy=40))):
        page.evaluate("studio.transport.seek(0)")
        _record_once(page, name, sweep)                      # record mode off after: the transport stops
    before = project(studio)
    box0, ball0 = curve(before, "box.position"), curve(before, "ball.position")
    # from the start, in record mode: the transport plays both tracks; grab the ball midway
    page.evaluate("studio.transport.seek(0)")
    page.click("[data-testid=record]")
    page.wait_for_function(f"studio.transport.time > {ball0[0].t[0] + 0.2}")
    start = page.evaluate("viewport.screenOf('ball')")
    drag(page, start, [(0, -40 * np.sin(np.pi * s)) for s in np.linspace(0, 1, 20)])
    layer = last_take(page)
    page.click("[data-testid=record]")
    after = project(studio)
    assert curve(after, "box.position")[1] == box0[1], "a track not grabbed changed"
    t = np.array(layer["times"])
    assert ball0[0].t[0] < t[0] and t[-1] < ball0[0].t[-1], "the layer is not inside the ball's track"
    spline1, _ = curve(after, "ball.position")
    outside = np.r_[np.linspace(ball0[0].t[0] - 1, t[0], 300, endpoint=False),
                    np.linspace(t[-1], ball0[0].t[-1] + 1, 300)[1:]]
    assert np.abs(held(spline1, outside) - held(ball0[0], outside)).max() <= 1e-9
    _check_within(layer, after, "ball.position", below=ball0[0])
    assert drew_something(page) > 5 and not page.errors


def test_a_slider_drag_in_record_mode_records_its_attribute(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    page.click("[data-testid=outliner] li[data-object=lamp]")
    page.click("[data-testid=record]")
    box = page.locator("[data-testid='slider-lamp.intensity']").bounding_box()
    y = box["y"] + box["height"] / 2
    start = {"x": box["x"] + box["width"] * 0.2, "y": y}
    drag(page, start, [(box["width"] * 0.6 * np.sin(np.pi * s) ** 2, 0) for s in np.linspace(0, 1, 50)])
    take = last_take(page)
    assert take["paths"] == ["lamp.intensity"]
    values = np.array(take["rows"])[:, 0]
    assert values.max() - values.min() > 1.0, "the slider did not move the intensity"
    _check_within(take, project(studio), "lamp.intensity")
    assert drew_something(page) > 5 and not page.errors


def test_a_gamepad_moves_and_turns_the_selected_object_into_a_take(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio, GAMEPAD)
    page.click("[data-testid=outliner] li[data-object=box]")
    page.click("[data-testid=record]")
    page.evaluate("window.__pad.axes = [0.9, 0, -0.8, 0]")       # left stick right, right stick left
    page.wait_for_timeout(1500)
    page.evaluate("window.__pad.axes = [0, 0, 0, 0]")
    take = last_take(page)
    assert take["paths"] == ["box.position", "box.orientation"]
    rows = np.array(take["rows"])
    assert np.linalg.norm(rows[-1, :3] - rows[0, :3]) > 0.3
    turned = (Rotation.from_quat(rows[0, 3:]).inv() * Rotation.from_quat(rows[-1, 3:])).magnitude()
    assert np.degrees(turned) > 20
    doc = project(studio)
    _check_within(take, doc, "box.position")
    _check_within(take, doc, "box.orientation")
    assert drew_something(page) > 5 and not page.errors


def test_undo_and_redo_a_take(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    _record_once(page, "box", _sweep(30))
    recorded = curve(project(studio), "box.position")[1]
    page.click("[data-testid=undo]")
    page.wait_for_function("() => studio.history.can_redo && !studio.tracks.has('box.position')")
    assert curve(project(studio), "box.position") is None
    page.click("[data-testid=redo]")
    page.wait_for_function("() => studio.tracks.has('box.position')")
    assert curve(project(studio), "box.position")[1] == recorded
    assert page.evaluate("studio.tracks.get('box.position').coef") == recorded["coef"]
    assert drew_something(page) > 5 and not page.errors


def test_reload_shows_the_same_state(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    _record_once(page, "box", _sweep(30))
    page.evaluate("studio.transport.setLoop([0.1, 0.4]); studio.transport.seek(0.25)")
    page.wait_for_timeout(300)
    before = page.evaluate("({coef: studio.tracks.get('box.position').coef, time: studio.transport.time, "
                           "loop: studio.transport.clock.loop, box: studio.values.get('box.position'), "
                           "history: studio.history.undo})")
    page.reload()
    page.wait_for_selector("body[data-ready=true]", timeout=60_000)
    after = page.evaluate("({coef: studio.tracks.get('box.position').coef, time: studio.transport.time, "
                          "loop: studio.transport.clock.loop, box: studio.values.get('box.position'), "
                          "history: studio.history.undo})")
    assert after["coef"] == before["coef"] and after["history"] == before["history"]
    assert after["time"] == pytest.approx(0.25) and after["loop"] == [0.1, 0.4]
    assert np.allclose(after["box"], before["box"], atol=1e-12)
    assert drew_something(page) > 5 and viewport_drew(page) > 5 and not page.errors


def test_a_stalled_stretch_inside_a_take_is_a_gap(_page, studio: str) -> None:  # noqa: ANN001
    """Frames stop for 1.5 s mid-take (the page's main thread busy, as a tab in the
    background): the track holds the value before the stall across it (no swing of the
    curve), and every sample is within tolerance but those the blend fades in after it."""
    page = _page(studio)
    page.click("[data-testid=record]")
    page.wait_for_timeout(100)
    start = page.evaluate("viewport.screenOf('box')")
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    for i in range(1, 21):
        page.wait_for_timeout(16)
        page.mouse.move(start["x"] + 4 * i, start["y"])
    page.evaluate("(() => { const t = performance.now(); while (performance.now() - t < 1500) {} })()")
    for i in range(21, 41):
        page.mouse.move(start["x"] + 4 * i, start["y"] - 3 * (i - 20))
        page.wait_for_timeout(16)
    page.mouse.up()
    take = last_take(page)
    times = np.array(take["times"])
    k = int(np.argmax(np.diff(times)))
    # the 1.5 s stall, less the start of the pointer's rest before it (1.5 of its pace after its last event)
    assert times[k + 1] - times[k] > max(take["gap"], 1.3), "no stall in the take"
    doc = project(studio)
    spline, entry = curve(doc, "box.position")
    rows = np.array(take["rows"])
    inside = np.linspace(times[k], times[k + 1], 50, endpoint=False)
    assert np.abs(held(spline, inside) - rows[k]).max() <= entry["tol"], "the curve swings across the stall"
    _check_within(take, doc, "box.position")
    assert drew_something(page) > 5 and not page.errors


def _overlaps(a: dict, b: dict) -> bool:
    return a["x"] < b["x"] + b["width"] and b["x"] < a["x"] + a["width"] and a["y"] < b["y"] + b["height"] \
        and b["y"] < a["y"] + a["height"]


def test_a_notice_shows_styled_readable_and_dismissable(_page, studio: str) -> None:  # noqa: ANN001
    """A server notice (a recorder's warning, injected as the server would send it) shows in
    the notice area by its level, clear of REC and the curve view, until dismissed; a refusal
    of a message (a real one from the server) shows too."""
    page = _page(studio)
    text = "the journal failed (disk full): this take is not safe from a crash"
    page.evaluate("(text) => studio.receive({type: 'notice', level: 'warning', text, source: 'recorder'})", text)
    notice = page.locator("[data-testid=notice][data-level=warning]")
    notice.wait_for(state="visible")
    assert text in notice.inner_text() and "recorder" in notice.inner_text().lower()
    assert "warning" in notice.get_attribute("class")
    box = notice.bounding_box()
    for other in ("[data-testid=record]", "[data-testid=curves]", "[data-testid=transport]"):
        assert not _overlaps(box, page.locator(other).bounding_box()), f"the notice covers {other}"
    colour = page.evaluate("getComputedStyle(document.querySelector('[data-testid=notice] .text')).color")
    assert colour == "rgb(255, 255, 255)"
    assert drew_something(page) > 5
    page.evaluate("studio.send({type: 'set', path: 'nothing.here', value: [1]})")     # the server refuses it
    refused = page.locator("[data-testid=notice][data-level=error]")
    refused.wait_for(state="visible")
    assert "refused" in refused.inner_text() and page.evaluate("studio.errors.length") == 1
    notice.locator("[data-testid=notice-dismiss]").click()
    notice.wait_for(state="detached")
    assert page.locator("[data-testid=notice][data-level=warning]").count() == 0
    assert drew_something(page) > 5 and not page.errors


def test_the_keys_drive_the_transport_and_the_gizmo(_page, studio: str) -> None:  # noqa: ANN001
    """L loops, R records, Space plays, W / E / S switch the gizmo; typed into a field, keys are the field's."""
    page = _page(studio)
    page.keyboard.press("l")
    assert page.evaluate("studio.transport.clock.loop") is not None
    page.keyboard.press("l")
    assert page.evaluate("studio.transport.clock.loop") is None
    page.keyboard.press("e")
    assert page.evaluate("viewport.transform.mode") == "rotate"
    page.keyboard.press("w")
    assert page.evaluate("viewport.transform.mode") == "translate"
    page.keyboard.press("r")
    assert page.evaluate("studio.transport.record") is True
    page.keyboard.press("r")
    assert page.evaluate("studio.transport.record") is False
    page.click("[data-testid=outliner] li[data-object=box]")
    page.locator("[data-testid='edit-box.position-0']").focus()
    page.keyboard.press("l")
    assert page.evaluate("studio.transport.clock.loop") is None, "a key typed into a field reached the studio"
    assert drew_something(page) > 5 and not page.errors


def _reducer_processes(project: Path) -> list[int]:
    """The studio server's reducer processes: forked from the server (same command line,
    naming ``project``), so their parent is a process of that command line too."""
    def cmdline(pid: str) -> str:
        try:
            return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
        except OSError:
            return ""

    def parent(pid: str) -> str:
        try:
            return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1]
        except (OSError, IndexError):
            return ""

    ours = {pid for pid in (p.name for p in Path("/proc").iterdir() if p.name.isdigit())
            if str(project) in cmdline(pid) and " studio " in cmdline(pid)}
    return [int(pid) for pid in ours if parent(pid) in ours]


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="finds the server's processes through /proc")
def test_a_reducer_process_killed_mid_take_shows_a_warning_notice_and_the_take_lands(_page, tmp_path: Path) -> None:  # noqa: ANN001
    """A real recorder warning, end to end: the server's reducer processes are killed while a
    take is held; at the release the recorder reduces from the raw take and warns, and the
    page shows that warning as a notice (not only the server's log), the take still laid."""
    import os
    import signal

    path = tmp_path / "studio.sketchanim"
    with studio_server(path) as url:
        page = _page(url)
        page.click("[data-testid=record]")
        page.wait_for_timeout(100)
        start = page.evaluate("viewport.screenOf('box')")
        page.mouse.move(start["x"], start["y"])
        page.mouse.down()
        for dx, dy in _sweep(20):
            page.wait_for_timeout(16)
            page.mouse.move(start["x"] + dx, start["y"] + dy)
        workers = _reducer_processes(path)
        assert workers, "no reducer process found under the studio server"
        for pid in workers:
            os.kill(pid, signal.SIGKILL)
        for dx, dy in _sweep(20, dx=-80, dy=40):
            page.wait_for_timeout(16)
            page.mouse.move(start["x"] + 160 + dx, start["y"] + dy)
        page.mouse.up()
        take = last_take(page, timeout=60_000)
        died = page.locator("[data-testid=notice][data-level=warning]", has_text="a reducer process died")
        died.wait_for(state="visible", timeout=30_000)
        assert "raw take" in died.inner_text() and "Traceback" not in died.inner_text()
        assert take["paths"] == ["box.position"]
        doc = page.evaluate("fetch('/api/project').then(r => r.json())")
        assert curve(doc, "box.position") is not None, "the take was not laid on its track"
        assert drew_something(page) > 5
    assert "reducer process" in path.with_name(path.name + ".log").read_text(), "the warning is not in the server's log"


def test_a_smooth_2_s_drag_gives_3_samples_per_control_point_at_the_default_tolerance(
        _page, studio: str, tmp_path: Path) -> None:  # noqa: ANN001
    """A smooth scripted 2 s pointer drag in record mode: the page sends 2 px at the grabbed
    point's depth as the take's tolerance (and shows it), the curve keeps every sample
    within it, with at least 3 samples per control point."""
    page = _page(studio)
    page.click("[data-testid=record]")
    page.wait_for_timeout(100)
    start = page.evaluate("viewport.screenOf('box')")
    # a pixel at the grabbed point's depth (the drag's plane faces the view through it), from the view
    pixel_now = """() => { const c = viewport.camera; const depth = -viewport.drag.plane.distanceToPoint(c.position);
        return 2 * depth * Math.tan(c.fov * Math.PI / 360) / viewport.renderer.domElement.clientHeight; }"""
    u = np.linspace(0, 1, 121)
    offsets = list(zip(260 * _smoothstep(u), -70 * np.sin(np.pi * u)))
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    status = ""
    for i, (dx, dy) in enumerate(offsets):
        page.wait_for_timeout(16)
        page.mouse.move(start["x"] + dx, start["y"] + dy)
        if i == 60:
            pixel = page.evaluate(pixel_now)
            status = page.locator("[data-testid=take-status]").inner_text()
            page.locator("[data-testid=transport]").screenshot(path=str(tmp_path / "take-status.png"))
    page.wait_for_timeout(16)
    page.mouse.up()
    take = last_take(page)
    sent = page.evaluate("studio.takes.at(-1).sampler.tolerance['box.position']")
    assert sent["steps"] == 2 and sent["input"] == "px"
    assert abs(sent["tol"] - 2 * pixel) <= 1e-9 * pixel, (sent, pixel)
    shown = float(format(sent["tol"], ".2g"))
    assert f"tol 2 px = {shown:g}" in status, status
    doc = project(studio)
    _, entry = curve(doc, "box.position")
    assert entry["tol"] == sent["tol"], "the track is not kept within the tolerance the page sent"
    times = _check_within(take, doc, "box.position")
    n = len(times)
    assert n >= 100, f"{n} samples for a 2 s drag"
    assert n / len(entry["coef"]) >= 3, f"{n} samples, {len(entry['coef'])} control points"
    assert "tol 2 px" in page.locator(".curve-title").inner_text()
    assert drew_something(page) > 5 and not page.errors


def test_the_inspector_sets_a_tolerance_the_project_keeps(_page, studio: str, tmp_path: Path) -> None:  # noqa: ANN001
    page = _page(studio)
    page.evaluate("studio.select('box')")
    field = page.locator("[data-testid='tol-box.position']")
    field.fill("0.05")
    page.select_option("[data-testid='tol-unit-box.position']", "units")
    field.press("Tab")
    page.wait_for_function("() => studio.tolerances.get('box.position')?.unit === 'units'")
    page.wait_for_timeout(800)                      # the server saves soon after
    assert project(studio)["tolerances"] == {"box.position": {"amount": 0.05, "unit": "units"}}
    page.reload()
    page.wait_for_selector("body[data-ready=true]", timeout=60_000)
    page.evaluate("studio.select('box')")
    assert page.locator("[data-testid='tol-box.position']").input_value() == "0.05"
    assert page.locator("[data-testid='tol-unit-box.position']").input_value() == "units"
    page.locator("[data-testid=inspector]").screenshot(path=str(tmp_path / "inspector.png"))
    page.click("[data-testid=record]")
    take = _record_drag(page, "box", _sweep(30))
    assert page.evaluate("studio.takes.at(-1).sampler.tolerance['box.position'].tol") == 0.05
    _, entry = curve(project(studio), "box.position")
    assert entry["tol"] == 0.05 and take["label"]
    assert drew_something(page) > 5 and not page.errors


def test_a_smoothed_take_from_the_smooth_menu(_page, studio: str) -> None:  # noqa: ANN001
    """The smooth menu's width goes with take.begin: the status says the take is smoothed,
    the project keeps the raw samples and the smoothing, and the curve is within its
    tolerance of the smoothed samples."""
    from sketchanim.reducer.smoothing import smooth

    page = _page(studio)
    page.select_option("[data-testid=smoothing]", "0.05")
    page.click("[data-testid=record]")
    page.wait_for_timeout(100)
    start = page.evaluate("viewport.screenOf('box')")
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    status = ""
    for i, (dx, dy) in enumerate(_sweep()):
        page.wait_for_timeout(16)
        page.mouse.move(start["x"] + dx, start["y"] + dy)
        if i == 20:
            status = page.text_content("[data-testid=take-status]")
    page.wait_for_timeout(16)
    page.mouse.up()
    take = last_take(page)
    assert "smoothed 0.05 s" in status, status
    doc = project(studio)
    spline, entry = curve(doc, "box.position")
    times, rows = np.array(take["times"]), np.array(take["rows"])
    parts = [doc["takes"][i] for i in entry["takes"]]          # one, or one per part between stalls
    assert doc["smoothing"] == {str(i): 0.05 for i in entry["takes"]}
    assert np.array_equal(np.concatenate([p["times"] for p in parts]), times)
    assert np.array_equal(np.vstack([p["values"] for p in parts]), rows)
    for k, part in enumerate(parts):
        t, x = np.array(part["times"]), np.array(part["values"])
        settled = t >= t[0] + (BLEND if k else 0)               # a part after a stall fades in
        error = np.abs(held(spline, t) - smooth(t, x, 0.05)).max(axis=1)
        assert error[settled].max() <= entry["tol"] * (1 + 1e-6)
    assert page.input_value("[data-testid=smoothing]") == "0.05"
    page.wait_for_function("document.querySelector('.curve-title').textContent.includes('smoothed 0.05 s')",
                           timeout=10_000)                   # the curve view says what its tolerance is against
    assert drew_something(page) > 5 and not page.errors
