"""The studio page in a browser (Debian's chromium, headless, WebGL through SwiftShader,
driven by Playwright) against a real server.

    .venv/bin/python benchmarks/bench_studio.py [--takes 20] [--objects 50] [--seconds 4] [--only page|curves|timeline|sound]
                                                [--sound-minutes 5]

1. Capture: ``--takes`` drags of the box in record mode (0.4 to 1.2 s each): samples per
   second of each take against the page's frame rate (one sample per animation frame is
   the promise), and the release-to-final-curve latency (the release's frame to the final
   curve in the page; target <= 100 ms), p50 / p99, with the server's share.
2. Playback: a project of ``--objects`` objects, each with a position and an orientation
   track (5 s, 24 control points), played in a loop for ``--seconds``: the page's
   per-frame time to evaluate every track and write the values into the three.js scene
   (target <= 4 ms), the whole frame's script, and the frame rate.
3. Curve editor: an object with 10 position tracks of 2,000 keys each (60 s), all shown:
   the editor's script per drawn frame and the page's whole script per frame while the
   view zooms (every frame draws everything again) and while a control point is dragged
   (the cached layer copied, the dragged track drawn over it); target <= 8 ms.
4. Tolerance after the take: a 60 s take at 120 Hz, its tolerance changed in the editor:
   change to the new curve in the page (one History step), a slider preview's answer, and
   the page's frame interval and script meanwhile.

5. Timeline (``--only timeline``, not in the default run): 50 lanes (25 objects, a position
   and an orientation track each) and the waveform of a 10 min sound (synthetic, 22.05 kHz,
   drawn by the sound panel's own peak pyramid, ``waveform.js``) above them, the view spanning the 10 min: the timeline's draw, everything painted again
   each frame, then the playhead alone moving (what playback draws), median and p99 ms
   (target: a few ms).
6. Sound (``--only sound``, not in the default run): a WAV of ``--sound-minutes`` imported, played through at 1x:
   the audio element's drift against the transport at every frame (``audio.currentTime -
   (transport.time - offset)``), p50 / p99 of its size in ms (target: within a frame, 41.7
   ms at 24 fps), and the re-seeks it took; and the waveform strip's drawing of the whole
   sound and of 2 s of it across 1,600 px (the peak pyramid's columns).

Software WebGL draws every pixel on the CPU, so the frame rate here is bounded by
rasterisation on this machine, not by the page's script; the script times are what a
GPU would leave. One run; medians and p99.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from sketchanim.anim.attributes import ORIENTATION, POSITION
from sketchanim.anim.layers import recorded_over
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.project.store import Project
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.takes import ORDER

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))
from studio_browser import drag, last_take, launch, open_page, studio_server  # noqa: E402
from studio.test_curve_editor_page import many_keys_project  # noqa: E402


def capture(browser, url: str, takes: int, rng: np.random.Generator) -> dict:  # noqa: ANN001
    """Record ``takes`` drags; per take: samples/s, frames/s, latencies."""
    page = open_page(browser, url)
    page.click("[data-testid=record]")
    rates, frames, latency, server = [], [], [], []
    for i in range(takes):
        page.wait_for_timeout(150)
        start = page.evaluate("viewport.screenOf('box')")
        steps = int(rng.integers(25, 75))
        s = np.linspace(0, 1, steps)
        sign = 1 if i % 2 == 0 else -1
        drag(page, start, list(zip(sign * 120 * s, -50 * np.sin(np.pi * s))))
        take = last_take(page)
        stamps = np.array(take["stamps"])
        rates.append((len(stamps) - 1) / ((stamps[-1] - stamps[0]) / 1000))
        interval = np.array(page.evaluate("studioStats.interval"))[-len(stamps):]
        frames.append(1000 / np.mean(interval))
        latency.append(take["latency"])
        server.append(page.evaluate("studio.takes.at(-1).serverMs"))
    page.close()
    return {"rates": np.array(rates), "frames": np.array(frames), "latency": np.array(latency),
            "server": np.array(server, dtype=float)}


def animated_project(path: Path, objects: int, rng: np.random.Generator) -> None:
    """A project of ``objects`` objects with position and orientation tracks (5 s)."""
    scene = Scene()
    tracks = {}
    knots = np.r_[[0.0] * 4, np.linspace(0, 5, 22)[1:-1], [5.0] * 4]
    for i in range(objects):
        name = f"obj{i}"
        scene.add(name)
        centre = np.array([(i % 10) - 4.5, 0.5, (i // 10) - 2.0])
        pos = centre + 0.4 * rng.standard_normal((24, 3))
        quat = Rotation.from_rotvec(rng.standard_normal((24, 3))).as_quat()
        tracks[f"{name}.position"] = ContinuousTrack(f"{name}.position", POSITION, BSpline(knots, pos, 3), 0.005)
        tracks[f"{name}.orientation"] = ContinuousTrack(f"{name}.orientation", ORIENTATION, BSpline(knots, quat, 3), 0.5)
    scene.add("lamp", "light").attributes["position"].value = np.array([2.0, 5.0, 4.0])
    scene.add("cam", "camera").attributes["position"].value = np.array([0.0, 2.0, 9.0])
    with Project(path) as project:
        project.save(scene, tracks)


def playback(browser, url: str, seconds: float) -> dict:  # noqa: ANN001
    """Loop the animation for ``seconds``; the page's per-frame timings."""
    page = open_page(browser, url)
    page.evaluate("studio.transport.setLoop([0, 5]); studio.transport.seek(0); studio.transport.play()")
    page.wait_for_timeout(500)
    page.evaluate("for (const k of Object.keys(studioStats)) studioStats[k].length = 0")
    page.wait_for_timeout(int(seconds * 1000))
    stats = page.evaluate("studioStats")
    tracks = page.evaluate("studio.packed.paths.length")
    page.close()
    return {k: np.array(v) for k, v in stats.items()} | {"tracks": tracks}


