"""Blender add-on: import sketchanim's glTF exports (.glb) with exact F-curves.

Install: Edit > Preferences > Add-ons > Install from Disk, pick this file, enable
"Import: sketchanim glTF". Then File > Import > sketchanim glTF (.glb).
Command line (no window):

    blender --background --python blender/sketchanim_import.py -- CLIP.glb [...] [--save OUT.blend]

Our clips and scenes are written as CUBICSPLINE samplers: cubic Hermite keys, which
are exactly Blender's Bezier keys with free handles a third of the segment away in time
(Blender's own glTF importer drops those tangents and guesses handles, which overshoots
between our few keys). Each joint becomes a bone whose rest orientation is the
armature's, so its pose channels are the file's curves unchanged (a translated joint's
location less its rest offset); a rotation is four quaternion F-curves, which Blender
normalises when it plays them, as glTF does. glTF's +Y up becomes Blender's +Z up by
one rotation of the root, so no key is converted. STEP samplers become constant keys.

LINEAR samplers (a clip's straight pieces, ``--keys frames`` and ``--keys compact`` files) become linear keys.
glTF turns LINEAR rotations spherically and F-curves interpolate the components; our
writers choose LINEAR rotation keys so that both stay within the file's bound (the
component-wise way after each key is put on the side of the one before, which this
does: the quaternion filter may flip signs). A joint's rotation where no channel
animates it is its pose (a compact file's constant track), held by a constant key.
Compact files store their data compressed (``EXT_meshopt_compression``, decoded with
the ``meshopt`` package, which Blender's Python needs then: the message says how to
install it).

Files this cannot play exactly are refused with a message: nodes given as matrices,
joints with a rest scale, and files not written by sketchanim.

Needs nothing beyond Blender (4.2 or later), and ``meshopt`` for compact files.
"""

import json
import math
import struct
import sys

import bpy
import numpy as np

bl_info = {
    "name": "Import: sketchanim glTF",
    "author": "sketchanim",
    "version": (1, 0, 0),
    "blender": (4, 2, 0),
    "location": "File > Import > sketchanim glTF (.glb)",
    "description": "Import sketchanim's .glb clips and scenes with exact Bezier F-curves",
    "category": "Import-Export",
}

#: Key frames closer than this to a whole frame are put on it (float32 key times).
SNAP = 1e-4

_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
_DTYPE = {5126: np.float32, 5123: np.uint16, 5125: np.uint32, 5121: np.uint8, 5122: np.int16, 5120: np.int8}
_PATHS = {"translation": ("location", 3), "rotation": ("rotation_quaternion", 4), "scale": ("scale", 3)}

MESHOPT = "EXT_meshopt_compression"

#: How to give Blender's Python the meshopt decoder (the version sketchanim writes with).
MESHOPT_INSTALL = ("blender -b --python-expr \"import subprocess, sys; "
                   "subprocess.check_call([sys.executable, '-m', 'pip', 'install', 'meshopt==0.1.0'])\"")


class SketchanimImportError(Exception):
    """A file this add-on cannot import exactly: the message says why and what to do."""


def read_glb(path: str) -> tuple[dict, bytes]:
    """The JSON document and binary chunk of a .glb."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 20 or data[:4] != b"glTF":
        raise SketchanimImportError(f"{path}: not a binary glTF (.glb) file")
    length, kind = struct.unpack_from("<I4s", data, 12)
    if kind != b"JSON":
        raise SketchanimImportError(f"{path}: the first chunk is not JSON")
    doc = json.loads(data[20:20 + length])
    rest = 20 + length
    blob = data[rest + 8:rest + 8 + struct.unpack_from("<I", data, rest)[0]] if len(data) > rest + 8 else b""
    return doc, blob


def _meshopt(path: str):
    """The meshopt module, or a refusal saying how to install it into Blender's Python."""
    try:
        import meshopt
    except ImportError:
        raise SketchanimImportError(
            f"{path}: a compact file ({MESHOPT}) needs the meshopt package in Blender's Python; "
            f"install it with: {MESHOPT_INSTALL}") from None
    return meshopt


