"""C3D marker trajectories: read with their gaps, reduced piece by piece within the
distance at every seen sample, never across a gap; written to glTF (validated, played by
the spec's formulas) and JSON; malformed files refused with the file named."""

from __future__ import annotations

import csv
import random
import warnings
from pathlib import Path

import c3d
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from clips import hermite_play, samplers, validate
from sketchanim.mocap.markers import Markers, ReducedMarkers, reduce_markers
from sketchanim.cli import app
from sketchanim.errors import FileFormatError
from sketchanim.formats.c3d import read_c3d
from sketchanim.export.files import write_reduced


def write_c3d(path: Path, positions: np.ndarray, seen: np.ndarray, rate: float, labels: list[str],
              first_frame: int = 1) -> Path:
    """A C3D file (the ``c3d`` package's writer) of float positions (n, M, 3), markers
    unseen where ``seen`` (n, M) is False (residual -1)."""
    writer = c3d.Writer(point_rate=rate, point_units="mm  ")
    writer.set_point_labels(labels)
    writer.set_start_frame(first_frame)
    frames = []
    for i in range(len(positions)):
        points = np.zeros((positions.shape[1], 5), np.float32)
        points[:, :3] = positions[i]
        points[:, 3] = np.where(seen[i], 0.0, -1.0)
        frames.append((points, np.zeros((0, 0), np.float32)))
    writer.add_frames(frames)
    with warnings.catch_warnings(), path.open("wb") as handle:
        warnings.simplefilter("ignore")
        writer.write(handle)
    return path


