"""Chains and walkers in the studio page, in Debian's chromium against a real server on a fresh
project: added from the outliner with the mouse, their goals dragged with the mouse in record
mode (a chain's goal handle in the plane facing the view, a walker's ground marker on the
floor), the takes are ``<name>.goal`` tracks, playback moves the figures, and the page's pose at
a tick is ik.js's ``solve`` / walk.js's ``walk`` run on the goal curve as the server has it,
sampled at the ticks here, and the model's (motion/ik.py, motion/walk.py) to 1e-6 rad; undo
takes the takes away. Screenshots go to /tmp/shots-rigs/."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from sketchanim.anim.rigs import LEAD
from sketchanim.motion import ik, walk
from studio_browser import GAMEPAD, curve, drag, drew_something, held, last_take, project

SHOTS = Path("/tmp/shots-rigs")
RATE = ik.RATE


def _led(k: int) -> np.ndarray:
    """The times a goal is sampled at for ticks 0..k, as anim/rigs.py does: LEAD ticks at 0, then the ticks."""
    return np.r_[np.zeros(LEAD), np.arange(k + 1) / RATE]


def _shot(page, name: str) -> np.ndarray:  # noqa: ANN001
    """A screenshot of the 3D view (kept in SHOTS), as RGB pixels."""
    from PIL import Image

    SHOTS.mkdir(exist_ok=True)
    shot = page.locator("[data-testid=viewport]").screenshot(path=str(SHOTS / f"{name}.png"))
    return np.asarray(Image.open(io.BytesIO(shot)).convert("RGB"), dtype=int)


def _add(page, kind: str) -> str:  # noqa: ANN001
    """Click "+ <kind>" in the outliner; the new rig's name, once the page draws it."""
    before = page.evaluate(f"studio.objects.filter(o => o.kind === '{kind}').length")
    page.click(f"[data-testid=add-{kind}]")
    page.wait_for_function(f"studio.objects.filter(o => o.kind === '{kind}').length === {before + 1}")
    name = page.evaluate(f"studio.objects.filter(o => o.kind === '{kind}').at(-1).name")
    page.wait_for_function(f"viewport.rigReport().some(r => r.name === '{name}' && r.points.length > 2)")
    return name


def _report(page, name: str) -> dict:  # noqa: ANN001
    return next(r for r in page.evaluate("viewport.rigReport()") if r["name"] == name)


def _pose_at_tick(page, name: str, k: int) -> dict:  # noqa: ANN001
    """The page's pose of ``name`` with the playhead on tick ``k`` (drawn, then read)."""
    page.evaluate(f"studio.transport.seek({k} / {RATE})")
    page.wait_for_function(f"studio.transport.time === {k} / {RATE}")
    page.wait_for_timeout(50)
    return _report(page, name)


def _sweep(n: int, dx: float, dy: float) -> list[tuple[float, float]]:
    s = np.linspace(0, 1, n)
    return list(zip(dx * np.sin(np.pi * s / 2), dy * np.sin(np.pi * s)))


