"""JSON sample streams: JSON Lines, arrays of records and columns read to the same table;
malformed streams refused naming the file, the line or record and the field; the command
line reduces them within tolerance."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from sketchanim.cli import app
from sketchanim.errors import FileFormatError
from sketchanim.formats.csvio import read_samples_csv
from sketchanim.formats.jsonio import read_samples_json
from sketchanim.reducer import Reduction

FORMS = ("jsonl", "records", "columns")


def write_stream(path: Path, times: np.ndarray, fields: dict[str, np.ndarray], form: str) -> Path:
    """``fields`` (name to (n,) or (n, w) values) at ``times`` as JSON in ``form``."""
    records = [{"t": float(t), **{k: v[i].tolist() for k, v in fields.items()}} for i, t in enumerate(times)]
    if form == "jsonl":
        path.write_text("".join(json.dumps(r) + "\n" for r in records))
    elif form == "records":
        path.write_text(json.dumps(records, indent=2))
    else:
        path.write_text(json.dumps({"t": times.tolist(), **{k: v.tolist() for k, v in fields.items()}}))
    return path


@st.composite
def streams(draw: st.DrawFn) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """2 to 150 samples at uneven times; 1 to 3 fields, each a number or an array of 2
    to 4."""
    n = draw(st.integers(2, 150))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    times = np.cumsum(rng.uniform(0.001, 0.05, n))
    fields = {}
    for k in range(draw(st.integers(1, 3))):
        width = draw(st.sampled_from([1, 2, 3, 4]))
        values = np.cumsum(rng.normal(0, 1, (n, width)), axis=0)
        fields[f"f{k}"] = values[:, 0] if width == 1 else values
    return times, fields


@settings(max_examples=30, deadline=None)
@given(streams(), st.sampled_from(FORMS))
def test_every_form_reads_the_same_table(tmp_path_factory: pytest.TempPathFactory,
                                         stream: tuple[np.ndarray, dict[str, np.ndarray]], form: str) -> None:
    times, fields = stream
    suffix = ".jsonl" if form == "jsonl" else ".json"
    table = read_samples_json(write_stream(tmp_path_factory.mktemp("j") / f"s{suffix}", times, fields, form))
    assert np.array_equal(table.times, times)
    assert np.array_equal(table.values, np.column_stack(list(fields.values())))
    assert table.channels == [k if v.ndim == 1 else f"{k}[{i}]" for k, v in fields.items()
                              for i in range(1 if v.ndim == 1 else v.shape[1])]
    assert table.where(len(times) - 1) == (f"line {len(times)}" if form == "jsonl" else f"record [{len(times) - 1}]")


@settings(max_examples=10, deadline=None)
@given(streams(), st.sampled_from([0.01, 0.1]))
def test_command_line_reduces_a_stream_within_tolerance(tmp_path_factory: pytest.TempPathFactory,
                                                        stream: tuple[np.ndarray, dict[str, np.ndarray]],
                                                        tol: float) -> None:
    times, fields = stream
    folder = tmp_path_factory.mktemp("cli")
    source = write_stream(folder / "s.jsonl", times, fields, "jsonl")
    result = CliRunner().invoke(app, ["reduce", str(source), "--tol", str(tol), "-o", str(folder / "out.json")])
    assert result.exit_code == 0, result.output
    reduction = Reduction.from_json((folder / "out.json").read_text())
    values = np.column_stack(list(fields.values()))
    assert np.abs(reduction.spline(times).reshape(len(times), -1) - values).max() <= tol


@pytest.mark.parametrize("name, text, message", [
    ("a.jsonl", '{"t": 0, "x": 1}\n{"t": 0.1, "x": 2\n', r"a\.jsonl, line 2: not JSON"),
    ("a.jsonl", '{"t": 0, "x": 1}\n\n{"t": 0.1}\n', r"a\.jsonl, line 3: lacks 'x'"),
    ("a.jsonl", '{"t": 0, "x": 1}\n{"t": 0.1, "x": 2, "y": 3}\n', r"line 2: has 'y', the first record not"),
    ("a.jsonl", '{"x": 1}\n', r"line 1: needs the time in seconds under one of t, time"),
    ("a.jsonl", '{"t": 0}\n', r"line 1: has no channel besides the time"),
    ("a.jsonl", '{"t": 0, "x": "1"}\n', r"line 1: field 'x' is not a number"),
    ("a.jsonl", '{"t": 0, "x": true}\n', r"line 1: field 'x' is not a number"),
    ("a.jsonl", '{"t": 0, "x": NaN}\n', r"line 1: field 'x' is nan"),
    ("a.jsonl", '{"t": 0, "x": [1, 2]}\n{"t": 1, "x": [1]}\n', r"line 2: field 'x' has 1 numbers, the first record 2"),
    ("a.jsonl", '{"t": 0, "x": []}\n', r"line 1: field 'x' is an empty array"),
    ("a.jsonl", '[1, 2]\n', r"line 1: is not an object"),
    ("a.jsonl", '\n\n', r"a\.jsonl: has no samples"),
    ("b.json", '[{"t": 0, "x": 1},\n {"t": 1, "x": [2, 3]}]', r"b\.json: record \[1\]: field 'x' has 2 numbers"),
    ("b.json", '[{"t": 0, "x": 1}, 5]', r"record \[1\]: is not an object"),
    ("b.json", '[]', r"b\.json: has no samples"),
    ("b.json", '{"t": [0, 1], "x": [1]}', r"fields have different lengths: t 2, x 1"),
    ("b.json", '{"t": [0, 1], "x": 1}', r"field 'x' is not an array"),
    ("b.json", '{"t": [0, 1],\n "x": [1, null]}', r"record \[1\]: field 'x' is not a number"),
    ("b.json", "7", r"is not a sample stream: expected an array of records or an object of columns"),
    ("b.json", '{"t": [0, 1],\n "x": [1, 2]', r"b\.json, line 2: not JSON"),
])
def test_malformed_streams_name_where(tmp_path: Path, name: str, text: str, message: str) -> None:
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(FileFormatError, match=message):
        read_samples_json(path)


def test_a_sample_out_of_order_is_named_by_its_line(tmp_path: Path) -> None:
    path = tmp_path / "s.jsonl"
    path.write_text('{"t": 0, "x": 1}\n{"t": 0.2, "x": 2}\n\n{"t": 0.1, "x": 3}\n')
    result = CliRunner().invoke(app, ["reduce", str(path), "--tol", "0.1"])
    assert result.exit_code == 2
    assert "s.jsonl, line 4:" in result.output and "Traceback" not in result.output


@pytest.mark.realdata
def test_real_stream_as_json_lines(data_dir: Path, tmp_path: Path) -> None:
    """A real IMU stream, rewritten as JSON Lines, reads back the same and reduces
    within tolerance."""
    table = read_samples_csv(data_dir / "imu" / "ngimu_quaternion.csv")
    fields = {"q": table.values}
    back = read_samples_json(write_stream(tmp_path / "imu.jsonl", table.times, fields, "jsonl"))
    assert np.array_equal(back.values, table.values) and np.array_equal(back.times, table.times)
    result = CliRunner().invoke(app, ["reduce", str(tmp_path / "imu.jsonl"), "--tol", "0.002", "-o",
                                      str(tmp_path / "imu.out.json")])
    assert result.exit_code == 0, result.output
    spline = Reduction.from_json((tmp_path / "imu.out.json").read_text()).spline
    assert np.abs(spline(table.times) - table.values).max() <= 0.002
