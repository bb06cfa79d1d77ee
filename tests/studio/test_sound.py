"""Sounds in the studio: imported through ``POST /api/sounds`` into the project's folder,
listed by the project (name, path, checksum, duration, offset, status), served for the
page, refused with nothing changed when they are not audio, too large or badly named;
a moved or changed file reported when the project loads; beats baked into an event track."""

from __future__ import annotations

import hashlib
import io
import json

import librosa
import numpy as np
import pytest
import soundfile
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.studio import protocol as p
from sketchanim.studio.handlers import handle
from sketchanim.studio.session import Session
from sketchanim.studio.sounds import decoded

RATE = 44100


def wav(seconds: float = 1.5, rate: int = RATE, channels: int = 2) -> bytes:
    """A WAV of a 440 Hz tone, ``seconds`` long (a whole number of samples at ``rate``)."""
    t = np.arange(round(seconds * rate)) / rate
    tone = 0.3 * np.sin(2 * np.pi * 440 * t)
    buffer = io.BytesIO()
    soundfile.write(buffer, np.repeat(tone[:, None], channels, axis=1), rate, format="WAV", subtype="PCM_16")
    return buffer.getvalue()


def upload(client, name: str, data, **params):  # noqa: ANN001, ANN201
    return client.post("/api/sounds", params={"name": name, **params}, content=data)


def sounds_of(client) -> list[dict]:  # noqa: ANN001
    return client.get("/api/project").json()["sounds"]


def test_an_imported_wav_is_listed_with_its_duration_stored_and_served(client):
    data = wav(1.5)
    reply = upload(client, "tone.wav", data)
    assert reply.status_code == 200, reply.text
    [sound] = sounds_of(client)
    assert sound["name"] == "tone.wav" and sound["path"] == "p.sounds/tone.wav"
    assert abs(sound["duration"] - 1.5) <= 1 / RATE
    assert sound["sha256"] == hashlib.sha256(data).hexdigest()
    assert sound["offset"] == 0.0 and sound["status"] == "ok"
    folder = client.app.state.hub.session.folder
    assert (folder / "p.sounds" / "tone.wav").read_bytes() == data
    assert reply.json()["url"] == "/api/sounds/tone.wav"
    served = client.get("/api/sounds/tone.wav")
    assert served.status_code == 200 and served.content == data
    part = client.get("/api/sounds/tone.wav", headers={"Range": "bytes=100-199"})
    assert part.status_code == 206 and part.content == data[100:200]
    assert client.get("/api/state").json()["sounds"][0]["duration"] == sound["duration"]


@pytest.mark.parametrize("data, why", [
    (b"these bytes are no sound at all" * 10, "not audio"),
    (wav(0.5)[:30], "not audio"),                   # a WAV cut inside its header
    (b"", "not audio"),
])
def test_bytes_that_are_not_audio_are_refused_by_name_and_nothing_changes(client, data, why):
    before = client.get("/api/project").content
    reply = upload(client, "song.wav", data)
    assert reply.status_code == 415, reply.text
    detail = reply.json()["detail"]
    assert "song.wav" in detail and why in detail
    assert client.get("/api/project").content == before
    assert not (client.app.state.hub.session.folder / "p.sounds" / "song.wav").exists()


def test_a_sound_over_the_cap_is_refused_while_read_and_nothing_changes(client):
    client.app.state.hub.session.sounds.limit = 4000
    before = client.get("/api/project").content
    reply = upload(client, "big.wav", wav(1.0))                 # its length said: refused before reading
    assert reply.status_code == 413 and "big.wav" in reply.json()["detail"] and "4000" in reply.json()["detail"]

    def chunks():                                               # no length said: refused while read
        for _ in range(10):
            yield b"\0" * 1000
    reply = upload(client, "big.wav", chunks())
    assert reply.status_code == 413, reply.text
    assert client.get("/api/project").content == before
    assert not (client.app.state.hub.session.folder / "p.sounds").exists()


@pytest.mark.parametrize("name, status", [("../up.wav", 400), ("notes.txt", 400), (".hidden.wav", 400),
                                          ("p.sketchanim.wav", 400)])
def test_a_bad_name_is_refused(client, name, status):
    before = client.get("/api/project").content
    reply = upload(client, name, wav(0.2))
    assert reply.status_code == status and repr(name)[1:-1] in reply.json()["detail"]
    assert client.get("/api/project").content == before


def test_a_taken_name_is_refused_unless_overwrite(client):
    assert upload(client, "a.wav", wav(0.5)).status_code == 200
    assert upload(client, "a.wav", wav(0.7)).status_code == 409
    assert abs(sounds_of(client)[0]["duration"] - 0.5) <= 1 / RATE
    assert upload(client, "a.wav", wav(0.7), overwrite="true").status_code == 200
    assert abs(sounds_of(client)[0]["duration"] - 0.7) <= 1 / RATE
    assert client.get("/api/sounds/none.wav").status_code == 404