CLEAR = ("for (const k of Object.keys(studioStats)) studioStats[k].length = 0;"
         " curveEditor.stats.draw.length = 0; curveEditor.stats.move.length = 0")
STATS = "({script: studioStats.script, interval: studioStats.interval, draw: curveEditor.stats.draw, move: curveEditor.stats.move})"


def curve_editor(browser, url: str) -> dict:  # noqa: ANN001
    """10 tracks of 2,000 keys in the editor: per-frame times while zooming, then while dragging a point."""
    page = open_page(browser, url, size=(1280, 800))
    page.evaluate("studio.select('rig')")
    page.locator("[data-testid=curve-all]").check()
    page.wait_for_function("() => curveEditor.lanes.length === 10", timeout=60_000)
    page.keyboard.press("Home")
    page.wait_for_timeout(500)
    box = page.locator("[data-testid=curve-editor]").bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.evaluate(CLEAR)
    for i in range(40):
        page.mouse.wheel(0, -60 if i < 20 else 60)
        page.wait_for_timeout(16)
    page.wait_for_timeout(200)
    zoom = {k: np.array(v) for k, v in page.evaluate(STATS).items()}
    page.keyboard.press("Home")
    page.wait_for_timeout(300)
    xy = page.evaluate("() => { const l = curveEditor.lanes[0]; return [l.px[1000], l.py[1][1000]]; }")
    steps = page.evaluate("studio.history.undo.length")
    page.evaluate(CLEAR)
    drag(page, {"x": box["x"] + xy[0], "y": box["y"] + xy[1]}, [(0, -k) for k in range(1, 61)])
    page.wait_for_function(f"() => studio.history.undo.length === {steps + 1}", timeout=60_000)
    dragging = {k: np.array(v) for k, v in page.evaluate(STATS).items()}
    page.close()
    return {"zoom": zoom, "drag": dragging}


