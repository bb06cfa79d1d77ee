"""Importing a clip into the studio's scene (``POST /api/clips``): a 1 min, 120 Hz, 30-joint
BVH (a synthetic chain-and-branch figure in centimetres, smooth motion on every joint), and
the real recordings in ../shared/data/bvh when present; the seconds from the upload to the
answer (read, forward kinematics, every joint's position and orientation reduced, added as
one step), and the tracks' control points against the frames.

    .venv/bin/python benchmarks/bench_clip_import.py [--seconds 60] [--rate 120] [--joints 30]

Through FastAPI's TestClient (the server's path, no browser). One run per clip.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
from fastapi.testclient import TestClient
from rich.console import Console
from rich.table import Table
from scipy.spatial.transform import Rotation

from sketchanim.formats.bvh import bvh_text
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.studio.app import create_app

REPO = Path(__file__).resolve().parents[1]


def synthetic_clip(seconds: float, rate: float, joints: int, seed: int = 3) -> Clip:
    """A figure of ``joints`` joints (each the child of one of the previous four), the root
    translating, every joint turning by sums of sines (up to 60 degrees, 0.2 to 1.5 Hz)."""
    rng = np.random.default_rng(seed)
    parents = tuple([-1] + [int(rng.integers(max(0, i - 4), i)) for i in range(1, joints)])
    offsets = np.r_[[[0.0, 90.0, 0.0]], rng.normal(0, 12, (joints - 1, 3))]
    t = np.arange(int(seconds * rate)) / rate
    rotations = np.empty((len(t), joints, 4))
    for j in range(joints):
        amp, freq, phase = rng.uniform(5, 60, 3), rng.uniform(0.2, 1.5, 3), rng.uniform(0, 2 * np.pi, 3)
        rotations[:, j] = Rotation.from_euler("ZXY", amp * np.sin(2 * np.pi * np.outer(t, freq) + phase),
                                              degrees=True).as_quat()
    translations = np.broadcast_to(offsets, (len(t), joints, 3)).copy()
    translations[:, 0] += np.c_[100 * np.sin(0.3 * t), 5 * np.sin(4 * t), 40 * t / seconds]
    rotating, translating = np.ones(joints, bool), np.zeros(joints, bool)
    translating[0] = True
    layout = [("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")] + \
        [("Zrotation", "Xrotation", "Yrotation")] * (joints - 1)
    return Clip(Skeleton(tuple(f"j{i}" for i in range(joints)), parents, offsets), t, rotations, translations,
                rotating, translating, tuple(layout))


def timed_import(folder: Path, name: str, data: bytes) -> tuple[float, dict, int]:
    """Seconds from the upload to the answer, the answer, and the tracks' control points."""
    app = create_app(folder / f"{Path(name).stem}.sketchanim", warm=False)
    try:
        with TestClient(app) as client:
            start = time.perf_counter()
            r = client.post(f"/api/clips?name={name}", content=data)
            seconds = time.perf_counter() - start
            r.raise_for_status()
            doc = client.get("/api/project").json()
    finally:
        app.state.hub.session.close()
    stem = Path(name).stem
    points = sum(len(c["coef"]) for c in doc["curves"] if c["path"].startswith(stem + "_"))
    return seconds, r.json(), points


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--rate", type=float, default=120.0)
    parser.add_argument("--joints", type=int, default=30)
    parser.add_argument("--data", type=Path, default=REPO.parent / "shared" / "data")
    args = parser.parse_args()
    clips = [(f"synthetic_{args.joints}j.bvh",
              bvh_text(synthetic_clip(args.seconds, args.rate, args.joints)).encode())]
    clips += [(p.name, p.read_bytes()) for p in sorted((args.data / "bvh").glob("*.bvh"))]
    table = Table(title="Clip import into the studio's scene (POST /api/clips, TestClient)")
    for col in ("clip", "joints", "frames", "seconds of motion", "import s", "control points / frame"):
        table.add_column(col, justify="left" if col == "clip" else "right")
    with tempfile.TemporaryDirectory() as tmp:
        for name, data in clips:
            seconds, answer, points = timed_import(Path(tmp), name, data)
            per_frame = points / (answer["frames"] * answer["tracks"])
            table.add_row(name, str(len(answer["objects"])), str(answer["frames"]), f"{answer['seconds']:.1f}",
                          f"{seconds:.2f}", f"{per_frame:.3f}")
    Console(width=140).print(table)


if __name__ == "__main__":
    main()
