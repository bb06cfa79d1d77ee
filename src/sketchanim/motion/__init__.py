"""Motion channels above the reducer: orientations (quaternion and Euler curves)."""

from sketchanim.motion.rotations import (
    ROTATION_MODES,
    RotationStream,
    continuous_quaternions,
    euler_angles,
    reduce_rotations,
)

__all__ = ["ROTATION_MODES", "RotationStream", "continuous_quaternions", "euler_angles", "reduce_rotations"]
