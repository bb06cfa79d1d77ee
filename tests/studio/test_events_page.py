"""Discrete events performed in a real browser: a cue marked with M and a light switched
off while the transport plays land within one frame of the transport's time the animator
saw; cues fire once each time playback passes them; each key is one undo step."""

from __future__ import annotations

from studio_browser import drew_something, project

#: Keeps the transport's time on the frames before and after the next event of a type (what the
#: animator saw as they pressed) in ``window.seen``.
SEEN = """(type) => window.addEventListener(type, () => {
  const before = studio.transport.time;
  requestAnimationFrame(() => { window.seen = [before, studio.transport.time]; });
}, { capture: true, once: true })"""


def _steps(url: str, path: str) -> dict | None:
    return next((s for s in project(url)["steps"] if s["path"] == path), None)


def _seen(page) -> tuple[float, float]:  # noqa: ANN001
    """The transport's time on the frames before and after the event :data:`SEEN` watched."""
    page.wait_for_function("window.seen !== undefined")
    return tuple(page.evaluate("window.seen"))


def _within_a_frame(page, t: float, seen: tuple[float, float]) -> bool:  # noqa: ANN001
    """``t`` is within one frame of the transport's time the animator saw as they pressed."""
    frame = 1 / page.evaluate("studio.fps")
    return seen[0] - frame <= t <= seen[1] + frame


def test_a_cue_marked_while_playing_lands_at_the_transport_time_and_fires_once_per_pass(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    page.click("[data-testid=outliner] li[data-object=box]")
    page.evaluate("studio.transport.setLoop([0, 1.5])")
    page.keyboard.press("Space")
    page.wait_for_function("studio.transport.time > 0.6")
    page.evaluate(SEEN, "keydown")
    page.keyboard.press("m")
    at = _seen(page)
    page.wait_for_function("studio.tracks.has('box.cue')")
    cue = _steps(studio, "box.cue")
    assert cue is not None and len(cue["times"]) == 1 and cue["values"] == [None]
    assert _within_a_frame(page, cue["times"][0], at), (cue["times"][0], at)
    # two more passes of the loop: the cue fires once each (flashed over the view)
    fired = page.evaluate("""() => new Promise((resolve) => {
      const times = [];
      studio.signals.on('fired', (f) => times.push(...f.map((e) => e.time)));
      const start = performance.now();
      const wait = () => (performance.now() - start > 3000 ? resolve(times) : setTimeout(wait, 50));
      wait();
    })""")
    assert len(fired) == 2 and all(t == cue["times"][0] for t in fired), fired
    assert page.evaluate("cueFlash.count") >= 2
    page.keyboard.press("Space")
    assert drew_something(page) > 5
    page.keyboard.press("Control+z")
    page.wait_for_function("!studio.tracks.has('box.cue')")
    assert _steps(studio, "box.cue") is None
    assert not page.errors


def test_switching_a_light_off_while_playing_keys_it_and_it_plays_back(_page, studio: str) -> None:  # noqa: ANN001
    page = _page(studio)
    page.click("[data-testid=outliner] li[data-object=lamp]")
    box = page.locator("[data-testid='edit-lamp.on']")
    page.wait_for_function("document.querySelector(\"[data-testid='edit-lamp.on']\")?.checked === true")
    page.keyboard.press("Space")
    page.wait_for_function("studio.transport.time > 0.8")
    page.evaluate(SEEN, "pointerdown")
    box.click()
    at = _seen(page)
    page.wait_for_function("studio.tracks.has('lamp.on')")
    page.keyboard.press("Space")
    on = _steps(studio, "lamp.on")
    assert on["values"] == [True, False] and on["times"][0] == 0.0           # on until it was switched off
    assert _within_a_frame(page, on["times"][1], at), (on["times"][1], at)
    # played back: on before the key, off after
    page.evaluate(f"studio.transport.seek({on['times'][1] / 2})")
    page.wait_for_function("studio.values.get('lamp.on') === true")
    page.evaluate(f"studio.transport.seek({on['times'][1] + 0.1})")
    page.wait_for_function("studio.values.get('lamp.on') === false")
    steps = page.evaluate("studio.history.undo.length")
    page.keyboard.press("Control+z")
    page.wait_for_function(f"studio.history.undo.length === {steps - 1}")
    assert _steps(studio, "lamp.on") is None and project(studio)["objects"][3]["name"] == "lamp"
    assert drew_something(page) > 5 and not page.errors
