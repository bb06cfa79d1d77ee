"""The studio page in a browser (Debian's chromium, headless, WebGL through SwiftShader,
driven by Playwright) against a real server.

    .venv/bin/python benchmarks/bench_studio.py [--takes 20] [--objects 50] [--seconds 4] [--only page|curves|timeline]

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
   and an orientation track each) and a 10 min strip of synthetic peaks (100 per second)
   above them, the view spanning the 10 min: the timeline's draw, everything painted again
   each frame, then the playhead alone moving (what playback draws), median and p99 ms
   (target: a few ms).

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
PEAKS_STRIP = """() => {
  const rate = 100, peaks = new Float32Array(600 * rate);
  for (let i = 0; i < peaks.length; i += 1) peaks[i] = Math.abs(Math.sin(i / 37) * Math.sin(i / 1111)) * (0.6 + 0.4 * Math.random());
  studio.strips.push({ id: 'peaks', label: 'sound (10 min)', height: 28, draw: (g, a, t0, t1) => {
    g.fillStyle = '#6fcf7f';
    for (let px = 0; px < a.width; px += 1) {
      const i0 = Math.max(0, Math.floor((t0 + (px / a.width) * (t1 - t0)) * rate));
      const i1 = Math.min(peaks.length, Math.ceil((t0 + ((px + 1) / a.width) * (t1 - t0)) * rate));
      let m = 0;
      for (let i = i0; i < i1; i += 1) if (peaks[i] > m) m = peaks[i];
      const h = m * a.height;
      g.fillRect(a.x + px, a.y + (a.height - h) / 2, 1, h);
    }
  } });
  studio.transport.setLoop([0, 600]);
}"""


def timeline_draw(browser, url: str, frames: int = 300) -> dict:  # noqa: ANN001
    """The timeline painted again ``frames`` times over 50 lanes and a 10 min strip: ms per draw."""
    page = open_page(browser, url, size=(1600, 900))
    page.evaluate("document.querySelector('[data-testid=timeline]').style.height = '1200px'")      # every lane shown
    page.evaluate(PEAKS_STRIP)
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
    table = Table(title=f"Timeline: {made['lanes']} lanes and a 10 min strip of peaks, the view over 10 min")
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
    parser.add_argument("--only", choices=("page", "curves", "timeline"),
                        help="only sections 1-2 (page), 3-4 (curves) or 5 (timeline)")
    args = parser.parse_args()
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


if __name__ == "__main__":
    main()
