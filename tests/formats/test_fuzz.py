"""Mutation fuzzing of every reader (tests/fuzzing.py): seeded mutations of real files
(../shared/data; generated seeds where it is absent) end as a named InputError or a
result within tolerance, never a traceback, an internal error on valid input, or a
damaged project loaded silently.

CI runs SKETCHANIM_FUZZ mutations per reader (default 25: a few hundred in all); a
long run: ``SKETCHANIM_FUZZ=3000 .venv/bin/python -m pytest tests/formats/test_fuzz.py`` or
``.venv/bin/python benchmarks/fuzz_readers.py --per-reader 3000`` (prints the table).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest

from conftest import DATA
from fuzzing import MUST_NOT, flip_bytes, fuzz, project_contents, real_project

PER_READER = int(os.environ.get("SKETCHANIM_FUZZ", "25"))
SEED = int(os.environ.get("SKETCHANIM_FUZZ_SEED", "19"))


def _data() -> Path | None:
    return DATA if DATA.is_dir() else None


@pytest.mark.realdata
def test_mutated_files_end_named_or_within_tolerance() -> None:
    tally = fuzz(_data(), PER_READER, SEED)
    bad = {outcome: tally.total(outcome) for outcome in MUST_NOT}
    assert not any(bad.values()), (bad, tally.examples)
    assert all(sum(c.values()) == PER_READER + 1 for c in tally.counts.values())
    assert tally.total("ok") > len(tally.counts)          # some mutations stay valid and are reduced


@pytest.mark.realdata
def test_a_byte_flipped_anywhere_in_a_real_project_is_refused_or_harmless() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = real_project(Path(tmp), _data())
        counts = flip_bytes(path, project_contents(path), 4 * PER_READER, SEED)
    assert counts["silent_damage"] == 0 and counts["traceback"] == 0, counts
    assert counts["named"] > 0