class _Views:
    """The bytes of each buffer view of a .glb: its slice of the binary chunk, or
    (``EXT_meshopt_compression``) that slice decoded, filter undone, once."""

    def __init__(self, path: str, doc: dict, blob: bytes) -> None:
        self.path, self.doc, self.blob = path, doc, blob
        self.decoded: dict[int, bytes] = {}

    def view(self, index: int) -> tuple[bytes, int | None]:
        """The view's bytes and its byte stride (None: tightly packed)."""
        view = self.doc["bufferViews"][index]
        ext = view.get("extensions", {}).get(MESHOPT)
        if ext is None:
            start = view.get("byteOffset", 0)
            return self.blob[start:start + view["byteLength"]], view.get("byteStride")
        if index not in self.decoded:
            if ext.get("buffer", 0) != 0:
                raise SketchanimImportError(f"{self.path}: buffer view {index} is compressed outside the binary chunk")
            meshopt = _meshopt(self.path)
            start = ext.get("byteOffset", 0)
            try:
                rows = meshopt.decode_gltf_buffer(self.blob[start:start + ext["byteLength"]], ext["count"],
                                                  ext["byteStride"], ext["mode"], ext.get("filter", "NONE"))
            except (ValueError, RuntimeError) as err:
                raise SketchanimImportError(f"{self.path}: buffer view {index} does not decode: {err}") from None
            self.decoded[index] = np.ascontiguousarray(rows).tobytes()
        return self.decoded[index], ext["byteStride"]

    def accessor(self, index: int) -> np.ndarray:
        """An accessor's values (count, width); normalised integers as floats (glTF's rule:
        x / max, at least -1)."""
        acc = self.doc["accessors"][index]
        data, stride = self.view(acc["bufferView"])
        dtype = np.dtype(_DTYPE[acc["componentType"]])
        width, count = _WIDTH[acc["type"]], acc["count"]
        size = width * dtype.itemsize
        start = acc.get("byteOffset", 0)
        if count and start + (count - 1) * (stride or size) + size > len(data):
            raise SketchanimImportError(f"{self.path}: accessor {index} runs past the end of its buffer view")
        raw = np.frombuffer(data, np.uint8)
        rows = raw[start + np.arange(count)[:, None] * (stride or size) + np.arange(size)]
        out = rows.copy().view(dtype).reshape(count, width)
        if acc.get("normalized") and dtype.kind in "iu":
            out = np.maximum(out / float(np.iinfo(dtype).max), -1.0).astype(np.float32)
        return out


def _check(path: str, doc: dict) -> None:
    """Refuse what this cannot play exactly, saying why."""
    if not str(doc.get("asset", {}).get("generator", "")).startswith("sketchanim"):
        raise SketchanimImportError(f"{path}: not written by sketchanim (generator "
                                    f"{doc.get('asset', {}).get('generator')!r}); use File > Import > glTF 2.0")
    for node in doc.get("nodes", []):
        if "matrix" in node:
            raise SketchanimImportError(f"{path}: node {node.get('name')!r} is given as a matrix")
    for anim in doc.get("animations", []):
        for ch in anim["channels"]:
            kind = anim["samplers"][ch["sampler"]].get("interpolation", "LINEAR")
            name = doc["nodes"][ch["target"]["node"]].get("name")
            if ch["target"]["path"] not in _PATHS or kind not in ("CUBICSPLINE", "LINEAR", "STEP"):
                raise SketchanimImportError(f"{path}: node {name!r}: cannot play {kind} {ch['target']['path']}")
    unknown = [e for e in doc.get("extensionsRequired", []) if e != MESHOPT]
    if unknown:
        raise SketchanimImportError(f"{path}: requires {', '.join(unknown)}, which this add-on cannot read")


