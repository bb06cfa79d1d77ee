"""The README and docs/ say what the code does: their Python snippets run, their relative
links lead to files that exist, the README stays a guide (under 200 lines), and the layer
picture in docs/architecture.md is the one tests/test_layers.py enforces."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from test_layers import LAYERS

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCS = ROOT / "docs"
PAGES = [README, *sorted(DOCS.glob("*.md"))]
#: Pages whose ```python blocks are run (each block on its own, in an empty folder).
RUN = [README, DOCS / "reducer.md", DOCS / "animation-model.md"]
#: The marker above the layer list in docs/architecture.md.
LAYER_MARK = "<!-- layers, bottom to top (tests/test_docs.py compares them with tests/test_layers.py) -->"

FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def blocks(page: Path, language: str) -> list[str]:
    """The fenced code blocks of ``page`` in ``language``, in order."""
    return [body for lang, body in FENCE.findall(page.read_text()) if lang == language]


def snippets() -> list[pytest.param]:
    found = [pytest.param(code, id=f"{page.name}-{i}")
             for page in RUN if page.exists() for i, code in enumerate(blocks(page, "python"), 1)]
    assert found, "no ```python block in the pages that are run"
    return found


def test_every_run_page_exists_and_has_a_snippet() -> None:
    for page in RUN:
        assert page.exists(), f"{page.relative_to(ROOT)} is missing"
        assert blocks(page, "python"), f"{page.relative_to(ROOT)} has no ```python block"


@pytest.mark.parametrize("code", snippets())
def test_python_snippet_runs(code: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "<snippet>", "exec"), {"__name__": "__snippet__"})


def test_readme_is_a_guide_under_200_lines() -> None:
    assert len(README.read_text().splitlines()) < 200


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_relative_links_point_to_files(page: Path) -> None:
    text = FENCE.sub("", page.read_text())                  # links inside code are not links
    missing = []
    for target in LINK.findall(text):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue
        if not (page.parent / target.split("#")[0]).exists():
            missing.append(target)
    assert not missing, f"{page.relative_to(ROOT)} links to missing files: {missing}"


def test_no_page_cites_the_design_notes_outside_the_repo() -> None:
    assert not [p.name for p in PAGES if "DESIGN.md" in p.read_text()]


#: Pages that describe the code as it is: no issue numbers, no branches, no history.
REFERENCE = [README, *(DOCS / name for name in ("architecture.md", "reducer.md", "animation-model.md",
                                                "mocap.md", "clients.md", "benchmarks.md"))]
WORK_LOG = re.compile(r"\bissue \d+|\bbranch\b|\bworktree\b|\bwe (changed|moved|now)\b", re.I)


@pytest.mark.parametrize("page", REFERENCE, ids=lambda p: p.name)
def test_reference_pages_describe_the_code_not_the_work(page: Path) -> None:
    assert not WORK_LOG.findall(page.read_text()), f"{page.name} reads like a work log"


def documented_layers() -> list[str]:
    text = (DOCS / "architecture.md").read_text()
    assert LAYER_MARK in text, "docs/architecture.md has lost its layer marker"
    lang, body = FENCE.search(text, text.index(LAYER_MARK)).groups()
    return [line.split()[0] for line in body.splitlines() if line.strip()]


def test_architecture_lists_the_enforced_layers_in_order() -> None:
    assert documented_layers() == LAYERS
