"""The page pairs each sampled value with the time it was true (Performer.js, run in
node): random pointer event streams (uneven intervals, pauses) against random uneven
frames; every sample is an event's value at that event's time, or the pointer at rest
(its last event's value, after 1.5 of its pace and at least 25 ms); times strictly
increase and follow the clock."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]
NODE = shutil.which("node")
pytestmark = pytest.mark.skipif(NODE is None, reason="node is not installed (scripts/setup needs node 20)")
#: Performer.js: REST, the least ms without an event that is rest.
REST = 25.0


@st.composite
def _script(draw: st.DrawFn) -> dict:
    """Pointer events (ms after the hold, x) with uneven intervals and pauses, and frames."""
    n = draw(st.integers(2, 60))
    gaps = draw(st.lists(st.one_of(st.floats(1.0, 20.0), st.floats(20.0, 300.0)), min_size=n, max_size=n))
    xs = draw(st.lists(st.floats(-5, 5, allow_nan=False), min_size=n, max_size=n))
    times = 5.0 + np.cumsum(gaps)
    frame_gaps = draw(st.lists(st.floats(4.0, 90.0), min_size=1, max_size=400))
    frames = 1.0 + np.cumsum(frame_gaps)
    frames = frames[frames <= times[-1] + 200] if frames[-1] > times[-1] else frames
    return {"events": [[float(t), float(x)] for t, x in zip(times, xs)], "frames": frames.tolist()}


@settings(max_examples=25, deadline=None)
@given(script=_script())
def test_every_sample_is_an_events_value_at_its_time_or_the_pointer_at_rest(script: dict,
                                                                           tmp_path_factory) -> None:  # noqa: ANN001
    path = tmp_path_factory.mktemp("perform") / "script.json"
    path.write_text(json.dumps(script))
    run = subprocess.run([NODE, str(ROOT / "tests/studio/js/perform_events.mjs"), str(path)], capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == 0, run.stderr[-2000:]
    out = json.loads(run.stdout)
    times, stamps = np.array(out["times"]), np.array(out["stamps"]) - out["t0"]
    if len(times) == 0:
        return
    x = np.array(out["rows"])[:, 0]
    assert np.all(np.diff(times) > 0), "times not strictly increasing"
    assert np.allclose(times - times[0], (stamps - stamps[0]) / 1000, atol=1e-9), "times off the clock"
    events = np.array(script["events"])
    frames = np.array(script["frames"])
    for stamp, value in zip(stamps, x):
        i = np.searchsorted(events[:, 0], stamp + 1e-6, side="right") - 1     # the last event at or before it
        if i >= 0 and abs(events[i, 0] - stamp) < 1e-6:
            assert value == events[i, 1], f"the event at {stamp} ms had {events[i, 1]}, the sample {value}"
            continue
        held = 0.0 if i < 0 else events[i, 1]                           # before any event: where it started
        assert value == held, f"a sample at {stamp} ms holds {value}, the pointer was at {held}"
        if i >= 0 and not np.any(np.abs(frames - stamp) < 1e-6):
            # a rest's start: 1.5 of the pointer's pace (at least REST) after its last event
            assert stamp - events[i, 0] >= REST - 1e-9
