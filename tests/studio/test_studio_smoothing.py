"""Smoothed takes through the studio: take.begin with smoothing records a curve within
tolerance of the smoothed samples, keeps the raw ones, says so, saves and recovers it."""

from __future__ import annotations

import json
import time

import numpy as np
import pytest

from sketchanim.project.store import Project
from sketchanim.reducer.smoothing import smooth
from sketchanim.studio import protocol as p
from sketchanim.studio.handlers import handle
from sketchanim.studio.session import Session

OWNER = 1


def jittery_drag(n: int = 180, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A page's drag: uneven frames, a smooth path with 1.5 mm of hand jitter."""
    rng = np.random.default_rng(seed)
    t = 0.2 + np.arange(n) / 60 + rng.uniform(0, 0.003, n)
    x = np.c_[np.sin(2 * t), 0.5 + 0.3 * np.cos(3 * t), 0.1 * t] + rng.normal(0, 0.0015, (n, 3))
    return t, x


def send(session: Session, **message) -> list[dict]:
    """One page message through the protocol and the handlers: what goes out."""
    return [m for _, m in handle(session, p.parse(json.dumps(message)), OWNER)]


def perform(session: Session, name: str, t: np.ndarray, x: np.ndarray, **begin) -> dict:
    send(session, type="take.begin", take=name, paths=["box.position"], time=float(t[0]),
         tol={"box.position": 0.002}, **begin)
    for i in range(0, len(t), 8):
        send(session, type="take.samples", take=name, t=t[i:i + 8].tolist(), values=x[i:i + 8].tolist())
    return next(m for m in send(session, type="take.end", take=name) if m["type"] == "take.ended")


def test_a_smoothed_take_holds_tol_against_the_smoothed_samples_and_keeps_the_raw(session, tmp_path):
    t, x = jittery_drag()
    ended = perform(session, "raw", t, x)
    raw = session.player.tracks["box.position"]
    assert ended["smoothing"] == 0 and raw.takes[-1].smoothing == 0
    ended = perform(session, "smooth", t, x, smoothing=0.05)
    track = session.player.tracks["box.position"]
    assert ended["smoothing"] == 0.05
    take = track.takes[-1]
    assert take.smoothing == 0.05 and np.array_equal(take.values, x) and np.array_equal(take.times, t)
    assert np.abs(track.evaluate(t) - smooth(t, x, 0.05)).max() <= 0.002
    assert track.n_coefficients < raw.n_coefficients
    curve = next(c for c in session.state()["tracks"] if c["path"] == "box.position")
    smoothings = [span["smoothing"] for span in curve["takes"]]   # before it: the raw take (and its hold and ease)
    assert smoothings[-1] == 0.05 and set(smoothings[:-1]) == {0.0}
    session.save()
    with Project(tmp_path / "s.sketchanim", read_only=True) as project:      # the saved project keeps it
        loaded = project.load()[1]["box.position"]
    assert loaded.takes[-1].smoothing == 0.05 and np.array_equal(loaded.takes[-1].values, x)


@pytest.mark.parametrize("smoothing", [-0.01, 0.6, "nan"])
def test_take_begin_refuses_smoothing_out_of_range(smoothing):
    with pytest.raises(p.BadMessage, match="smoothing"):
        p.parse(json.dumps({"type": "take.begin", "take": "a", "paths": ["box.position"],
                            "smoothing": float(smoothing) if smoothing == "nan" else smoothing}))


def test_a_smoothed_take_cut_by_a_crash_comes_back_smoothed(tmp_path):
    path = tmp_path / "crash.sketchanim"
    s = Session(path)
    t, x = jittery_drag()
    send(s, type="take.begin", take="a", paths=["box.position"], time=float(t[0]), smoothing=0.02)
    send(s, type="take.samples", take="a", t=t.tolist(), values=x.tolist())
    time.sleep(0.3)                                     # committed by the journal thread; then the process "dies"
    s.lock.handle.close()
    again = Session(path)
    try:
        track = again.player.tracks["box.position"]
        assert track.takes[-1].smoothing == 0.02
        assert np.abs(track.evaluate(t) - smooth(t, x, 0.02)).max() <= track.tol
    finally:
        again.close()
        s.take.recorder.stop()
        s.takes.take = None
        s.project.close()
