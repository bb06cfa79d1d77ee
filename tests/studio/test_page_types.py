"""The studio page type-checks: ``tsc --noEmit -p .`` (TypeScript pinned in package-lock.json,
tsconfig.json at the repository's root: ``checkJs``, ``strict``) over the page's modules and
their node tests reports no error, so a wrong message field or an undeclared signal fails here."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TSC = ROOT / "node_modules" / ".bin" / "tsc"
pytestmark = pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed (scripts/setup needs node 20)")


def test_every_page_module_type_checks() -> None:
    """Every page module is marked ``// @ts-check`` and is in tsc's program, and tsc reports
    no error over them."""
    assert TSC.exists(), "TypeScript is not installed: run scripts/setup (npm ci)"
    modules = sorted((ROOT / "src/sketchanim/studio/web/js").glob("*.js"))
    assert modules, "no page modules found"
    unmarked = [m.name for m in modules if not m.read_text().startswith("// @ts-check")]
    assert not unmarked, f"modules without // @ts-check: {unmarked}"
    run = subprocess.run([str(TSC), "--noEmit", "-p", ".", "--listFiles"], cwd=ROOT, capture_output=True, text=True,
                         timeout=300)
    lines = run.stdout.splitlines()
    errors = [line for line in lines if ": error TS" in line or line.startswith("error TS")]
    assert run.returncode == 0 and not errors, "\n".join(errors)[-6000:] + run.stderr[-2000:]
    listed = {Path(line).resolve() for line in lines if line.startswith("/") and "node_modules" not in line}
    assert set(modules) <= listed, f"not type-checked: {sorted(set(modules) - listed)}"
