"""Layers import only downward (docs/architecture.md): a module may import its own layer and
the ones below it, never one above."""

from __future__ import annotations

import ast
from pathlib import Path

import sketchanim

PACKAGE = Path(sketchanim.__file__).parent
#: Bottom to top.
LAYERS = ["errors", "limits", "atomic", "float32", "spline", "reducer", "motion", "anim", "mocap", "formats",
          "export", "project", "plot", "pipeline", "batch", "paper", "studio", "cli"]


def layer(module: str) -> int:
    """The layer of a ``sketchanim...`` module name (the package itself counts as the top)."""
    parts = module.split(".")
    return LAYERS.index(parts[1]) if len(parts) > 1 else len(LAYERS)


def test_every_module_imports_only_downward() -> None:
    wrong = []
    for path in sorted(PACKAGE.rglob("*.py")):
        relative = path.relative_to(PACKAGE.parent).with_suffix("")
        name = ".".join(p for p in relative.parts if p != "__init__")
        if name == "sketchanim":
            continue                                   # the public face re-exports the layers
        here = layer(name)
        for node in ast.walk(ast.parse(path.read_text())):
            targets = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module] if isinstance(node, ast.ImportFrom) and node.module and node.level == 0 else []
            wrong += [f"{name} imports {t}" for t in targets if t.startswith("sketchanim") and layer(t) > here]
    assert not wrong, wrong
