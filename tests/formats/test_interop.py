"""Motion capture in (BVH, ASF/AMC), reduced clips out (glTF, BVH, USD, JSON), batch.

Every promise is checked on random clips (hypothesis) and on the recordings in
../shared/data: round trips within tolerance at every frame and joint, the Khronos
validator finds no error, and an independent Hermite evaluator reads the glTF curves
as our splines.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from clips import assert_within, clips, hermite_at, sampler_play32, samplers, validate
from sketchanim.mocap.clip_reduction import ReducedClip, reduce_clip
from sketchanim.motion.skeleton import Clip
from sketchanim.cli import app
from sketchanim.errors import FileFormatError, InputError
from sketchanim.formats.amc import read_amc, read_asf
from sketchanim.formats.bvh import read_bvh, write_bvh
from sketchanim.export.files import write_reduced
from sketchanim.formats.clip_files import read_clip
from sketchanim.export.mocap_gltf import clip_glb
from sketchanim.reducer.metric import rotation_angle

TOL, ROT_TOL = 0.5, 0.5
runner = CliRunner()


def _round_trip(clip: Clip, folder: Path, tol: float = TOL, rot_tol: float = ROT_TOL) -> tuple[Clip, ReducedClip]:
    """BVH in, reduce, BVH out at the source's rate, read again."""
    source = read_bvh(write_bvh(folder / "in.bvh", clip))
    reduced = reduce_clip(source, tol, rot_tol)
    back = read_bvh(write_reduced(folder / "out.bvh", reduced))
    return source, back


def _glb_matches_splines(path: Path, reduced: ReducedClip) -> None:
    """The .glb's samplers are our curves: LINEAR keys our straight pieces' values at
    their breakpoints, CUBICSPLINE keys evaluated by the spec's formula (1e-6)."""
    channels = samplers(path)
    gltf = {"orientation": "rotation", "position": "translation"}
    curves = [(name, gltf[attribute], r.reduction) for path, r in reduced.tracks.items()
              for name, attribute in [path.rsplit(".", 1)]]
    assert len(channels) == len(curves)
    u = np.linspace(0, 1, 7)
    for name, kind, r in curves:
        interpolation, times, keys = channels[(name, kind)]
        assert interpolation == ("LINEAR" if r.spline.k == 1 else "CUBICSPLINE"), (name, kind, r.spline.k)
        assert np.allclose(times, np.unique(r.spline.t), atol=1e-6 * max(1.0, times[-1]))
        ours_t = np.unique(r.spline.t)
        if interpolation == "LINEAR":
            ours = r.columns(ours_t)
            assert np.abs(keys - ours).max() <= 1e-6 * max(1.0, float(np.abs(ours).max())), (name, kind)
            values = keys
        else:
            segment = np.repeat(np.arange(len(times) - 1), len(u))
            uu = np.tile(u, len(times) - 1)
            ours = r.columns(ours_t[segment] + uu * (ours_t[segment + 1] - ours_t[segment]))
            theirs = hermite_at(times, keys, segment, uu)
            # float32 keys: relative to the largest term of the formula (a value, or a tangent times its span),
            # plus what float32 key times move a tangent's term
            tangent = float(np.abs(keys[:, [0, 2]]).max())
            scale = max(1.0, float(np.abs(ours).max()), tangent * np.diff(times).max())
            bound = 1e-6 * scale + tangent * float(np.abs(times - ours_t).max())
            assert np.abs(theirs - ours).max() <= bound, (name, kind)
            values = keys[:, 1]
        if kind == "rotation":
            assert np.allclose(np.linalg.norm(values, axis=1), 1.0, atol=1e-6)


@settings(max_examples=12)
@given(clips(), st.sampled_from([(0.5, 0.5), (0.1, 0.1), (2.0, 1.0)]))
def test_bvh_round_trip_keeps_every_frame_and_joint(tmp_path_factory: pytest.TempPathFactory, clip: Clip,
                                                     tols: tuple[float, float]) -> None:
    tol, rot_tol = tols
    source, back = _round_trip(clip, tmp_path_factory.mktemp("rt"), tol, rot_tol)
    assert back.skeleton.names == source.skeleton.names
    assert np.allclose(back.skeleton.offsets, source.skeleton.offsets)
    assert back.channels == source.channels
    assert_within(back, source, tol, rot_tol, slack=1e-5)      # + the text's 10 significant digits


