"""What a client plays from our float32 files: within the asked tolerance (not only our
float64 curves), the last frame inside the clip, no validator warning, and USD keeping
rotations too small for float32's ``2 acos(w)``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from scipy.spatial.transform import Rotation

from clips import clips, play32, sampler_play32, samplers, validate
from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.mocap.markers import Markers, reduce_markers
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import read_clip
from sketchanim.reducer.metric import rotation_angle

TOL, ROT_TOL = 0.5, 0.5


def assert_played_within(path: Path, clip: Clip, tol: float, rot_tol: float) -> None:
    """Every joint channel of the .glb, played in float32 at every source frame, within
    the asked tolerances of the source (no slack); LINEAR rotations both spherically
    (glTF's rule) and component-wise (Blender's F-curves)."""
    channels = samplers(path)
    for j, name in enumerate(clip.skeleton.names):
        if clip.rotating[j]:
            kind, times, keys = channels[(name, "rotation")]
            for way in (True, False):
                played = sampler_play32(kind, times, keys, clip.times, True, way).astype(float)
                angle = np.degrees(rotation_angle(played, clip.rotations[:, j]))
                assert angle.max() <= rot_tol, (name, way, angle.max())
        if clip.translating[j]:
            kind, times, keys = channels[(name, "translation")]
            dist = np.linalg.norm(sampler_play32(kind, times, keys, clip.times, False) - clip.translations[:, j],
                                  axis=1)
            assert dist.max() <= tol, (name, dist.max())


def _ends_after_the_last_frame(path: Path, last: float) -> None:
    """The clip's duration (its latest key, float32) is past the last frame: a looping
    player (three.js wraps at the duration) shows the last frame, not the first."""
    assert max(float(times[-1]) for _, times, _ in samplers(path).values()) > last


@settings(max_examples=10)
@given(clips())
def test_float32_glb_plays_within_tolerance_to_the_last_frame(tmp_path_factory: pytest.TempPathFactory,
                                                              clip: Clip) -> None:
    path = write_reduced(tmp_path_factory.mktemp("f32") / "clip.glb", reduce_clip(clip, TOL, ROT_TOL))
    assert_played_within(path, clip, TOL, ROT_TOL)
    _ends_after_the_last_frame(path, float(clip.times[-1]))


def test_clip_glb_has_no_validator_warning(tmp_path: Path) -> None:
    from hypothesis import find

    clip = find(clips(), lambda c: len(c.times) > 40)
    clip = Clip(clip.skeleton, clip.times, clip.rotations, clip.translations, clip.rotating, clip.translating,
                clip.channels, 0.01)                               # in cm: under a 'to metres' node
    path = write_reduced(tmp_path / "c.glb", reduce_clip(clip, TOL, ROT_TOL))
    (report,) = validate(path)
    assert report["numErrors"] == 0 and report["numWarnings"] == 0, report["messages"]


def test_marker_glb_plays_within_tolerance_in_float32(tmp_path: Path) -> None:
    t = 1000.0 + np.arange(400) / 100.0                 # late times: float32 times are coarse there
    p = np.stack([300 * np.cos(t), 200 * np.sin(3 * t), 1000 + 50 * t], axis=1)[:, None]
    p[150:170] = np.nan
    markers = Markers(("m",), t, p, 0.001)
    path = write_reduced(tmp_path / "m.glb", reduce_markers(markers, 0.5))
    _, times, keys = samplers(path)[("m", "translation")]
    seen = np.isfinite(p[:, 0, 0])
    dist = np.linalg.norm(play32(times, keys, t[seen]) - p[seen, 0], axis=1)
    assert dist.max() <= 0.5
    _ends_after_the_last_frame(path, float(t[-1]))


def test_usd_keeps_rotations_float32_would_lose(tmp_path: Path) -> None:
    from pxr import Gf, Usd, UsdGeom

    s = Skeleton(("root", "toe"), (-1, 0), np.array([[0.0, 0, 0], [0, -10, 0]]))
    t = np.arange(60) / 30
    clip = Clip.still(s, t)
    clip.rotations[:, 1] = Rotation.from_euler("X", np.radians(0.02) * np.sin(t)[:, None]).as_quat()  # 0.02 deg
    reduced = reduce_clip(clip, 0.01, 0.001)
    stage = Usd.Stage.Open(str(write_reduced(tmp_path / "c.usda", reduced)))
    xform = UsdGeom.Xformable(stage.GetPrimAtPath("/root/toe"))
    frames = reduced.resample(30)
    for f in range(len(t)):
        m = xform.GetLocalTransformation(Usd.TimeCode(f))
        played = Gf.Rotation(m.ExtractRotationQuat())          # through USD's own angle-axis form
        q = played.GetQuat()
        angle = np.degrees(rotation_angle(np.array([*q.GetImaginary(), q.GetReal()]), frames.rotations[f, 1]))
        assert angle.max() < 1e-4, (f, angle)


@pytest.mark.realdata
def test_real_clips_play_within_tolerance_in_float32(real_clips: list[Path], tmp_path: Path) -> None:
    for source in real_clips:
        clip = read_clip(source)
        tol = 0.005 / clip.guess_unit_m()
        path = write_reduced(tmp_path / f"{source.stem}.glb", reduce_clip(clip, tol, 0.5))
        assert_played_within(path, clip, tol, 0.5)
        _ends_after_the_last_frame(path, float(clip.times[-1]))