def _fcurves(obj: bpy.types.Object, action: bpy.types.Action, data_path: str, size: int, group: str) -> list:
    if hasattr(action, "fcurve_ensure_for_datablock"):           # layered actions (Blender 4.4 and later)
        return [action.fcurve_ensure_for_datablock(obj, data_path, index=i, group_name=group) for i in range(size)]
    return [action.fcurves.new(data_path, index=i, action_group=group) for i in range(size)]


def _set_keys(fcurve, frames: np.ndarray, values: np.ndarray, left: np.ndarray, right: np.ndarray,
              kind: str) -> None:
    """Keys at ``frames``: Bezier with free handles a third of each segment away
    (``left``/``right``: the handle values), or linear / constant."""
    n = len(frames)
    points = fcurve.keyframe_points
    points.add(n)
    points.foreach_set("co", np.c_[frames, values].ravel().tolist())
    gap = np.diff(frames) / 3
    before = frames - np.r_[gap[:1] if n > 1 else [1.0], gap]
    after = frames + np.r_[gap, gap[-1:] if n > 1 else [1.0]]
    points.foreach_set("handle_left", np.c_[before, left].ravel().tolist())
    points.foreach_set("handle_right", np.c_[after, right].ravel().tolist())
    ipo = {"CUBICSPLINE": "BEZIER", "LINEAR": "LINEAR", "STEP": "CONSTANT"}[kind]
    items = bpy.types.Keyframe.bl_rna.properties
    points.foreach_set("interpolation", [items["interpolation"].enum_items[ipo].value] * n)
    free = items["handle_left_type"].enum_items["FREE"].value
    points.foreach_set("handle_left_type", [free] * n)
    points.foreach_set("handle_right_type", [free] * n)


def _animate(obj, action, channels: list, offset: dict, fps: float, group: str) -> None:
    """The channels of one node on ``obj`` (an object, or a pose bone via ``group``)."""
    for path, kind, times, out in channels:
        prop, size = _PATHS[path]
        frames = times.astype(float) * fps
        # A key a float32 hair off a whole frame goes on it: Blender evaluates a frame within
        # 1e-4 of a key as that key's segment, and finds no value just before its start.
        frames = np.where(np.abs(frames - np.round(frames)) < SNAP, np.round(frames), frames)
        if kind == "CUBICSPLINE":
            out = out.reshape(len(times), 3, -1).astype(float)
            gaps = np.diff(times.astype(float))
            values = out[:, 1]
            left = values - out[:, 0] * np.r_[gaps[:1] if len(gaps) else [0.0], gaps][:, None] / 3
            right = values + out[:, 2] * np.r_[gaps, gaps[-1:] if len(gaps) else [0.0]][:, None] / 3
        else:
            values = left = right = out.astype(float)
        if path == "rotation" and kind == "LINEAR":
            values = left = right = _continuous(values)
        if path == "rotation":                                    # glTF x, y, z, w -> Blender w, x, y, z
            values, left, right = (a[:, [3, 0, 1, 2]] for a in (values, left, right))
        if path in offset:
            values, left, right = (a - offset[path] for a in (values, left, right))
        base = f'pose.bones["{group}"].{prop}' if obj.type == "ARMATURE" else prop
        for i, fc in enumerate(_fcurves(obj, action, base, size, group)):
            _set_keys(fc, frames, values[:, i], left[:, i], right[:, i], kind)


def _continuous(q: np.ndarray) -> np.ndarray:
    """Quaternion keys (m, 4), each on the side of the one before: interpolated
    component-wise, every segment then turns the shorter way, as glTF's does."""
    flips = np.cumsum(np.r_[0, np.sum(q[1:] * q[:-1], axis=1) < 0]) % 2
    return np.where(flips[:, None] == 1, -q, q)


def _mesh(views: _Views, index: int, name: str):
    prim = views.doc["meshes"][index]["primitives"][0]
    verts = views.accessor(prim["attributes"]["POSITION"]).astype(float)
    faces = views.accessor(prim["indices"]).reshape(-1, 3).astype(int)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts.tolist(), [], faces.tolist())
    return mesh


