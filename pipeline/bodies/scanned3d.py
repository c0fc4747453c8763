"""A body given by its scan, judged in 3D (``[simulation] scanned_model = "contact3d"``): the scan's hull moves on the
moving ground as one rigid convex body by the 3D contact model (:mod:`pipeline.rocking.scanned.hull3d`,
:mod:`pipeline.rocking.solids.contact3d`): it may slide, twist, rock on an edge or a corner, roll over its hull's
facets and lift off, under both horizontals and the vertical at once. Its registry entry, :data:`SCANNED_3D`,
claims every block with a scan when that model is chosen; otherwise the scanned body model in planes
(:mod:`.scanned`) claims it.

**The frame.** The contact model's x axis points to a compass azimuth (the body's settled x axis where the
inventory gives its azimuth and the record's azimuth is known, else the record's first horizontal), its y axis 90
degrees counter-clockwise of it seen from above; the horizontals are projected on both (one horizontal: along its
own azimuth). **The yaw.** Where the body's azimuth is given on a record of known azimuth, the body stands as
given; otherwise it is judged at every yaw of a :data:`YAW_STEP_DEG` grid, in turn, until one overturns it (the
worst yaw: overturned first, then the largest tilt). **Probabilities**: each draw of the declared uncertainty
(amplitude, the scan's width and height about G, friction; :func:`~pipeline.uncertainty.two_sided.draw_factors`) is
one run, at the worst yaw (``p_overturn``) and, where the yaw is not known, at the grid's yaws in turn
(``p_random_orientation``: the draws cycle over the grid). The restitution draw does not apply: the contacts are
plastic (Housner's rule at a pivot). **Margins**: the first factor on the record that overturns the body at the
worst yaw in the upward scan of :func:`~.factor_sweep.factor_sweep` (steps of ``margin_step``), from the factor at
which the ground's demand first reaches the at-rest threshold
min(mu, tan alpha_min) (:func:`~pipeline.rocking.solids.convex_body.base_threshold`). **Pulses** (``screen infer``):
along the direction the body tips in most easily (:func:`~pipeline.rocking.scanned.hull3d.smallest_tipping`), either
way.
"""

from __future__ import annotations

from ..rocking.block import BlockShape
from ..rocking.scanned.hull3d import scaled_scan, scan_body, smallest_tipping
from ..rocking.settings import ScannedModel, SimulationConfig
from ..rocking.solids.convex_body import ConvexBody
from .contract import Placement
from .convex3d import YAW_STEP_DEG as YAW_STEP_DEG  # the yaws of an unknown orientation, read here too
from .convex3d import ConvexBodies, convex_model


def body_of(shape: BlockShape, *, width: float = 1.0, height: float = 1.0, friction: float = 1.0) -> ConvexBody:
    """The contact model's body of the scanned ``shape``, stretched by a draw's factors."""
    assert shape.scan is not None
    scan = shape.scan if width == height == 1.0 else scaled_scan(shape.scan, width, height)
    return scan_body(scan, mu=shape.mu * friction)


def weakest_deg(shape: BlockShape) -> float:
    """The azimuth toward which the scan tips most easily, in its settled axes [deg]."""
    assert shape.scan is not None
    return float(smallest_tipping(shape.scan.hull_m, shape.scan.com_height_m, outlines=shape.scan.outlines)[1])


def _claims(shape: BlockShape, placement: Placement, settings: SimulationConfig) -> bool:
    return shape.scan is not None and settings.scanned_model == ScannedModel.contact3d


#: How an inventory row given by its scan becomes the contact model's body.
SCANNED_BODIES = ConvexBodies(body_of, weakest_deg)

#: A body given by its scan, in 3D on its hull, where ``[simulation] scanned_model = "contact3d"`` chooses it: its
#: kernel is the contact model the cylinder and the box hand over to.
SCANNED_3D = convex_model("scanned body in 3D", _claims, SCANNED_BODIES)
