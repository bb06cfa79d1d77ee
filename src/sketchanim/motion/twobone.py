"""Two-bone analytic inverse kinematics (a leg or an arm): the frames of a limb's upper
and lower bones reaching from a joint to a target, bending toward a direction, and the
frame arithmetic a pose needs (a child's frame in its parent's, a frame's quaternion).

A frame is a rotation given by its columns: the world directions of its x, y and z axes,
each a 3-tuple. A bone lies along its rest -y. Scalar arithmetic (no numpy), so the
page's copy (``studio/web/js/twobone.js``) does the same operations in the same order.
"""

from __future__ import annotations

import math

Vec = tuple[float, float, float]
Frame = tuple[Vec, Vec, Vec]


def two_bone(root: Vec, target: Vec, upper: float, lower: float, front: Vec) -> tuple[Frame, Frame]:
    """The world frames of a limb's upper and lower bones (``upper`` and ``lower`` long)
    from a joint at ``root`` reaching for ``target``, the distance clamped to the limb's
    reach (just short of straight, just longer than folded), the middle joint bending
    toward ``front`` (its part off the root-target line; +y, or +z for a limb along y,
    where that part is under 1e-6, too short to give a direction to the digits kept); each
    bone's rest +z turns toward ``front`` too.

    >>> up, low = two_bone((0.0, 1.0, 0.0), (0.0, 0.4, 0.0), 0.5, 0.5, (0.0, 0.0, 1.0))
    >>> [round(v, 6) + 0.0 for v in up[1]], [round(v, 6) + 0.0 for v in low[1]]   # +y: back up each bone
    ([0.0, 0.6, -0.8], [0.0, 0.6, 0.8])
    """
    dx, dy, dz = target[0] - root[0], target[1] - root[1], target[2] - root[2]
    d = math.sqrt(dx * dx + dy * dy + dz * dz)
    l1, l2 = upper, lower
    longest = (l1 + l2) * (1.0 - 1e-9)
    shortest = abs(l1 - l2) + 1e-6 * (l1 + l2)
    if d > 1e-12:
        ux, uy, uz = dx / d, dy / d, dz / d
    else:
        ux, uy, uz = 0.0, -1.0, 0.0
    d = longest if d > longest else shortest if d < shortest else d
    px, py, pz = front
    along = px * ux + py * uy + pz * uz
    nx, ny, nz = px - along * ux, py - along * uy, pz - along * uz
    n = math.sqrt(nx * nx + ny * ny + nz * nz)
    if n < 1e-6:                        # the limb points (nearly) along ``front``: bend toward +y (or +z)
        px, py, pz = (0.0, 1.0, 0.0) if abs(uy) < 0.9 else (0.0, 0.0, 1.0)
        along = px * ux + py * uy + pz * uz
        nx, ny, nz = px - along * ux, py - along * uy, pz - along * uz
        n = math.sqrt(nx * nx + ny * ny + nz * nz)
    nx, ny, nz = nx / n, ny / n, nz / n
    c1 = (l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d)
    c2 = (l2 * l2 + d * d - l1 * l1) / (2.0 * l2 * d)
    s1 = math.sqrt(max(0.0, 1.0 - c1 * c1))
    s2 = math.sqrt(max(0.0, 1.0 - c2 * c2))
    first = bone((ux * c1 + nx * s1, uy * c1 + ny * s1, uz * c1 + nz * s1),
                 (nx * c1 - ux * s1, ny * c1 - uy * s1, nz * c1 - uz * s1))
    second = bone((ux * c2 - nx * s2, uy * c2 - ny * s2, uz * c2 - nz * s2),
                  (nx * c2 + ux * s2, ny * c2 + uy * s2, nz * c2 + uz * s2))
    return first, second


def bone(down: Vec, front: Vec) -> Frame:
    """The frame of a bone along ``down`` (its rest -y) with its rest +z on ``front``
    (both unit, perpendicular).

    >>> [[v + 0.0 for v in axis] for axis in bone((0.0, -1.0, 0.0), (0.0, 0.0, 1.0))]
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    y = (-down[0], -down[1], -down[2])
    z = front
    return (y[1] * z[2] - y[2] * z[1], y[2] * z[0] - y[0] * z[2], y[0] * z[1] - y[1] * z[0]), y, z


def local_frame(parent: Frame, child: Frame) -> Frame:
    """The child's frame in the parent's (``parent^T child``), as columns too.

    >>> turn = ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0))      # a quarter turn about y
    >>> local_frame(turn, turn)
    ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    """
    (a, b, c), (d, e, f), (g, h, k) = parent
    return tuple((a * x + b * y + c * z, d * x + e * y + f * z, g * x + h * y + k * z)
                 for x, y, z in child)  # type: ignore[return-value]


def frame_quaternion(m: Frame) -> tuple[float, float, float, float]:
    """The unit quaternion ``(x, y, z, w)``, ``w >= 0``, of the rotation with columns
    ``m`` (Shepperd's method: the largest of the four squares first).

    >>> [round(v, 6) for v in frame_quaternion(((0.0, 0.0, -1.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)))]
    [0.0, 0.707107, 0.0, 0.707107]
    """
    m00, m10, m20 = m[0]
    m01, m11, m21 = m[1]
    m02, m12, m22 = m[2]
    tr = m00 + m11 + m22
    if tr > 0.0:
        k = math.sqrt(tr + 1.0) * 2.0
        w, x, y, z = 0.25 * k, (m21 - m12) / k, (m02 - m20) / k, (m10 - m01) / k
    elif m00 > m11 and m00 > m22:
        k = math.sqrt(1.0 + m00 - m11 - m22) * 2.0
        w, x, y, z = (m21 - m12) / k, 0.25 * k, (m01 + m10) / k, (m02 + m20) / k
    elif m11 > m22:
        k = math.sqrt(1.0 + m11 - m00 - m22) * 2.0
        w, x, y, z = (m02 - m20) / k, (m01 + m10) / k, 0.25 * k, (m12 + m21) / k
    else:
        k = math.sqrt(1.0 + m22 - m00 - m11) * 2.0
        w, x, y, z = (m10 - m01) / k, (m02 + m20) / k, (m12 + m21) / k, 0.25 * k
    n = math.sqrt(x * x + y * y + z * z + w * w)
    if w < 0.0:
        n = -n
    return x / n, y / n, z / n, w / n
