"""Contacts kept: where the source plants an end joint on the ground, the export keeps it
there. Detected contacts follow a generated walker's own stance; a planted joint's world
error on its planted frames stays within ``CONTACT_SHARE`` of the tolerance; and a
planted foot slides (median speed while planted, sampled at 60 Hz) no more in the
export than in the source, plus 1 cm/s, on real walks and generated ones."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sketchanim.errors import ArgumentError
from sketchanim.export.mocap_gltf import clip_glb
from sketchanim.formats.clip_files import read_clip
from sketchanim.mocap.clip_reduction import reduce_clip
from sketchanim.mocap.contacts import CONTACT_SHARE, SLIDING_RATE, SLIDING_SLACK_M_S, planted, sliding
from sketchanim.mocap.world_reduction import reduce_clip_world
from sketchanim.motion import walk
from sketchanim.motion.skeleton import JOINT_CHANNELS, ROOT_CHANNELS, Clip
from threejs_client import three_play
from walk_paths import segments, straight

#: The default export's tolerances: 0.5 cm, 0.5 degree; the world mode's shell, m.
TOL_M, TOL_DEG, SHELL_M = 0.005, 0.5, 0.03
#: Real walks: recorded at 120 Hz or more (sampled at 60 Hz, every other frame), and one
#: at 30 Hz (sampled between its frames too).
WALKS = ["bvh/xia_angry_13_000.bvh", "amc/cmu_11_01.amc", "bvh/cmu_01_01_playground_jumps.bvh",
         "bvh/bandai1_walk_happy_001.bvh"]


def walker_clip(path: np.ndarray, tall: float = 1.7, every: int = 1) -> tuple[Clip, np.ndarray]:
    """The walker's clip following ``path`` (its marker per tick, metres) and its stance,
    at ``every``-th tick."""
    skeleton = walk.humanoid(tall)
    done = walk.walk(skeleton, path)
    n = len(path)
    _, translations = skeleton.rest_pose(n)
    translations[:, 0] = done.root
    translating = np.zeros(len(skeleton), bool)
    translating[0] = True
    channels = (ROOT_CHANNELS,) + (JOINT_CHANNELS,) * (len(skeleton) - 1)
    clip = Clip(skeleton, np.arange(n)[::every] / walk.RATE, done.rotations[::every], translations[::every],
                np.ones(len(skeleton), bool), translating, channels, unit_m=1.0)
    return clip, done.stance[::every]


def assert_contacts_kept(clip: Clip, reduced, tol: float, unit: float) -> None:
    """Planted joints within the contact bound on their frames, and sliding no more than
    the source's plus ``SLIDING_SLACK_M_S``, either way the curves play."""
    held = planted(clip)
    assert held.any()
    err = reduced.world_errors(clip)[held]
    assert err.max() <= CONTACT_SHARE * tol * (1 + 1e-9), err.max() / tol
    source = sliding(clip, contacts=held) * unit
    for way in (True, False):                         # as glTF plays straight rotation pieces, and as Blender
        export = sliding(clip, lambda t: reduced.sample(t, spherical=way), contacts=held) * unit
        assert export <= source + SLIDING_SLACK_M_S, (way, source, export)


def test_a_walkers_detected_contacts_are_its_stance() -> None:
    clip, stance = walker_clip(straight(1.4, 6.0))
    held = planted(clip)
    names = clip.skeleton.names
    assert {names[j] for j in np.flatnonzero(held.any(axis=0))} == {"l_toe", "r_toe"}
    for side, toe in enumerate(("l_toe", "r_toe")):
        found = held[:, names.index(toe)]
        assert found.sum() > 0.3 * len(found)
        assert np.mean(stance[found, side]) > 0.95, toe            # found only where the foot stands


@settings(max_examples=6, deadline=None)
@given(st.floats(0.8, 2.0), st.floats(-0.6, 0.6), st.floats(1.5, 1.9), st.sampled_from([1, 2, 4]))
def test_a_generated_walks_planted_feet_slide_no_more_than_the_walks(speed: float, turn: float, tall: float,
                                                                     every: int) -> None:
    """At 120, 60 and 30 Hz (the last sampled between its frames)."""
    clip, _ = walker_clip(segments([(1.0, 0.0, 0.0), (2.0, speed, 0.0), (2.0, speed, turn)]), tall, every)
    assert_contacts_kept(clip, reduce_clip(clip, TOL_M, TOL_DEG), TOL_M, 1.0)


def test_the_world_mode_keeps_a_generated_walks_contacts() -> None:
    clip, _ = walker_clip(segments([(1.0, 0.0, 0.0), (3.0, 1.5, 0.3)]))
    assert_contacts_kept(clip, reduce_clip_world(clip, TOL_M, SHELL_M), TOL_M, 1.0)


def test_no_contacts_asked_holds_none_and_a_bad_shape_is_named() -> None:
    clip, _ = walker_clip(straight(1.4, 3.0))
    free = reduce_clip(clip, TOL_M, TOL_DEG, contacts=np.zeros((len(clip.times), len(clip.skeleton)), bool))
    assert free.reduced_bytes() < reduce_clip(clip, TOL_M, TOL_DEG).reduced_bytes()
    with pytest.raises(ArgumentError, match="contacts"):
        reduce_clip(clip, TOL_M, TOL_DEG, contacts=np.zeros((3, 2), bool))


@pytest.mark.realdata
@pytest.mark.parametrize("name", WALKS)
def test_real_walks_planted_feet_slide_no_more_than_the_source(data_dir: Path, name: str) -> None:
    clip = read_clip(data_dir / name)
    unit = clip.guess_unit_m()
    assert unit is not None
    assert_contacts_kept(clip, reduce_clip(clip, TOL_M / unit, TOL_DEG), TOL_M / unit, unit)
    assert_contacts_kept(clip, reduce_clip_world(clip, TOL_M / unit, SHELL_M / unit), TOL_M / unit, unit)


@pytest.mark.realdata
def test_three_js_plays_a_real_walk_with_its_contacts_kept(data_dir: Path, tmp_path: Path) -> None:
    """The default export as written (.glb, curves), played by three.js at 60 Hz."""
    clip = read_clip(data_dir / "bvh/xia_angry_13_000.bvh")
    unit = clip.guess_unit_m()
    assert unit is not None
    (tmp_path / "walk.glb").write_bytes(clip_glb(reduce_clip(clip, TOL_M / unit, TOL_DEG)))

    def played(times: np.ndarray) -> Clip:
        nodes = three_play(tmp_path / "walk.glb", times)
        names = clip.skeleton.names
        rotations = np.stack([nodes[n]["quaternion"] for n in names], axis=1)
        translations = np.stack([nodes[n]["position"] for n in names], axis=1)      # clip units, under a scale node
        return Clip(clip.skeleton, times, rotations, translations, clip.rotating, clip.translating, clip.channels)

    held = planted(clip)
    source = sliding(clip, contacts=held, rate=SLIDING_RATE) * unit
    export = sliding(clip, played, contacts=held, rate=SLIDING_RATE) * unit
    assert export <= source + SLIDING_SLACK_M_S, (source, export)