def test_add_chain_and_walker_record_their_goals_play_and_undo(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    chain, walker = _add(page, "chain"), _add(page, "walker")
    assert _report(page, chain)["kind"] == "chain" and _report(page, walker)["kind"] == "walker"
    _shot(page, "added")
    base = np.array(page.evaluate(f"studio.values.get('{chain}.position')"))
    # record mode: drag the chain's goal handle, then the walker's ground marker
    page.click("[data-testid=record]")
    page.wait_for_timeout(100)
    drag(page, page.evaluate(f"viewport.goalScreen('{chain}')"), _sweep(50, -70, -50))
    take = last_take(page)
    assert take["paths"] == [f"{chain}.goal"] and take["label"], take["errors"]
    page.wait_for_timeout(100)
    marker = page.evaluate(f"viewport.goalScreen('{walker}')")
    drag(page, marker, _sweep(60, 110, 40))
    take = last_take(page)
    assert take["paths"] == [f"{walker}.goal"] and take["label"], take["errors"]
    rows = np.array(take["rows"])
    assert np.abs(rows[:, 1]).max() < 1e-9, "the marker left the ground plane"
    assert np.ptp(rows[:, 0]) > 0.3 or np.ptp(rows[:, 2]) > 0.3, "the marker hardly moved"
    page.click("[data-testid=record]")
    for name in (chain, walker):          # its goal's motion path, the playhead in its take
        page.evaluate(f"studio.transport.seek(studio.tracks.get('{name}.goal').start)")
        page.click(f"[data-testid=outliner] li[data-object={name}]")
        page.wait_for_function(f"viewport.paths.report().some(p => p.path === '{name}.goal')")
        assert page.evaluate("curveEditor.shownPaths()") == [f"{name}.goal"], "the curve view does not show the goal"
        page.evaluate(f"studio.transport.seek(studio.tracks.get('{name}.goal').start + 0.5)")
        page.keyboard.press("o")                        # onion skin: ghosts of the figure either side
        page.wait_for_function(f"viewport.onion.report().filter(g => g.name === '{name}').length >= 4")
        sides = {g["side"] for g in page.evaluate("viewport.onion.report()")}
        assert sides == {"before", "after"}
        _shot(page, f"onion-{name}")
        page.keyboard.press("o")
    doc = project(studio)
    goal, entry = curve(doc, f"{chain}.goal")
    path, walked = curve(doc, f"{walker}.goal")
    _shot(page, "recorded")
    # playback moves both figures: each at a quarter and three quarters of its take's span
    spans = {chain: (entry["knots"][0], entry["knots"][-1]), walker: (walked["knots"][0], walked["knots"][-1])}
    marks = sorted((a + f * (b - a), name) for name, (a, b) in spans.items() for f in (0.25, 0.75))
    page.evaluate("studio.transport.seek(0)")
    page.click("[data-testid=play]")
    seen: dict[str, list[np.ndarray]] = {chain: [], walker: []}
    for t, name in marks:
        page.wait_for_function(f"studio.transport.time > {t}")
        seen[name].append(np.array(_report(page, name)["points"]))
    page.click("[data-testid=play]")
    for name, (a, b) in seen.items():
        assert np.abs(a - b).max() > 1e-3, f"{name} did not move in playback"
    # the page's pose on a tick is the solver's on the goal curve sampled here
    k = int(0.5 * (entry["knots"][0] + entry["knots"][-1]) * RATE)
    goals = held(goal, _led(k)) - base
    solved = page.evaluate("""async ([name, goals]) => { const ik = await import('/js/ik.js');
        const o = studio.objectOf(name); const v = (a) => studio.values.get(`${name}.${a}`);
        const chain = ik.chainFromSlots(v('lengths'), v('limits'), v('hinges'));
        return Array.from(ik.solve(chain, Float64Array.from(goals.flat())).slice(-4 * chain.lengths.length)); }""",
                           [chain, goals.tolist()])
    shown = _pose_at_tick(page, chain, k)
    assert np.abs(np.array(shown["rotations"]) - solved).max() < 1e-6
    v = {a: page.evaluate(f"studio.values.get('{chain}.{a}')") for a in ("lengths", "limits", "hinges")}
    model = ik.solve(ik.Chain.from_slots(v["lengths"], v["limits"], v["hinges"]), goals)[-1]
    assert np.abs(np.array(shown["rotations"]) - model.ravel()).max() < 1e-6
    assert np.allclose(shown["goal"], held(goal, np.array([k / RATE]))[0], atol=1e-6)
    k = int(0.6 * (walked["knots"][0] + walked["knots"][-1]) * RATE)
    markers = held(path, _led(k))
    stepped = page.evaluate("""async ([name, markers]) => { const w = await import('/js/walk.js');
        const sk = w.humanoid(studio.values.get(`${name}.height`)[0]);
        const out = w.walk(sk, Float64Array.from(markers.flat())); const J = 4 * sk.names.length;
        return {rotations: Array.from(out.rotations.slice(-J)), root: Array.from(out.root.slice(-3))}; }""",
                            [walker, markers.tolist()])
    shown = _pose_at_tick(page, walker, k)
    assert np.abs(np.array(shown["rotations"]) - stepped["rotations"]).max() < 1e-6
    assert np.abs(np.array(shown["root"]) - stepped["root"]).max() < 1e-6
    model = walk.walk(walk.humanoid(page.evaluate(f"studio.values.get('{walker}.height')[0]")), markers)
    assert np.abs(np.array(shown["rotations"]) - model.rotations[-1].ravel()).max() < 1e-6
    assert np.abs(np.array(shown["root"]) - model.root[-1]).max() < 1e-6
    # a notice names the walker exactly when the model's walk falls behind its marker somewhere
    end = walked["knots"][-1]
    behind = walk.walk(walk.humanoid(1.75), held(path, _led(int(np.ceil((end + 1) * RATE))))).behind
    page.wait_for_function(f"viewport.rigs.behindUntil('{walker}', {end + 1}, 0) !== null")
    page.wait_for_timeout(100)
    told = [n["text"] for n in page.evaluate("studio.notices") if n["source"] == "walker"]
    assert bool(told) == bool(behind), (told, behind)
    assert all(t.startswith(f"{walker} falls behind its marker from") for t in told)
    pixels = _shot(page, "played")
    assert pixels.std() > 5 and drew_something(page) > 5
    # undo takes the walker's take away, then the chain's
    page.click("[data-testid=undo]")
    page.wait_for_function(f"!studio.tracks.has('{walker}.goal') && studio.tracks.has('{chain}.goal')")
    page.click("[data-testid=undo]")
    page.wait_for_function(f"!studio.tracks.has('{chain}.goal')")
    doc = project(studio)
    assert curve(doc, f"{chain}.goal") is None and curve(doc, f"{walker}.goal") is None
    assert not page.errors


def test_a_chains_body_drags_its_base_and_the_gizmo_moves_a_walkers_goal(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    chain, walker = _add(page, "chain"), _add(page, "walker")
    base = page.evaluate(f"studio.values.get('{chain}.position')")
    goal = page.evaluate(f"studio.values.get('{chain}.goal')")
    # while its goal is held, the chain follows it live: the tip reaches the goal where the hand is
    start = page.evaluate(f"viewport.goalScreen('{chain}')")
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    for i in range(1, 11):
        page.mouse.move(start["x"] - 3 * i, start["y"] + 2 * i)
        page.wait_for_timeout(16)
    page.wait_for_timeout(600)                          # the catch-up settles (2 reaches a second)
    held_goal = page.evaluate(f"studio.values.get('{chain}.goal')")
    assert held_goal != goal and page.evaluate(f"studio.performer.holds('{chain}.goal')")
    tip = _report(page, chain)["points"][-1]
    assert np.linalg.norm(np.array(tip) - held_goal) < 1e-2, "the chain does not follow its held goal"
    page.mouse.up()
    page.wait_for_function(f"studio.served.get('{chain}.goal')[0] !== {goal[0]}")
    page.click("[data-testid=undo]")
    page.wait_for_function(f"studio.served.get('{chain}.goal')[0] === {goal[0]}")
    # the chain drawn back at its goal before its joints are aimed at (a loaded machine draws late)
    page.wait_for_function(f"(() => {{ const p = viewport.rigReport().find(r => r.name === '{chain}').points.at(-1); "
                           f"return Math.hypot(p[0] - {goal[0]}, p[1] - {goal[1]}, p[2] - {goal[2]}) < 1e-2; }})()")
    # (nothing selected: no gizmo over it; the joint farthest on screen from the goal handle and the base)
    page.keyboard.press("Escape")
    at = {i: page.evaluate(f"viewport.jointScreen('{chain}', {i})") for i in range(6)}
    aim = page.evaluate(f"viewport.goalScreen('{chain}')")
    far = max(range(1, 5), key=lambda i: min(np.hypot(at[i]["x"] - p["x"], at[i]["y"] - p["y"]) for p in (aim, at[0])))
    drag(page, at[far], [(4 * i, 0) for i in range(1, 16)])
    page.wait_for_function(f"studio.served.get('{chain}.position')[0] !== {base[0]}")
    assert page.evaluate(f"studio.values.get('{chain}.goal')") == goal, "dragging the body moved the goal"
    assert page.evaluate("studio.selected") == chain
    # the inspector's joints table: a length of 0 ends the chain there; a new joint in the spare row
    page.click(f"[data-testid=outliner] li[data-object={chain}]")
    assert page.locator(f"[data-testid=joints-{chain}] input[type=number][data-testid*=lengths]").count() == 6   # 5 joints and a spare
    page.fill(f"[data-testid='edit-{chain}.lengths-2']", "0")
    page.press(f"[data-testid='edit-{chain}.lengths-2']", "Enter")
    page.wait_for_function(f"viewport.rigReport().find(r => r.name === '{chain}').points.length === 3")
    page.wait_for_function(f"studio.served.get('{chain}.lengths').join() === '0.5,0.4,0,0,0,0,0,0'")
    page.fill(f"[data-testid='edit-{chain}.lengths-2']", "0.6")
    page.press(f"[data-testid='edit-{chain}.lengths-2']", "Enter")
    page.wait_for_function(f"viewport.rigReport().find(r => r.name === '{chain}').points.length === 4")
    page.click(f"[data-testid='edit-{chain}.hinges-0']")
    page.wait_for_function(f"studio.served.get('{chain}.hinges')[0] === 1")
    for _ in range(3):
        page.click("[data-testid=undo]")
    page.wait_for_function(f"viewport.rigReport().find(r => r.name === '{chain}').points.length === 6")
    # pressing on the walker's body (its head) drags its goal, level on the ground
    marker = page.evaluate(f"studio.values.get('{walker}.goal')")
    head = page.evaluate(f"viewport.nodes.get('{walker}').rig.skeleton.names.indexOf('head')")
    drag(page, page.evaluate(f"viewport.jointScreen('{walker}', {head})"), [(-5 * i, 2 * i) for i in range(1, 16)])
    page.wait_for_function(f"studio.served.get('{walker}.goal')[0] !== {marker[0]}")
    moved = page.evaluate(f"studio.served.get('{walker}.goal')")
    assert moved[1] == marker[1] and np.hypot(moved[0] - marker[0], moved[2] - marker[2]) > 0.1
    # the walker selected, W: the gizmo is on its marker and moves its goal
    page.click(f"[data-testid=outliner] li[data-object={walker}]")
    page.keyboard.press("w")
    assert page.evaluate(f"viewport.transform.object === viewport.nodes.get('{walker}').rig.goal")
    page.keyboard.press("e")
    assert page.evaluate("viewport.transform.object") is None, "a walker has no rotate gizmo"
    page.keyboard.press("Control+z")
    page.wait_for_function(f"studio.served.get('{walker}.goal')[0] === {marker[0]}")
    page.keyboard.press("Control+z")
    page.wait_for_function(f"studio.served.get('{chain}.position')[0] === {base[0]}")
    assert drew_something(page) > 5 and not page.errors


def test_a_gamepad_steers_a_walkers_goal_on_its_ground_into_a_take(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio, GAMEPAD)
    walker = _add(page, "walker")
    page.click(f"[data-testid=outliner] li[data-object={walker}]")
    start = np.array(_report(page, walker)["points"][0])
    page.click("[data-testid=record]")
    page.evaluate("window.__pad.axes = [0.9, 0.5, 0, 0]")         # left stick: right and back
    page.wait_for_timeout(1500)
    page.evaluate("window.__pad.axes = [0, 0, 0, 0]")
    take = last_take(page)
    assert take["paths"] == [f"{walker}.goal"], take["errors"]
    rows = np.array(take["rows"])
    assert np.ptp(rows[:, 1]) == 0, "the marker left its ground"
    assert np.linalg.norm(rows[-1] - rows[0]) > 0.5
    page.click("[data-testid=record]")
    page.evaluate(f"studio.transport.seek(studio.tracks.get('{walker}.goal').end + 1)")
    page.wait_for_timeout(200)
    hips = np.array(_report(page, walker)["points"][0])
    assert np.linalg.norm((hips - start)[[0, 2]]) > 0.4, "the walker did not walk after its goal"
    assert drew_something(page) > 5 and not page.errors
