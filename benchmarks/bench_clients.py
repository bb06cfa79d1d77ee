"""What the clients animators use play from our files: max error against the source.

    .venv/bin/python benchmarks/bench_clients.py [--data ../shared/data]

For every BVH clip in ``DATA/bvh`` and the CMU ASF/AMC clip, reduced at 0.5 cm / 0.5
degree (centimetres through the clip's guessed unit), and for the layered-take
example's scene (examples/layered_take.py: its position and orientation tracks against
the samples each take asked for), each file is played at every source frame by:

- three.js (scripts/play-gltf.mjs: GLTFLoader, AnimationMixer, in node) from the .glb;
- Blender through our add-on (blender/sketchanim_import.py, the bpy wheel) from the .glb;
- Blender's own glTF importer from the ``--keys frames`` .glb (and, to show why that
  option exists, from the exact .glb, whose tangents it drops);
- usd-core from the .usda (clips only: scenes have no USD export).

Errors are the largest over joints (objects) and frames: the rotation angle (degrees,
geodesic) of each joint's local rotation, and the distance (cm) of each translating
joint's local translation; for the scene, each track's error in its own unit. "ok" says
whether both are within what was asked; "play s": seconds to import and play (one run).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import layered  # noqa: E402
from clips import local_errors  # noqa: E402
from blender_client import blender_play, joint_locals  # noqa: E402
from threejs_client import three_play  # noqa: E402

from sketchanim.mocap.clip_reduction import reduce_clip  # noqa: E402
from sketchanim.motion.skeleton import Clip  # noqa: E402
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import read_clip  # noqa: E402

TOL_CM, ROT_TOL = 0.5, 0.5


def three_locals(glb: Path, clip: Clip) -> tuple[np.ndarray, np.ndarray]:
    played = three_play(glb, clip.times)
    names = clip.skeleton.names
    return (np.stack([played[n]["quaternion"] for n in names], axis=1),
            np.stack([played[n]["position"] for n in names], axis=1))


def usd_locals(path: Path, clip: Clip) -> tuple[np.ndarray, np.ndarray]:
    from pxr import Usd, UsdGeom

    stage = Usd.Stage.Open(str(path))
    prims = {p.GetName(): UsdGeom.Xformable(p) for p in stage.Traverse()}
    n, j = len(clip.times), len(clip.skeleton)
    rot, trans = np.empty((n, j, 4)), np.empty((n, j, 3))
    for k, name in enumerate(clip.skeleton.names):
        for f in range(n):
            m = prims[name].GetLocalTransformation(Usd.TimeCode(f))
            q = m.ExtractRotationQuat()
            rot[f, k] = [*q.GetImaginary(), q.GetReal()]
            trans[f, k] = m.ExtractTranslation()
    return rot, trans


def clip_rows(source: Path, folder: Path) -> list[tuple]:
    clip = read_clip(source)
    unit = clip.guess_unit_m()
    tol = TOL_CM / 100 / unit
    reduced = reduce_clip(clip, tol, ROT_TOL)
    curves = write_reduced(folder / f"{source.stem}.glb", reduced)
    frames = write_reduced(folder / f"{source.stem}.frames.glb", reduced, keys="frames")
    usd = write_reduced(folder / f"{source.stem}.usda", reduced)
    clients = [
        ("three.js", lambda: three_locals(curves, clip)),
        ("three.js, --keys frames", lambda: three_locals(frames, clip)),
        ("Blender, our add-on", lambda: joint_locals(blender_play("addon", curves, clip.times), clip.skeleton,
                                                      clip.unit_m)),
        ("Blender glTF importer, --keys frames", lambda: joint_locals(blender_play("gltf", frames, clip.times),
                                                                      clip.skeleton, clip.unit_m)),
        ("Blender glTF importer, exact keys", lambda: joint_locals(blender_play("gltf", curves, clip.times),
                                                                   clip.skeleton, clip.unit_m)),
        ("usd-core", lambda: usd_locals(usd, clip)),
    ]
    rows = []
    for client, play in clients:
        start = time.perf_counter()
        angle, dist = local_errors(*play(), clip)
        rows.append((source.name, client, angle, dist * unit * 100, angle <= ROT_TOL and dist <= tol,
                     time.perf_counter() - start))
    return rows


def scene_rows(folder: Path) -> list[tuple]:
    ex = layered.exported(folder)
    clients = [("three.js", "three", ex.curves), ("three.js, --keys frames", "three", ex.frames),
               ("Blender, our add-on", "addon", ex.curves), ("Blender glTF importer, --keys frames", "gltf", ex.frames),
               ("Blender glTF importer, exact keys", "gltf", ex.curves)]
    rows = []
    for name, kind, path in clients:
        start = time.perf_counter()
        worst = layered.errors(ex, layered.client(kind, path, ex.tracks, ex.times))
        angle = max(v for p, v in worst.items() if p.endswith("orientation"))
        dist = max(v for p, v in worst.items() if p.endswith("position"))
        ok = all(worst[p] <= ex.tracks[p].tol for p in ex.tracks)
        rows.append(("layered take (scene)", name, angle, dist * 100, ok, time.perf_counter() - start))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    args = parser.parse_args()
    sources = [*sorted((args.data / "bvh").glob("*.bvh")), args.data / "amc" / "cmu_11_01.amc"]
    table = Table(title=f"max error against the source, per client (asked: {ROT_TOL} degree, {TOL_CM} cm; "
                        "scene: 0.5 degree, 0.5 cm = 0.005 scene units)")
    for col in ("file", "client", "rotation (deg)", "position (cm)", "within", "play s"):
        table.add_column(col, justify="left" if col in ("file", "client") else "right")
    with tempfile.TemporaryDirectory() as tmp:
        rows = [row for s in sources if s.exists() for row in clip_rows(s, Path(tmp))] + scene_rows(Path(tmp))
    for file, client, angle, dist, ok, seconds in rows:
        table.add_row(file, client, f"{angle:.5f}", f"{dist:.5f}", "yes" if ok else "NO", f"{seconds:.1f}")
    Console(width=160).print(table)


if __name__ == "__main__":
    main()