def long_take_project(path: Path) -> None:
    """The box with one recorded position take of 60 s at 120 Hz (a wandering hand, 1 mm of jitter)."""
    rng = np.random.default_rng(11)
    t = np.arange(0, 60, 1 / 120)
    x = np.c_[np.sin(0.7 * t) + 0.3 * np.sin(2.3 * t), 0.5 + 0.2 * np.cos(1.1 * t), 0.4 * np.sin(0.37 * t)]
    x += rng.normal(0, 0.001, x.shape)
    track = recorded_over("box.position", POSITION, None, Take(t, x), 0.005, ORDER)
    with Project(path) as project:
        project.save(default_scene(), {"box.position": track}, {})


#: Sets the tolerance input and times the answer: the new curve (a `tracks` message) or a preview (`reduced`).
RETOLERANCE = """([tol, preview]) => new Promise((done) => {
  const started = performance.now();
  const signal = preview ? 'reduced' : 'tracks';
  let waiting = true;
  studio.signals.on(signal, () => { if (waiting) { waiting = false; done(performance.now() - started); } });
  if (preview) {
    const s = document.querySelector('[data-testid=tolerance-slider]');
    s.value = String(Number(s.value) + 40); s.dispatchEvent(new Event('input'));
  } else {
    const i = document.querySelector('[data-testid=tolerance]');
    i.value = String(tol); i.dispatchEvent(new Event('change'));
  }
})"""


def retolerance(browser, url: str, repeats: int = 5) -> dict:  # noqa: ANN001
    """The tolerance of a 60 s, 120 Hz take changed `repeats` times: ms to the new curve, to a preview; frames meanwhile."""
    page = open_page(browser, url, size=(1280, 800))
    page.evaluate("studio.select('box'); studio.showAttribute('position')")
    page.wait_for_function("() => curveEditor.lanes.length === 1")
    page.wait_for_timeout(300)
    applied, previews, interval, script = [], [], [], []
    for i in range(repeats):
        previews.append(page.evaluate(RETOLERANCE, [0, True]))
        page.evaluate("curveEditor.tolerance.previewing = false")
        page.evaluate(CLEAR)
        applied.append(page.evaluate(RETOLERANCE, [[0.01, 0.02, 0.005][i % 3], False]))
        stats = page.evaluate(STATS)
        interval += stats["interval"]
        script += stats["script"]
        page.wait_for_timeout(200)
    page.close()
    return {"applied": np.array(applied), "preview": np.array(previews), "interval": np.array(interval), "script": np.array(script)}


#: A strip of 10 minutes of synthetic peaks (100 a second): per pixel, the largest peak
#: of the seconds under it, as a waveform is drawn.
WAVEFORM_STRIP = """async () => {
  // 10 minutes of a synthetic sound at 22.05 kHz through the sound panel's own waveform (its
  // peak pyramid and drawing): what the timeline draws for an imported 10 min sound
  const { peakPyramid, drawWaveform } = await import('/js/waveform.js');
  const rate = 22050, samples = new Float32Array(600 * rate);
  for (let i = 0; i < samples.length; i += 1) samples[i] = Math.sin(i / 7) * Math.abs(Math.sin(i / 40000)) * (0.6 + 0.4 * Math.random());
  const pyramid = peakPyramid(samples, rate);
  studio.strips.push({ id: 'sound', label: 'sound (10 min)', height: 28,
    draw: (g, a, t0, t1) => drawWaveform(g, a, pyramid, t0, t1, 0, '#6fcf7f') });
  studio.transport.setLoop([0, 600]);
}"""