def load(path: str, context=None, fps: float | None = None) -> list:
    """Import one .glb: objects and armatures, animated by exact F-curves at ``fps``
    frames per second (the scene's by default). Returns the root objects."""
    context = context or bpy.context
    scene = context.scene
    fps = fps or scene.render.fps / scene.render.fps_base
    doc, blob = read_glb(path)
    _check(path, doc)
    nodes = doc.get("nodes", [])
    parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    joints = {j for skin in doc.get("skins", []) for j in skin["joints"]}
    for j in joints:
        if nodes[j].get("scale", [1, 1, 1]) != [1, 1, 1]:
            raise SketchanimImportError(f"{path}: joint {nodes[j].get('name')!r} has a rest scale")
    views = _Views(path, doc, blob)
    channels: dict[int, list] = {}
    for anim in doc.get("animations", [])[:1]:
        for ch in anim["channels"]:
            s = anim["samplers"][ch["sampler"]]
            channels.setdefault(ch["target"]["node"], []).append(
                (ch["target"]["path"], s.get("interpolation", "LINEAR"), views.accessor(s["input"])[:, 0],
                 views.accessor(s["output"])))
    for j in joints:           # a joint's rotation that no channel animates is its pose: a constant key
        turned = nodes[j].get("rotation", [0, 0, 0, 1]) != [0, 0, 0, 1]
        if turned and all(c[0] != "rotation" for c in channels.get(j, [])):
            channels.setdefault(j, []).append(("rotation", "STEP", np.zeros(1), np.array([nodes[j]["rotation"]])))
    name = doc.get("animations", [{}])[0].get("name", "sketchanim") if doc.get("animations") else "sketchanim"
    collection = context.collection
    root = bpy.data.objects.new(f"{name} (glTF Y up)", None)
    root.rotation_euler = (math.pi / 2, 0.0, 0.0)
    collection.objects.link(root)
    objects: dict[int, bpy.types.Object] = {}
    armature = None
    for i, node in enumerate(nodes):
        if i in joints or (node.get("skin") is not None):
            continue
        data = None
        if node.get("mesh") is not None:
            data = _mesh(views, node["mesh"], node.get("name", f"node{i}"))
        elif node.get("camera") is not None:
            cam = doc["cameras"][node["camera"]]
            data = bpy.data.cameras.new(cam.get("name", "camera"))
            data.sensor_fit = "VERTICAL"
            data.angle_y = cam["perspective"]["yfov"]
            data.clip_start = cam["perspective"].get("znear", 0.01)
        elif node.get("extensions", {}).get("KHR_lights_punctual") is not None:
            light = doc["extensions"]["KHR_lights_punctual"]["lights"][node["extensions"]["KHR_lights_punctual"]["light"]]
            data = bpy.data.lights.new(light.get("name", "light"), "SPOT")
            data.color = light.get("color", [1, 1, 1])
            data.spot_size = 2 * light.get("spot", {}).get("outerConeAngle", math.pi / 4)
        obj = bpy.data.objects.new(node.get("name", f"node{i}"), data)
        obj.rotation_mode = "QUATERNION"
        obj.location = node.get("translation", [0, 0, 0])
        x, y, z, w = node.get("rotation", [0, 0, 0, 1])
        obj.rotation_quaternion = (w, x, y, z)
        obj.scale = node.get("scale", [1, 1, 1])
        collection.objects.link(obj)
        objects[i] = obj
    for i, obj in objects.items():
        obj.parent = objects.get(parent.get(i), root)
    if joints:
        armature = _armature(doc, nodes, parent, sorted(joints), objects, root, collection, name)
    action_of: dict = {}
    for i, chans in channels.items():
        target = armature if i in joints else objects.get(i)
        if target is None:
            continue
        if target.name not in action_of:
            action = bpy.data.actions.new(f"{name} {target.name}")
            target.animation_data_create()
            target.animation_data.action = action
            action_of[target.name] = action
        offset = {"translation": np.array(nodes[i].get("translation", [0, 0, 0]))} if i in joints else {}
        _animate(target, action_of[target.name], chans, offset, fps, nodes[i].get("name", f"node{i}"))
    end = max((float(times[-1]) for chans in channels.values() for _, _, times, _ in chans), default=0.0)
    scene.frame_end = max(scene.frame_end, math.ceil(end * fps - SNAP))       # the timeline shows all of it
    return [root]


