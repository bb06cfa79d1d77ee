"""Layered recording, end to end, without a UI.

    .venv/bin/python examples/layered_take.py [--project PATH]

Builds a scene with two objects and a light, records a synthetic performance of each
(positions, an orientation, the light's colour) through the recorder, then plays the
animation back and, during playback, records a new layer on one object's position over
[2 s, 4 s] (punch-in) while every other track keeps playing, plus an additive wobble on
the other object. Saves the project and prints a JSON summary: per track, control points
and samples, the largest error against the raw samples of its takes, and at the
punch-in seams the jump in value and in velocity (both zero for a C1 join).
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from sketchanim.anim.history import History
from sketchanim.anim.player import Player
from sketchanim.anim.recorder import Recorder
from sketchanim.anim.scene import Scene
from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.project.store import Project
from sketchanim.reducer.metric import max_errors

RATE = 120.0


def performance(t: float) -> np.ndarray:
    """One frame of the first pass: ball and cube positions, cube orientation, lamp colour."""
    ball = [np.sin(t), 0.5 + 0.5 * abs(np.sin(2 * t)), np.cos(t)]
    cube = [0.3 * t, 0.0, 0.2 * np.sin(3 * t)]
    turn = Rotation.from_rotvec([0.0, 0.6 * t, 0.2 * np.sin(t)]).as_quat()
    colour = [0.5 + 0.5 * np.sin(t), 0.5, 0.5 - 0.4 * np.sin(t)]
    return np.r_[ball, cube, turn, colour]


def seam(spline: BSpline, x: float) -> dict[str, float]:
    """Jumps in value and velocity of ``spline`` at ``x`` (left limit against right)."""
    mirror = BSpline(-spline.t[::-1], spline.c[::-1], spline.k)
    left = mirror(-x), -mirror.derivative()(-x)
    right = spline(x), spline.derivative()(x)
    return {"time": x, "value_jump": float(np.abs(left[0] - right[0]).max()),
            "velocity_jump": float(np.abs(left[1] - right[1]).max())}


def max_error(track: ContinuousTrack, before: ContinuousTrack | None) -> float:
    """Largest error of ``track`` (in its unit) against what each take asked for where
    that take is in force: the first take's raw samples outside the last take's span,
    and inside it (past the seam fades) the last take's samples, added onto the curve
    ``before`` it for an additive take."""
    first, last = track.takes[0], track.takes[-1]
    outside = (first.times < last.start) | (first.times > last.end) if len(track.takes) > 1 else slice(None)
    t, x = [first.times[outside]], [first.values[outside]]
    if len(track.takes) > 1:
        inner = (last.times >= last.start + last.blend) & (last.times <= last.end - last.blend)
        t.append(last.times[inner])
        x.append(last.values[inner] + (before.evaluate(last.times[inner]) if last.mode == "additive" else 0))
    angle = np.radians(1.0) if track.type.is_rotation else 0.0
    err = float(max_errors(track.evaluate(np.concatenate(t)), np.vstack(x), angle).max())
    return float(np.degrees(err)) if angle else err


def perform() -> tuple[Scene, Player, History, dict[str, ContinuousTrack]]:
    """Both passes: the scene, its player (the tracks after pass 2), the history, and
    the tracks as pass 1 left them."""
    scene = Scene()
    scene.add("ball")
    scene.add("cube")
    scene.add("lamp", "light")
    player = Player(scene)
    history = History(player)

    # Pass 1: perform everything at once (a device's frames).
    rec = Recorder(scene)
    for path in ("ball.position", "cube.position", "cube.orientation", "lamp.color"):
        rec.arm(path)
    times = np.arange(0, 6, 1 / RATE)
    rec.start()
    for t in times:
        rec.push_frame(t, performance(t))
    history.apply("record pass 1", rec.stop())
    first = dict(player.tracks)

    # Pass 2: play back; grab the ball over [2, 4] s and push it up; wobble the cube on top.
    rec = Recorder(scene)
    rec.arm("ball.position")
    rec.arm("cube.position", mode="additive")
    rec.start(player.tracks)
    for t in times[(times >= 2.0) & (times <= 4.0)]:
        player.seek(t)
        player.apply(skip=["ball.position", "cube.position"])   # the grabbed ones follow the hands
        ball = performance(t)[:3] + [0.0, 0.8 * np.sin(np.pi * (t - 2.0) / 2.0), 0.0]
        rec.push("ball.position", t, ball)
        rec.push("cube.position", t, [0.0, 0.05 * np.sin(8 * t), 0.0])
    history.apply("record pass 2", rec.stop())
    return scene, player, history, first


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--project", type=Path, default=Path(tempfile.mkdtemp()) / "layered.sketchanim")
    args = parser.parse_args()
    scene, player, history, first = perform()
    with Project(args.project) as project:
        project.save(scene, player.tracks)

    untouched = [p for p in first if player.tracks[p] is first[p]]
    summary = {
        "project": str(args.project),
        "untouched_by_pass_2": untouched,
        "tracks": {
            path: {
                "control_points": track.n_coefficients,
                "raw_samples": int(sum(len(take.times) for take in track.takes)),
                "takes": [take.mode for take in track.takes],
                "tolerance": track.tol,
                "unit": track.type.unit,
                "max_error_vs_raw": max_error(track, first.get(path)),
            }
            for path, track in player.tracks.items()
        },
        "seams": {path: [seam(player.tracks[path].spline, x) for x in (2.0, 4.0)]
                  for path in ("ball.position", "cube.position")},
        "undo": history.undo(),
        "after_undo_ball_points": player.tracks["ball.position"].n_coefficients,
        "redo": history.redo(),
    }
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
