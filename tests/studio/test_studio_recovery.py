"""Never lose a performance: a studio server killed with SIGKILL in the middle of a take
gives the take back at its next start."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import httpx
import numpy as np
from websockets.sync.client import connect

REPO = Path(__file__).resolve().parents[2]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(project: Path, port: int) -> subprocess.Popen:
    server = subprocess.Popen([str(Path(sys.executable).with_name("sketchanim")), "studio", str(project), "--no-browser",
                               "--port", str(port)], cwd=project.parent, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, start_new_session=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        try:
            if httpx.get(f"http://127.0.0.1:{port}/api/ready", timeout=1).json()["ready"]:
                return server
        except httpx.HTTPError:
            pass
        if server.poll() is not None:
            raise AssertionError(server.stdout.read().decode())
        time.sleep(0.2)
    raise AssertionError("the studio did not become ready")


def test_sigkill_mid_take_recovers_the_take(tmp_path):
    project = tmp_path / "show.sketchanim"
    port = free_port()
    server = start(project, port)
    t = np.arange(0, 1.5, 1 / 60)
    x = np.c_[np.sin(2 * t), 0.5 + 0 * t, np.cos(2 * t)]
    try:
        with connect(f"ws://127.0.0.1:{port}/ws") as ws:
            assert json.loads(ws.recv())["type"] == "state"
            ws.send(json.dumps({"type": "take.begin", "take": "k", "paths": ["box.position"]}))
            for i in range(0, len(t), 10):
                ws.send(json.dumps({"type": "take.samples", "take": "k", "t": t[i:i + 10].tolist(),
                                    "values": x[i:i + 10].tolist()}))
            ws.send(json.dumps({"type": "ping", "id": "sent"}))
            while json.loads(ws.recv()).get("id") != "sent":     # every batch was pushed
                pass
            time.sleep(0.5)                                        # the journal commits every 50 ms
            os.killpg(server.pid, signal.SIGKILL)                  # the server and its reducer processes
            server.wait(10)
    finally:
        if server.poll() is None:
            os.killpg(server.pid, signal.SIGKILL)
    server = start(project, port)
    try:
        state = httpx.get(f"http://127.0.0.1:{port}/api/state").json()
        assert state["history"]["undo"] == ["recovered take"]
        doc = httpx.get(f"http://127.0.0.1:{port}/api/project").json()
    finally:
        os.killpg(server.pid, signal.SIGTERM)
        server.wait(20)
    curve = doc["curves"][0]
    assert curve["path"] == "box.position"
    take = doc["takes"][curve["takes"][0]]
    assert np.array_equal(take["times"], t) and np.array_equal(np.array(take["values"]), x)
    from scipy.interpolate import BSpline
    s = BSpline(np.array(curve["knots"]), np.array(curve["coef"]), curve["order"] - 1)
    assert np.abs(s(t) - x).max() <= curve["tol"]