def timeline_draw(browser, url: str, frames: int = 300) -> dict:  # noqa: ANN001
    """The timeline painted again ``frames`` times over 50 lanes and a 10 min strip: ms per draw."""
    page = open_page(browser, url, size=(1600, 900))
    page.evaluate("document.querySelector('[data-testid=timeline]').style.height = '1200px'")      # every lane shown
    page.evaluate(WAVEFORM_STRIP)
    lanes = page.evaluate("timeline.invalidate(), timeline.draw(), timeline.rows.filter((r) => r.kind === 'lane').length")
    page.wait_for_timeout(500)                    # the canvas resized and first painted before the frames timed
    # each draw then flushed (one pixel read back): the canvas's rasterisation counted in, as a frame's end does
    times = page.evaluate(f"""() => {{ const out = [], flushed = [], g = timeline.canvas.getContext('2d');
        for (let i = 0; i < {frames}; i += 1) {{
          const began = performance.now();
          studio.transport.seek(i / 10); timeline.invalidate(); timeline.draw(); out.push(timeline.drawMs);
          g.getImageData(0, 0, 1, 1); flushed.push(performance.now() - began); }}
        const moving = [];                        // the playhead alone moving, nothing invalidated
        for (let i = 0; i < {frames}; i += 1) {{
          const began = performance.now();
          studio.transport.seek(i / 10); timeline.draw(); g.getImageData(0, 0, 1, 1); moving.push(performance.now() - began); }}
        return [out, flushed, moving]; }}""")
    page.close()
    return {"draw": np.array(times[0]), "flushed": np.array(times[1]), "moving": np.array(times[2]), "lanes": lanes}


def timeline_table(console: Console, made: dict) -> None:
    """The table of section 5."""
    table = Table(title=f"Timeline: {made['lanes']} lanes and a 10 min sound's waveform, the view over 10 min")
    for col in ("per frame", "frames", "median ms", "p99 ms", "target"):
        table.add_column(col, justify="right" if col != "per frame" else "left")
    for name, d, target in (("the timeline's draw (its script)", made["draw"], ""),
                            ("  and its rasterisation (a pixel read back)", made["flushed"], "a few ms"),
                            ("the playhead alone moving (what playback draws), rasterised", made["moving"], "a few ms")):
        table.add_row(name, str(len(d)), f"{np.median(d):.2f}", f"{np.percentile(d, 99):.2f}", target)
    console.print(table)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--takes", type=int, default=20)
    parser.add_argument("--objects", type=int, default=50)
    parser.add_argument("--seconds", type=float, default=4.0)
    parser.add_argument("--only", choices=("page", "curves", "timeline", "sound"),
                        help="only sections 1-2 (page), 3-4 (curves), 5 (timeline) or 6 (sound)")
    parser.add_argument("--sound-minutes", type=float, default=5.0, help="the sound's length and its playback's")
    args = parser.parse_args()
    if args.only == "sound":
        sound_bench(Console(), args.sound_minutes)
        return
    from playwright.sync_api import sync_playwright

    rng = np.random.default_rng(7)
    console = Console()
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        browser = launch(p)
        if args.only == "timeline":
            animated_project(Path(tmp) / "lanes.sketchanim", 25, rng)
            with studio_server(Path(tmp) / "lanes.sketchanim") as url:
                made = timeline_draw(browser, url)
            browser.close()
            timeline_table(console, made)
            return
        if args.only != "curves":
            with studio_server(Path(tmp) / "capture.sketchanim") as url:
                cap = capture(browser, url, args.takes, rng)
            animated_project(Path(tmp) / "play.sketchanim", args.objects, rng)
            with studio_server(Path(tmp) / "play.sketchanim") as url:
                play = playback(browser, url, args.seconds)
            browser.close()
            page_tables(console, args, cap, play)
            if args.only == "page":
                return
            browser = launch(p)
        many_keys_project(Path(tmp) / "keys.sketchanim")
        with studio_server(Path(tmp) / "keys.sketchanim") as url:
            editor = curve_editor(browser, url)
        long_take_project(Path(tmp) / "long.sketchanim")
        with studio_server(Path(tmp) / "long.sketchanim") as url:
            tol = retolerance(browser, url)
        browser.close()
    curve_tables(console, editor, tol)


