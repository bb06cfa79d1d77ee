"""Beats baked from a sound: its onsets (librosa's onset detector on the decoded file)
as an event track, as Blender bakes a sound to F-curves.

:func:`onsets` is the work (seconds of audio analysis: the app runs it beside the
model's thread); :func:`beat_change` the History step that puts the track, at the
sound's offset plus each onset, on an event attribute: an existing one, or a new cue
object's (``beats.cue`` unless the animator names another).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import soundfile

from sketchanim.anim.attributes import EVENT
from sketchanim.anim.commands import Change
from sketchanim.anim.player import Player
from sketchanim.anim.scene import SceneObject, check_name
from sketchanim.anim.tracks import DiscreteTrack
from sketchanim.errors import ArgumentError, FileFormatError

#: Where beats go when the animator names no event attribute: a cue object's event.
DEFAULT_PATH = "beats.cue"
#: The label each beat carries.
BEAT = "beat"


def onsets(path: Path) -> np.ndarray:
    """The times (s, from the sound's start, increasing) of the onsets in the sound at
    ``path``: librosa's spectral-flux onset detector on its channels' mean.
    :class:`FileFormatError` naming the file if it cannot be decoded.

    >>> import tempfile, librosa
    >>> path = Path(tempfile.mkdtemp()) / "clicks.wav"
    >>> soundfile.write(path, librosa.clicks(times=[0.5, 1.0, 1.5], sr=22050, length=44100), 22050)
    >>> bool(np.abs(onsets(path) - [0.5, 1.0, 1.5]).max() < 1 / 24)     # within a frame at 24 fps
    True
    """
    import librosa                      # heavy (numba): loaded for the first bake only

    try:
        samples, rate = soundfile.read(path, dtype="float32", always_2d=True)
    except (soundfile.LibsndfileError, RuntimeError, OSError) as err:
        raise FileFormatError(str(path), f"cannot be decoded for its beats ({err})") from None
    mono = samples.mean(axis=1)
    return np.asarray(librosa.onset.onset_detect(y=mono, sr=rate, units="time"), dtype=float)


def beat_change(player: Player, path: str, times: np.ndarray, sound: str) -> Change:
    """The History step putting an event track of a beat at each of ``times`` at
    ``path``: an event attribute of an existing object (its track replaced), or
    ``<new object>.cue``, a cue object made in the same step.

    >>> from sketchanim.anim.scene import Scene
    >>> player = Player(Scene())
    >>> step = beat_change(player, "beats.cue", np.array([0.5, 1.0]), "click.wav")
    >>> step.do(); player.tracks["beats.cue"].times, step.label
    ([0.5, 1.0], 'beats of click.wav on beats.cue')
    >>> step.undo(); list(player.scene.objects)
    []
    """
    scene = player.scene
    if not isinstance(path, str) or path.count(".") != 1:
        raise ArgumentError("path", f"must be 'object.attribute', got {path!r}")
    name, attribute = path.split(".")
    label = f"beats of {sound} on {path}"
    track = DiscreteTrack(path, EVENT, [float(t) for t in times], [BEAT] * len(times))
    if name in scene.objects:
        kind = scene.type(path)
        if kind.name != "event":
            raise ArgumentError("path", f"{path}: a {kind.name} attribute; beats go on an event attribute")
        return Change(player, label, {path: track})
    check_name(name, "object")
    if attribute != "cue":
        raise ArgumentError("path", f"{path}: a new cue object holds its beats in {name}.cue")
    cue = SceneObject(name, "cue")
    return Change(player, label, {path: track}, ((lambda: scene.insert(cue), lambda: scene.remove(name)),))
