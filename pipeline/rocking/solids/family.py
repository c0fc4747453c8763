"""What the shared 3D code (:mod:`.solid3d`) asks of a family of solid bodies: one record per family, so that the
screening, the draws and the margins treat a box and a cylinder alike, and a new body is one module and one line of
:data:`~.solid3d.FAMILIES`.

The family's module defines its record (:data:`~.cylinder_scene.CYLINDER`, :data:`~.box_scene.BOX`); nothing outside
it reads the body's type.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

from ..scene import Physics


class SolidFamily(NamedTuple):
    """A family of 3D bodies (the body's model and how it is placed, drawn and run).

    Attributes
    ----------
    physics : Physics
        the code its exact model's scenes carry
    tipping_tans : callable
        ``tipping_tans(body)``: the tan of each static tipping angle as it stands [-] (a cylinder's r / h; a box's
        b / h and d / h, half sizes)
    drawn : callable
        ``drawn(body, azimuth_deg, *, R_m, alpha, mu, restitution)``: the body of one draw of the declared
        uncertainty (its sampled R [m], alpha [rad], friction and restitution) and its azimuth in the model's frame
        [deg] (``azimuth_deg``: the drawn one, where the family has an azimuth)
    run : callable
        ``run(h1, h2, vertical, dt_s, body, azimuth_deg, *, settings, g_ms2, amplitude)``: its exact 3D model on a
        record's two horizontals (the second 90 deg clockwise of the first) and its vertical (None: none), all scaled
        by ``amplitude``; an outcome with ``theta``, ``azimuth``, ``flag``, ``handoff`` and the peak's fields
    certified_scene : callable or None
        ``certified_scene(h1, h2, vertical, dt_s, body, azimuth_deg, *, settings, g_ms2, amplitude, history)``: a
        cheaper scene that stands for the 3D one where it is certified (a box's planar scene in the plane of its
        width, :mod:`.box_planar`); None where the family has none
    alternated : callable or None
        ``alternated(ax, ay, az, dt_s, body, azimuth_deg, start, *, g_ms2, settings)``: the contact model's outcome
        of a scene the exact model left, handed back to the exact model wherever it can take the scene again (a
        box on an edge, :mod:`.alternate`), for a verdict only; None where the family has none (the contact model
        alone)
    """

    physics: Physics
    tipping_tans: Callable[[Any], tuple[float, ...]]
    drawn: Callable[..., tuple[Any, float]]
    run: Callable[..., Any]
    certified_scene: Callable[..., Any] | None = None
    alternated: Callable[..., Any] | None = None