def page_tables(console: Console, args: argparse.Namespace, cap: dict, play: dict) -> None:
    """The tables of sections 1 and 2."""
    table = Table(title=f"Capture: {args.takes} drags in record mode (chromium, SwiftShader)")
    for col in ("measure", "p50", "p99", "target"):
        table.add_column(col, justify="right" if col != "measure" else "left")
    ratio = cap["rates"] / cap["frames"]
    table.add_row("samples / s of a take", f"{np.median(cap['rates']):.1f}", f"{np.percentile(cap['rates'], 1):.1f} (p1)", "")
    table.add_row("page frames / s meanwhile", f"{np.median(cap['frames']):.1f}", f"{np.percentile(cap['frames'], 1):.1f} (p1)", "")
    table.add_row("capture rate / frame rate", f"{np.median(ratio):.3f}", f"{np.percentile(ratio, 1):.3f} (p1)", "1")
    table.add_row("release to final curve, ms", f"{np.median(cap['latency']):.1f}", f"{np.percentile(cap['latency'], 99):.1f}", "<= 100")
    table.add_row("  of which the server, ms", f"{np.median(cap['server']):.1f}", f"{np.percentile(cap['server'], 99):.1f}", "")
    console.print(table)

    table = Table(title=f"Playback: {args.objects} animated objects ({play['tracks']} tracks), looping {args.seconds:g} s")
    for col in ("per frame", "median ms", "p99 ms", "target"):
        table.add_column(col, justify="right" if col != "per frame" else "left")
    table.add_row("evaluate + write every track", f"{np.median(play['play']):.3f}", f"{np.percentile(play['play'], 99):.3f}", "<= 4")
    table.add_row("whole frame's script", f"{np.median(play['script']):.3f}", f"{np.percentile(play['script'], 99):.3f}", "")
    table.add_row("  of which render calls", f"{np.median(play['render']):.3f}", f"{np.percentile(play['render'], 99):.3f}", "")
    fps = 1000 / np.median(play["interval"])
    table.add_row("frame rate (frames / s)", f"{fps:.1f}", f"{1000 / np.percentile(play['interval'], 99):.1f} (slowest 1%)", "60")
    console.print(table)


def drag_script(m: dict) -> np.ndarray:
    """The editor's script per drawn frame while dragging: the frame's drawing and its share of
    the pointer moves' previews (the moves spread evenly over the frames)."""
    return m["draw"] + m["move"].sum() / max(len(m["draw"]), 1)


def curve_tables(console: Console, editor: dict, tol: dict) -> None:
    """The tables of sections 3 and 4."""
    table = Table(title="Curve editor: 10 tracks of 2,000 keys, all shown")
    for col in ("per frame", "frames", "median ms", "p99 ms", "target"):
        table.add_column(col, justify="right" if col != "per frame" else "left")
    rows = [("zooming: the editor's frame (everything redrawn)", editor["zoom"]["draw"], ""),
            ("  the page's whole frame script", editor["zoom"]["script"], ""),
            ("dragging a point: the editor's frame (layer + dragged track)", editor["drag"]["draw"], "<= 8"),
            ("  its pointer move (preview on a copy of the curve)", editor["drag"]["move"], ""),
            ("  frame + moves, per frame (the drag's script)", drag_script(editor["drag"]), "<= 8"),
            ("  the page's whole frame script", editor["drag"]["script"], "")]
    for name, m, target in rows:
        table.add_row(name, str(len(m)), f"{np.median(m):.2f}", f"{np.percentile(m, 99):.2f}", target)
    console.print(table)

    table = Table(title="Tolerance after the take: a 60 s take at 120 Hz (7,200 samples)")
    for col in ("measure", "median", "max"):
        table.add_column(col, justify="right" if col != "measure" else "left")
    table.add_row("change to the new curve in the page, ms", f"{np.median(tol['applied']):.1f}", f"{tol['applied'].max():.1f}")
    table.add_row("slider move to its preview, ms", f"{np.median(tol['preview']):.1f}", f"{tol['preview'].max():.1f}")
    table.add_row("frame interval meanwhile, ms", f"{np.median(tol['interval']):.1f}", f"{tol['interval'].max():.1f}")
    table.add_row("page script per frame meanwhile, ms", f"{np.median(tol['script']):.2f}", f"{tol['script'].max():.2f}")
    console.print(table)



