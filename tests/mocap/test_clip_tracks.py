"""A reduced clip is a set of tracks addressed by path (``hips.orientation``,
``hips.position``) on the animation model's track type; its JSON document is the one
the joint-indexed clips wrote (version 1), which still loads."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from sketchanim.anim.tracks import ContinuousTrack
from sketchanim.mocap.clip_reduction import ReducedClip, reduce_clip
from sketchanim.mocap.markers import Markers, reduce_markers
from sketchanim.motion.skeleton import Clip, Skeleton
from sketchanim.reducer.metric import rotation_angle

#: A clip document written before clips held tracks (hips rotating and translating, knee rotating).
OLD_DOCUMENT = Path(__file__).with_name("clip_v1.json")


def test_a_version_1_document_loads_as_tracks_and_writes_back_the_same() -> None:
    text = OLD_DOCUMENT.read_text()
    clip = ReducedClip.from_json(text, source=OLD_DOCUMENT.name)
    assert list(clip.tracks) == ["hips.orientation", "knee.orientation", "hips.position"]
    assert all(isinstance(t.track, ContinuousTrack) for t in clip.tracks.values())
    assert clip.tracks["hips.position"].track.evaluate([0.05]).tolist() == [[0.0, 90.0, 0.0]]
    assert json.loads(clip.to_json()) == json.loads(text)


def test_tracks_by_path_are_what_the_joints_play() -> None:
    s = Skeleton(("hips", "knee"), (-1, 0), np.array([[0.0, 90, 0], [0, -45, 0]]))
    t = np.arange(120) / 60
    clip = Clip.still(s, t)
    clip.rotations[:, 1] = Rotation.from_euler("X", np.sin(3 * t)[:, None]).as_quat()
    clip.translating[0] = True
    clip.translations[:, 0] = np.c_[np.sin(t), 90 + 0 * t, t]
    reduced = reduce_clip(clip, 0.05, 0.5)
    assert list(reduced.tracks) == ["hips.orientation", "knee.orientation", "hips.position"]
    frames = reduced.sample(t)
    knee = reduced.tracks["knee.orientation"]
    assert knee.spline.k == 1                                       # straight pieces: glTF's LINEAR keys
    assert np.array_equal(reduced.sample(t, spherical=False).rotations[:, 1], knee.track.evaluate(t))
    for way in (True, False):                                       # glTF's rule, and Blender's
        played = reduced.sample(t, spherical=way).rotations[:, 1]
        assert np.degrees(rotation_angle(played, clip.rotations[:, 1])).max() <= 0.5
    assert np.array_equal(frames.translations[:, 0], reduced.tracks["hips.position"].track.evaluate(t))
    assert reduced.joint_track(1, "position") is None
    assert reduced.tracks["knee.orientation"].error <= 0.5


def test_markers_are_tracks_of_pieces() -> None:
    t = np.arange(20) / 100
    p = np.repeat(t[:, None, None], 3, axis=2).repeat(2, axis=1)
    p[5:8, 1] = np.nan
    reduced = reduce_markers(Markers(("LFHD", "RFHD"), t, p), 0.001)
    assert {path: len(track.pieces) for path, track in reduced.tracks.items()} == {"LFHD.position": 1,
                                                                                "RFHD.position": 2}
    assert reduced.names == ("LFHD", "RFHD")
