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
    Gf, _, UsdGeom = pxr_modules()
    codes = np.asarray(times, dtype=float) * rate

    def build(stage: Any) -> str:
        xform = UsdGeom.Xform.Define(stage, f"/{name}")
        if positions is not None:
            translate = xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble)
            for code, p in zip(codes, np.asarray(positions, dtype=float)):
                translate.Set(Gf.Vec3d(*map(float, p)), float(code))
        if orientations is not None:
            orient = xform.AddOrientOp(UsdGeom.XformOp.PrecisionDouble)
            for code, (x, y, z, w) in zip(codes, np.asarray(orientations, dtype=float)):
                orient.Set(Gf.Quatd(float(w), float(x), float(y), float(z)), float(code))
        return f"/{name}"

    return _write_stage(Path(path), rate, float(codes[0]), float(codes[-1]), unit_m, build)
