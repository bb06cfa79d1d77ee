"""USD export of transform animation (needs the optional ``usd-core``: ``pip install
sketchanim[usd]``): one Xform prim per joint, nested as the skeleton (a clip), or one
prim for a sampled path (a table), with translate and orient time samples (USD
transforms have no B-spline form), both
in double precision: USD turns an orientation into an angle through ``2 acos(w)``, and
in float32 ``w`` rounds to exactly 1 for rotations under about 0.03 degree.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from sketchanim.motion.skeleton import Clip
from sketchanim.errors import InputError
from sketchanim.atomic import write_atomic


def pxr_modules():  # type: ignore[no-untyped-def]
    """usd-core's ``Gf, Usd, UsdGeom``, or an :class:`InputError` saying how to install it."""
    try:
        from pxr import Gf, Usd, UsdGeom
    except ImportError:
        raise InputError("USD export needs usd-core: pip install 'sketchanim[usd]'") from None
    return Gf, Usd, UsdGeom


def _write_stage(target: Path, rate: float, start: float, end: float, unit_m: float | None,
                 build: Callable[[Any], str]) -> Path:
    """A new y-up stage at ``rate`` time codes per second, filled by ``build`` (which
    returns the default prim's path), saved, then written to ``target`` atomically."""
    _, Usd, UsdGeom = pxr_modules()
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp) / target.name
        stage = Usd.Stage.CreateNew(str(scratch))
        stage.SetTimeCodesPerSecond(rate)
        stage.SetStartTimeCode(start)
        stage.SetEndTimeCode(end)
        UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
        if unit_m is not None:
            UsdGeom.SetStageMetersPerUnit(stage, unit_m)
        stage.SetDefaultPrim(stage.GetPrimAtPath(build(stage)))
        stage.GetRootLayer().Save()
        return write_atomic(target, scratch.read_bytes())


def write_usd(path: str | os.PathLike[str], clip: Clip) -> Path:
    """Write ``clip``'s frames as USD (.usda text, .usd / .usdc crate), atomically.

    Time codes are frames (``timeCodesPerSecond`` is the clip's frame rate); the stage's
    ``metersPerUnit`` is the clip's unit where known.
    """
    Gf, _, UsdGeom = pxr_modules()

    def build(stage: Any) -> str:
        sk = clip.skeleton
        paths: list[str] = []
        for i, (name, parent) in enumerate(zip(sk.names, sk.parents)):
            paths.append(f"{paths[parent] if parent >= 0 else ''}/{name}")
            xform = UsdGeom.Xform.Define(stage, paths[i])
            translate = xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble)
            orient = xform.AddOrientOp(UsdGeom.XformOp.PrecisionDouble)
            if not clip.translating[i]:
                translate.Set(Gf.Vec3d(*sk.offsets[i]))
            if not clip.rotating[i]:
                orient.Set(Gf.Quatd(1.0, 0.0, 0.0, 0.0))
            for f in range(len(clip.times)) if clip.translating[i] or clip.rotating[i] else ():
                if clip.translating[i]:
                    translate.Set(Gf.Vec3d(*clip.translations[f, i]), f)
                if clip.rotating[i]:
                    x, y, z, w = np.asarray(clip.rotations[f, i], dtype=float)
                    orient.Set(Gf.Quatd(float(w), float(x), float(y), float(z)), f)
        return paths[0]

    return _write_stage(Path(path), 1.0 / clip.frame_time, 0, len(clip.times) - 1, clip.unit_m, build)


