"""Shared test settings: hypothesis profile and the real recordings beside the repo."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# Shared, noisy machines: no per-example deadline; examples are bounded in size instead.
settings.register_profile("sketchanim", deadline=None, max_examples=60,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("sketchanim")

REPO = Path(__file__).resolve().parents[1]
DATA = Path(os.environ.get("SKETCHANIM_DATA", REPO.parent / "shared" / "data"))


@pytest.fixture
def data_dir() -> Path:
    """../shared/data (or $SKETCHANIM_DATA); tests that need it skip when it is absent."""
    if not DATA.is_dir():
        pytest.skip(f"real recordings not found at {DATA}")
    return DATA
