"""Keying discrete attributes (what performing a toggle, a choice or a cue lands in the model):
keys stay in time order, a bool or an enum holds the value keyed from its time on, events
accumulate, and each key is one undoable step."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.anim.attributes import BOOL, EVENT, AttributeType
from sketchanim.anim.edits import with_key
from sketchanim.anim.tracks import DiscreteTrack
from sketchanim.errors import ArgumentError
from sketchanim.studio.defaults import default_scene
from sketchanim.studio.editor import Editor

MOOD = AttributeType.enum(["calm", "angry", "sad"])
times = st.floats(-100, 100, allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(times, st.sampled_from(["calm", "angry", "sad"])), min_size=1, max_size=30))
def test_a_value_keyed_holds_from_its_time_until_the_next_key(keys) -> None:
    track = DiscreteTrack("box.mood", MOOD)
    for t, v in keys:
        track = with_key(track, t, v)
    assert track.times == sorted(track.times) and len(set(track.times)) == len(track.times)
    last = {t: v for t, v in keys}                          # the last key at a time wins
    assert dict(zip(track.times, track.values)) == last
    for t, v in last.items():
        assert track.value_at(t) == v


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(times, st.one_of(st.none(), st.text(max_size=8))), min_size=1, max_size=30))
def test_every_cue_keyed_is_kept_in_time_order_and_fires_once(keys) -> None:
    track = DiscreteTrack("box.cue", EVENT)
    for t, label in keys:
        track = with_key(track, t, label)
    assert track.times == sorted(track.times)
    assert sorted(zip(track.times, map(str, track.values))) == sorted((t, str(v)) for t, v in keys)
    lo, hi = min(track.times) - 1, max(track.times)
    assert len(track.between(lo, hi)) == len(keys)          # a pass over all of them fires each once


def test_keys_are_undoable_steps_and_refused_where_they_do_not_fit() -> None:
    editor = Editor(default_scene(), [])
    editor.key("lamp.on", 1.0, False)
    editor.key("lamp.on", 2.0, True)
    editor.key("box.cue", 1.5, "hit")
    assert editor.player.tracks["lamp.on"].times == [0.0, 1.0, 2.0]   # on until it was switched off
    assert editor.history.labels[0][-1] == "cue box.cue at 1.500 s"
    editor.undo()
    assert "box.cue" not in editor.player.tracks
    editor.undo()
    assert editor.player.tracks["lamp.on"].values == [True, False]
    editor.redo()
    assert editor.player.tracks["lamp.on"].values == [True, False, True]
    for path, value, field in (("box.position", None, "path"), ("lamp.on", "yes", "lamp.on"), ("box.cue", 3, "box.cue")):
        with pytest.raises(ArgumentError) as err:
            editor.key(path, 1.0, value)
        assert err.value.argument == field
    with pytest.raises(ArgumentError, match="finite"):
        editor.key("lamp.on", float("nan"), True)
    assert len(editor.history.labels[0]) == 2                # the refused keys made no step


def test_a_bool_key_plays_back_as_a_step() -> None:
    editor = Editor(default_scene(), [])
    editor.key("box.visible", 1.0, False)
    player = editor.player
    for t, seen in ((0.5, True), (1.0, False), (3.0, False)):
        player.seek(t)
        player.apply()
        assert editor.scene.get("box.visible") is seen
    assert editor.player.tracks["box.visible"].type == BOOL
