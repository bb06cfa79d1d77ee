"""`sketchanim reduce TABLE -o X.usda`: a sampled path and orientation as one animated
USD Xform, read back with pxr: every sample within --tol and --rot-tol-deg at every
source sample time, the clock and the rate kept; tables USD cannot take are refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from sketchanim.cli import app

pxr = pytest.importorskip("pxr")
from pxr import Usd, UsdGeom  # noqa: E402

runner = CliRunner()


def read_back(out: Path, times: np.ndarray) -> tuple[Usd.Stage, np.ndarray | None, np.ndarray | None]:
    """The stage, and /path's translate and orient (x, y, z, w) at ``times`` (seconds)."""
    stage = Usd.Stage.Open(str(out))
    rate = stage.GetTimeCodesPerSecond()
    prim = stage.GetPrimAtPath("/path")
    assert prim.IsValid() and UsdGeom.Xform(prim)
    got = []
    for name in ("xformOp:translate", "xformOp:orient"):
        attr = prim.GetAttribute(name)
        if not attr:
            got.append(None)
            continue
        values = [attr.Get(float(t) * rate) for t in times]
        if name.endswith("orient"):
            values = [(*q.GetImaginary(), q.GetReal()) for q in values]
        got.append(np.array([tuple(v) for v in values], dtype=float))
    return stage, got[0], got[1]


def angles_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees((Rotation.from_quat(a).inv() * Rotation.from_quat(b)).magnitude())


def tum_table(path: Path, t: np.ndarray, x: np.ndarray, q: np.ndarray) -> None:
    np.savetxt(path, np.c_[t, x, q], header="timestamp tx ty tz qx qy qz qw")


def test_tum_table_to_usda_within_tolerance_at_every_sample(tmp_path):
    t = np.linspace(0, 4, 400) + 1.3e9
    s = t - t[0]
    x = np.c_[np.sin(2 * s), np.cos(3 * s), 0.5 * s]
    q = Rotation.from_rotvec(np.c_[np.sin(s), 0.5 * s, 0 * s]).as_quat()
    f = tmp_path / "gt.txt"
    tum_table(f, t, x, q)
    out = tmp_path / "cam.usda"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.005", "--rot-tol-deg", "0.5", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "wrote" in res.output and "Xform" in res.output
    assert out.read_text().startswith("#usda")
    stage, pos, rot = read_back(out, t)
    assert np.abs(pos - x).max() <= 0.005 * (1 + 1e-9)
    assert angles_deg(rot, q).max() <= 0.5 + 1e-9
    rate = stage.GetTimeCodesPerSecond()
    assert rate == pytest.approx(1 / np.median(np.diff(t)), rel=1e-5)
    assert stage.GetStartTimeCode() == pytest.approx(t[0] * rate)      # the clock is kept (USD times are doubles)
    assert stage.GetEndTimeCode() == pytest.approx(t[-1] * rate)
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert stage.GetDefaultPrim().GetPath() == "/path"
    attr = stage.GetPrimAtPath("/path").GetAttribute("xformOp:orient")
    assert attr.GetTypeName() == "quatd"                              # double precision
    assert len(attr.GetTimeSamples()) == len(t)


@pytest.mark.parametrize("suffix", [".usd", ".usdc"])
def test_crate_outputs_and_rate(tmp_path, suffix):
    frames = np.arange(120.0)
    s = frames / 30
    x = np.c_[np.sin(s), np.cos(s), s]
    f = tmp_path / "p.csv"
    np.savetxt(f, np.c_[frames, x], delimiter=",", header="frame,x,y,z", comments="")
    out = tmp_path / ("p" + suffix)
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.001", "--rate", "30", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_bytes()[:8] == b"PXR-USDC"
    stage, pos, rot = read_back(out, s)
    assert stage.GetTimeCodesPerSecond() == 30 and stage.GetEndTimeCode() == 119  # time codes are the frames
    assert rot is None and np.abs(pos - x).max() <= 0.001 * (1 + 1e-9)


def test_position_only_2d_csv_lies_in_z_zero(tmp_path):
    t = np.linspace(0, 3, 200)
    x = np.c_[np.sin(3 * t), t ** 2]
    f = tmp_path / "pen.csv"
    np.savetxt(f, np.c_[t, x], delimiter=",", header="t,x,y", comments="")
    out = tmp_path / "pen.usda"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.002", "-o", str(out)])
    assert res.exit_code == 0, res.output
    _, pos, rot = read_back(out, t)
    assert rot is None
    assert np.abs(pos[:, :2] - x).max() <= 0.002 * (1 + 1e-9) and np.all(pos[:, 2] == 0)


