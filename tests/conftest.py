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


@pytest.fixture(scope="session", autouse=True)
def _own_state_folder(tmp_path_factory: pytest.TempPathFactory) -> None:
    """The user's state folder (the recent projects' list) is the tests' own, for the
    tests and the studio servers they start."""
    os.environ["XDG_STATE_HOME"] = str(tmp_path_factory.mktemp("state"))


@pytest.fixture
def data_dir() -> Path:
    """../shared/data (or $SKETCHANIM_DATA); tests that need it skip when it is absent."""
    if not DATA.is_dir():
        pytest.skip(f"real recordings not found at {DATA}")
    return DATA


#: The ASF/AMC clip among the real recordings (its skeleton, 11.asf / cmu_11.asf, beside it).
REAL_AMC = Path("amc") / "cmu_11_01.amc"


def real_files(data: Path, folder: str, pattern: str) -> list[Path]:
    """The files matching ``pattern`` in ``data / folder``, sorted; a test over them
    fails (never passes on nothing) when there are none."""
    found = sorted((data / folder).glob(pattern))
    if not found:
        pytest.fail(f"no {pattern} recordings in {data / folder}: the test would check nothing")
    return found


@pytest.fixture
def real_bvh(data_dir: Path) -> list[Path]:
    """Every BVH recording in ../shared/data/bvh (fails when there is none)."""
    return real_files(data_dir, "bvh", "*.bvh")


@pytest.fixture
def real_clips(real_bvh: list[Path], data_dir: Path) -> list[Path]:
    """The real skeletal clips: every BVH recording, and the CMU ASF/AMC clip (fails
    when it is missing)."""
    amc = data_dir / REAL_AMC
    if not amc.is_file():
        pytest.fail(f"{amc} is missing: the test would not check an AMC clip")
    return [*real_bvh, amc]


@pytest.fixture
def real_c3d(data_dir: Path) -> list[Path]:
    """Every C3D marker recording in ../shared/data/c3d (fails when there is none)."""
    return real_files(data_dir, "c3d", "*.c3d")
