"""Roundings that hold planted joints still: of the values a filter can store near each
key of a leg (:func:`~sketchanim.formats.gltf_compact.roundings`), the one that keeps
the planted joints below it steadiest in the world.

Rounding every key to the nearest stored value leaves each joint off by up to half a
step, at random from frame to frame; down a leg these add up at the foot, which then
trembles on the ground. In motion capture the rounding, not the keys chosen, is what
makes a planted foot slide more than the source's. Picking, key by key, among the
roundings a step either side lets the joints of a leg cancel each other's at
the foot, for a few per cent more bytes than the nearest: the planted joints' error is
aimed at its own average over a few frames (:data:`SMOOTHING`), since sliding is a
speed.

A leg is a joint every end below which is held on the ground somewhere
(:meth:`PlantedRounding.legs`; the hips carry the arms too, whose points have no room
to spare). Its keys are picked top down, each pick only where every point below the
joint stays within its world bound, either way the file plays: measured at the key's
frame, and bounded between keys (a turn moves a point no more than the turn's chord
times its distance from the joint, plus the shell).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.ndimage import gaussian_filter1d
from scipy.spatial.transform import Rotation

from sketchanim.motion.kinematics import shell_error
from sketchanim.motion.skeleton import Skeleton
from sketchanim.reducer.metric import rotation_angle

#: Frames (a Gaussian's sigma) over which the planted joints' error is averaged to give
#: what the picks aim at: 1.5, 2 and 3 made files within 0.3% of each other on the
#: project's shared clips (3 the smallest at 1 cm); aiming the error itself at zero let
#: the feet slide more, the picks patchy where the bound leaves no room.
SMOOTHING = 3.0


def _rotated(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vectors ``v`` (..., 3) turned by unit quaternions ``q`` (..., 4, scalar last)."""
    axis, w = q[..., :3], q[..., 3:]
    twice = 2 * np.cross(axis, v)
    return v + w * twice + np.cross(axis, twice)


def _world_change(rotation: bool, up: np.ndarray, unit: np.ndarray | None, change: np.ndarray) -> np.ndarray:
    """What a key's change does in the world under its parent's rotations ``up`` (R, 3,
    3): a turn (R, 3, 3) about the joint, from the quaternions ``unit`` to ``change``
    (R, 4), or a shift (R, 3) by the translations ``change``."""
    if rotation:
        local = Rotation.from_quat(change).as_matrix() @ np.swapaxes(Rotation.from_quat(unit).as_matrix(), 1, 2)
        return up @ local @ np.swapaxes(up, 1, 2)
    return np.einsum("rij,rj->ri", up, change)


def _changed(rotation: bool, delta: np.ndarray, at: np.ndarray, points: np.ndarray, turns: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray]:
    """Points (R, ..., 3) and their world rotations (R, ..., 3, 3) after ``delta``
    (:func:`_world_change`): turned about the joint at ``at`` (R, 3), or shifted."""
    lead = (len(points),) + (1,) * (points.ndim - 2) + (3,)
    if not rotation:
        return points + delta.reshape(lead), turns
    centre = at.reshape(lead)
    return centre + np.einsum("rij,r...j->r...i", delta, points - centre), np.einsum("rij,r...jk->r...ik", delta, turns)


