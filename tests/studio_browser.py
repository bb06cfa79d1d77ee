"""Driving the studio page in Debian's chromium (headless, WebGL through SwiftShader)
with Playwright: a server on a fresh project, a page on it, and what the page drew.
Shared by tests/studio/test_studio_page.py, test_studio_recovery.py (the server) and
benchmarks/bench_studio.py."""

from __future__ import annotations

import base64
import io
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

import numpy as np
from scipy.interpolate import BSpline

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM_ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                 "--autoplay-policy=no-user-gesture-required"]   # the sound plays without a click (tests)


def chromium() -> str:
    """Debian's chromium (scripts/setup installs it); Playwright's own browsers are not used."""
    for name in ("chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    raise RuntimeError("chromium is not installed: run scripts/setup (apt-get install chromium)")


def free_port() -> int:
    """A TCP port free on 127.0.0.1 now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def unread_socket(port: int) -> socket.socket:
    """A page that opens the studio's websocket on ``port`` and never reads it (its
    receive buffer kept small): the handshake only, then nothing."""
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.connect(("127.0.0.1", port))
    key = base64.b64encode(os.urandom(16)).decode()
    sock.sendall(f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                 f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n".encode())
    reply = b""
    while b"\r\n\r\n" not in reply:
        reply += sock.recv(1)
    if not reply.startswith(b"HTTP/1.1 101"):
        raise ConnectionError(f"the studio refused the websocket: {reply!r}")
    return sock


def start_studio(project: Path, port: int, log: IO, *options: str) -> subprocess.Popen:
    """``sketchanim studio PROJECT --port PORT`` (and ``options``) in a process group of its own (so that
    ``os.killpg`` ends it with its reducer processes), its output to ``log``; returned
    once ``/api/ready`` says it is ready (RuntimeError with its output if it exits, or
    is not ready in 120 s)."""
    cli = Path(sys.executable).with_name("sketchanim")
    proc = subprocess.Popen([str(cli), "studio", str(project), "--port", str(port), "--no-browser", *options],
                            cwd=project.parent, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    url = f"http://127.0.0.1:{port}/"
    deadline = time.monotonic() + 120
    while True:
        try:
            with urllib.request.urlopen(url + "api/ready", timeout=2) as r:
                if json.load(r)["ready"]:
                    return proc
        except OSError:
            pass
        if proc.poll() is not None:
            raise RuntimeError(f"the studio server exited: {Path(log.name).read_text()[-3000:]}")
        if time.monotonic() > deadline:
            proc.kill()
            raise RuntimeError("the studio server did not get ready in 120 s")
        time.sleep(0.2)


@contextmanager
def studio_server(project: Path, *options: str) -> Iterator[str]:
    """``sketchanim studio PROJECT`` (and ``options``) in a process of its own
    (:func:`start_studio`); yields its URL, and stops it after."""
    port = free_port()
    log = project.with_name(project.name + ".log")
    with log.open("w") as out:
        proc = start_studio(project, port, out, *options)
        try:
            yield f"http://127.0.0.1:{port}/"
        finally:
            proc.terminate()
            try:
                proc.wait(10)
            except subprocess.TimeoutExpired:
                proc.kill()
    print(f"--- the studio server's output ({log}) ---\n{log.read_text()[-5000:]}")   # shown when a test fails


def launch(playwright):  # noqa: ANN001, ANN201 (Playwright's own types)
    """Debian's chromium, headless, WebGL through SwiftShader."""
    return playwright.chromium.launch(executable_path=chromium(), headless=True, args=CHROMIUM_ARGS)


def open_page(browser, url: str, init_script: str | None = None, size: tuple[int, int] = (960, 600)):  # noqa: ANN001, ANN201
    """A page on the studio, once it says it is ready (scene loaded and drawn)."""
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.errors = errors
    if init_script:
        page.add_init_script(init_script)
    page.goto(url)
    page.wait_for_selector("body[data-ready=true]", timeout=60_000)
    return page


def drew_something(page) -> float:  # noqa: ANN001
    """The spread of the screenshot's pixel values (0 for a uniform picture: no WebGL
    context, nothing drawn)."""
    from PIL import Image

    pixels = np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB"), dtype=float)
    return float(pixels.std())


def viewport_drew(page) -> float:  # noqa: ANN001
    """The spread of the 3D view's pixels alone (the panels around it do not count)."""
    from PIL import Image

    shot = page.locator("[data-testid=viewport]").screenshot()
    return float(np.asarray(Image.open(io.BytesIO(shot)).convert("RGB"), dtype=float).std())


def project(url: str) -> dict:
    """GET /api/project: the project document as the export writes it."""
    with urllib.request.urlopen(url + "api/project", timeout=30) as r:
        return json.load(r)


def curve(doc: dict, path: str) -> tuple[BSpline, dict] | None:
    """The spline of the track at ``path`` in a project document, and its entry."""
    for c in doc["curves"]:
        if c["path"] == path:
            return BSpline(np.array(c["knots"]), np.array(c["coef"]), c["order"] - 1), c
    return None


def held(spline: BSpline, times: np.ndarray) -> np.ndarray:
    """A track's values at ``times``, held outside its span (as the player plays it)."""
    k = spline.k
    return spline(np.clip(times, spline.t[k], spline.t[-k - 1]))


def drag(page, start: dict, offsets: list[tuple[float, float]], step_ms: float = 16) -> None:  # noqa: ANN001
    """Press at ``start`` and move through ``offsets`` from it, ``step_ms`` apart, then release."""
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    for dx, dy in offsets:
        page.wait_for_timeout(step_ms)
        page.mouse.move(start["x"] + dx, start["y"] + dy)
    page.wait_for_timeout(step_ms)
    page.mouse.up()


def last_take(page, timeout: float = 30_000) -> dict:  # noqa: ANN001
    """The page's last take once its final curve is back: what it sent (times,
    rows, frame stamps), its paths, and release-to-final-curve milliseconds."""
    page.wait_for_function("() => studio.takes.length && studio.takes.at(-1).final !== null", timeout=timeout)
    return page.evaluate("""() => { const l = studio.takes.at(-1); const s = l.sampler;
        return {id: l.id, paths: s.paths, dims: s.dims, times: s.times, rows: s.rows, stamps: s.stamps,
                label: l.label, latency: l.final - l.released, errors: studio.errors, gap: s.gap}; }""")


#: An init script standing in for a gamepad: ``window.__pad.axes`` (and ``buttons``) are what
#: ``navigator.getGamepads()`` reports, set them to move its sticks.
GAMEPAD = """
window.__pad = {axes: [0, 0, 0, 0], buttons: []};
navigator.getGamepads = () => [{id: 'stub pad', index: 0, connected: true, mapping: 'standard',
    timestamp: performance.now(), axes: window.__pad.axes, buttons: window.__pad.buttons}];
"""
