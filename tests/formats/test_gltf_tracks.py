"""The one glTF writer: tracks addressed by path become channels of the node named by
the path; a path glTF cannot animate, or without a node, is refused by name."""

from __future__ import annotations

import numpy as np
import pygltflib as gl
import pytest
from scipy.interpolate import BSpline

from sketchanim.errors import ArgumentError
from sketchanim.formats.gltf import Node
from sketchanim.formats.gltf_tracks import CurvePiece, ExportTrack, tracks_glb


def _piece(dim: int = 3) -> CurvePiece:
    s = BSpline(np.r_[[0.0] * 4, [1.0] * 4], np.linspace(0, 1, 4 * dim).reshape(4, dim), 3)
    return CurvePiece(0.0, 1.0, s, np.linspace(0, 1, 11), 1e-6)


def test_tracks_by_path_are_channels_of_their_nodes() -> None:
    tracks = [ExportTrack("arm.position", (_piece(),)), ExportTrack("hips.orientation", (_piece(4),)),
              ExportTrack("hips.scale", (_piece(),))]
    doc = gl.GLTF2.load_from_bytes(tracks_glb([Node("hips"), Node("arm", 0)], tracks, name="walk"))
    got = [(doc.nodes[c.target.node].name, c.target.path, doc.animations[0].samplers[c.sampler].interpolation)
           for c in doc.animations[0].channels]
    assert got == [("arm", "translation", "CUBICSPLINE"), ("hips", "rotation", "CUBICSPLINE"),
                   ("hips", "scale", "CUBICSPLINE")]
    doc = gl.GLTF2.load_from_bytes(tracks_glb([Node("hips"), Node("arm", 0)], tracks, keys="frames"))
    assert {doc.animations[0].samplers[c.sampler].interpolation for c in doc.animations[0].channels} == {"LINEAR"}


def test_a_marker_track_is_hidden_outside_its_pieces() -> None:
    first, second = _piece(), CurvePiece(2.0, 3.0, BSpline(np.r_[[2.0] * 4, [3.0] * 4], np.ones((4, 3)), 3),
                                         np.linspace(2, 3, 11), 1e-6)
    track = ExportTrack("LFHD.position", (first, second), shown=(0.0, 4.0, 0.1))
    doc = gl.GLTF2.load_from_bytes(tracks_glb([Node("LFHD")], [track]))
    assert [c.target.path for c in doc.animations[0].channels] == ["translation", "scale"]


@pytest.mark.parametrize("track, field", [
    (lambda: ExportTrack("box.color", (_piece(),)), "path"),
    (lambda: ExportTrack("box.position", (_piece(), _piece())), "pieces"),
])
def test_tracks_glTF_cannot_write_are_refused(track, field) -> None:  # noqa: ANN001
    with pytest.raises(ArgumentError, match=field):
        track()


def test_a_track_without_its_node_is_refused_by_path() -> None:
    with pytest.raises(ArgumentError, match="no node for ghost.position"):
        tracks_glb([Node("box")], [ExportTrack("ghost.position", (_piece(),))])
    with pytest.raises(ArgumentError, match="keys"):
        tracks_glb([Node("box")], [], keys="sometimes")
