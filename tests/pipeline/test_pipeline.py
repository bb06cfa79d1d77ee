"""The library functions per input kind: options objects checked once when made (errors
name fields, never flags), a table and a clip reduced through the API as the command
line does, a folder with its report; which flags apply to which kind comes from the
options objects."""

from __future__ import annotations

from dataclasses import FrozenInstanceError
from pathlib import Path

import numpy as np
import pytest

from mocap.test_contacts import walker_clip
from walk_paths import segments
from sketchanim.batch import FolderOptions, reduce_folder
from sketchanim.cli.reduce_flags import INPUT_KINDS
from sketchanim.errors import ArgumentError, InputError
from sketchanim.formats.bvh import write_bvh
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.pipeline import ClipOptions, TableOptions, reduce_clip_file, reduce_table
from sketchanim.reducer import Reduction


def table(tmp_path: Path, n: int = 200) -> tuple[Path, np.ndarray, np.ndarray]:
    t = np.linspace(0, 4, n)
    x = np.c_[np.sin(2 * t), np.cos(3 * t)]
    path = tmp_path / "s.csv"
    np.savetxt(path, np.c_[t, x], delimiter=",", header="t,x,y", comments="")
    return path, t, x


def clip(tmp_path: Path, name: str = "c.bvh") -> Path:
    s = Skeleton(("hips", "knee"), (-1, 0), np.array([[0.0, 90, 0], [0, -45, 0]]))
    return write_bvh(tmp_path / name, Clip.still(s, np.arange(60) / 30))


@pytest.mark.parametrize(("make", "field"), [
    (lambda: TableOptions(order=60), "order"),
    (lambda: TableOptions(tol=(0.1, 0.0)), "tol"),
    (lambda: TableOptions(method="sideways"), "method"),
    (lambda: TableOptions(gap=0.5), "gap"),
    (lambda: TableOptions(rate=1e9), "rate"),
    (lambda: TableOptions(time_unit="h"), "time_unit"),
    (lambda: TableOptions(duplicates="last"), "duplicates"),
    (lambda: TableOptions(keys="bezier"), "keys"),
    (lambda: ClipOptions(rate=5000), "rate"),
    (lambda: ClipOptions(keys="bezier"), "keys"),
    (lambda: ClipOptions(units="furlong"), "units"),
    (lambda: ClipOptions(shell_cm=-1), "shell_cm"),
    (lambda: FolderOptions(workers=0), "workers"),
    (lambda: FolderOptions(format="fbx"), "format"),
])
def test_options_are_checked_when_made_and_errors_name_fields(make, field) -> None:
    with pytest.raises(ArgumentError) as caught:
        make()
    assert caught.value.argument == field and "--" not in str(caught.value)


def test_options_are_frozen_and_normalised() -> None:
    options = TableOptions(tol=0.01, cols="x, y", groups="x:y")
    assert options.tol == (0.01,) and options.cols == ("x", "y") and options.groups == (("x",), ("y",))
    with pytest.raises(FrozenInstanceError):
        options.order = 3                                               # type: ignore[misc]


def test_reduce_table_writes_what_it_reduced(tmp_path) -> None:
    path, t, x = table(tmp_path)
    out = tmp_path / "o.json"
    result = reduce_table(path, TableOptions(tol=0.01), output=out)
    assert [w.path for w in result.written] == [out]
    assert np.all(np.abs(Reduction.from_json(out.read_text()).spline(t) - x) <= 0.01 * (1 + 1e-9))
    assert result.table.notes[0] == "comma-separated table"


def test_reduce_table_errors_name_fields_and_write_nothing(tmp_path) -> None:
    path, _, _ = table(tmp_path)
    cases = [(TableOptions(), "tol: needed for x, y"), (TableOptions(tol=(0.1, 0.1, 0.1)), "tol: needs 1 or 2"),
             (TableOptions(tol=0.1, groups="x,z"), "groups: 'z' is not a channel"),
             (TableOptions(tol=0.1, cols="q"), "cols: "), (TableOptions(tol=0.1, rot_cols="x,y"), "rot_cols: ")]
    for options, words in cases:
        with pytest.raises(InputError, match=words) as caught:
            reduce_table(path, options, output=tmp_path / "o.json")
        assert "--" not in str(caught.value)
    with pytest.raises(ArgumentError, match="output: .* is the input"):
        reduce_table(path, TableOptions(tol=0.1), output=path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.csv"]


def test_reduce_clip_file_and_a_folder(tmp_path) -> None:
    source = clip(tmp_path)
    result = reduce_clip_file(source, ClipOptions(tol=0.5), tmp_path / "c.glb")
    assert (tmp_path / "c.glb").is_file() and result.outcome.status == "reduced" and result.outcome.frames == 60
    library = tmp_path / "lib"
    library.mkdir()
    clip(library, "a.bvh")
    (library / "bad.bvh").write_text("HIERARCHY\n")
    done = reduce_folder(library, tmp_path / "out", FolderOptions(ClipOptions(tol=0.5), format="bvh"))
    assert [Path(o.source).name for o in done.outcomes] == ["a.bvh", "bad.bvh"]
    assert done.count("reduced") == 1 and done.count("failed") == 1 and done.report.is_file()
    with pytest.raises(ArgumentError, match="output: a folder of clips needs an output folder"):
        reduce_folder(library, None, FolderOptions())


@pytest.mark.parametrize("options", [{}, {"world": True}], ids=["joints", "world"])
def test_a_clip_holds_its_planted_feet_unless_contacts_is_false(tmp_path, options) -> None:
    """Holding the feet tightens the legs: more control points than the same clip
    reduced with ``contacts=False`` (compact files: ``test_compact_clip``)."""
    walker, _ = walker_clip(segments([(1.0, 0.0, 0.0), (2.0, 1.2, 0.0)]))
    source = tmp_path / "walk.bvh"
    write_bvh(source, walker)
    points = {}
    for contacts in (True, False):
        done = reduce_clip_file(source, ClipOptions(tol_cm=1.0, units="m", contacts=contacts, **options))
        points[contacts] = done.outcome.control_points
    assert points[True] > points[False], points


def test_flags_apply_where_the_options_have_the_field() -> None:
    assert {"plot", "cols", "order", "tol", "rate", "keys"} <= INPUT_KINDS["sample table"]
    assert not {"world", "units", "workers", "shell_cm", "contacts"} & INPUT_KINDS["sample table"]
    assert {"world", "units", "keys", "tol", "rate", "output", "order", "contacts"} <= INPUT_KINDS["clip"]
    assert not {"plot", "method", "workers", "format"} & INPUT_KINDS["clip"]
    assert {"workers", "scheduler", "format", "world"} <= INPUT_KINDS["folder of clips"]
