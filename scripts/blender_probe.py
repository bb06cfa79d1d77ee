"""Run in Blender's Python (the bpy wheel, .venv-blender): import a .glb with our add-on
(``addon``) or Blender's own glTF importer (``gltf``), play it at the given times and
save every pose bone's and object's world matrix; several files one after the other,
each in a new empty scene (Blender starts once).

    .venv-blender/bin/python scripts/blender_probe.py addon|gltf FILE.glb TIMES.npy FPS OUT.npz [FILE.glb ...]

With the add-on the scene runs at FPS (the source's rate: its frames are whole frames,
as an animator plays them).
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import bpy
import numpy as np

mode, jobs = sys.argv[1], sys.argv[2:]
if mode == "addon":
    spec = importlib.util.spec_from_file_location("sketchanim_import",
                                                  Path(__file__).resolve().parents[1] / "blender" / "sketchanim_import.py")
    addon = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(addon)


def probe(glb: str, times_file: str, rate: str, out: str) -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    fps = float(rate)
    scene.render.fps = max(1, round(fps))
    # Blender's glTF importer places keys at seconds x fps x fps_base (where playback runs at
    # fps / fps_base): give it fps_base 1, and play at the fractional frames of the times.
    scene.render.fps_base = scene.render.fps / fps if mode == "addon" else 1.0
    fps = scene.render.fps / scene.render.fps_base
    if mode == "addon":
        try:
            addon.load(glb)
        except addon.SketchanimImportError as err:
            print(f"refused: {err}")
            sys.exit(3)
    else:
        bpy.ops.import_scene.gltf(filepath=glb)
    times = np.load(times_file)
    objects = [o for o in scene.objects]
    bones = [(o, pb.name) for o in objects if o.type == "ARMATURE" for pb in o.pose.bones]
    rest = {f"bone:{name}": np.array(o.matrix_world @ o.data.bones[name].matrix_local) for o, name in bones}
    poses = {key: np.empty((len(times), 4, 4)) for key in [*rest, *(f"object:{o.name}" for o in objects)]}
    for k, t in enumerate(times):
        frame = float(t) * fps
        frame = round(frame) if abs(frame - round(frame)) < 1e-6 else frame
        scene.frame_set(int(np.floor(frame)), subframe=float(frame - np.floor(frame)))
        depsgraph = bpy.context.evaluated_depsgraph_get()
        for o in objects:
            ev = o.evaluated_get(depsgraph)
            poses[f"object:{o.name}"][k] = np.array(ev.matrix_world)
            if o.type == "ARMATURE":
                for pb in ev.pose.bones:
                    poses[f"bone:{pb.name}"][k] = np.array(ev.matrix_world @ pb.matrix)
    np.savez(out, **poses, **{f"rest:{k}": v for k, v in rest.items()})


for i in range(0, len(jobs), 4):
    probe(*jobs[i:i + 4])
