"""The animation model: scene, attributes, tracks, the recorder and playback, and every
change as an undoable command run by a history (no UI, no files)."""
