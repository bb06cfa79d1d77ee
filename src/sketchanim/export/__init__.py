"""Export: what the model and mocap hold, prepared for files. Scenes' tracks within the
float32 budget (refitted from their takes where needed), reduced clips and markers,
and sample tables' paths, as tracks by path for the one glTF writer
(:mod:`sketchanim.formats.gltf_tracks`); reduced clips and markers by extension
(:mod:`~sketchanim.export.files`)."""
