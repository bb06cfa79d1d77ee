"""`sketchanim reduce` on real-world tables: formats, time units, quirks as choices,
groups, outputs of the asked type or a refusal, argument ranges (exit status 2, a
message naming what is wrong, nothing written)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from clips import played, validate
from tolerance import within
from sketchanim.cli import app
from sketchanim.export.scene_gltf import KEY_SHARE
from sketchanim.float32 import float32_margin
from sketchanim.pipeline.table_outputs import GLB_CLOCK
from sketchanim.reducer import Reduction
from sketchanim.reducer.metric import rotation_angle

runner = CliRunner()


def motion(n: int = 400) -> tuple[np.ndarray, np.ndarray]:
    t = np.linspace(0, 4, n)
    return t, np.c_[np.sin(2 * t), np.cos(3 * t), 0.5 * t]


def quats(t: np.ndarray) -> np.ndarray:
    return Rotation.from_rotvec(np.c_[np.sin(t), 0.5 * t, 0 * t]).as_quat()


def refused(res, *words: str) -> None:
    assert res.exit_code == 2, res.output
    assert "Traceback" not in res.output
    for w in words:
        assert w in res.output, res.output


def reduced_at(out: Path, t: np.ndarray) -> np.ndarray:
    """The curve a reduce command wrote to ``out``, at ``t``."""
    return Reduction.from_json(out.read_text()).spline(t)


def test_whitespace_and_tab_tables(tmp_path):
    t, x = motion()
    for name, sep in (("s.txt", " "), ("s.tsv", "\t")):
        f = tmp_path / name
        np.savetxt(f, np.c_[t, x], delimiter=sep)
        out = tmp_path / (name + ".json")
        res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "-o", str(out)])
        assert res.exit_code == 0, res.output
        assert within(reduced_at(out, t), x, 0.01, slack=1e-9)


def test_bom_headerless_keeps_its_first_sample(tmp_path):
    t, x = motion(50)
    f = tmp_path / "bom.csv"
    f.write_bytes(b"\xef\xbb\xbf" + "\n".join(f"{a},{b}" for a, b in zip(t, x[:, 0])).encode())
    out = tmp_path / "o.json"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.001", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "50 samples" in res.output


def test_tum_finds_its_quaternion_and_writes_glb(tmp_path):
    t, x = motion()
    q = quats(t)
    f = tmp_path / "gt.txt"
    np.savetxt(f, np.c_[t + 1.3e9, x, q], header="timestamp tx ty tz qx qy qz qw")
    out = tmp_path / "cam.glb"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.005", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "TUM trajectory" in res.output and "rotation (quaternion, qx, qy, qz, qw)" in res.output
    assert out.read_bytes()[:4] == b"glTF"
    doc = gl.GLTF2.load_from_bytes(out.read_bytes())
    assert {c.target.path for c in doc.animations[0].channels} == {"translation", "rotation"}
    assert "from the first sample, at 1.3e+09 s" in res.output
    # what a viewer plays: valid, and within tolerance of every sample (float32 keys)
    (report,) = validate(out)
    assert report["numErrors"] == 0, report["messages"][:3]
    assert "glTF keeps float32 times" in res.output                   # the clock starts at 0 there
    assert np.abs(played(out, "path", "translation", t) - x).max() <= 0.005
    angle = np.degrees(rotation_angle(played(out, "path", "rotation", t), q))
    assert angle.max() <= 0.5 * (1 + KEY_SHARE) + 1e-3


def test_keys_frames_and_compact_write_a_glb_of_linear_keys(tmp_path):
    t, x = motion()
    f = tmp_path / "gt.txt"
    np.savetxt(f, np.c_[t + 1.3e9, x, quats(t)], header="timestamp tx ty tz qx qy qz qw")
    sizes = {}
    for keys in ("curves", "frames", "compact"):
        out = tmp_path / f"cam.{keys}.glb"
        res = runner.invoke(app, ["reduce", str(f), "--tol", "0.005", "-o", str(out), "--keys", keys])
        assert res.exit_code == 0, res.output
        assert ("LINEAR keys" in res.output) == (keys != "curves") and "glTF keeps float32 times" in res.output
        doc = gl.GLTF2.load_from_bytes(out.read_bytes())
        kinds = {doc.animations[0].samplers[c.sampler].interpolation for c in doc.animations[0].channels}
        assert kinds == ({"CUBICSPLINE"} if keys == "curves" else {"LINEAR"})
        assert ("EXT_meshopt_compression" in (doc.extensionsRequired or [])) == (keys == "compact")
        sizes[keys] = out.stat().st_size
    assert sizes["compact"] < sizes["frames"]


def test_scalar_first_quaternions_play_in_glb_and_euler_curves_are_refused(tmp_path):
    t, x = motion()
    q = quats(t)
    f = tmp_path / "wxyz.csv"
    np.savetxt(f, np.c_[t, x, q[:, [3, 0, 1, 2]]], delimiter=",", header="t,x,y,z,qw,qx,qy,qz", comments="")
    out = tmp_path / "p.glb"
    args = ["reduce", str(f), "--tol", "0.005", "--rot-cols", "qw,qx,qy,qz", "--scalar-first"]
    res = runner.invoke(app, [*args, "-o", str(out)])
    assert res.exit_code == 0, res.output
    angle = np.degrees(rotation_angle(played(out, "path", "rotation", t), q))     # glTF plays x, y, z, w
    assert angle.max() <= 0.5 * (1 + KEY_SHARE) + 1e-3
    euler = tmp_path / "e.glb"
    refused(runner.invoke(app, [*args, "--rot-mode", "euler", "-o", str(euler)]), "--rot-mode euler", ".glb")
    assert not euler.exists()


def test_svc_and_kitti(tmp_path):
    t, x = motion(300)
    svc = tmp_path / "pen.svc"
    rows = np.c_[1000 * x[:, 0], 1000 * x[:, 1], np.round(t * 1000) + 5000, np.ones_like(t), 0 * t, 0 * t, 500 + t]
    svc.write_text(f"{len(t)}\n" + "\n".join(" ".join(f"{v:.0f}" for v in r) for r in rows) + "\n")
    res = runner.invoke(app, ["reduce", str(svc), "--tol", "2", "--cols", "x,y"])
    assert res.exit_code == 0, res.output
    assert "Wacom SVC" in res.output and "read as ms" in res.output
    kitti = tmp_path / "poses.txt"
    m = Rotation.from_quat(quats(t)).as_matrix()
    np.savetxt(kitti, np.concatenate([m, x[:, :, None]], axis=2).reshape(len(t), 12))
    out = tmp_path / "k.json"
    res = runner.invoke(app, ["reduce", str(kitti), "--tol", "0.01", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "KITTI" in res.output and "10 Hz" in res.output
    assert within(reduced_at(out, np.arange(len(t)) / 10.0), x, 0.01, slack=1e-9)
    assert (tmp_path / "k.rotation.json").exists()


def test_nanosecond_times_are_recognised_and_counters_refused(tmp_path):
    t, x = motion()
    f = tmp_path / "ns.csv"
    np.savetxt(f, np.c_[np.round(1.7e18 + t * 1e9), x], delimiter=",", fmt="%.0f,%.9f,%.9f,%.9f")
    out = tmp_path / "o.json"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "nanoseconds since 1970" in res.output
    r = Reduction.from_json(out.read_text())
    assert abs(r.spline.t[-1] - r.spline.t[0] - 4.0) < 1e-5          # seconds, origin kept
    assert r.spline.t[0] > 1e9
    counter = tmp_path / "frames.csv"
    np.savetxt(counter, np.c_[np.arange(5000, 5000 + len(t)), x], delimiter=",")
    res = runner.invoke(app, ["reduce", str(counter), "--tol", "0.01", "-o", str(tmp_path / "c.json")])
    refused(res, str(counter), "whole numbers", "--rate")
    assert not (tmp_path / "c.json").exists()
    res = runner.invoke(app, ["reduce", str(counter), "--tol", "0.01", "--rate", "100"])
    assert res.exit_code == 0 and "frame numbers at 100 Hz" in res.output


def test_gap_is_reported_and_bridged(tmp_path):
    t, x = motion()
    t = np.where(t > 2, t + 12, t)
    f = tmp_path / "gap.csv"
    np.savetxt(f, np.c_[t, x], delimiter=",")
    out = tmp_path / "g.json"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.001", "-o", str(out), "--plot", str(tmp_path / "g.svg")])
    assert res.exit_code == 0, res.output
    assert "gap 1.995-14.005 s" in res.output
    r = Reduction.from_json(out.read_text())
    inside = r.spline(np.linspace(1.996, 14.004, 200))
    cut = np.searchsorted(t, 2.0, side="right")
    lo, hi = np.minimum(x[cut - 1], x[cut]) - 0.001, np.maximum(x[cut - 1], x[cut]) + 0.001
    assert np.all((inside >= lo) & (inside <= hi))
    assert (tmp_path / "g.svg").read_text().lstrip().startswith("<?xml")


@pytest.mark.parametrize(("rows", "option", "count"), [
    ("0,1\n1,2\n1,3\n2,4\n3,5\n", ["--duplicates", "mean"], "merged 1"),
    ("0,1\n2,2\n1,3\n3,4\n4,5\n", ["--unordered", "sort"], "sorted 1"),
    ("0,1\n2,2\n1,3\n3,4\n4,5\n", ["--unordered", "drop"], "dropped 1"),
])
def test_quirks_are_choices(tmp_path, rows, option, count):
    f = tmp_path / "q.csv"
    f.write_text(rows)
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01"])
    refused(res, str(f), "line", option[0])
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", *option])
    assert res.exit_code == 0, res.output
    assert count in res.output


def test_text_column_named_and_cols_and_groups(tmp_path):
    t, x = motion()
    f = tmp_path / "mixed.csv"
    f.write_text("t,x,y,label,pressure\n" + "".join(f"{a},{b},{c},tap,{d}\n" for a, b, c, d in
                                                    zip(t, x[:, 0], x[:, 1], x[:, 2] + 0.01 * np.sin(90 * t))))
    refused(runner.invoke(app, ["reduce", str(f), "--tol", "0.01"]), str(f), "line 2", "column 4", "--cols")
    out = tmp_path / "o.json"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01,0.01,0.001", "--cols", "x,y,p=pressure",
                              "--groups", "x,y:p", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert within(reduced_at(out, t), x[:, :2], 0.01, slack=1e-9)
    assert within(reduced_at(tmp_path / "o.p.json", t), (x[:, 2] + 0.01 * np.sin(90 * t))[:, None], 0.001, slack=1e-9)
    ours = Reduction.from_json(out.read_text()).n_coefficients
    together = tmp_path / "t.json"
    assert runner.invoke(app, ["reduce", str(f), "--tol", "0.01,0.01,0.001", "--cols", "x,y,pressure",
                               "-o", str(together)]).exit_code == 0
    assert ours < Reduction.from_json(together.read_text()).n_coefficients / 3   # x, y: not the noise's knots


@pytest.mark.parametrize(("args", "words"), [
    (["-o", "{d}/x.fbx"], ["-o", ".json", ".glb", ".usda"]),
    (["-o", "{d}/x.bvh"], ["-o", ".json", ".glb"]),
    (["--plot", "{d}/x.xyz"], ["--plot", ".png"]),
    (["-o", "{d}/x.glb", "--order", "6"], ["--order", "glTF"]),
    (["--order", "60"], ["--order", "2 to 8", "60"]),
    (["--order", "1"], ["--order", "2 to 8"]),
    (["--method", "incremental", "--window", "100000000"], ["--window", "4 to 1000"]),
    (["--rate", "0"], ["--rate", "above 0", "got 0"]),
    (["--rate", "-30"], ["--rate", "got -30"]),
    (["--rate", "1e9"], ["--rate", "at most 1000000", "got 1e+09"]),
    (["--tol", "0"], ["--tol", "got 0"]),
    (["--tol", "nan"], ["--tol"]),
    (["--world"], ["--world", "not for a sample table"]),
    (["--units", "cm"], ["--units", "not for a sample table"]),
    (["--method", "sideways"], ["--method", "global or incremental"]),
    (["--duplicates", "last"], ["--duplicates", "error, first, mean"]),
    (["--time-unit", "h"], ["--time-unit", "s, ms, us, ns"]),
    (["--gap", "0.5"], ["--gap"]),
    (["-o", "{d}/x.json", "--keys", "compact"], ["--keys: compact files are .glb, not .json"]),
    (["-o", "{d}/x.usda", "--keys", "frames"], ["--keys: frames files are .glb, not .usda"]),
    (["-o", "{d}/x.glb", "--keys", "bezier"], ["--keys", "curves, frames, compact", "'bezier'"]),
])
def test_bad_arguments_are_refused_before_any_work(tmp_path, args, words):
    t, x = motion(50)
    f = tmp_path / "s.csv"
    np.savetxt(f, np.c_[t, x], delimiter=",")
    args = [a.format(d=tmp_path) for a in args]
    base = ["reduce", str(f)] + ([] if "--tol" in args else ["--tol", "0.01"])
    res = runner.invoke(app, base + args)
    refused(res, *words)
    assert "np.float64" not in res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.csv"]      # nothing written


def test_output_or_plot_that_is_the_input_is_refused(tmp_path):
    t, x = motion(50)
    f = tmp_path / "s.json"
    f.write_text(json.dumps({"t": t.tolist(), "x": x[:, 0].tolist()}))
    before = f.read_text()
    refused(runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "-o", str(f)]), "is the input")
    c = tmp_path / "s.csv"
    np.savetxt(c, np.c_[t, x], delimiter=",")
    kept = c.read_text()
    refused(runner.invoke(app, ["reduce", str(c), "--tol", "0.01", "-o", str(c)]), "-o", "is the input")
    refused(runner.invoke(app, ["reduce", str(c), "--tol", "0.01", "--plot", str(c)]), "--plot", "is the input")
    assert f.read_text() == before and c.read_text() == kept


def test_clip_refuses_table_options(tmp_path):
    bvh = Path(__file__).resolve().parents[1] / "no.bvh"
    for args, word in ((["--plot", "x.png"], "--plot"), (["--method", "incremental"], "--method")):
        refused(runner.invoke(app, ["reduce", str(bvh), *args]), word, "not for a clip")
    refused(runner.invoke(app, ["reduce", str(bvh), "--order", "6"]), "--order", "order 2, 3 or 4")


def test_output_folder_for_one_input(tmp_path):
    t, x = motion(80)
    f = tmp_path / "take.csv"
    np.savetxt(f, np.c_[t, x], delimiter=",")
    folder = tmp_path / "out"
    folder.mkdir()
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "-o", str(folder)])
    assert res.exit_code == 0, res.output
    assert within(reduced_at(folder / "take.json", t), x, 0.01, slack=1e-9)


def test_version():
    res = runner.invoke(app, ["--version"])
    assert res.exit_code == 0 and res.output.startswith("sketchanim ")


def test_json_that_is_not_a_sample_stream_says_what_was_expected(tmp_path):
    t, x = motion(40)
    src = tmp_path / "s.csv"
    np.savetxt(src, np.c_[t, x], delimiter=",")
    spline = tmp_path / "spline.json"
    assert runner.invoke(app, ["reduce", str(src), "--tol", "0.01", "-o", str(spline)]).exit_code == 0
    res = runner.invoke(app, ["reduce", str(spline), "--tol", "0.01"])
    refused(res, str(spline), "not a sample stream", "'t' or 'time'", "an object with fields")


@pytest.mark.realdata
def test_unreachable_scheduler_is_a_named_error(data_dir, tmp_path):
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "a.bvh").write_bytes((data_dir / "bvh" / "bandai1_dash_normal_001.bvh").read_bytes())
    res = runner.invoke(app, ["reduce", str(lib), "-o", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:1"])
    refused(res, "--scheduler", "cannot reach a Dask scheduler at tcp://127.0.0.1:1")


def test_outputs_get_the_umask_mode(tmp_path):
    import os

    t, x = motion(40)
    f = tmp_path / "s.csv"
    np.savetxt(f, np.c_[t, x], delimiter=",")
    old = os.umask(0o027)
    try:
        assert runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "-o", str(tmp_path / "o.json")]).exit_code == 0
    finally:
        os.umask(old)
    assert (tmp_path / "o.json").stat().st_mode & 0o777 == 0o640


def test_euroc_ground_truth(tmp_path):
    t, x = motion(300)
    q = quats(t)                                            # x, y, z, w
    names = ["#timestamp", "p_RS_R_x [m]", "p_RS_R_y [m]", "p_RS_R_z [m]", "q_RS_w []", "q_RS_x []", "q_RS_y []",
             "q_RS_z []", "v_RS_R_x [m s^-1]"]
    f = tmp_path / "data.csv"
    rows = np.c_[np.round(1.403636579763555e18 + t * 1e9), x, q[:, [3, 0, 1, 2]], 0 * t]
    f.write_text(",".join(names) + "\n" + "".join(
        f"{int(r[0])}," + ",".join(f"{v:.9f}" for v in r[1:]) + "\n" for r in rows))
    out = tmp_path / "body.json"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.001", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "EuRoC" in res.output and "left out v_RS_R_x" in res.output and "nanoseconds since 1970" in res.output
    r = Reduction.from_json(out.read_text())
    assert np.all(np.abs(r.spline(r.spline.t[0] + t) - x) <= 0.001 + 1e-9)
    rot = Reduction.from_json((tmp_path / "body.rotation.json").read_text())
    got = rot.spline(rot.spline.t[0] + t)
    angle = Rotation.from_quat(got / np.linalg.norm(got, axis=1, keepdims=True)).inv() * Rotation.from_quat(q)
    assert np.degrees(angle.magnitude()).max() <= 0.5 + 1e-6


@pytest.mark.parametrize("order", [2, 3, 4])
def test_path_with_a_gap_to_glb_plays_within_tolerance(tmp_path, order):
    t, x = motion(300)
    t = np.where(t > 2, t + 5, t)
    f = tmp_path / "xy.csv"
    np.savetxt(f, np.c_[t, x[:, :2]], delimiter=",", header="t,x,y", comments="")
    out = tmp_path / "xy.glb"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.002", "--order", str(order), "-o", str(out)])
    assert res.exit_code == 0, res.output
    (report,) = validate(out)
    assert report["numErrors"] == 0, report["messages"][:3]
    if order > 2:
        got = played(out, "path", "translation", t)
        assert np.abs(got[:, :2] - x[:, :2]).max() <= 0.002 + 1e-5 and np.all(got[:, 2] == 0)


def test_plot_of_an_orientation_only_take_is_refused(tmp_path):
    t, _ = motion(100)
    f = tmp_path / "imu.csv"
    np.savetxt(f, np.c_[t, quats(t)], delimiter=",", header="t,qx,qy,qz,qw", comments="")
    res = runner.invoke(app, ["reduce", str(f), "--rot-cols", "qx,qy,qz,qw", "--plot", str(tmp_path / "p.png")])
    refused(res, "--plot", "only an orientation")
    assert not (tmp_path / "p.png").exists()


def test_help_has_examples_choices_and_limits():
    res = runner.invoke(app, ["reduce", "--help"], env={"COLUMNS": "200"})
    assert res.exit_code == 0
    for text in ("Examples:", "global or incremental", "paper or lm", "2 to 8", "4 to 1000", "error, first, mean",
                 "error, drop, sort", "s, ms, us, ns", "tum, svc, euroc, kitti"):
        assert text in res.output, text
    assert "<bool>" not in res.output.split("--help")[0]              # flags show no type (typer's own --help does)
    for command in ("export", "paper"):
        assert "Example" in runner.invoke(app, [command, "--help"], env={"COLUMNS": "200"}).output


@pytest.mark.parametrize(("name", "data", "words"), [
    ("empty.csv", b"", ["has no samples"]),
    ("blank.csv", b"\n\n\n", ["has no samples"]),
    ("bom.csv", b"\xef\xbb\xbf", ["has no samples"]),
    ("random.csv", bytes(range(128, 256)) * 8, ["is not UTF-8 text"]),
    ("ragged.txt", b"t x y\n0 1 2\n1 2\n", ["line 3", "2 columns, expected 3"]),
    ("mixed.txt", b"0 1\n1\t2\n2,3\n", ["line 1", "header names 1 columns"]),
    ("short.svc", b"5\n1 2 3\n", ["line 1", "says 5 samples", "holds 1"]),
    ("huge.csv", b"t,x\n0,1e400\n1,2\n", ["line 2", "column 2 is '1e400'"]),
    ("one.csv", b"0\n1\n2\n", ["line 1", "needs a time column and at least one channel"]),
])
def test_malformed_tables_are_named_errors(tmp_path, name, data, words):
    f = tmp_path / name
    f.write_bytes(data)
    out = tmp_path / "o.json"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.1", "-o", str(out)])
    refused(res, str(f), *words)
    assert not out.exists()


def test_column_options_a_format_fixes_are_refused(tmp_path):
    t, x = motion(50)
    f = tmp_path / "gt.txt"
    np.savetxt(f, np.c_[t, x, quats(t)])
    refused(runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "--cols", "tx"]), "--cols", "tum")
    refused(runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "--time-col", "1"]), "--time-col", "tum")


def test_library_errors_name_fields_and_the_cli_tells_them_as_flags(tmp_path):
    t, x = motion(60)
    f = tmp_path / "s.csv"
    np.savetxt(f, np.c_[t, x], delimiter=",", header="t,x,y,z", comments="")
    tum = tmp_path / "gt.txt"
    np.savetxt(tum, np.c_[t, x, quats(t)], header="timestamp tx ty tz qx qy qz qw")
    for source, args, words in (
            (f, ["--groups", "x,q"], ["--groups: 'q' is not a channel"]),
            (f, ["--groups", "x:x"], ["--groups: 'x' is in two groups"]),
            (f, ["--tol", "0.1,0.1"], ["--tol: needs 1 or 3 values"]),
            (f, ["--rot-cols", "x,y"], ["--rot-cols: needs 4 distinct columns"]),
            (tum, ["--cols", "tx"], ["--cols:", "whose channels are fixed", "--cols applies to"]),
            (tum, ["--time-col", "1"], ["--time-col:", "whose time column is fixed"]),
            (f, ["--rate", "30", "--time-unit", "ms"], ["--rate (times are frame numbers) or --time-unit, not both"])):
        res = runner.invoke(app, ["reduce", str(source), *(["--tol", "0.1"] if "--tol" not in args else []), *args])
        refused(res, *words)
        assert "cols=" not in res.output and "rate=" not in res.output


@given(st.floats(0.0, GLB_CLOCK - 10), st.floats(2e-5, 2e-3), st.floats(0.0, 200.0))
@settings(max_examples=12, deadline=None)
def test_a_fast_start_late_in_a_take_plays_in_float32_within_tol_or_is_refused(tmp_path_factory, offset, tol, jump):
    """A path whose first step jumps at ``jump`` per s (a capture starting from its rest
    pose), then moves at a few per s, ``offset`` s into a recording (the clock kept): what
    a float32 client plays from the .glb is within --tol at every sample, or --tol is
    refused and nothing is written. Each sample's float32 margin comes from the speed
    around it, so the jump at the start does not count late in the take."""
    folder = tmp_path_factory.mktemp("fast")
    t, x = motion()
    x[0, 0] = x[1, 0] + jump * (t[1] - t[0])
    f, out = folder / "path.txt", folder / "path.glb"
    np.savetxt(f, np.c_[t + offset, x], header="timestamp tx ty tz", fmt="%.17g")
    res = runner.invoke(app, ["reduce", str(f), "--tol", repr(tol), "-o", str(out)])
    if res.exit_code == 2:
        refused(res, "--tol:", "is less than twice what float32 may move it")
        assert not out.exists()
        event("refused")
        return
    assert res.exit_code == 0, res.output
    times = np.loadtxt(f)[:, 0]                  # as the file was read
    assert np.abs(played(out, "path", "translation", times) - x).max() <= tol


def test_a_jump_into_the_first_sample_costs_no_margin_a_minute_later(tmp_path):
    """A minute-long path at 50 Hz whose first step jumps at 200 per s (a capture starting
    from its rest pose): taken over the whole take, the jump's speed at its last time
    would leave float32 more than half of 0.002 (2^-24 x 4 x 200 x 60 s alone is 0.0029),
    but each sample's margin comes from the speed within a second of it, so the file is
    written, and plays within 0.002 of every sample in float32."""
    t = np.arange(3000) / 50
    x = np.c_[np.sin(2 * t), np.cos(3 * t), 0.05 * t]
    x[0, 0] = x[1, 0] + 200 / 50
    f, out = tmp_path / "jump.txt", tmp_path / "jump.glb"
    np.savetxt(f, np.c_[t, x], header="timestamp tx ty tz", fmt="%.17g")
    assert float32_margin(t, float(np.linalg.norm(x, axis=1).max()), 200.0) > 0.002 / 2
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.002", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert np.abs(played(out, "path", "translation", np.loadtxt(f)[:, 0]) - x).max() <= 0.002


@pytest.mark.parametrize("keys", ["frames", "compact"])
def test_a_tolerance_float32_cannot_keep_late_in_a_take_is_refused_and_nothing_is_written(tmp_path, keys):
    """Eight minutes into a recording (the clock kept: under GLB_CLOCK), float32 key
    times alone move a point moving 3 per s by more than half of 0.0001."""
    t, x = motion()
    f = tmp_path / "late.txt"
    np.savetxt(f, np.c_[t + 480.0, x, quats(t)], header="timestamp tx ty tz qx qy qz qw")
    out = tmp_path / "late.glb"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.0001", "-o", str(out), "--keys", keys])
    refused(res, "--tol: 0.0001 for track 'path.position' is less than twice what float32 may move it",
            "ask for a larger tolerance, or start the times nearer 0")
    assert len([line for line in res.output.splitlines() if line.startswith("error:")]) == 1
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["late.txt"]
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "--rot-tol-deg", "1e-5", "-o", str(out),
                              "--keys", keys])
    refused(res, "--rot-tol-deg: 1e-05 degrees for track 'path.orientation' is less than twice", "nearer 0")
    assert not out.exists()
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "-o", str(out), "--keys", keys])
    assert res.exit_code == 0, res.output                 # a tolerance float32 leaves room for: written
    assert out.read_bytes()[:4] == b"glTF"