def _imported(session: Session, name: str, data: bytes) -> None:
    session.add_sound(session.sounds.stored(name, data))


def test_a_moved_or_changed_file_is_reported_when_the_project_loads(tmp_path):
    path = tmp_path / "show.sketchanim"
    session = Session(path)
    for name in ("kept.wav", "moved.wav", "changed.wav"):
        _imported(session, name, wav(0.3))
    session.close()
    folder = tmp_path / "show.sounds"
    (folder / "moved.wav").rename(tmp_path / "elsewhere.wav")
    data = bytearray((folder / "changed.wav").read_bytes())
    data[-1] ^= 0xFF
    (folder / "changed.wav").write_bytes(bytes(data))
    session = Session(path)
    try:
        status = {s["name"]: s["status"] for s in session.state()["sounds"]}
        assert status == {"kept.wav": "ok", "moved.wav": "missing", "changed.wav": "changed"}
        doc = json.loads(session.export_document())
        assert {s["name"]: s["status"] for s in doc["sounds"]} == status
        with pytest.raises(Exception, match="missing"):
            session.sounds.path("moved.wav")
    finally:
        session.close()


def test_offset_and_removal_are_kept_by_the_project(tmp_path):
    path = tmp_path / "show.sketchanim"
    session = Session(path)
    _imported(session, "a.wav", wav(0.3))
    _imported(session, "b.wav", wav(0.3))
    out = handle(session, p.parse('{"type": "sound.set", "name": "a.wav", "offset": 2.5}'), 0)
    assert out[0][1]["sounds"][0]["offset"] == 2.5
    handle(session, p.parse('{"type": "sound.remove", "name": "b.wav"}'), 0)
    with pytest.raises(Exception, match="no sound 'b.wav'"):
        handle(session, p.parse('{"type": "sound.set", "name": "b.wav", "offset": 1}'), 0)
    session.close()
    session = Session(path)
    try:
        assert [(s["name"], s["offset"]) for s in session.state()["sounds"]] == [("a.wav", 2.5)]
        assert (tmp_path / "show.sounds" / "b.wav").exists()          # the file stays: only the reference went
    finally:
        session.close()


def test_beats_of_a_click_track_land_within_one_frame_of_the_clicks_as_one_step(session):
    rng = np.random.default_rng(7)
    clicks = np.cumsum(rng.uniform(0.3, 0.7, 12)) + 0.2
    sound = librosa.clicks(times=clicks, sr=RATE, length=int((clicks[-1] + 0.5) * RATE))
    buffer = io.BytesIO()
    soundfile.write(buffer, sound, RATE, format="WAV")
    _imported(session, "clicks.wav", buffer.getvalue())
    handle(session, p.parse('{"type": "sound.set", "name": "clicks.wav", "offset": 1.25}'), 0)
    steps = len(session.history.labels[0])
    out = handle(session, p.parse('{"type": "sound.beats", "name": "clicks.wav"}'), 0)
    assert out[-1][1] == {"type": "beats", "name": "clicks.wav", "path": "beats.cue", "count": len(clicks)}
    track = session.player.tracks["beats.cue"]
    assert len(track.times) == len(clicks)
    assert np.abs(np.array(track.times) - (1.25 + clicks)).max() <= 1 / session.fps
    assert set(track.values) == {"beat"} and session.scene.objects["beats"].kind == "cue"
    assert len(session.history.labels[0]) == steps + 1
    session.undo()
    assert "beats" not in session.scene.objects and "beats.cue" not in session.player.tracks


def test_beats_are_refused_on_an_attribute_that_is_not_an_event(session):
    _imported(session, "a.wav", wav(0.3))
    with pytest.raises(Exception, match="event attribute"):
        handle(session, p.parse('{"type": "sound.beats", "name": "a.wav", "path": "box.visible"}'), 0)
    assert "beats" not in session.scene.objects


@settings(max_examples=30, deadline=None)
@given(frames=st.integers(1, 20_000), rate=st.sampled_from([8000, 11025, 22050, 44100, 48000, 96000]))
def test_the_duration_is_the_frames_over_the_rate(frames, rate):
    buffer = io.BytesIO()
    soundfile.write(buffer, np.zeros(frames), rate, format="WAV")
    assert abs(decoded(buffer.getvalue(), "x.wav").duration - frames / rate) <= 1e-12


def test_a_read_only_project_refuses_an_import_and_writes_nothing(tmp_path):
    from fastapi.testclient import TestClient

    from sketchanim.studio.app import create_app

    path = tmp_path / "ro.sketchanim"
    Session(path).close()
    app = create_app(path, warm=False, read_only=True)
    with TestClient(app) as client:
        reply = upload(client, "a.wav", wav(0.2))
        assert reply.status_code == 403 and "read-only" in reply.json()["detail"]
        assert client.get("/api/sounds").json() == []
    app.state.hub.session.close()
    assert not (tmp_path / "ro.sounds").exists()
