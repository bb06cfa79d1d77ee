"""What storing a curve in float32 costs its tolerance: the budget a reducer may use so
that a file played in float32 still stays within the tolerance.

A client plays a file's keys and key times as float32, and computes in float32 (Blender
evaluates F-curves in float32, three.js keeps float32 results). So every curve meant for
a file is reduced, or checked, against the tolerance less what float32 can move it
(:func:`float32_margin`): mocap reductions aim at these budgets, and the scene export
refits a track that is not within them. Where the margin would take more than half of a
tolerance (a fine tolerance, values far from the origin, or times late in a long
recording), the tolerance is refused (:func:`margin_refusal`): no file could promise it.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import maximum_filter1d

from sketchanim.errors import ArgumentError

#: float32's unit roundoff: storing a number as float32 moves it by at most this, relative.
EPS32 = 2.0**-24

#: float32 roundings a played value may gather: its keys, a client's own float32
#: arithmetic (a joint's world position, down its chain).
ROUNDINGS = 16

#: The least share of a tolerance a budget keeps for the reducer: a tolerance float32's
#: margin would take more of is refused (a curve reduced to a sliver of its tolerance
#: would be keyed at nearly every sample).
KEEP = 0.5

#: float32 roundings of time a played value may gather, each moving it by its speed times
#: the rounding: the key times on either side, the time played, the fraction between keys.
TIME_ROUNDINGS = 4

#: Seconds around a sample whose fastest step sets its time margin in the budgets: a
#: rounded key time moves the curve over the spans beside that key, and a reduced take's
#: spans are long only where it moves slowly. A fast move early in a take (a jump into
#: the first pose) so costs nothing late in it.
REACH_S = 1.0


def float32_margin(times: np.ndarray, size: float, speed: float | np.ndarray) -> float | np.ndarray:
    """How far a curve of values up to ``size`` (a norm), moving at up to ``speed`` per
    second over ``times``, may move once stored and played in float32: ``ROUNDINGS``
    roundings of its values, and ``TIME_ROUNDINGS`` of its times (a time rounded moves
    the value by the speed times the rounding).

    ``speed`` is one number for the whole curve (the margin then holds at its latest
    time), or one per time (n, ...): the margin at each time, from that time's speed and
    how late it is (the budgets here take each sample's speed within ``REACH_S``).

    >>> m = float32_margin(np.array([0.0, 30.0]), 200.0, 300.0)     # a hips in cm, 30 s
    >>> bool(1e-4 < m < 1e-2)
    True
    >>> per = float32_margin(np.array([0.0, 30.0]), 200.0, np.array([300.0, 300.0]))
    >>> bool(per[1] == m and per[0] < m)
    True
    """
    late = np.abs(np.asarray(times, dtype=float))
    if np.ndim(speed):
        span = late.reshape(late.shape + (1,) * (np.ndim(speed) - 1))
    else:
        span = float(late.max()) if len(late) else 0.0
    return EPS32 * (ROUNDINGS * size + TIME_ROUNDINGS * speed * span)


def margin_refusal(asked: float, margin: float, size_share: float, subject: str, moving: str, *,
                   field: str = "tol", unit: str = "", whose: str = "the times", keep: float = KEEP) -> ArgumentError:
    """The error refusing a tolerance ``asked`` of which float32's ``margin`` would take
    more than ``1 - keep`` (half, by default): an
    :class:`~sketchanim.errors.ArgumentError` naming ``field``, the tolerance asked for
    ``subject`` (where it is asked: a track, a joint, a frame), what float32 may move it
    by and why (``moving``: the values' size and speed), and the advice: a larger
    tolerance, and where the times' share of the margin is the larger (more than
    ``size_share``, the share of the values' size), ``whose`` nearer 0. Every refusal of
    a budget here, and compact clips' frame by frame, is worded by it.

    Parameters
    ----------
    asked, margin, size_share : float
        The tolerance, :func:`float32_margin`, and the part of it from the values' size
        alone (in the tolerance's units).
    subject, moving : str
        Where the tolerance is asked (``"for joint 'hips'"``, or ``""``), and what moves
        it (``"points up to 200 from the origin, moving up to 300 per s"``).
    field, unit, whose : str
        The argument refused, the units of the tolerance and the margin after their
        numbers (``" degrees"``, or ``""``), and whose times start late
        (``"the clip's times"``).
    keep : float
        The share of ``asked`` the budget had to keep (``KEEP``, said "twice").

    Returns
    -------
    ArgumentError
        For the caller to raise.

    Examples
    --------
    >>> print(margin_refusal(1e-4, 2e-4, 1e-5, "", "moving up to 2 per s"))
    tol: 0.0001 is less than twice what float32 may move it (0.0002: moving up to 2 per s): ask for a larger tolerance, or start the times nearer 0
    """
    subject = f" {subject}" if subject else ""
    advice = f", or start {whose} nearer 0" if margin > 2 * size_share else ""
    times = "twice" if keep == 0.5 else f"{1 / (1 - keep):.3g} times"
    return ArgumentError(field, f"{asked:.6g}{unit}{subject} is less than {times} what float32 may move it "
                                f"({margin:.3g}{unit}: {moving}): ask for a larger tolerance{advice}")


def position_budget(times: np.ndarray, points: np.ndarray, tol: float, *, field: str = "tol",
                    subject: str = "", whose: str = "the times", keep: float = KEEP) -> float:
    """The distance a reducer may use of ``tol`` for points (n, d) sampled at ``times``
    (n,) so that the float32 file still plays within ``tol``: ``tol`` less
    :func:`float32_margin`, at least ``keep`` of ``tol``.

    Parameters
    ----------
    times : numpy.ndarray
        Sample times (n,), as the file will hold them.
    points : numpy.ndarray
        Samples (n, d).
    tol : float
        The distance promised.
    field, subject, whose : str
        How a refusal names the tolerance, where it was asked, and whose times start
        late (:func:`margin_refusal`).
    keep : float
        The least share of the tolerance the budget keeps (``KEEP``: half; less for a
        tolerance a caller derived as a share of another, tightened to hold it).

    Returns
    -------
    float
        The budget: ``budget + float32_margin(...) <= tol``. Samples that are not
        finite or times that do not increase (an infinite margin), or a ``tol`` that is
        not positive: ``tol / 2``, for the reducer to refuse them as it does.

    Raises
    ------
    ArgumentError
        Naming ``field``, where the margin is more than ``1 - keep`` of ``tol`` (a fine
        tolerance, points far from the origin, or late times): no float32 file keeps it.

    Examples
    --------
    >>> t = np.arange(100) / 30
    >>> 0.49 < position_budget(t, np.c_[100 * np.sin(t), 90 + 0 * t, t], 0.5) < 0.5
    True
    >>> position_budget(t + 600, np.c_[100 * np.sin(t), 90 + 0 * t, t], 1e-3)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: tol: 0.001 is less than twice what float32 may move it (0.0145: ...): ask for a larger tolerance, or start the times nearer 0
    """
    t = np.asarray(times, dtype=float)
    x = np.asarray(points, dtype=float).reshape(len(t), -1)
    speed = _sample_speeds(t, np.linalg.norm(np.diff(x, axis=0), axis=1) / np.diff(t))
    size = float(np.linalg.norm(x, axis=1).max()) if len(t) else 0.0
    margins = float32_margin(t, size, speed)
    margin = float(margins.max(initial=0.0))
    if not np.isfinite(margin) or not tol > 0:          # samples or a tolerance the reducer refuses itself
        return tol / 2
    if margin > (1 - keep) * tol:
        i = int(np.argmax(margins))
        raise margin_refusal(tol, margin, float(float32_margin(t[:0], size, 0.0)), subject,
                             f"points up to {size:.4g} from the origin, moving up to {speed[i]:.3g} per s "
                             f"within {REACH_S:g} s of {t[i]:.6g} s (sample {i})", field=field, whose=whose,
                             keep=keep)
    return tol - margin


def rotation_budget(times: np.ndarray, quats: np.ndarray, tol_deg: float, *, field: str = "rot_tol_deg",
                    subject: str = "", whose: str = "the times", keep: float = KEEP) -> float:
    """The angle (degrees) a reducer may use of ``tol_deg`` for quaternions (n, 4)
    sampled at ``times`` (n,), so that the float32 file still plays within ``tol_deg``
    (an error ``e`` in a unit quaternion turns it by up to ``2 e`` radians): ``tol_deg``
    less the margin, at least ``keep`` of ``tol_deg``.

    Parameters
    ----------
    times : numpy.ndarray
        Sample times (n,), as the file will hold them.
    quats : numpy.ndarray
        Quaternions (n, 4).
    tol_deg : float
        The angle promised, in degrees.
    field, subject, whose, keep
        As :func:`position_budget`'s.

    Returns
    -------
    float
        The budget in degrees: it leaves float32's margin of ``tol_deg``. Samples that
        are not finite or times that do not increase, or a ``tol_deg`` that is not
        positive: ``tol_deg / 2``, for the reducer to refuse them as it does.

    Raises
    ------
    ArgumentError
        Naming ``field``, where the margin is more than ``1 - keep`` of ``tol_deg`` (a fine
        tolerance, or a fast turn late in a long recording).

    Examples
    --------
    >>> from scipy.spatial.transform import Rotation
    >>> t = np.arange(100) / 30
    >>> q = Rotation.from_euler("Z", 3 * t[:, None]).as_quat()
    >>> 0.499 < rotation_budget(t, q, 0.5) < 0.5
    True
    >>> rotation_budget(t + 600, q, 0.01, subject="for joint 'hips'")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    sketchanim.errors.ArgumentError: rot_tol_deg: 0.01 degrees for joint 'hips' is less than twice ... or start the times nearer 0
    """
    t = np.asarray(times, dtype=float)
    margins, speed = _turn_margins(t, quats)
    margin = float(margins.max(initial=0.0))
    if not np.isfinite(margin) or not tol_deg > 0:      # samples or a tolerance the reducer refuses itself
        return tol_deg / 2
    if margin > (1 - keep) * tol_deg:
        i = int(np.argmax(margins))
        raise margin_refusal(tol_deg, margin, float(np.degrees(2 * float32_margin(t[:0], 1.0, 0.0))), subject,
                             f"turning up to {np.degrees(2 * speed[i]):.3g} degrees per s within {REACH_S:g} s of "
                             f"{t[i]:.6g} s (sample {i})",
                             field=field, unit=" degrees", whose=whose, keep=keep)
    return tol_deg - margin


def rotation_margin(times: np.ndarray, quats: np.ndarray) -> float:
    """What float32 may turn quaternions (n, 4) sampled at ``times`` (n,) by, in
    degrees: what :func:`rotation_budget` leaves of a tolerance.

    >>> from scipy.spatial.transform import Rotation
    >>> t = np.arange(100) / 30
    >>> q = Rotation.from_euler("Z", 3 * t[:, None]).as_quat()
    >>> bool(abs(rotation_margin(t, q) - (0.5 - rotation_budget(t, q, 0.5))) < 1e-12)
    True
    """
    return float(_turn_margins(np.asarray(times, dtype=float), quats)[0].max(initial=0.0))


def _sample_speeds(times: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """Each sample's speed (n,): the fastest of the ``steps`` (n - 1,) within ``REACH_S``
    of it at least (as many steps either side as the shortest sampling interval fits in
    ``REACH_S``: more where the sampling is sparser or uneven, never less)."""
    if not len(steps):
        return np.zeros(len(times))
    interval = float(np.diff(times).min())
    reach = int(min(np.ceil(REACH_S / interval), len(steps))) if interval > 0 else len(steps)
    both = np.maximum(np.concatenate([steps[:1], steps]), np.concatenate([steps, steps[-1:]]))
    return maximum_filter1d(both, 2 * reach + 1, mode="nearest")


def _turn_margins(times: np.ndarray, quats: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each sample's float32 margin of quaternions (n, 4), in degrees, and its turn speed
    (:func:`_sample_speeds`) of the unit quaternion, in radians per second (half the
    rotation's)."""
    q = np.asarray(quats, dtype=float)
    turn = np.arccos(np.clip(np.abs(np.sum(q[1:] * q[:-1], axis=1)) / (np.linalg.norm(q[1:], axis=1)
                                                                     * np.linalg.norm(q[:-1], axis=1)), 0, 1))
    speed = _sample_speeds(times, turn / np.diff(times))
    return np.degrees(2 * float32_margin(times, 1.0, speed)), speed
