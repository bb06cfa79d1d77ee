"""Never lose a performance: a studio server killed with SIGKILL in the middle of a take
gives the take back at its next start."""

from __future__ import annotations

import json
import os
import signal
import time

import httpx
import numpy as np
import pytest
from websockets.sync.client import connect

from studio_browser import free_port, start_studio


@pytest.fixture
def log(tmp_path):
    with (tmp_path / "studio.log").open("w") as out:
        yield out


def test_sigkill_mid_take_recovers_the_take(tmp_path, log):
    project = tmp_path / "show.sketchanim"
    port = free_port()
    server = start_studio(project, port, log)
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
    server = start_studio(project, port, log)
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