def test_euler_and_scalar_first_orientations(tmp_path):
    t = np.linspace(0, 2, 150)
    r = Rotation.from_rotvec(np.c_[0.3 * t, np.sin(t), 0 * t])
    for name, cols, extra, bound in (
            ("e.csv", r.as_euler("ZXY", degrees=True), ["--rot-cols", "a,b,c"], 0.3),
            ("w.csv", r.as_quat(scalar_first=True), ["--rot-cols", "w,x,y,z", "--scalar-first"], 0.3),
            ("m.csv", r.as_quat(), ["--rot-cols", "x,y,z,w", "--rot-mode", "euler"], 3 * 0.3)):  # 0.3 per axis
        f = tmp_path / name
        header = "t," + ",".join(extra[1].split(","))
        np.savetxt(f, np.c_[t, cols], delimiter=",", header=header, comments="")
        out = tmp_path / (name + ".usda")
        res = runner.invoke(app, ["reduce", str(f), "--rot-tol-deg", "0.3", *extra, "-o", str(out)])
        assert res.exit_code == 0, res.output
        _, pos, rot = read_back(out, t)
        assert pos is None
        assert angles_deg(rot, r.as_quat()).max() <= bound + 1e-9, name


@pytest.mark.parametrize(("columns", "words"), [
    (1, ["-o", ".usda", "2 or 3 channels", "x"]),
    (4, ["-o", ".usda", "2 or 3 channels", "x, y, z, w2"]),
])
def test_tables_usd_cannot_take_are_refused(tmp_path, columns, words):
    t = np.linspace(0, 1, 50)
    names = ["x", "y", "z", "w2"][:columns]
    f = tmp_path / "s.csv"
    np.savetxt(f, np.c_[t, np.sin(np.outer(t, np.arange(1, columns + 1)))], delimiter=",",
               header="t," + ",".join(names), comments="")
    out = tmp_path / "s.usda"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "-o", str(out)])
    assert res.exit_code == 2, res.output
    assert "Traceback" not in res.output
    for w in words:
        assert w in res.output, res.output
    assert not out.exists() and list(tmp_path.iterdir()) == [f]


def test_groups_to_usd_are_refused(tmp_path):
    t = np.linspace(0, 1, 50)
    f = tmp_path / "s.csv"
    np.savetxt(f, np.c_[t, t, t ** 2, np.sin(t)], delimiter=",", header="t,x,y,p", comments="")
    out = tmp_path / "s.usd"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.01", "--groups", "x,y:p", "-o", str(out)])
    assert res.exit_code == 2 and "one animated node" in res.output, res.output
    assert not out.exists()


@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 2 ** 31 - 1), tol=st.sampled_from([1e-3, 1e-2, 0.1]),
       rot_tol=st.sampled_from([0.2, 1.0, 5.0]), n=st.integers(20, 200))
def test_any_motion_to_usda_keeps_both_tolerances(tmp_path_factory, seed, tol, rot_tol, n):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.005, 0.02, n)) + rng.uniform(-10, 10)
    x = np.cumsum(rng.normal(0, 0.02, (n, 3)), axis=0)
    q = Rotation.from_rotvec(np.cumsum(rng.normal(0, 0.05, (n, 3)), axis=0)).as_quat()
    d = tmp_path_factory.mktemp("any")
    f = d / "gt.txt"
    tum_table(f, t, x, q)
    out = d / "o.usda"
    res = runner.invoke(app, ["reduce", str(f), "--format", "tum", "--tol", str(tol), "--rot-tol-deg",
                              str(rot_tol), "-o", str(out)])
    assert res.exit_code == 0, res.output
    _, pos, rot = read_back(out, t)
    assert np.abs(pos - x).max() <= tol * (1 + 1e-9)
    assert angles_deg(rot, q).max() <= rot_tol + 1e-9


@pytest.mark.realdata
def test_freiburg_camera_to_usda(data_dir, tmp_path):
    f = data_dir / "camera" / "freiburg1_xyz-groundtruth.txt"
    raw = np.loadtxt(f)
    t, x, q = raw[:, 0], raw[:, 1:4], raw[:, 4:8]
    out = tmp_path / "cam.usda"
    res = runner.invoke(app, ["reduce", str(f), "--tol", "0.005", "--rot-tol-deg", "0.5", "-o", str(out)])
    assert res.exit_code == 0, res.output
    stage, pos, rot = read_back(out, t)
    assert len(stage.GetPrimAtPath("/path").GetAttribute("xformOp:translate").GetTimeSamples()) == len(t)
    assert np.abs(pos - x).max() <= 0.005 * (1 + 1e-9)
    assert angles_deg(rot, q / np.linalg.norm(q, axis=1, keepdims=True)).max() <= 0.5 + 1e-9