def write_usd_path(path: str | os.PathLike[str], times: np.ndarray, rate: float, *,
                   positions: np.ndarray | None = None, orientations: np.ndarray | None = None,
                   unit_m: float | None = 1.0, name: str = "path") -> Path:
    """Write one animated Xform prim, ``/name``, as USD (.usda, .usd, .usdc), atomically:
    ``positions`` (n, 3) as translate and ``orientations`` (n, 4, unit quaternions
    x, y, z, w) as orient time samples at ``times`` (seconds, kept as they are: time
    code ``t * rate``, ``timeCodesPerSecond`` is ``rate``).

    Examples
    --------
    >>> import tempfile
    >>> from pxr import Usd
    >>> t = np.array([0.0, 0.5, 1.0])
    >>> out = Path(tempfile.mkdtemp()) / "p.usda"
    >>> _ = write_usd_path(out, t, 30.0, positions=np.c_[t, t, t], orientations=np.tile([0, 0, 0, 1.0], (3, 1)))
    >>> stage = Usd.Stage.Open(str(out))
    >>> stage.GetPrimAtPath("/path").GetAttribute("xformOp:translate").Get(15.0)
    Gf.Vec3d(0.5, 0.5, 0.5)
    >>> stage.GetEndTimeCode()
    30.0
    """
    times = np.asarray(times, dtype=float)
    xform = XformSamples(name, translate=None if positions is None else (times, positions),
                         orient=None if orientations is None else (times, orientations))
    return write_usd_xforms(path, rate, [xform], unit_m)


#: An Xform op's values: time samples (times in seconds (n,), values (n, d)), or one
#: constant value (None, (d,)).
OpValues = tuple[np.ndarray | None, np.ndarray]


@dataclass(frozen=True)
class XformSamples:
    """One Xform prim, ``/name`` (a path, ``a/b``, nests it under an earlier prim): its
    translate, orient (unit quaternions x, y, z, w) and scale ops, each time samples or a
    constant (:data:`OpValues`), or absent (None)."""

    name: str
    translate: OpValues | None = None
    orient: OpValues | None = None
    scale: OpValues | None = None


def write_usd_xforms(path: str | os.PathLike[str], rate: float, xforms: list[XformSamples],
                     unit_m: float | None = 1.0) -> Path:
    """Write Xform prims (:class:`XformSamples`) as USD (.usda, .usd, .usdc), atomically,
    in double precision: each op's samples at time code ``t * rate``
    (``timeCodesPerSecond`` is ``rate``), applied translate, orient, scale (as glTF's
    T R S); the stage spans every sample. The first prim is the default one.

    >>> import tempfile
    >>> from pxr import Usd
    >>> out = Path(tempfile.mkdtemp()) / "s.usda"
    >>> a = XformSamples("a", translate=(np.array([0.0, 1.0]), np.array([[0.0, 0, 0], [2.0, 0, 0]])))
    >>> b = XformSamples("b", scale=(None, np.array([1.0, 2.0, 3.0])))
    >>> stage = Usd.Stage.Open(str(write_usd_xforms(out, 24.0, [a, b])))
    >>> stage.GetPrimAtPath("/a").GetAttribute("xformOp:translate").Get(12.0), stage.GetEndTimeCode()
    (Gf.Vec3d(1.0, 0.0, 0.0), 24.0)
    >>> stage.GetPrimAtPath("/b").GetAttribute("xformOp:scale").Get()
    Gf.Vec3d(1.0, 2.0, 3.0)
    """
    Gf, _, UsdGeom = pxr_modules()
    sampled = [np.asarray(op[0], dtype=float) * rate for x in xforms
               for op in (x.translate, x.orient, x.scale) if op is not None and op[0] is not None and len(op[0])]
    codes = np.concatenate(sampled) if sampled else np.zeros(1)

    def value(kind: str, v: np.ndarray) -> Any:
        if kind == "orient":
            x, y, z, w = map(float, v)
            return Gf.Quatd(w, x, y, z)
        return Gf.Vec3d(*map(float, v))

    def build(stage: Any) -> str:
        for xform in xforms:
            prim = UsdGeom.Xform.Define(stage, f"/{xform.name}")
            adders = {"translate": prim.AddTranslateOp, "orient": prim.AddOrientOp, "scale": prim.AddScaleOp}
            for kind, add in adders.items():
                op_values = getattr(xform, kind)
                if op_values is None:
                    continue
                op = add(UsdGeom.XformOp.PrecisionDouble)
                times, values = op_values
                if times is None:
                    op.Set(value(kind, np.asarray(values, dtype=float)))
                    continue
                for code, v in zip(np.asarray(times, dtype=float) * rate, np.asarray(values, dtype=float)):
                    op.Set(value(kind, v), float(code))
        return f"/{xforms[0].name}"

    return _write_stage(Path(path), rate, float(codes.min()), float(codes.max()), unit_m, build)
