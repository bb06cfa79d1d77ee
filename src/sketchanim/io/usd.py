"""USD export of transform animation (needs the optional ``usd-core``: ``pip install
sketchanim[usd]``): one Xform prim per joint, nested as the skeleton, with translate and
orient time samples at a chosen frame rate (USD transforms have no B-spline form), both
in double precision: USD turns an orientation into an angle through ``2 acos(w)``, and
in float32 ``w`` rounds to exactly 1 for rotations under about 0.03 degree.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from sketchanim.anim.skeleton import Clip
from sketchanim.errors import InputError
from sketchanim.io.atomic import write_atomic


def _pxr():  # type: ignore[no-untyped-def]
    try:
        from pxr import Gf, Usd, UsdGeom
    except ImportError:
        raise InputError("USD export needs usd-core: pip install 'sketchanim[usd]'") from None
    return Gf, Usd, UsdGeom


def write_usd(path: str | os.PathLike[str], clip: Clip) -> Path:
    """Write ``clip``'s frames as USD (.usda text, .usd / .usdc crate), atomically.

    Time codes are frames (``timeCodesPerSecond`` is the clip's frame rate); the stage's
    ``metersPerUnit`` is the clip's unit where known.
    """
    Gf, Usd, UsdGeom = _pxr()
    target = Path(path)
    rate = 1.0 / clip.frame_time
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp) / target.name
        stage = Usd.Stage.CreateNew(str(scratch))
        stage.SetTimeCodesPerSecond(rate)
        stage.SetStartTimeCode(0)
        stage.SetEndTimeCode(len(clip.times) - 1)
        UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
        if clip.unit_m is not None:
            UsdGeom.SetStageMetersPerUnit(stage, clip.unit_m)
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
        stage.SetDefaultPrim(stage.GetPrimAtPath(paths[0]))
        stage.GetRootLayer().Save()
        return write_atomic(target, scratch.read_bytes())
