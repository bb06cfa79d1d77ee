"""File formats: readers and writers by format (tables, BVH, ASF/AMC, C3D, JSON, glTF, USD); one glTF animation
writer over tracks by path (:mod:`~sketchanim.formats.gltf_tracks`); every writer atomic; no reduction runs here."""