@settings(max_examples=8)
@given(clips(), st.sampled_from([2, 4]))
def test_glb_is_valid_exact_and_within_tolerance(tmp_path_factory: pytest.TempPathFactory, clip: Clip,
                                                 order: int) -> None:
    folder = tmp_path_factory.mktemp("glb")
    reduced = reduce_clip(clip, TOL, ROT_TOL, order=order)
    path = write_reduced(folder / "clip.glb", reduced)
    (report,) = validate(path)
    assert report["numErrors"] == 0, report["messages"]
    _glb_matches_splines(path, reduced)
    # The glTF curves, played as glTF plays them (normalised rotations; LINEAR ones spherically
    # and, as Blender's F-curves, component-wise), at the source frames.
    channels = samplers(path)
    for j in np.flatnonzero(clip.rotating):
        kind, times, keys = channels[(clip.skeleton.names[j], "rotation")]
        for way in (True, False):
            played = sampler_play32(kind, times, keys, clip.times, True, way).astype(float)
            angle = np.degrees(rotation_angle(played, clip.rotations[:, j]))
            assert angle.max() <= ROT_TOL + 1e-3        # float32 keys and times


def test_rotation_keys_are_unit_quaternions_and_every_frame_holds() -> None:
    from hypothesis import find

    clip = find(clips(), lambda c: len(c.times) > 100)
    reduced = reduce_clip(clip, TOL, ROT_TOL)
    for j in np.flatnonzero(clip.rotating):
        r = reduced.joint_track(j, "orientation").reduction
        keys = r.spline(np.unique(r.spline.t))
        assert np.allclose(np.linalg.norm(keys, axis=1), 1.0, atol=1e-12)
        assert np.degrees(rotation_angle(r.spline(clip.times), clip.rotations[:, j]).max()) <= ROT_TOL


def test_json_round_trip_and_bad_documents(tmp_path: Path) -> None:
    from hypothesis import find

    clip = find(clips(), lambda c: len(c.times) > 50)
    reduced = reduce_clip(clip, TOL, ROT_TOL)
    back = ReducedClip.from_json(write_reduced(tmp_path / "c.json", reduced).read_text(), source="c.json")
    assert np.array_equal(back.sample(clip.times).rotations, reduced.sample(clip.times).rotations)
    assert np.array_equal(back.sample(clip.times).translations, reduced.sample(clip.times).translations)
    with pytest.raises(InputError, match="c.json, line 1: not JSON"):
        ReducedClip.from_json("{", source="c.json")
    with pytest.raises(InputError, match="not a sketchanim.clip document"):
        ReducedClip.from_json('{"schema": "other"}', source="c.json")
    broken = reduced.to_json().replace('"parent"', '"parnt"', 1)
    with pytest.raises(InputError, match="c.json: malformed clip document"):
        ReducedClip.from_json(broken, source="c.json")