@st.composite
def marker_takes(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray, float]:
    """1 to 4 markers moving smoothly (sums of sines, mm), 2 to 200 frames at a lab's
    rate, each lost over random gaps: from none to many, single frames seen between them
    included."""
    n = draw(st.integers(2, 200))
    m = draw(st.integers(1, 4))
    rate = draw(st.sampled_from([60.0, 100.0, 120.0, 250.0]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    t = np.arange(n) / rate
    freq = rng.uniform(0.1, 3.0, (3, m, 3))
    positions = sum(rng.uniform(10, 300, (m, 3)) * np.sin(2 * np.pi * f * t[:, None, None] + rng.uniform(0, 6, (m, 3)))
                    for f in freq) + rng.uniform(-1000, 1000, (m, 3))
    seen = np.ones((n, m), bool)
    for j in range(m):
        for _ in range(draw(st.integers(0, 6))):
            a = int(rng.integers(0, n))
            seen[a:a + int(rng.integers(1, 12)), j] = False
        if draw(st.booleans()):                       # flicker: single frames seen inside a gap
            seen[rng.integers(0, n, 5), j] = rng.random(5) < 0.5
    return positions, seen, rate


def _check_reduced(reduced: ReducedMarkers, markers: Markers, tol: float) -> None:
    """Every seen sample within ``tol``; nothing where the marker was not seen."""
    got = reduced.evaluate(markers.times)
    gaps = np.isnan(markers.positions[..., 0])
    assert np.array_equal(np.isnan(got[..., 0]), gaps)
    distance = np.linalg.norm(got - markers.positions, axis=2)[~gaps]
    assert distance.size == 0 or distance.max() <= tol * (1 + 1e-9)
    for m, name in enumerate(markers.names):
        assert len(reduced.tracks[f"{name}.position"].pieces) == len(markers.runs(m))


def _check_glb(path: Path, reduced: ReducedMarkers, markers: Markers) -> None:
    """The glTF translation, played by the spec's Hermite formula at every seen frame,
    is our curve; the STEP scale shows each marker exactly at the frames it was seen."""
    channels = samplers(path)
    gaps = np.isnan(markers.positions[..., 0])
    ours = reduced.evaluate(markers.times)
    for m, name in enumerate(markers.names):
        if not reduced.tracks[f"{name}.position"].pieces:
            assert (name, "translation") not in channels
            continue
        _, times, keys = channels[(name, "translation")]
        seen = ~gaps[:, m]
        played = hermite_play(times, keys, markers.times[seen])
        tangent = float(np.abs(keys[:, [0, 2]]).max())
        scale = max(1.0, float(np.abs(ours[seen, m]).max()), tangent * float(np.diff(times).max(initial=0.0)))
        assert np.abs(played - ours[seen, m]).max() <= 2e-6 * scale + tangent * 1e-6 * markers.times[-1]
        kind, step_times, shown = channels[(name, "scale")]
        assert kind == "STEP"
        held = shown[np.clip(np.searchsorted(step_times, markers.times, side="right") - 1, 0, None), 0]
        assert np.array_equal(held == 1.0, seen) and set(held) <= {0.0, 1.0}


@settings(max_examples=40, deadline=None)
@given(marker_takes(), st.sampled_from([0.5, 2.0, 5.0]))
def test_gaps_split_markers_into_pieces_within_tolerance(tmp_path_factory: pytest.TempPathFactory,
                                                         take: tuple[np.ndarray, np.ndarray, float], tol: float) -> None:
    positions, seen, rate = take
    folder = tmp_path_factory.mktemp("c3d")
    labels = [f"m{j}" for j in range(positions.shape[1])]
    markers = read_c3d(write_c3d(folder / "take.c3d", positions, seen, rate, labels))
    assert markers.names == tuple(labels) and markers.unit_m == 0.001
    assert np.allclose(markers.times, np.arange(len(positions)) / rate)
    assert np.array_equal(np.isnan(markers.positions[..., 0]), ~seen)
    assert np.array_equal(markers.positions[seen], positions.astype(np.float32)[seen])
    reduced = reduce_markers(markers, tol)
    _check_reduced(reduced, markers, tol)
    back = ReducedMarkers.from_json(write_reduced(folder / "take.json", reduced).read_text())
    assert np.array_equal(back.evaluate(markers.times), reduced.evaluate(markers.times), equal_nan=True)
    _check_glb(write_reduced(folder / "take.glb", reduced), reduced, markers)


def test_marker_glb_files_validate(tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    paths = []
    for k, (n, m) in enumerate([(2, 1), (50, 3), (300, 2)]):
        positions = np.cumsum(rng.normal(0, 2, (n, m, 3)), axis=0)
        seen = rng.random((n, m)) > 0.15
        if k == 2:
            seen[:, 1] = False                        # a marker never seen
        markers = read_c3d(write_c3d(tmp_path / f"{k}.c3d", positions, seen, 100.0, [f"p{j}" for j in range(m)]))
        reduced = reduce_markers(markers, 1.0)
        paths.append(write_reduced(tmp_path / f"{k}.glb", reduced))
        _check_glb(paths[-1], reduced, markers)
    for report in validate(*paths):
        assert report["numErrors"] == 0, report["messages"][:3]


def test_labels_and_start_frame(tmp_path: Path) -> None:
    positions = np.zeros((5, 3, 3))
    markers = read_c3d(write_c3d(tmp_path / "l.c3d", positions, np.ones((5, 3), bool), 50.0, ["RASI", "", "RASI"],
                                 first_frame=11))
    assert markers.names == ("RASI", "marker2", "RASI_2")
    assert markers.times[0] == pytest.approx(10 / 50.0)


# ---- malformed files --------------------------------------------------------------------

@pytest.fixture()
def good_c3d(tmp_path: Path) -> Path:
    rng = np.random.default_rng(0)
    return write_c3d(tmp_path / "good.c3d", rng.normal(0, 100, (60, 4, 3)), rng.random((60, 4)) > 0.1, 100.0,
                     ["a", "b", "c", "d"])


@pytest.mark.parametrize("cut, reason", [(0, "not a readable C3D file"), (300, "not a readable C3D file"),
                                         (-400, r"truncated: the header says 60 frames, the file holds 5\d\b")])
def test_truncated_or_empty_c3d_is_refused(good_c3d: Path, cut: int, reason: str) -> None:
    data = good_c3d.read_bytes()
    bad = good_c3d.with_name("bad.c3d")
    bad.write_bytes(data[:cut])
    with pytest.raises(FileFormatError, match=reason) as err:
        read_c3d(bad)
    assert err.value.path == str(bad)


def test_text_is_not_c3d(tmp_path: Path) -> None:
    path = tmp_path / "notes.c3d"
    path.write_text("time,x\n0,1\n")
    with pytest.raises(FileFormatError, match=r"notes\.c3d: not a readable C3D file"):
        read_c3d(path)


def test_damaged_c3d_fails_cleanly_or_reads(good_c3d: Path) -> None:
    """Bytes flipped in the header and parameters: the file reads, or fails with a
    FileFormatError naming it; never another exception (nor a crash)."""
    data = good_c3d.read_bytes()
    rng = random.Random(7)
    refused = 0
    for k in range(150):
        damaged = bytearray(data)
        for _ in range(rng.randint(1, 20)):
            damaged[rng.randrange(0, min(len(data), 3072))] = rng.randrange(256)
        path = good_c3d.with_name(f"damaged{k}.c3d")
        path.write_bytes(bytes(damaged))
        try:
            markers = read_c3d(path)
        except FileFormatError as err:
            assert err.path == str(path)
            refused += 1
        else:
            assert markers.positions.ndim == 3
    assert refused > 0


# ---- command line and batch ------------------------------------------------------------

def test_command_line_writes_markers_and_refuses_bvh(good_c3d: Path, tmp_path: Path) -> None:
    runner = CliRunner()
    result = runner.invoke(app, ["reduce", str(good_c3d), "-o", str(tmp_path / "m.json")])
    assert result.exit_code == 0, result.output
    assert "markers" in result.output and "frames unseen" in result.output
    reduced = ReducedMarkers.from_json((tmp_path / "m.json").read_text())
    _check_reduced(reduced, read_c3d(good_c3d), 5.0)                       # 0.5 cm in mm
    result = runner.invoke(app, ["reduce", str(good_c3d), "-o", str(tmp_path / "m.bvh")])
    assert result.exit_code == 2
    assert "markers are written as .glb or .json" in result.output
    assert not (tmp_path / "m.bvh").exists()


def test_batch_reduces_c3d_beside_clips(good_c3d: Path, tmp_path: Path) -> None:
    library = tmp_path / "lib"
    library.mkdir()
    good_c3d.rename(library / "good.c3d")
    (library / "cut.c3d").write_bytes((library / "good.c3d").read_bytes()[:-400])
    result = CliRunner().invoke(app, ["reduce", str(library), "-o", str(tmp_path / "out")])
    assert result.exit_code == 1
    rows = {Path(r["source"]).name: r for r in csv.DictReader((tmp_path / "out" / "report.csv").open())}
    assert rows["good.c3d"]["status"] == "reduced" and int(rows["good.c3d"]["joints"]) == 4
    assert float(rows["good.c3d"]["max_world_error"]) <= 5.0
    assert rows["cut.c3d"]["status"] == "failed" and "truncated" in rows["cut.c3d"]["message"]
    assert validate(tmp_path / "out" / "good.glb")[0]["numErrors"] == 0


# ---- real recordings ----------------------------------------------------------------

@pytest.mark.realdata
def test_real_c3d_keeps_its_gaps_and_tolerance(data_dir: Path, tmp_path: Path) -> None:
    markers = read_c3d(data_dir / "c3d" / "pyomeca_markers_analogs.c3d")
    assert markers.unit_m == 0.001 and np.isnan(markers.positions).any()
    tol = 5.0                                                    # 0.5 cm, in mm
    reduced = reduce_markers(markers, tol)
    _check_reduced(reduced, markers, tol)
    assert any(len(t.pieces) > 1 for t in reduced.tracks.values())               # gaps split pieces
    path = write_reduced(tmp_path / "real.glb", reduced)
    _check_glb(path, reduced, markers)
    assert validate(path)[0]["numErrors"] == 0
