"""`sketchanim reduce` end to end: report, JSON, plot, and errors that name file and line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from sketchanim.cli import app
from sketchanim.reducer import Reduction

from recordings import shared_cases

REPO = Path(__file__).resolve().parents[2]
runner = CliRunner()


def test_reduce_example_writes_json_and_plot(tmp_path):
    out, png = tmp_path / "take.json", tmp_path / "take.png"
    res = runner.invoke(app, ["reduce", str(REPO / "examples" / "sketched_path.csv"), "--tol", "0.01",
                              "-o", str(out), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "720 samples" in res.output and "max error" in res.output
    r = Reduction.from_json(out.read_text(), source=str(out))
    data = np.loadtxt(REPO / "examples" / "sketched_path.csv", delimiter=",", skiprows=1)
    assert np.all(np.abs(r.spline(data[:, 0]) - data[:, 1:]) <= 0.01)
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_per_channel_tolerances(tmp_path):
    csv = tmp_path / "s.csv"
    t = np.linspace(0, 2, 300)
    np.savetxt(csv, np.c_[t, np.sin(3 * t), 100 * np.cos(t)], delimiter=",")
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.001,0.5", "-o", str(tmp_path / "o.json")])
    assert res.exit_code == 0, res.output
    r = Reduction.from_json((tmp_path / "o.json").read_text())
    assert r.tol.tolist() == [0.001, 0.5]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("t,x\n0,1\n1,oops\n", "line 3: column 2 is not a number: 'oops'"),
        ("t,x\n0,1\n1,2,3\n", "line 3: 3 columns, expected 2"),
        ("t,x\n0,1\n2,2\n1,3\n", "line 4: time goes backwards (1 after 2)"),
        ("t,x\n0,1\n1,nan\n", "line 3: column 2 is 'nan'"),
        ("t,x\n", "has no samples"),
    ],
)
def test_bad_csv_is_named_by_file_and_line(tmp_path, text, message):
    csv = tmp_path / "bad.csv"
    csv.write_text(text)
    out = tmp_path / "out.json"
    out.write_text("previous result")
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.1", "-o", str(out)])
    assert res.exit_code == 2
    assert str(csv) in res.output and message in res.output
    assert "Traceback" not in res.output
    assert out.read_text() == "previous result"      # nothing saved is lost


def test_bad_tolerance_is_named(tmp_path):
    csv = tmp_path / "s.csv"
    csv.write_text("0,1\n1,2\n2,4\n")
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0"])
    assert res.exit_code == 2 and "--tol: each tolerance must be above 0 and at most 1e12, got 0" in res.output


def test_unwritable_output_is_reported(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    res = runner.invoke(app, ["reduce", str(REPO / "examples" / "sketched_path.csv"), "--tol", "0.01",
                              "-o", str(blocker / "out.json")])
    assert res.exit_code == 2 and "cannot write" in res.output and "Traceback" not in res.output


def test_brackets_in_messages_survive(tmp_path):
    csv = tmp_path / "s.csv"
    csv.write_text("t,x\n0,[bold]\n")
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.1"])
    assert res.exit_code == 2 and "'[bold]'" in res.output


def test_console_script_runs_on_a_real_recording(data_dir, tmp_path):
    name, t, pos, tol = shared_cases(data_dir)[0]
    csv = tmp_path / "camera.csv"
    np.savetxt(csv, np.c_[t, pos], delimiter=",", header="t,x,y,z", comments="", fmt="%.9g")
    exe = Path(sys.executable).with_name("sketchanim")
    done = subprocess.run([str(exe), "reduce", str(csv), "--tol", str(tol), "-o", str(tmp_path / "c.json"),
                           "--plot", str(tmp_path / "c.png")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    back = np.loadtxt(csv, delimiter=",", skiprows=1)
    r = Reduction.from_json((tmp_path / "c.json").read_text())
    assert np.all(np.abs(r.spline(back[:, 0]) - back[:, 1:]) <= tol)
    assert r.n_coefficients < len(back) / 10


def _pose_csv(tmp_path: Path, euler: bool = False) -> tuple[Path, np.ndarray, np.ndarray]:
    from scipy.spatial.transform import Rotation

    t = np.arange(480) / 120.0
    rot = Rotation.from_rotvec(np.c_[np.sin(t), t, 0.3 * np.cos(t)])
    cols = rot.as_euler("ZXY", degrees=True) if euler else rot.as_quat()
    names = "rz,rx,ry" if euler else "qx,qy,qz,qw"
    csv = tmp_path / "pose.csv"
    np.savetxt(csv, np.c_[t, np.sin(t), np.cos(t), cols], delimiter=",", header=f"t,x,y,{names}", comments="",
               fmt="%.12g")
    return csv, t, rot.as_quat()


@pytest.mark.parametrize("euler", [False, True])
def test_rotation_columns_are_reduced_within_the_angle(tmp_path, euler):
    from scipy.spatial.transform import Rotation

    csv, t, quats = _pose_csv(tmp_path, euler)
    out = tmp_path / "pose.json"
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.001", "--rot-cols", "rz,rx,ry" if euler else
                              "qx,qy,qz,qw", "--rot-tol-deg", "0.2", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "rotation (degrees)" in res.output
    position = Reduction.from_json(out.read_text())
    rotation = Reduction.from_json((tmp_path / "pose.rotation.json").read_text())
    assert position.spline(t).shape == (len(t), 2) and rotation.metric == "rotation"
    curve = rotation.spline(t)
    err = (Rotation.from_quat(curve / np.linalg.norm(curve, axis=1)[:, None]).inv() * Rotation.from_quat(quats))
    assert np.degrees(err.magnitude()).max() <= 0.2


def test_rotation_column_errors_are_named(tmp_path):
    csv, _, _ = _pose_csv(tmp_path)
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.01", "--rot-cols", "qx,qy,qz,qq"])
    assert res.exit_code == 2 and "--rot-cols" in res.output and "qq not in the file" in res.output
    res = runner.invoke(app, ["reduce", str(csv), "--rot-cols", "qx,qy,qz,qw"])
    assert res.exit_code == 2 and "--tol: needed for x, y" in res.output
    lines = csv.read_text().splitlines()
    lines[10] = ",".join(lines[10].split(",")[:3] + ["0", "0", "0", "0"])
    csv.write_text("\n".join(lines) + "\n")
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.01", "--rot-cols", "qx,qy,qz,qw"])
    assert res.exit_code == 2 and "line 11" in res.output and "quaternion: has norm 0" in res.output
    assert "Traceback" not in res.output


def test_feature_switches_report_and_plot(tmp_path):
    csv, png = tmp_path / "stop.csv", tmp_path / "stop.png"
    t = np.arange(0, 3, 1 / 120)
    np.savetxt(csv, np.c_[t, np.where(t < 1, t, 1.0), np.where(t < 1, 2 * t, 2.0)], delimiter=",",
               header="t,x,y", comments="")
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.001", "--plot", str(png), "-o", str(tmp_path / "o.json")])
    assert res.exit_code == 0, res.output
    assert "features: pause 1.000-2.992 s" in res.output
    assert Reduction.from_json((tmp_path / "o.json").read_text()).features[0].kind == "pause"
    assert png.read_bytes()[:4] == b"\x89PNG"
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.001", "--no-pauses", "--no-breaks", "--gap", "0"])
    # no pause, no break: the corner where the motion stops is only bridged, so the curve does
    # not swing past the samples there
    assert res.exit_code == 0 and "features: gap 1.000-1.008 s" in res.output
    assert "pause" not in res.output and "break" not in res.output
    res = runner.invoke(app, ["reduce", str(csv), "--tol", "0.001", "--min-pause", "0"])
    assert res.exit_code == 2 and "--min-pause" in res.output


def test_a_clip_tolerance_float32_cannot_keep_is_refused_naming_the_joint(tmp_path):
    """A skeleton 90 units from the origin: float32 rounds its joints' world positions by
    more than half of 1e-6 units (its planted hand's share, or in the world), and its
    rotations by more than half of 1e-7 degrees, so no file can promise them: one line
    naming the flag and the joint, nothing written."""
    import re

    from scipy.spatial.transform import Rotation

    from sketchanim.formats.bvh import write_bvh
    from sketchanim.motion.skeleton import Clip, Skeleton

    s = Skeleton(("hips", "arm"), (-1, 0), np.array([[0.0, 90, 0], [30.0, 0, 0]]))
    t = np.arange(60) / 30
    clip = Clip.still(s, t)
    clip.rotations[:, 1] = Rotation.from_euler("Z", np.sin(3 * t)[:, None]).as_quat()
    source = write_bvh(tmp_path / "walk.bvh", clip)
    out = tmp_path / "walk.glb"
    for args, flag in ((["--tol", "1e-6"], "--tol"), (["--tol", "0.01", "--rot-tol-deg", "1e-7"], "--rot-tol-deg"),
                       (["--tol", "1e-6", "--world", "--units", "cm"], "--tol")):
        res = runner.invoke(app, ["reduce", str(source), *args, "-o", str(out)])
        assert res.exit_code == 2, res.output
        assert "Traceback" not in res.output and len(res.output.strip().splitlines()) == 1, res.output
        assert re.match(rf"error: {flag}: \S+ (degrees )?(in the world )?for joint '(hips|arm)'.* is less than "
                        r"twice what float32 may move it \(.*\): ask for a larger tolerance$", res.output.strip()), \
            res.output                          # times from 0: the values' size is the cause, not lateness
        assert not out.exists()
    res = runner.invoke(app, ["reduce", str(source), "--tol", "0.01", "-o", str(out)])
    assert res.exit_code == 0 and out.exists(), res.output


def test_export_of_a_project_whose_tolerance_float32_cannot_keep_is_refused_and_writes_nothing(tmp_path):
    from sketchanim.anim.attributes import POSITION
    from sketchanim.anim.layers import reduce_samples
    from sketchanim.anim.tracks import ContinuousTrack, Take
    from sketchanim.project.store import Project
    from sketchanim.studio.defaults import default_scene

    t = 600.0 + np.linspace(0, 2, 61)                    # ten minutes into the scene's time
    x = np.c_[np.sin(2 * t), 0.5 + 0 * t, np.cos(3 * t)]
    track = ContinuousTrack("box.position", POSITION, reduce_samples(POSITION, t, x, 1e-5, 4), 1e-5, (Take(t, x),))
    Project(tmp_path / "late.sketchanim").save(default_scene(), {"box.position": track})
    for keys in ("curves", "frames"):
        out = tmp_path / f"late.{keys}.glb"
        res = runner.invoke(app, ["export", str(tmp_path / "late.sketchanim"), "-o", str(out), "--keys", keys])
        assert res.exit_code == 2 and len(res.output.strip().splitlines()) == 1, res.output
        assert res.output.startswith("error: tolerance: 1e-05 for track 'box.position' is less than twice"), res.output
        assert "start the times nearer 0" in res.output and not out.exists()
