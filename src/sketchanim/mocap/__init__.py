"""Motion capture: skeleton clips and marker sets reduced as tracks, in joint space or within a distance in the world."""