@dataclass
class PlantedRounding:
    """The clip as its file plays at the frames, both ways (spherically as glTF, and
    component-wise as Blender's F-curves), kept up to date as keys are picked.

    Attributes
    ----------
    skeleton : Skeleton
    source : tuple of ndarray
        The source's world rotations (n, J, 3, 3) and positions (n, J, 3).
    turns, positions : ndarray
        The file's, each way it plays: (2, n, J, 3, 3) and (2, n, J, 3).
    bound : ndarray
        (n, J): the world bound of each joint at each frame.
    still : ndarray
        (n, J): the frames each joint is held on the ground.
    shell : float
        A joint's world error is its distance from the source's plus ``shell`` times
        the chord of their rotations' difference.
    moved : ndarray
        (n, J): at frames a changed key is played between, not at, the most the
        changes may have moved each joint's points (what ``turns`` and ``positions``
        do not follow).
    """

    skeleton: Skeleton
    source: tuple[np.ndarray, np.ndarray]
    turns: np.ndarray
    positions: np.ndarray
    bound: np.ndarray
    still: np.ndarray
    shell: float
    moved: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.moved = np.zeros(self.bound.shape)

    def below(self, joint: int) -> np.ndarray:
        """The joint and its descendants, as a mask (J,).

        >>> s = Skeleton(("a", "b", "c"), (-1, 0, 0), np.zeros((3, 3)))
        >>> z = np.zeros((2, 1, 3, 3))
        >>> PlantedRounding(s, (z[0], z[0]), z, z, z[0, ..., 0], z[0, ..., 0] > 0, 0.0).below(1).tolist()
        [False, True, False]
        """
        return np.array([joint in chain for chain in self.skeleton.chains()])

    def legs(self) -> np.ndarray:
        """(J,) the joints with ends below them, every one held on the ground somewhere.

        >>> s = Skeleton(("hips", "leg", "foot", "arm"), (-1, 0, 1, 0), np.zeros((4, 3)))
        >>> z = np.zeros((2, 1, 4, 3, 3))
        >>> held = np.array([[False, False, True, False]])
        >>> PlantedRounding(s, (z[0], z[0, ..., 0]), z, z[..., 0], held * 0.0, held, 0.0).legs().tolist()
        [False, True, True, False]
        """
        ends = self.still.any(axis=0)
        leaves = np.setdiff1d(np.arange(len(self.skeleton)), self.skeleton.parents)
        return np.array([ends[leaves[self.below(j)[leaves]]].all() for j in range(len(self.skeleton))])

    def frames(self, joint: int, rotation: bool) -> np.ndarray:
        """(n,) the frames where a joint held on the ground moves with ``joint``'s
        rotation (a joint strictly below it) or translation (it, or one below).

        >>> s = Skeleton(("hip", "foot"), (-1, 0), np.zeros((2, 3)))
        >>> z = np.zeros((2, 2, 2, 3, 3))
        >>> held = np.array([[False, True], [False, False]])
        >>> state = PlantedRounding(s, (z[0], z[0, ..., 0]), z, z[..., 0], held * 0.0, held, 0.0)
        >>> state.frames(0, True).tolist(), state.frames(1, True).tolist(), state.frames(1, False).tolist()
        ([True, False], [False, False], [True, False])
        """
        below = self.below(joint)
        if rotation:
            below[joint] = False
        return self.still[:, below].any(axis=1)

    def pick(self, joint: int, rotation: bool, keys: np.ndarray, frames: np.ndarray, current: np.ndarray,
             near: np.ndarray, allowed: np.ndarray) -> np.ndarray:
        """Of ``near`` (K, F, d: quaternions scalar last, or translations; NaN: none),
        the values ``joint`` could hold at ``frames`` (F,: of its track's keyed frames
        ``keys``, (n,)) instead of ``current`` (F, d), the index of the one that puts
        the planted joints below it nearest what they aim at (as glTF
        plays), or -1 where none is nearer than ``current``; only ``allowed`` (K, F)
        ones that keep every point below the joint within its world bound, at the
        frame and between keys, either way the file plays. The state is moved by the
        picks.

        >>> s = Skeleton(("hip", "foot"), (-1, 0), np.array([[0.0, 1, 0], [0, -1, 0]]))
        >>> eye = np.broadcast_to(np.eye(3), (2, 5, 2, 3, 3)).copy()
        >>> source = (eye[0], np.array([[[0.0, 1, 0], [0, 0, 0]]] * 5))
        >>> played = source[1].copy()
        >>> played[:, 1, 0] = [0.01, -0.01, 0.01, -0.01, 0.01]            # the foot trembles by 1 cm
        >>> state = PlantedRounding(s, source, eye, np.stack([played, played]), np.full((5, 2), 0.05),
        ...                         np.array([[False, True]] * 5), 0.0)
        >>> turns = Rotation.from_euler("z", [[0.6], [-0.6]], degrees=True).as_quat()    # picks at hand
        >>> near = np.repeat(turns[:, None], 5, axis=1)                                 # (K=2, F=5, 4)
        >>> rest = np.array([0.0, 0, 0, 1])
        >>> state.pick(0, True, np.ones(5, bool), np.arange(5), np.tile(rest, (5, 1)), near,
        ...            np.ones((2, 5), bool)).tolist()
        [1, 0, 1, 0, 1]
        >>> bool(np.abs(state.positions[:, :, 1, 0]).max() < 0.002)
        True
        """
        below = self.below(joint)
        joints = np.flatnonzero(below)
        ends = below & self.still.any(axis=0)                                    # the planted joints below
        parent = self.skeleton.parents[joint]
        at = self.positions[:, frames, joint]                                     # (2, F, 3)
        up = self.turns[:, frames, parent] if parent >= 0 else np.broadcast_to(np.eye(3), (2, len(frames), 3, 3))
        held = self.still[frames][:, ends]                                        # (F, L)
        feet = self.positions[0, frames][:, ends]
        goal = self.source[1][frames][:, ends] + self._aim(ends)[frames]
        points = self.positions[:, frames][:, :, joints]                          # (2, F, D, 3)
        if rotation:
            unit = current / np.linalg.norm(current, axis=-1, keepdims=True)
            near = near / np.linalg.norm(near, axis=-1, keepdims=True)           # as a client plays them
            angle = rotation_angle(near.reshape(-1, 4), np.broadcast_to(unit, near.shape).reshape(-1, 4))
            move = 2 * np.sin(angle.reshape(near.shape[:2]) / 2)                  # each pick's turn, as a chord
            local = np.einsum("fji,flj->fli", self.turns[0, frames, joint], feet - at[0, :, None])
            moved = at[0, None, :, None] + np.einsum("fij,kflj->kfli", up[0], _rotated(near[:, :, None], local[None]))
            change = np.where(np.isnan(near[..., :1]), unit[None], near)         # (K, F, 4): NaN, no change
        else:
            change = np.nan_to_num(near - current[None])                          # (K, F, 3), in the parent's frame
            move = np.where(np.isnan(near[..., 0]), np.inf, np.linalg.norm(change, axis=-1))
            moved = feet[None] + np.einsum("fij,kfj->kfi", up[0], change)[:, :, None]
        cost = np.where(held[None], np.sum((moved - goal[None]) ** 2, axis=-1), 0.0).sum(axis=-1)           # (K, F)
        now = np.where(held, np.sum((feet - goal) ** 2, axis=-1), 0.0).sum(axis=-1)
        viable = allowed & ~np.isnan(cost) & (move <= self._between(joint, rotation, keys)[frames][None])
        cost = np.where(viable & (cost < now * (1 - 1e-6)), cost, np.inf)        # nearer, not a tie
        order = np.argsort(cost, axis=0)
        out = np.full(len(frames), -1)
        waiting = np.flatnonzero(np.isfinite(cost[order[0], np.arange(len(frames))]))
        for rank in range(len(near)):                 # each frame's nearest pick that keeps the world bound
            k = order[rank, waiting]
            waiting, k = waiting[np.isfinite(cost[k, waiting])], k[np.isfinite(cost[k, waiting])]
            if not len(waiting):
                break
            fit = self._fits(joint, rotation, frames[waiting], joints, up[:, waiting], at[:, waiting],
                             points[:, waiting], unit[waiting] if rotation else None, change[k, waiting],
                             move[k, waiting])
            out[waiting[fit]] = k[fit]
            waiting = waiting[~fit]
        take = np.flatnonzero(out >= 0)
        self._move(joint, rotation, keys, frames[take], joints, up[:, take], at[:, take], points[:, take],
                   unit[take] if rotation else None, change[out[take], take], move[out[take], take])
        return out

    def _aim(self, ends: np.ndarray) -> np.ndarray:
        """(n, L, 3): where the planted joints ``ends`` aim, from the source's: their
        error (as glTF plays) averaged over :data:`SMOOTHING` frames of their own
        planted frames."""
        weight = self.still[:, ends].astype(float)[..., None]
        error = (self.positions[0][:, ends] - self.source[1][:, ends]) * weight
        return gaussian_filter1d(error, SMOOTHING, axis=0) / np.maximum(gaussian_filter1d(weight, SMOOTHING, axis=0),
                                                                        1e-12)

    def _errors(self, frames: np.ndarray, joints: np.ndarray) -> np.ndarray:
        """(F, D): the world error of ``joints`` at ``frames``, the worse way it plays."""
        out = shell_error(self.turns[:, frames][:, :, joints], self.positions[:, frames][:, :, joints],
                          self.source[0][frames][:, joints], self.source[1][frames][:, joints], self.shell)
        return out.max(axis=0) + self.moved[frames][:, joints]

    def _levers(self, joint: int, rotation: bool, joints: np.ndarray, frames: np.ndarray | slice = slice(None)
                ) -> np.ndarray:
        """(n or F, D): how far a unit move of ``joint``'s track moves each of
        ``joints``' points, at most: a turn's chord times their distance from the joint
        plus the shell; a translation's length."""
        positions = self.positions[:, frames]
        if not rotation:
            return np.ones((positions.shape[1], len(joints)))
        return np.linalg.norm(positions[:, :, joints] - positions[:, :, [joint]], axis=-1).max(axis=0) + self.shell

    def _between(self, joint: int, rotation: bool, keys: np.ndarray) -> np.ndarray:
        """(n,) at each key (``keys``: (n,) the keyed frames), how far it may move what
        plays and keep every point below ``joint`` within its world bound at the frames
        it is played between, before and after it."""
        joints = np.flatnonzero(self.below(joint))
        room = (self.bound[:, joints] - self._errors(np.arange(len(keys)), joints))
        each = np.clip(room / np.maximum(self._levers(joint, rotation, joints), 1e-300), 0, None).min(axis=1)
        at = np.flatnonzero(keys)
        each[at] = np.inf                                                   # a key's own frame: measured
        after = np.minimum.reduceat(np.r_[each, np.inf], np.r_[at, len(each)])[:-1]
        out = np.zeros(len(keys))
        out[at] = np.minimum(after, np.r_[np.inf, after[:-1]])
        return out

    def _fits(self, joint: int, rotation: bool, frames: np.ndarray, joints: np.ndarray, up: np.ndarray,
              at: np.ndarray, points: np.ndarray, unit: np.ndarray | None, change: np.ndarray,
              move: np.ndarray) -> np.ndarray:
        """(F,): whether a pick at each of ``frames`` keeps every point below the joint
        within its world bound there, either way the file plays: where the pick's move
        times a point's lever fits in the room left, so does the point; the others are
        measured (``change`` (F, d): the picks, as unit quaternions, or as translations
        less the current ones; ``up``, ``at``, ``points``: the parent's rotation, the
        joint's and its points' positions there, each way)."""
        room = self.bound[frames][:, joints] - self._errors(frames, joints)                      # (F, D)
        doubt = np.argwhere(move[:, None] * self._levers(joint, rotation, joints, frames) > room)  # (P, 2)
        f, d = doubt.T
        key, point = frames[f], joints[d]
        worst = np.zeros(len(f))
        for way in (0, 1):
            delta = _world_change(rotation, up[way, f], unit[f] if rotation else None, change[f])
            there, turned = _changed(rotation, delta, at[way, f], points[way, f, d], self.turns[way, key, point])
            error = shell_error(turned, there, self.source[0][key, point], self.source[1][key, point], self.shell)
            worst = np.maximum(worst, error)
        misses = worst + self.moved[key, point] > self.bound[key, point]
        return np.bincount(f[misses], minlength=len(frames)) == 0

    def _move(self, joint: int, rotation: bool, keys: np.ndarray, frames: np.ndarray, joints: np.ndarray,
              up: np.ndarray, at: np.ndarray, points: np.ndarray, unit: np.ndarray | None, change: np.ndarray,
              move: np.ndarray) -> None:
        """The state after ``joint``'s keys at ``frames`` take ``change`` (as
        :meth:`_fits`), ``move`` apart from what they held."""
        for way in (0, 1):                                    # the same local change under each way's parent
            delta = _world_change(rotation, up[way], unit, change)
            rows = frames[:, None], joints
            self.positions[way][rows], self.turns[way][rows] = _changed(rotation, delta, at[way], points[way],
                                                                        self.turns[way][rows])
        at_keys = np.flatnonzero(keys)
        between = np.flatnonzero(~keys)
        if len(at_keys) > 1 and len(between):
            spent = np.zeros(len(keys))
            spent[frames] = move
            step = np.maximum(spent[at_keys][:-1], spent[at_keys][1:])       # each span's keys' moves, the larger
            span = np.clip(np.searchsorted(at_keys, between) - 1, 0, len(at_keys) - 2)
            self.moved[np.ix_(between, joints)] += step[span][:, None] * self._levers(joint, rotation, joints,
                                                                                      between)
