"""Events fire once each time playback passes them in the page (``events.js`` on the page's
``Clock``), forwards, backwards and round the loop range, at any speed and frame rate: the
page fires what the playhead's continuous path passes, in the order it passes them."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]
NODE = shutil.which("node")
pytestmark = pytest.mark.skipif(NODE is None, reason="node is not installed (scripts/setup needs node 20)")


def expected(case: dict) -> list[float]:
    """The events the playhead's path passes: unwrapped, it runs from ``start`` to the end;
    an event at ``e`` of the loop range ``[a, b)`` is passed at ``e + n (b - a)`` for every
    whole ``n`` on the way (forwards in ``(start, end]``, backwards in ``[end, start)``...
    as the model fires them: ``(end, start]``)."""
    speed, start = case["speed"], case["start"]
    end = start + speed * sum(case["frames"]) / 1000
    lo, hi = min(start, end), max(start, end)
    crossings = []
    for e in case["events"]:
        if case["loop"] is None:
            hits = [e]
        else:
            a, b = case["loop"]
            n0, n1 = math.floor((lo - e) / (b - a)) - 1, math.ceil((hi - e) / (b - a)) + 1
            hits = [e + n * (b - a) for n in range(n0, n1 + 1)]
        crossings += [(u, e) for u in hits if (start < u <= end if speed > 0 else end < u <= start)]
    return [e for _, e in sorted(crossings, reverse=speed < 0)]


@st.composite
def cases(draw: st.DrawFn) -> dict:
    """Cues and loop ranges on frames (as snapped edits put them: a cue on the loop's first
    frame is common) or anywhere; frames of 1 ms to half a second (a slow or busy page
    passes several cues in one)."""
    fps = draw(st.sampled_from([24.0, 30.0, 60.0]))
    on_frames = draw(st.booleans())
    when = (st.integers(-120, 120).map(lambda f: f / fps) if on_frames else st.floats(-5, 5))
    looped = draw(st.booleans())
    a = draw(when)
    length = draw(st.integers(5, 96).map(lambda f: f / fps) if on_frames else st.floats(0.2, 4))
    loop = [a, a + length] if looped else None
    if on_frames:
        first, count = round(a * fps), round(length * fps)
        inside = st.integers(first, first + count - (1 if looped else 0)).map(lambda f: f / fps)
        events = sorted(draw(st.lists(inside, max_size=8)))
    else:
        # anywhere but within rounding of the loop's ends (which side of an end a cue a
        # hair from it is on is the floating point's call there, not the page's)
        events = sorted(draw(st.lists(st.floats(a + 1e-9, a + length - 1e-9), max_size=8)))
    speed = draw(st.sampled_from([1.0, 0.5, 0.25, 2.0, 4.0, -1.0, -0.5, 0.1]))
    start = draw(st.floats(a, a + length, exclude_max=True)) if looped else draw(st.floats(a - 3, a + length + 3))
    frames = draw(st.lists(st.floats(1, 500), min_size=1, max_size=60))
    return {"events": events, "loop": loop, "speed": speed, "start": start, "frames": frames}


def fired(batch: list[dict], tmp_path: Path) -> list[list[float]]:
    dump = tmp_path / "cases.json"
    dump.write_text(json.dumps(batch))
    run = subprocess.run([NODE, str(ROOT / "tests/studio/js/fire_events.mjs"), str(dump)], capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout)


@settings(max_examples=40, deadline=None)
@given(batch=st.lists(cases(), min_size=1, max_size=25))
def test_the_page_fires_each_event_once_each_time_playback_passes_it(batch, tmp_path_factory) -> None:
    got = fired(batch, tmp_path_factory.mktemp("fire"))
    for case, page in zip(batch, got):
        want = expected(case)
        assert len(page) == len(want) and all(math.isclose(x, y, abs_tol=1e-12) for x, y in zip(page, want)), case


def test_a_pass_round_a_loop_fires_its_cues_in_order(tmp_path) -> None:
    case = {"events": [0.25, 0.5, 0.75], "loop": [0.0, 1.0], "speed": 1.0, "start": 0.1, "frames": [100.0] * 25}
    assert fired([case], tmp_path)[0] == [0.25, 0.5, 0.75] * 2 + [0.25, 0.5] == expected(case)
