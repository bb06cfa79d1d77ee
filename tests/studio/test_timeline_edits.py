"""The timeline's messages through the session: take.edit shift / scale, track.retime,
track.cut, track.copy and track.paste, each one History step that undo takes back exactly,
refused while the path is recorded and with errors that name the field."""

from __future__ import annotations

import json

import numpy as np
import pytest

from sketchanim.errors import ArgumentError
from sketchanim.studio import protocol as p
from sketchanim.studio.handlers import handle


def _send(session, message: dict) -> list:  # noqa: ANN001
    return handle(session, p.parse(json.dumps(message)), 1)


def _record(session, path: str = "box.position", start: float = 0.0) -> None:  # noqa: ANN001
    """A take of ``path`` over 2 s from ``start``."""
    session.begin_take(1, "t", [path], "replace", 0.1, start, 1.0, {}, None, 0.25)
    t = start + np.arange(121) / 60
    session.samples(1, "t", t, np.c_[np.sin(t), 0.5 + 0 * t, np.cos(t)])
    session.end_take(1, "t", None)


def _steps(session) -> int:  # noqa: ANN001
    return len(session.history.labels[0])


def test_a_take_shifted_then_scaled_is_one_step_each_and_undo_gives_it_back(session) -> None:  # noqa: ANN001
    _record(session)
    before = session.player.tracks["box.position"]
    steps = _steps(session)
    _send(session, {"type": "take.edit", "path": "box.position", "take": 0, "op": "shift", "by": 0.5})
    shifted = session.player.tracks["box.position"]
    assert np.array_equal(shifted.takes[0].times, before.takes[0].times + 0.5) and _steps(session) == steps + 1
    _send(session, {"type": "take.edit", "path": "box.position", "take": 0, "op": "scale", "factor": 2, "pivot": 1})
    assert np.array_equal(session.player.tracks["box.position"].takes[0].times, 1 + 2 * (shifted.takes[0].times - 1))
    session.undo()
    session.undo()
    assert session.player.tracks["box.position"] is before


def test_retime_and_cut_change_several_tracks_in_one_step(session) -> None:  # noqa: ANN001
    _record(session)
    _send(session, {"type": "set", "path": "box.visible", "value": False})
    _record(session, "ball.position", 0.5)
    before = dict(session.player.tracks)
    steps = _steps(session)
    _send(session, {"type": "track.retime", "paths": ["box.position", "ball.position"], "factor": 1.5, "pivot": 0.5})
    assert _steps(session) == steps + 1
    assert session.player.tracks["ball.position"].start == pytest.approx(0.5)
    assert session.player.tracks["box.position"].start == pytest.approx(0.5 - 0.75)
    _send(session, {"type": "track.cut", "paths": ["box.position", "ball.position"], "t0": 1.0, "t1": 1.5})
    assert _steps(session) == steps + 2 and session.history.labels[0][-1].startswith("delete range")
    session.undo()
    session.undo()
    assert all(session.player.tracks[k] is v for k, v in before.items())


def test_copy_answers_a_piece_the_page_pastes_back(session) -> None:  # noqa: ANN001
    _record(session)
    _record(session, "ball.position")
    [(audience, piece)] = _send(session, {"type": "track.copy", "path": "box.position", "t0": 0.5, "t1": 1.5})
    assert audience == "self" and piece["type"] == "track.piece" and piece["length"] == pytest.approx(1.0)
    assert piece["piece"]["start"] == 0.0 and piece["piece"]["takes"] == []
    steps = _steps(session)
    _send(session, {"type": "track.paste", "path": "ball.position", "at": 0.25, "piece": piece["piece"],
                    "length": piece["length"]})
    ball = session.player.tracks["ball.position"]
    assert _steps(session) == steps + 1 and ball.takes[-1].name == "paste" and ball.takes[-1].start == 0.25


def test_paste_refuses_another_type_and_a_bad_piece_naming_the_field(session) -> None:  # noqa: ANN001
    _record(session)
    _send(session, {"type": "set", "path": "box.scale", "value": [2, 2, 2]})
    session.begin_take(1, "s", ["box.scale"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    t = np.arange(61) / 60
    session.samples(1, "s", t, np.c_[1 + t, 1 + t, 1 + t])
    session.end_take(1, "s", None)
    [(_, piece)] = _send(session, {"type": "track.copy", "path": "box.position", "t0": 0.2, "t1": 0.8})
    paste = {"type": "track.paste", "path": "box.scale", "at": 0, "piece": piece["piece"], "length": 0.6}
    with pytest.raises(ArgumentError, match=r"^piece: .*box\.position.*box\.scale"):
        _send(session, paste)
    bad = {**paste, "path": "box.position", "piece": {**piece["piece"], "knots": piece["piece"]["knots"][:-1]}}
    with pytest.raises(ArgumentError, match=r"^piece\.knots"):
        _send(session, bad)
    with pytest.raises(p.BadMessage, match=r"track\.retime\.factor"):
        p.parse('{"type": "track.retime", "paths": ["box.position"], "factor": 0}')
    with pytest.raises(ArgumentError, match="^path: box.orientation: is not animated"):
        _send(session, {"type": "track.cut", "paths": ["box.orientation"], "t0": 0, "t1": 1})


def test_refused_while_the_path_is_being_recorded(session) -> None:  # noqa: ANN001
    _record(session)
    session.begin_take(1, "again", ["box.position"], "replace", 0.1, 0.0, 1.0, {}, None, 0.25)
    for message in ({"type": "track.retime", "paths": ["box.position"], "shift": 1},
                    {"type": "track.cut", "paths": ["box.position"], "t0": 0.2, "t1": 0.5},
                    {"type": "take.edit", "path": "box.position", "take": 0, "op": "shift", "by": 1}):
        with pytest.raises(ArgumentError, match="being recorded"):
            _send(session, message)
    session.cancel_take(1, "again")