def _armature(doc, nodes, parent, joints, objects, root, collection, name):
    """One armature of every joint: bones with the armature's orientation, heads at the
    joints' rest positions, so pose channels are the file's (translations less offsets)."""
    data = bpy.data.armatures.new(f"{name} skeleton")
    arm = bpy.data.objects.new(f"{name} skeleton", data)
    collection.objects.link(arm)
    top = {parent.get(j) for j in joints} - set(joints)
    arm.parent = objects.get(next(iter(top)), root) if len(top) == 1 else root
    heads: dict[int, np.ndarray] = {}
    for j in joints:                                       # parents before children: walk up as needed
        chain, k = [], j
        while k in joints and k not in heads:
            chain.append(k)
            k = parent.get(k)
        for c in reversed(chain):
            heads[c] = heads.get(parent.get(c), np.zeros(3)) + np.array(nodes[c].get("translation", [0, 0, 0]))
    size = max(float(np.ptp(np.array(list(heads.values())), axis=0).max()), 1e-3)
    view = bpy.context.view_layer
    view.update()
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode="EDIT")
    bones = {}
    for j in sorted(joints, key=lambda j: len(_ancestors(j, parent, joints))):
        bone = data.edit_bones.new(nodes[j].get("name", f"joint{j}"))
        bone.head = heads[j].tolist()
        bone.tail = (heads[j] + [0.0, 0.05 * size, 0.0]).tolist()
        bone.roll = 0.0
        if parent.get(j) in bones:
            bone.parent = bones[parent[j]]
        bones[j] = bone
    bpy.ops.object.mode_set(mode="OBJECT")
    for pb in arm.pose.bones:
        pb.rotation_mode = "QUATERNION"
    return arm


def _ancestors(j, parent, joints):
    out = []
    while parent.get(j) in joints:
        j = parent[j]
        out.append(j)
    return out


class ImportSketchanim(bpy.types.Operator):
    """Import a sketchanim .glb with exact F-curves"""

    bl_idname = "import_scene.sketchanim_glb"
    bl_label = "Import sketchanim glTF"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    filter_glob: bpy.props.StringProperty(default="*.glb", options={"HIDDEN"})

    def execute(self, context):
        try:
            load(self.filepath, context)
        except SketchanimImportError as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        return {"FINISHED"}

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


def _menu(self, context):
    self.layout.operator(ImportSketchanim.bl_idname, text="sketchanim glTF (.glb)")


def register():
    bpy.utils.register_class(ImportSketchanim)
    bpy.types.TOPBAR_MT_file_import.append(_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_menu)
    bpy.utils.unregister_class(ImportSketchanim)


def main(argv: list[str]) -> int:
    """Command line: import each .glb given, then save the .blend if ``--save`` is given."""
    args = argv[argv.index("--") + 1:] if "--" in argv else argv
    save = None
    if "--save" in args:
        k = args.index("--save")
        save, args = args[k + 1], args[:k] + args[k + 2:]
    try:
        for path in args:
            load(path)
    except SketchanimImportError as err:
        print(f"sketchanim import: {err}", file=sys.stderr)
        return 2
    if save:
        bpy.ops.wm.save_as_mainfile(filepath=save)
    return 0


if __name__ == "__main__":
    code = main(sys.argv[1:] if bpy.app.background and "--" not in sys.argv else sys.argv)
    if code:
        sys.exit(code)