def test_usd_holds_the_frames(tmp_path: Path) -> None:
    from hypothesis import find
    from pxr import Usd, UsdGeom

    clip = find(clips(), lambda c: len(c.times) > 30)
    reduced = reduce_clip(clip, TOL, ROT_TOL)
    path = write_reduced(tmp_path / "c.usda", reduced)
    stage = Usd.Stage.Open(str(path))
    frames = reduced.resample(1 / clip.frame_time)
    assert stage.GetTimeCodesPerSecond() == pytest.approx(1 / clip.frame_time)
    prim = stage.GetPrimAtPath("/j0")
    ops = UsdGeom.Xformable(prim).GetOrderedXformOps()
    for f in (0, len(frames.times) // 2, len(frames.times) - 1):
        translate = np.array(ops[0].Get(f))
        q = ops[1].Get(f)
        quat = np.array([*q.GetImaginary(), q.GetReal()])
        assert np.allclose(translate, frames.translations[f, 0], atol=1e-9)
        assert np.degrees(rotation_angle(quat, frames.rotations[f, 0])[0]) < 1e-4


# ---- malformed files -----------------------------------------------------------------

GOOD = ("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation "
        "Yrotation\n  JOINT Knee\n  {\n    OFFSET 0 -10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
        "    End Site\n    {\n      OFFSET 0 -10 0\n    }\n  }\n}\nMOTION\nFrames: 3\nFrame Time: 0.0333333\n"
        "0 1 2 3 4 5 6 7 8\n0 1 2 3 4 5 6 7 9\n0 1 2 3 4 5 6 7 10\n")


@pytest.mark.parametrize("broken, message", [
    (GOOD.replace("0 1 2 3 4 5 6 7 10\n", ""), r"line 20: MOTION is truncated: 'Frames: 3' but 2 frames"),
    (GOOD.replace("0 1 2 3 4 5 6 7 10\n", "0 1 2 3 4\n"), r"line 21: frame 2 has 5 values.*\(truncated\?\)"),
    (GOOD.replace("CHANNELS 3 Zrotation", "CHANNELS 3 Wrotation"), r"line 9: joint 'Knee': unknown channel"),
    (GOOD.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 2 Zrotation Xrotation"),
     r"line 9: joint 'Knee': needs all three rotation"),
    (GOOD.replace("CHANNELS 3", "CHANNELS x"), r"line 9: joint 'Knee': channel count"),
    (GOOD.replace("Frame Time: 0.0333333", "Frame Time: -1"), r"line 18: frame time must be a positive"),
    (GOOD.replace("Frame Time: 0.0333333", "Frame Tim 0.1"), r"line 18: expected 'Frame Time: \.\.\.'"),
    (GOOD.replace("0 1 2 3 4 5 6 7 9", "0 1 2 3 x 5 6 7 9"), r"line 20: frame 1: not a number: 'x'"),
    (GOOD.replace("0 1 2 3 4 5 6 7 9", "0 1 2 3 nan 5 6 7 9"), r"line 20: frame 1: value is not finite"),
    (GOOD.replace("OFFSET 0 -10 0\n    CHANNELS", "OFFSET 0 -10\n    CHANNELS"), r"line 9: joint 'Knee' OFFSET: not"),
    (GOOD.replace("MOTION", "MOTON"), r"no MOTION section"),
    (GOOD.replace("JOINT Knee", "JOINT Hips"), r"line 6: joint 'Hips' appears twice"),
    (GOOD.replace("  }\n}\nMOTION", "  }\nMOTION"), r"file ends where JOINT, End Site or '}' was expected"),
])
def test_malformed_bvh_names_file_line_and_reason(tmp_path: Path, broken: str, message: str) -> None:
    path = tmp_path / "bad.bvh"
    path.write_text(broken)
    with pytest.raises(FileFormatError, match=message) as err:
        read_bvh(path)
    assert str(err.value).startswith(str(path))


@settings(max_examples=150)
@given(st.data())
def test_bvh_fuzz_fails_only_with_file_format_errors(tmp_path_factory: pytest.TempPathFactory,
                                                      data: st.DataObject) -> None:
    text = GOOD
    for _ in range(data.draw(st.integers(1, 3))):
        at = data.draw(st.integers(0, len(text)))
        edit = data.draw(st.sampled_from(["cut", "insert", "delete"]))
        if edit == "cut":
            text = text[:at]
        elif edit == "insert":
            text = text[:at] + data.draw(st.sampled_from(["{", "}", "x", " 1e999", "\n", "JOINT", "-", "\x00", ":"])) \
                + text[at:]
        else:
            text = text[:at] + text[at + data.draw(st.integers(1, 5)):]
    path = tmp_path_factory.mktemp("fuzz") / "f.bvh"
    path.write_text(text)
    try:
        clip = read_bvh(path)
    except FileFormatError as err:
        assert str(err).startswith(str(path))
        return
    assert np.all(np.isfinite(clip.rotations)) and np.all(np.isfinite(clip.translations))


def test_malformed_asf_and_amc(tmp_path: Path) -> None:
    asf = tmp_path / "s.asf"
    asf.write_text(":units\n length 0.45\n angle deg\n:root\n order TX TY TZ RX RY RZ\n axis XYZ\n:bonedata\n begin\n"
                   "  name femur\n  direction 0 -1 0\n  length 7\n  axis 0 0 20 XYZ\n  dof rx rz\n end\n"
                   ":hierarchy\n begin\n  root femur\n end\n")
    skeleton = read_asf(asf)
    amc = tmp_path / "m.amc"
    amc.write_text(":FULLY-SPECIFIED\n:DEGREES\n1\nroot 0 1 2 3 4 5\nfemur 10 20\n2\nroot 0 1 2 3 4 5\nfemur 11 21\n")
    clip = read_amc(amc, skeleton)
    assert clip.rotations.shape == (2, 3, 4) and clip.unit_m == pytest.approx(0.0254 / 0.45)
    for text, message in [
        ("1\nroot 0 1 2 3 4 5\nfemur 10 20\n2\nroot 0 1 2 3 4 5\n", r"line 4: frame 1 lacks bone 'femur' \(truncated"),
        ("1\nroot 0 1 2 3 4 5\nfemur 10\n2\nroot 0 1 2 3 4 5\nfemur 1 2\n", r"line 3: bone 'femur': expected 2"),
        ("1\nroot 0 1 2 3 4 5\ntibia 10 2\n", r"line 3: frame 1: no bone 'tibia'"),
        ("root 0 1 2 3 4 5\n", r"line 1: expected a frame number"),
        ("1\nroot 0 1 2 3 4 5\nfemur 10 20\n", r"needs at least 2 frames"),
    ]:
        amc.write_text(text)
        with pytest.raises(FileFormatError, match=message):
            read_amc(amc, skeleton)
    asf.write_text(asf.read_text().replace("root femur", "root tibia"))
    with pytest.raises(FileFormatError, match=r"line 17: hierarchy names bone 'tibia'"):
        read_asf(asf)


# ---- the command line and batches ----------------------------------------------------

def _library(folder: Path, n: int = 3) -> list[Path]:
    from hypothesis import find

    paths = []
    for i in range(n):
        clip = find(clips(), lambda c, i=i: len(c.times) > 40 + 10 * i)
        paths.append(write_bvh(folder / f"clip{i}.bvh", clip))
    return paths


def test_cli_reduces_one_clip_to_each_format(tmp_path: Path) -> None:
    (source,) = _library(tmp_path, 1)
    for ext in ("glb", "bvh", "json", "usda"):
        result = runner.invoke(app, ["reduce", str(source), "-o", str(tmp_path / f"out.{ext}"), "--tol", "0.5",
                                     "--rot-tol-deg", "0.5"])
        assert result.exit_code == 0, result.output
        assert (tmp_path / f"out.{ext}").stat().st_size > 0
    assert "compression" in result.output
    assert validate(tmp_path / "out.glb")[0]["numErrors"] == 0
    assert_within(read_bvh(tmp_path / "out.bvh"), read_bvh(source), 0.5, 0.5, slack=1e-5)
    result = runner.invoke(app, ["reduce", str(source), "-o", str(tmp_path / "out.fbx"), "--tol", "0.5"])
    assert result.exit_code == 2 and "cannot write .fbx" in result.output


def test_cli_needs_units_or_tolerance_when_it_cannot_tell(tmp_path: Path) -> None:
    (source,) = _library(tmp_path, 1)
    text = source.read_text()
    result = runner.invoke(app, ["reduce", str(source), "-o", str(tmp_path / "o.glb")])
    if read_bvh(source).guess_unit_m() is None:
        assert result.exit_code == 2 and "cannot tell the clip's units" in result.output
    result = runner.invoke(app, ["reduce", str(source), "-o", str(tmp_path / "o.glb"), "--units", "cm"])
    assert result.exit_code == 0, result.output
    assert source.read_text() == text
    doc = gl.GLTF2().load_binary(str(tmp_path / "o.glb"))          # shown in metres, curves untouched
    root, mesh = doc.scenes[0].nodes                              # the skinned mesh at the root, as the spec advises
    assert doc.nodes[root].name == "to metres" and doc.nodes[root].scale == [0.01] * 3
    assert doc.nodes[mesh].skin == 0


def test_batch_reports_a_corrupt_clip_and_skips_done_ones(tmp_path: Path) -> None:
    lib, out = tmp_path / "lib", tmp_path / "out"
    lib.mkdir()
    good = _library(lib, 2)
    corrupt = lib / "clip0b.bvh"                     # sorts between the two good clips
    corrupt.write_text(good[0].read_text()[:-200])   # MOTION cut short
    args = ["reduce", str(lib), "-o", str(out), "--tol", "0.5", "--workers", "2"]
    result = runner.invoke(app, args)
    assert result.exit_code == 1
    assert "1 of 3 clips failed" in result.output and "truncated" in result.output
    rows = list(csv.DictReader((out / "report.csv").open()))
    assert [Path(r["source"]).name for r in rows] == ["clip0.bvh", "clip0b.bvh", "clip1.bvh"]
    assert [r["status"] for r in rows] == ["reduced", "failed", "reduced"]
    assert "clip0b.bvh" in rows[1]["message"] and "truncated" in rows[1]["message"]
    for r in (rows[0], rows[2]):
        assert float(r["max_rotation_error_deg"]) <= 0.5 and float(r["max_position_error"]) <= 0.5
        assert validate(Path(r["output"]))[0]["numErrors"] == 0
    before = {p: p.stat().st_mtime_ns for p in out.glob("*.glb")}
    result = runner.invoke(app, args)
    rows2 = list(csv.DictReader((out / "report.csv").open()))
    assert [r["status"] for r in rows2] == ["skipped", "failed", "skipped"]
    assert rows2[0]["control_points"] == rows[0]["control_points"]
    assert {p: p.stat().st_mtime_ns for p in out.glob("*.glb")} == before


def test_batch_on_a_dask_cluster(tmp_path: Path) -> None:
    from distributed import LocalCluster

    lib = tmp_path / "lib"
    lib.mkdir()
    _library(lib, 2)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        result = runner.invoke(app, ["reduce", str(lib), "-o", str(tmp_path / "out"), "--tol", "0.5",
                                     "--format", "json", "--scheduler", cluster.scheduler_address])
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader((tmp_path / "out" / "report.csv").open()))
    assert [r["status"] for r in rows] == ["reduced", "reduced"]
    for r in rows:
        reduced = ReducedClip.from_json(Path(r["output"]).read_text())
        source = read_bvh(r["source"])
        assert_within(reduced.sample(source.times), source, 0.5, 0.5)


