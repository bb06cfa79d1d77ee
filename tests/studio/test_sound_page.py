"""A sound in the page, in a real browser (Debian's chromium through Playwright) against a
real server: imported through the file input, listed by the project with its duration,
its waveform drawn in the timeline, its playback following the transport within a frame at
1x and 1/2x, a scrub playing grains, non-audio bytes refused on the page with nothing
changed. Every test checks the page drew something."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import soundfile
from PIL import Image

from studio_browser import project

RATE = 44100


def _wav(path: Path, seconds: float) -> Path:
    """A WAV of a tone whose loudness swells and fades every second (a waveform with a shape)."""
    t = np.arange(round(seconds * RATE)) / RATE
    tone = 0.8 * np.abs(np.sin(np.pi * t)) * np.sin(2 * np.pi * 220 * t)
    soundfile.write(path, np.c_[tone, tone], RATE, subtype="PCM_16")
    return path


def _import(page, path: Path) -> None:  # noqa: ANN001
    page.set_input_files("[data-testid=import-audio]", str(path))
    page.wait_for_function(f"() => sounds.report().some((s) => s.name === {path.name!r})", timeout=30_000)


def _drifts(page, speed: float, seconds: float) -> tuple[np.ndarray, dict]:  # noqa: ANN001
    """Play from 0 at ``speed`` for ``seconds`` of real time; each frame's drift of the audio
    against the transport (s), measured after the first second of real time (the element started, a seek's landing learnt)."""
    page.evaluate(f"""() => {{ const t = studio.transport; t.pause(); t.seek(0); t.setSpeed({speed});
        sounds.report()[0].drifts.length = 0; sounds.report()[0].times.length = 0; t.play(); }}""")
    page.wait_for_timeout(seconds * 1000)
    report = page.evaluate("() => { studio.transport.pause(); return sounds.report()[0]; }")
    times = np.array(report["times"])
    return np.array(report["drifts"])[times >= 1.0 * speed], report


def test_an_imported_wav_is_listed_drawn_and_plays_in_sync_at_1x_and_half(studio, _page, tmp_path):
    page = _page(studio)
    before = page.locator("[data-testid=timeline]").screenshot()
    _import(page, _wav(tmp_path / "swell.wav", 8.0))
    [sound] = project(studio)["sounds"]
    assert sound["name"] == "swell.wav" and sound["status"] == "ok"
    assert abs(sound["duration"] - 8.0) <= 1 / RATE
    page.wait_for_timeout(300)
    shot = np.asarray(Image.open(io.BytesIO(page.locator("[data-testid=timeline]").screenshot())).convert("RGB"), float)
    green = (shot[..., 1] > shot[..., 0] + 40) & (shot[..., 1] > 120)     # the waveform's colour
    assert green.sum() > 200 and shot.std() > 5, "no waveform in the timeline"
    assert shot.shape[0] > np.asarray(Image.open(io.BytesIO(before))).shape[0], "the timeline did not grow its strip"
    page.locator("[data-testid=timeline]").screenshot(path=str(tmp_path / "waveform.png"))
    frame = 1 / page.evaluate("studio.fps")
    for speed in (1.0, 0.5):
        drifts, report = _drifts(page, speed, 3.0)
        assert len(drifts) > 8, f"{speed}x: the sound did not play ({report})"
        assert report["rate"] == speed and report["preservesPitch"]
        assert np.abs(drifts).max() <= frame, f"{speed}x: drift up to {np.abs(drifts).max() * 1000:.1f} ms ({report})"
    assert page.errors == []


def test_backwards_the_sound_is_paused_and_a_scrub_plays_grains(studio, _page, tmp_path):
    page = _page(studio)
    _import(page, _wav(tmp_path / "a.wav", 4.0))
    page.evaluate("() => { const t = studio.transport; t.seek(3); t.setSpeed(-1); t.play(); }")
    page.wait_for_timeout(500)
    report = page.evaluate("() => sounds.report()[0]")
    assert report["paused"] and page.evaluate("studio.transport.clock.playing")
    page.evaluate("() => { studio.transport.pause(); studio.transport.setSpeed(1); }")
    grains = page.evaluate("sounds.grains")
    box = page.locator("[data-testid=timeline]").bounding_box()
    page.mouse.move(box["x"] + box["width"] * 0.2, box["y"] + box["height"] / 2)
    page.mouse.down()
    for i in range(10):
        page.mouse.move(box["x"] + box["width"] * (0.2 + 0.03 * i), box["y"] + box["height"] / 2)
        page.wait_for_timeout(50)
    page.mouse.up()
    assert page.evaluate("sounds.grains") > grains + 3
    page.click("[data-testid=sound-mute]")
    assert page.evaluate("sounds.report()[0].muted")


def test_non_audio_bytes_are_refused_on_the_page_and_change_nothing(studio, _page, tmp_path):
    page = _page(studio)
    before = project(studio)
    bad = tmp_path / "song.wav"
    bad.write_bytes(b"RIFF this is not a sound at all" * 100)
    page.set_input_files("[data-testid=import-audio]", str(bad))
    status = page.locator("[data-testid=sound-status]")
    status.wait_for(state="visible")
    page.wait_for_function("() => document.querySelector('[data-testid=sound-status]').textContent.includes('not imported')")
    text = status.text_content()
    assert "song.wav" in text and "not audio" in text
    assert page.locator("[data-testid=notices]").text_content().count("song.wav") >= 1
    assert project(studio) == before
    assert page.evaluate("sounds.report().length") == 0


def test_recording_plays_the_sound_through_the_count_in_and_at_the_capture_speed(studio, _page, tmp_path):
    page = _page(studio)
    _import(page, _wav(tmp_path / "beat.wav", 8.0))
    page.evaluate("""() => { const t = studio.transport; t.seek(3); t.setCountIn(1); t.setCaptureSpeed(0.5);
        sounds.report()[0].drifts.length = 0; sounds.report()[0].times.length = 0; t.setRecord(true); }""")
    page.wait_for_timeout(3000)
    report = page.evaluate("() => { const r = sounds.report()[0]; studio.transport.setRecord(false); return r; }")
    times, drifts = np.array(report["times"]), np.array(report["drifts"])
    assert report["rate"] == 0.5 and report["preservesPitch"]
    assert times.min() < 3.0, "the sound did not play during the count-in (from 2.5 s)"
    assert times.min() >= 2.5 - 1e-9 and times.max() > 3.0
    settled = drifts[times >= 2.5 + 0.5]                       # after a second of real time
    assert len(settled) > 5 and np.abs(settled).max() <= 1 / page.evaluate("studio.fps")


def test_the_beats_button_bakes_the_onsets_into_an_event_track_one_undo_step(studio, _page, tmp_path):
    import librosa

    page = _page(studio)
    clicks = np.array([0.4, 0.9, 1.3, 1.9, 2.2, 2.8])
    path = tmp_path / "clicks.wav"
    soundfile.write(path, librosa.clicks(times=clicks, sr=RATE, length=3 * RATE), RATE)
    _import(page, path)
    steps = page.evaluate("studio.history.undo.length")
    page.click("[data-testid=sound-beats]")
    page.wait_for_function("() => studio.tracks.has('beats.cue')", timeout=120_000)
    track = page.evaluate("studio.tracks.get('beats.cue')")
    assert np.abs(np.array(track["times"]) - clicks).max() <= 1 / page.evaluate("studio.fps")
    assert page.evaluate("studio.history.undo.length") == steps + 1
    assert page.locator("#outliner [data-object=beats]").count() == 1
    page.evaluate("studio.undo()")
    page.wait_for_function("() => !studio.tracks.has('beats.cue') && !studio.objectOf('beats')")
    assert page.errors == []


def test_a_file_over_200_mb_is_refused_on_the_page_and_changes_nothing(studio, _page, tmp_path):
    page = _page(studio)
    before = project(studio)
    big = tmp_path / "huge.wav"
    with big.open("wb") as out:                                  # a sparse file: 201 MiB of nothing
        out.truncate(201 * 2**20)
    page.set_input_files("[data-testid=import-audio]", str(big))
    page.wait_for_function("() => document.querySelector('[data-testid=sound-status]').textContent.includes('not imported')",
                           timeout=60_000)
    text = page.locator("[data-testid=sound-status]").text_content()
    assert "huge.wav" in text and "209715200 bytes" in text
    assert project(studio) == before
    assert not (tmp_path / "studio.sounds").exists()


def test_a_changed_or_missing_sound_is_a_notice_on_the_page(tmp_path, _page):
    from sketchanim.project.store import Project
    from sketchanim.studio.defaults import default_scene
    from sketchanim.studio.sounds import SoundShelf
    from studio_browser import studio_server

    path = tmp_path / "show.sketchanim"                        # made without a Session: no reducer processes here
    shelf = SoundShelf(path, [])
    sounds = [shelf.stored(name, _wav(tmp_path / name, 1.0).read_bytes()) for name in ("gone.wav", "edited.wav")]
    with Project(path) as made:
        made.save(default_scene(), {}, sounds=sounds)
    (tmp_path / "show.sounds" / "gone.wav").unlink()
    _wav(tmp_path / "show.sounds" / "edited.wav", 1.5)
    with studio_server(path) as url:
        page = _page(url)
        page.wait_for_function("() => sounds.report().length === 1")        # the changed one still plays
        notices = page.locator("[data-testid=notices]").text_content()
        assert "gone.wav" in notices and "missing" in notices
        assert "edited.wav" in notices and "changed" in notices
        rows = page.locator("[data-testid=sound-list]").text_content()
        assert "missing" in rows and "changed" in rows
        assert {s["name"]: s["status"] for s in project(url)["sounds"]} == {"gone.wav": "missing", "edited.wav": "changed"}
