"""How a clip is reduced and written: one frozen object, checked once against
:data:`sketchanim.limits.LIMITS` and the choices each field takes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sketchanim.errors import ArgumentError, InputError
from sketchanim.formats.gltf_frames import KEYS
from sketchanim.limits import LIMITS, one_of
from sketchanim.mocap.clip_reduction import ORDER
from sketchanim.mocap.markers import Markers
from sketchanim.motion.skeleton import UNITS_M, Clip


@dataclass(frozen=True)
class ClipOptions:
    """How a clip (a skeleton's or C3D markers) is reduced and written; every field is
    checked when the object is made, numeric ranges against :data:`~sketchanim.limits.LIMITS`.

    Attributes
    ----------
    tol : float or None
        Position tolerance in the clip's units; None: ``tol_cm`` converted with the
        clip's unit.
    tol_cm : float
        Position tolerance in centimetres, used when ``tol`` is None.
    rot_tol_deg : float
        Rotation tolerance, degrees.
    units : str or None
        The clip's unit (a key of :data:`~sketchanim.motion.skeleton.UNITS_M`); None: the
        file's, else guessed from the figure's height.
    rate : float or None
        Frames per second of BVH / USD output (or of glTF keys with ``keys``
        ``"frames"``); None: the source's.
    skeleton : str or None
        ASF file for AMC input; None: found beside it.
    world : bool
        Skeletal clips: keep every joint, and every point ``shell_cm`` from a joint,
        within the distance in the world (:func:`~sketchanim.mocap.world_reduction.reduce_clip_world`),
        instead of every joint's rotation within ``rot_tol_deg``.
    shell_cm : float
        The shell's distance from each joint, centimetres.
    keys : {"curves", "frames", "compact"}
        glTF output: the curves exactly, or LINEAR keys at frames (``rate``) for
        importers that ignore tangents (:mod:`sketchanim.formats.gltf_frames`), or
        ``"compact"``: for a skeleton, the smallest file that plays within the distance
        in the world (every joint and every point ``shell_cm`` from one, as ``world``)
        at every frame, its keys picked from the source's frames and compressed
        (:mod:`sketchanim.export.compact_clip`); markers as keys at their frames.
    order : {2, 3, 4}
        Skeletal clips: the curves' order (:data:`~sketchanim.mocap.clip_reduction.ORDER`,
        2: straight pieces, glTF's LINEAR keys; 4: cubic, CUBICSPLINE keys).
    contacts : bool
        Skeletal clips: hold the end joints the source plants on the ground (feet:
        :func:`~sketchanim.mocap.contacts.planted`) within a tighter bound there, so
        that they slide no more than the source's; False bounds them as every other
        joint, for a smaller file.
    """

    tol: float | None = None
    tol_cm: float = 0.5
    rot_tol_deg: float = 0.5
    units: str | None = None
    rate: float | None = None
    skeleton: str | None = None
    world: bool = False
    shell_cm: float = 3.0
    keys: str = "curves"
    order: int = ORDER
    contacts: bool = True

    def __post_init__(self) -> None:
        for name in ("tol", "tol_cm"):
            if getattr(self, name) is not None:
                LIMITS["tol"].check(getattr(self, name), name)
        LIMITS["rot_tol_deg"].check(self.rot_tol_deg)
        if self.rate is not None:
            LIMITS["clip_rate"].check(self.rate)
        LIMITS["shell_cm"].check(self.shell_cm)
        if self.units is not None:
            one_of("units", self.units, tuple(UNITS_M))
        one_of("keys", self.keys, KEYS)
        if self.order not in (2, 3, 4):
            raise ArgumentError("order", f"a clip's curves are of order 2, 3 or 4 (what glTF keys hold), "
                                         f"got {self.order!r}")

    def unit_m(self, clip: Clip | Markers) -> float | None:
        """Metres per unit of ``clip``: ``units`` if given, else the file's, else (a
        skeleton) guessed from the figure's height."""
        if self.units:
            return UNITS_M[self.units]
        return clip.unit_m if isinstance(clip, Markers) else clip.guess_unit_m()

    def distance(self, clip: Clip | Markers) -> float:
        """The position tolerance for ``clip``, in its units (``clip.unit_m``, as
        :func:`~sketchanim.pipeline.clip.reduce_clip_file` sets it with :meth:`unit_m`)."""
        if self.tol is not None:
            return self.tol
        unit = clip.unit_m
        if unit is None:
            why = ("the file does not say" if isinstance(clip, Markers) else
                   f"its figure is {float(np.ptp(clip.skeleton.rest_positions(), axis=0).max()):.4g} units tall")
            raise InputError(f"cannot tell the clip's units ({why}); give tol=DISTANCE in its units or "
                             f"units=UNIT ({', '.join(UNITS_M)})")
        return self.tol_cm * 0.01 / unit

    def contacts_of(self, clip: Clip) -> np.ndarray | None:
        """The ``contacts`` argument of the clip reducers for ``clip``: None (they find
        the planted frames themselves), or with ``contacts`` False, no frame held.

        >>> from sketchanim.motion.skeleton import Skeleton
        >>> clip = Clip.still(Skeleton(("root",), (-1,), np.zeros((1, 3))), [0.0, 0.1])
        >>> ClipOptions().contacts_of(clip) is None, bool(ClipOptions(contacts=False).contacts_of(clip).any())
        (True, False)
        """
        return None if self.contacts else np.zeros((len(clip.times), len(clip.skeleton)), bool)