# ---- real recordings -----------------------------------------------------------------

@pytest.mark.realdata
def test_real_clips_round_trip_and_validate(real_clips: list[Path], tmp_path: Path) -> None:
    glbs = []
    for source in real_clips:
        clip = read_clip(source)
        unit = clip.guess_unit_m()
        assert unit is not None, source.name
        tol = 0.005 / unit                                  # 0.5 cm
        reduced = reduce_clip(clip, tol, 0.5)
        back = read_bvh(write_reduced(tmp_path / f"{source.stem}.bvh", reduced))
        assert_within(back, clip, tol, 0.5, slack=1e-5)
        glbs.append(write_reduced(tmp_path / f"{source.stem}.glb", reduced))
        _glb_matches_splines(glbs[-1], reduced)
    for report in validate(*glbs):
        assert report["numErrors"] == 0, (report["file"], report["messages"][:3])


@pytest.mark.realdata
def test_real_bvh_text_round_trip_is_lossless(real_bvh: list[Path], tmp_path: Path) -> None:
    for source in real_bvh:
        clip = read_bvh(source)
        back = read_bvh(write_bvh(tmp_path / source.name, clip))
        assert_within(back, clip, 1e-6, 1e-6, slack=1e-6)
        assert back.channels == clip.channels and back.skeleton.names == clip.skeleton.names


def test_glb_of_a_clip_without_bones_is_valid(tmp_path: Path) -> None:
    from sketchanim.motion.skeleton import Skeleton

    clip = Clip.still(Skeleton(("only",), (-1,), np.zeros((1, 3))), np.arange(10) / 30)
    path = tmp_path / "one.glb"
    path.write_bytes(clip_glb(reduce_clip(clip, 0.1, 0.5)))
    assert validate(path)[0]["numErrors"] == 0


def test_reading_a_missing_or_foreign_clip(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError, match="cannot read"):
        read_clip(tmp_path / "none.bvh")
    with pytest.raises(FileFormatError, match="not a clip format"):
        read_clip(tmp_path / "x.fbx")
    (tmp_path / "a.asf").write_text("")
    (tmp_path / "b.asf").write_text("")
    with pytest.raises(FileFormatError, match="cannot tell which .asf"):
        read_clip(tmp_path / "m.amc")
