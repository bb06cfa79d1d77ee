"""A sample table as a .glb of LINEAR keys (``TableOptions(keys="frames")``, ``"compact"``):
written, valid, and played from the decoded file in float32 (as glTF plays, as Blender's
F-curves do, and by three.js) within the table's tolerance, per channel, at every sample; the
refusals (a compact or frames file that is not a .glb, a keys value that is not one)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from clips import linear_play32, samplers, validate
from threejs_client import three_play
from tolerance import max_error
from sketchanim.errors import ArgumentError
from sketchanim.pipeline import TableOptions, TableReduction, reduce_table


def write_table(path: Path, t: np.ndarray, x: np.ndarray, q: np.ndarray | None = None,
                scalar_first: bool = False) -> Path:
    """A CSV of times, position columns (x, y[, z]) and, given ``q`` (scalar-last), a
    quaternion (qx, qy, qz, qw; qw first with ``scalar_first``)."""
    names = ["t", *"xyz"[:x.shape[1]]]
    columns = [t[:, None], x]
    if q is not None:
        order = [3, 0, 1, 2] if scalar_first else [0, 1, 2, 3]
        names += [("qx", "qy", "qz", "qw")[i] for i in order]
        columns.append(q[:, order])
    np.savetxt(path, np.hstack(columns), delimiter=",", header=",".join(names), comments="")
    return path


def played_errors(path: Path, result: TableReduction, scalar_first: bool = False,
                  spherical: bool = True) -> tuple[np.ndarray, float]:
    """The largest error per position channel, and of the orientation in degrees (0
    without one), of the .glb at ``path`` played in float32 at every sample of the
    table it was written from (its times from the first sample where the file says so);
    rotations spherically, or component-wise (``spherical=False``) as the Blender add-on
    plays them, its keys put on one hemisphere first."""
    table = result.table
    assert table is not None
    origin = result.span[0] if abs(result.span[1]) >= 1000 else 0.0
    channels = samplers(path)
    position = np.zeros(0)
    if result.parts:
        kind, times, keys = channels[("path", "translation")]
        assert kind == "LINEAR"
        got = linear_play32(times, keys, table.times - origin, False).astype(float)
        part = result.parts[0]
        position = max_error(got[:, :len(part)], table.values[:, part])
        if len(part) == 2:
            assert np.all(got[:, 2] == 0.0)                         # a plane's path at z = 0
    angle = 0.0
    if result.rotation_columns:
        kind, times, keys = channels[("path", "rotation")]
        assert kind == "LINEAR"
        if not spherical:                          # each key on the side of the one before, as the add-on puts them
            flips = np.cumsum(np.r_[0, np.sum(keys[1:] * keys[:-1], axis=1) < 0]) % 2
            keys = np.where(flips[:, None] == 1, -keys, keys)
        got = linear_play32(times, keys, table.times - origin, True, spherical).astype(float)
        q = table.values[:, list(result.rotation_columns)]
        angle = float(max_error(got, q[:, [1, 2, 3, 0]] if scalar_first else q, rotation=True)[0])
    return position, angle


def motion(n: int = 400, start: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = start + np.linspace(0, 4, n)
    s = t - start
    return t, np.c_[np.sin(2 * s), np.cos(3 * s), 0.5 * s], Rotation.from_rotvec(
        np.c_[np.sin(s), 0.5 * s, 0 * s]).as_quat()


@pytest.mark.parametrize("keys", ["compact", "frames"])
def test_a_table_written_with_keys_is_valid_and_plays_within_tolerance_at_every_sample(tmp_path, keys) -> None:
    t, x, q = motion(start=1.3e9)                                   # a wall clock: the file starts at zero
    source = write_table(tmp_path / "cam.csv", t, x, q)
    out = tmp_path / "cam.glb"
    result = reduce_table(source, TableOptions(tol=0.005, rot_tol_deg=0.5, rot_cols="qx,qy,qz,qw", keys=keys),
                          output=out)
    assert [w.path for w in result.written] == [out] and "LINEAR keys" in result.written[0].note
    (report,) = validate(out)
    assert report["numErrors"] == 0 and report["numWarnings"] == 0, report["messages"][:3]
    for spherical in (True, False):                                  # glTF's slerp, Blender's F-curves
        position, angle = played_errors(out, result, spherical=spherical)
        assert np.all(position <= 0.005) and angle <= 0.5, (position, angle)
    node = three_play(out, t - t[0])["path"]                         # three.js, its meshopt decoder
    assert np.all(max_error(node["position"], x) <= 0.005)
    assert max_error(node["quaternion"], q, rotation=True)[0] <= 0.5
    if keys == "compact":
        assert b"EXT_meshopt_compression" in out.read_bytes()
        frames = tmp_path / "cam.frames.glb"
        reduce_table(source, TableOptions(tol=0.005, rot_cols="qx,qy,qz,qw", keys="frames"), output=frames)
        assert out.stat().st_size < frames.stat().st_size / 1.5


def test_a_real_camera_path_plays_within_tolerance_from_the_smallest_file(data_dir: Path, tmp_path: Path) -> None:
    source = data_dir / "camera" / "freiburg1_xyz-groundtruth.txt"
    sizes = {}
    for keys in ("curves", "compact"):
        out = tmp_path / f"cam.{keys}.glb"
        result = reduce_table(source, TableOptions(tol=0.005, keys=keys), output=out)
        sizes[keys] = out.stat().st_size
    position, angle = played_errors(out, result)
    assert np.all(position <= 0.005) and angle <= 0.5, (position, angle)
    assert sizes["compact"] < sizes["curves"] / 2, sizes


def test_compact_keys_hold_each_channel_to_its_own_tolerance_and_read_a_streamed_table_whole(tmp_path) -> None:
    t, x, _ = motion()
    source = write_table(tmp_path / "xyz.csv", t, x)
    out = tmp_path / "xyz.glb"
    tol = (0.01, 0.001, 0.004)
    result = reduce_table(source, TableOptions(tol=tol, method="incremental", keys="compact"), output=out)
    assert not result.streamed                                       # its keys are picked from every sample
    position, _ = played_errors(out, result)
    assert np.all(position <= np.array(tol)), position


def test_frames_and_compact_take_any_order_but_curves_only_gltfs(tmp_path) -> None:
    t, x, _ = motion(200)
    source = write_table(tmp_path / "xy.csv", t, x[:, :2])
    for keys in ("frames", "compact"):
        out = tmp_path / f"{keys}.glb"
        result = reduce_table(source, TableOptions(tol=0.002, order=6, keys=keys), output=out)
        position, _ = played_errors(out, result)
        assert np.all(position <= 0.002), (keys, position)
    with pytest.raises(ArgumentError, match="order: glTF plays orders 2 to 4"):
        reduce_table(source, TableOptions(tol=0.002, order=6), output=tmp_path / "curves.glb")


@pytest.mark.parametrize("output", ["o.json", "o.usda", "folder"])
def test_keys_other_than_curves_are_a_glbs_and_refused_before_any_work(tmp_path, output) -> None:
    t, x, _ = motion(50)
    source = write_table(tmp_path / "s.csv", t, x)
    if output == "folder":
        (tmp_path / output).mkdir()                                  # written into as STEM.json
    for keys in ("compact", "frames"):
        with pytest.raises(ArgumentError, match=f"keys: {keys} files are .glb, not .(json|usda)") as caught:
            reduce_table(source, TableOptions(tol=0.01, keys=keys), output=tmp_path / output)
        assert caught.value.argument == "keys" and "--" not in str(caught.value)
    assert sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*")) == sorted(
        ["s.csv"] + (["folder"] if output == "folder" else []))
    with pytest.raises(ArgumentError, match="keys: one of curves, frames, compact, got 'bezier'"):
        TableOptions(tol=0.01, keys="bezier")


def test_compact_keys_refuse_a_tolerance_finer_than_their_most_bits_hold(tmp_path) -> None:
    """Far from the origin float32 itself rounds the values by more than half of the
    tolerance: refused for that (before the compact keys' own bits), naming ``tol``."""
    t, x, _ = motion(100)
    source = write_table(tmp_path / "far.csv", t, x[:, :2] + [1e5, 2e5])     # float32 steps of 8 mm there
    with pytest.raises(ArgumentError, match=r"^tol: 0.001 for track 'path.position' is less than twice what float32 "
                                            r"may move it \(.*points up to 2.236e\+05 from the origin.*\): ask for a "
                                            r"larger tolerance$") as caught:
        reduce_table(source, TableOptions(tol=0.001, keys="compact"), output=tmp_path / "far.glb")
    assert caught.value.argument == "tol"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["far.csv"]


@st.composite
def tables(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """A table of 20 to 300 samples at 30 to 200 Hz with a little jitter in time,
    starting at 0, 100 s or a wall clock, at up to 100 m, its position 2 or 3 channels
    (some noise on them, up to the tolerance), and sometimes a quaternion turning up to a
    few times."""
    n = draw(st.integers(20, 300))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    start = draw(st.sampled_from([0.0, 100.0, 1.3e9]))
    t = np.sort(start + np.arange(n) / draw(st.sampled_from([30.0, 100.0, 200.0])) + rng.uniform(0, 1e-3, n))
    s = t - start

    def wave(amp: float, d: int) -> np.ndarray:
        return sum(rng.uniform(0, amp, d) * np.sin(rng.uniform(0.2, 3.0) * s[:, None] + rng.uniform(0, 6, d))
                   for _ in range(3))

    d = draw(st.sampled_from([2, 3]))
    x = wave(2.0, d) + draw(st.sampled_from([0.0, 100.0])) + rng.normal(0, draw(st.sampled_from([0.0, 1e-3])), (n, d))
    q = Rotation.from_rotvec(wave(draw(st.floats(0.1, 4.0)), 3)).as_quat() if draw(st.booleans()) else None
    return t, x, q


@settings(max_examples=10, deadline=None)
@given(tables(), st.sampled_from([(0.005, 0.5), (0.001, 0.1)]), st.sampled_from(["compact", "frames"]),
       st.sampled_from(["global", "incremental"]), st.booleans())
def test_random_tables_play_within_tolerance_at_every_sample(tmp_path_factory: pytest.TempPathFactory,
                                                             table: tuple[np.ndarray, np.ndarray, np.ndarray | None],
                                                             tols: tuple[float, float], keys: str, method: str,
                                                             scalar_first: bool) -> None:
    t, x, q = table
    tol, rot_tol = tols
    folder = tmp_path_factory.mktemp("table")
    source = write_table(folder / "s.csv", t, x, q, scalar_first)
    rot_cols = None if q is None else ("qw,qx,qy,qz" if scalar_first else "qx,qy,qz,qw")
    options = TableOptions(tol=tol, rot_tol_deg=rot_tol, rot_cols=rot_cols, scalar_first=scalar_first,
                           method=method, keys=keys)
    out = folder / "s.glb"
    result = reduce_table(source, options, output=out)
    (report,) = validate(out)
    assert report["numErrors"] == 0, report["messages"][:3]
    for spherical in (True, False):
        position, angle = played_errors(out, result, scalar_first, spherical)
        assert np.all(position <= tol) and angle <= rot_tol, (position, angle)