# -- 5. sound ---------------------------------------------------------------------------------


def sound_drift(browser, url: str, folder: Path, minutes: float) -> dict:  # noqa: ANN001
    """Import a WAV of ``minutes`` (22.05 kHz mono, a swelling tone), play it through at 1x;
    each frame's drift (s), the re-seeks, and the waveform strip's drawing times (ms)."""
    import soundfile
    import urllib.request

    rate = 22050
    t = np.arange(int(minutes * 60 * rate)) / rate
    path = folder / "long.wav"
    soundfile.write(path, 0.8 * np.abs(np.sin(np.pi * t)) * np.sin(2 * np.pi * 220 * t), rate, subtype="PCM_16")
    page = open_page(browser, url)
    request = urllib.request.Request(url + "api/sounds?name=long.wav", data=path.read_bytes(), method="POST")
    with urllib.request.urlopen(request, timeout=120) as reply:
        assert reply.status == 200
    page.wait_for_function("() => sounds.report().length === 1", timeout=300_000)
    draw = page.evaluate("""() => { const strip = studio.strips.find((s) => s.id === 'sound:long.wav');
        const canvas = new OffscreenCanvas(1600, 28); const g = canvas.getContext('2d');
        const area = {x: 0, y: 0, width: 1600, height: 28}; const d = studio.sounds[0].duration;
        const time = (t0, t1) => { const out = []; for (let i = 0; i < 50; i++) {
            const a = performance.now(); strip.draw(g, area, t0, t1); out.push(performance.now() - a); } return out; };
        return {whole: time(0, d), zoomed: time(d / 2, d / 2 + 2)}; }""")
    page.evaluate("() => { const t = studio.transport; t.seek(0); t.setSpeed(1); t.play(); }")
    page.wait_for_timeout(int(minutes * 60 * 1000))
    report = page.evaluate("() => { studio.transport.pause(); const r = sounds.report()[0]; "
                           "return {drifts: r.drifts, times: r.times, seeks: r.seeks, lead: r.lead}; }")
    fps = page.evaluate("studio.fps")
    page.close()
    return {"drift": np.abs(np.array(report["drifts"])), "signed": np.array(report["drifts"]), "times": np.array(report["times"]), "seeks": report["seeks"],
            "lead": report["lead"], "fps": fps, "whole": np.array(draw["whole"]), "zoomed": np.array(draw["zoomed"])}


def sound_bench(console: Console, minutes: float) -> None:
    """Section 5: a studio on a fresh project, a sound of ``minutes`` played through."""
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        browser = launch(p)
        with studio_server(Path(tmp) / "sound.sketchanim") as url:
            m = sound_drift(browser, url, Path(tmp), minutes)
        browser.close()
    settled = m["drift"][m["times"] >= 1.0]          # after the first second: the element started, a seek learnt
    frame = 1000 / m["fps"]
    table = Table(title=f"Sound: {minutes:g} min played through at 1x ({len(m['drift'])} frames, {m['seeks']} re-seeks, "
                        f"a seek aims {m['lead'] * 1000:.0f} ms ahead)")
    for col in ("measure", "p50", "p99", "max", "target"):
        table.add_column(col, justify="right" if col != "measure" else "left")
    for label, values in (("drift, ms (all frames)", m["drift"] * 1000), ("drift, ms (after 1 s)", settled * 1000)):
        table.add_row(label, f"{np.median(values):.1f}", f"{np.percentile(values, 99):.1f}", f"{values.max():.1f}",
                      f"<= {frame:.1f}")
    for label, values in (("waveform strip, whole sound, 1,600 px, ms", m["whole"]),
                          ("waveform strip, 2 s of it, 1,600 px, ms", m["zoomed"])):
        table.add_row(label, f"{np.median(values):.2f}", f"{np.percentile(values, 99):.2f}", f"{values.max():.2f}", "")
    console.print(table)


if __name__ == "__main__":
    main()
