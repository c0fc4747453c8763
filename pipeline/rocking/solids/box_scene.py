"""A box of the inventory with a depth and a known azimuth on a record with two horizontal components: its 3D
model's body (:mod:`.box3d`), one run, and the planar scene that stands for it where its other base axis is
certified (:mod:`.box_planar`). :mod:`.solid3d` makes it a :class:`~.scene.Scene` the screening stores like any
other.

Frames: the model's x is the record's first horizontal and its y is 90 deg counter-clockwise of it seen from above,
that is the record's second horizontal reversed; the box's width axis is at ``azimuth_deg`` in that frame.
"""

from __future__ import annotations

import math

import numpy as np

from ...constants import G
from ..block import BlockShape
from ..geometry import effective_restitution
from ..scene import Physics
from ..settings import SimulationConfig
from .alternate import alternate
from .box3d import Box, BoxOutcome, box_from_corner, housner_e_box, simulate_box
from .box_handback import box_model
from .box_planar import planar_box_scene
from .contact3d import Contact3DOutcome
from .contact_start import Start
from .family import SolidFamily


def box_of(shape: BlockShape, *, restitution_factor: float = 1.0) -> Box:
    """The 3D model's :class:`~.box3d.Box` of an inventory box with a depth: its flat landings keep the ratio of
    the declared restitution (NaN: Housner's) to Housner's value in the plane of its width."""
    b, h = shape.width_m / 2.0, shape.height_m / 2.0
    e_h = housner_e_box(b, h)
    e = float(effective_restitution(np.array(shape.restitution), e_h, restitution_factor))
    return Box(half_width_m=b, half_depth_m=shape.depth_m / 2.0, half_height_m=h, mu=shape.mu,
               restitution_ratio=e / e_h if e_h > 0.0 else 0.0)


def _tipping_tans(box: Box) -> tuple[float, ...]:
    """The tans of its static tipping angles about the edges across its width and across its depth, b / h and
    d / h (half sizes) [-]."""
    return box.half_width_m / box.half_height_m, box.half_depth_m / box.half_height_m


def _drawn(box: Box, azimuth_deg: float, *, R_m: float, alpha: float, mu: float,
           restitution: float) -> tuple[Box, float]:
    """The box of one draw: its depth-to-width ratio kept, at the drawn azimuth [deg]."""
    ratio = box.half_depth_m / box.half_width_m
    return box_from_corner(R_m, alpha, 2.0 * ratio * R_m * math.sin(alpha), mu=mu, restitution=restitution), azimuth_deg


def _run(h1, h2, vertical, dt_s: float, box: Box, azimuth_deg: float, *, settings: SimulationConfig,
         g_ms2: float = G, amplitude: float = 1.0) -> BoxOutcome:
    """The 3D box model on the record (the models' frame: the second horizontal reversed), all scaled by
    ``amplitude``."""
    av = None if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, dtype=float)
    return simulate_box(amplitude * np.asarray(h1, dtype=float), -amplitude * np.asarray(h2, dtype=float), av,
                        dt_s, box, azimuth_deg=azimuth_deg, g_ms2=g_ms2, rtol=settings.rtol, atol_alpha=settings.atol)


def _alternated(ax, ay, az, dt_s: float, box: Box, azimuth_deg: float, start: Start | None, *, g_ms2: float,
                settings: SimulationConfig) -> Contact3DOutcome:
    """The contact model handed back to the box's exact model on every edge it rocks on without slipping
    (:func:`~.alternate.alternate`, the exact model at the settings' tolerances)."""
    model = box_model(box, dt_s=dt_s, g_ms2=g_ms2, rtol=settings.rtol, atol_alpha=settings.atol)
    return alternate(ax, ay, az, dt_s, model, azimuth_deg, start, g_ms2=g_ms2)


#: The boxes' family (:class:`~.family.SolidFamily`).
BOX = SolidFamily(physics=Physics.rocking3d, tipping_tans=_tipping_tans, drawn=_drawn, run=_run,
                  certified_scene=planar_box_scene, alternated=_alternated)
