"""One limits table: every entry listed in docs/input-limits.md with the same range,
shown in ``reduce --help``, and errors that name the field; no library message names
a command-line flag."""

from __future__ import annotations

import ast
import math
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

import sketchanim
from sketchanim.cli import app
from sketchanim.cli.flags import FLAGS, in_flags
from sketchanim.errors import ArgumentError
from sketchanim.limits import LIMITS

DOCS = Path(__file__).resolve().parents[2] / "docs" / "input-limits.md"


def _rows() -> dict[str, list[str]]:
    rows = {}
    for line in DOCS.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| `") and len(cells) >= 4:
            rows[cells[0].strip("`")] = cells
    return rows


def test_docs_list_every_limit_with_its_range() -> None:
    rows = _rows()
    for name, limit in LIMITS.items():
        assert name in rows, f"docs/input-limits.md has no row for {name}"
        assert rows[name][3] == limit.describe(), (name, rows[name][3], limit.describe())
        assert rows[name][1].startswith(f"`{limit.field}`"), (name, rows[name][1])
        assert f"`{FLAGS[limit.field]}`" in rows[name][1], (name, rows[name][1])


def test_every_limit_has_a_flag_and_shows_in_help() -> None:
    words = CliRunner().invoke(app, ["reduce", "--help"], terminal_width=200).output.split()
    text = " ".join(w for w in words if w.strip("│╭╮╰╯─"))
    for name, limit in LIMITS.items():
        assert limit.field in FLAGS
        assert limit.describe() in text, (name, limit.describe())


@pytest.mark.parametrize("name", sorted(LIMITS))
def test_bounds_are_kept_and_errors_name_the_field(name: str) -> None:
    limit = LIMITS[name]
    inside = limit.high if math.isfinite(limit.high) else limit.low + 1
    assert limit.check(inside) == inside
    outside = [limit.low - 0.5, math.nan] + ([] if limit.zero else [limit.low - 1]) + ([limit.high * 2 + 1] if math.isfinite(limit.high) else [])
    if limit.above and not limit.zero:
        outside.append(limit.low)
    for value in outside:
        with pytest.raises(ArgumentError) as caught:
            limit.check(value)
        assert caught.value.argument == limit.field and str(caught.value).startswith(f"{limit.field}: ")
        assert "--" not in str(caught.value)
        assert in_flags(str(caught.value)).startswith(FLAGS[limit.field] + ": ")


def test_flags_are_told_only_where_a_field_is_named() -> None:
    assert in_flags("s.csv: cols: 'z' is not a column") == "s.csv: --cols: 'z' is not a column"
    assert in_flags("(unordered=drop or sort goes on)") == "(--unordered drop or sort goes on)"
    assert in_flags("time_unit=UNIT to change") == "--time-unit UNIT to change"
    assert in_flags("sample 3, rot_cols: Euler angle is not finite") == "sample 3, --rot-cols: Euler angle is not finite"
    for text in ("BVH format: bad", "the frame rate: 30", "gap 1.995-14.005 s", "tolerance=0.1"):
        assert in_flags(text) == text


def _strings(tree: ast.Module) -> list[ast.Constant]:
    """The string constants of a module that are not docstrings."""
    docs = {id(node.body[0].value) for node in ast.walk(tree)
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body
            and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant)}
    return [node for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs]


def test_no_library_message_names_a_flag() -> None:
    flags = set(FLAGS.values()) - {"-o"}
    package = Path(sketchanim.__file__).parent
    wrong = []
    for path in sorted(package.rglob("*.py")):
        if "cli" in path.relative_to(package).parts:
            continue
        for node in _strings(ast.parse(path.read_text(encoding="utf-8"))):
            wrong += [f"{path.relative_to(package)}:{node.lineno}: {flag}"
                      for flag in re.findall(r"(?<![\w-])--[a-z][a-z-]*", node.value) if flag in flags]
    assert not wrong, wrong
