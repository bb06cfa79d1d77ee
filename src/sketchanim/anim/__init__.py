"""The animation model: scene, attributes, tracks, playback (no UI, no files)."""
