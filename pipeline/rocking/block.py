"""One block, from the inventory to the compiled kernels.

A block is described once, by :class:`BlockShape`: what the inventory says of it (its size, friction,
restitution, rocking plane, and the fields the next models read, such as its depth and its kind of shape), built
and read by keyword only. Everything the simulator takes is derived from it in one place each:

* :func:`dynamics` gives the nominal :class:`Block` (Housner's p, alpha, R and the effective restitution);
* :func:`pipeline.uncertainty.sampling.sample_block` gives its uncertainty samples (the same derivation on the
  sampled sizes, through :func:`~.geometry.effective_restitution`);
* :func:`rigid_block` gives the compiled models' :class:`~.structures.RigidBlock`.

A new model that needs more of a block (a depth, a measured body's pivots and inertia) adds a keyword field with
a default to :class:`BlockShape` (the inventory fills it), and derives what it needs from it in its own module.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import IntEnum
from typing import TYPE_CHECKING

import numpy as np

from ..compiled import jit
from ..constants import G
from .geometry import effective_restitution, geometry
from .structures import RigidBlock

if TYPE_CHECKING:
    from ..assemblies.stack import StackPlace
    from ..shapes.scan import ScannedShape


class ShapeKind(IntEnum):
    """The kind of body a block is."""

    box = 0             # a rectangular block; planar models take it as infinitely deep in its rocking plane
    cylinder = 1        # a solid cylinder standing on its base (width: the diameter); 3D on two horizontals
    scanned = 2         # a body given by its scan (inventory column ``mesh``): planar, two-sided (rocking.scanned)


#: The inventory's ``object`` column: an asset (blank or ``asset``), or ``natural``: a precariously balanced rock, a
#: rock of a hazard study, which is monitored, never anchored (:mod:`pipeline.risk` words its recommendation so).
NATURAL = "natural"
OBJECT_KINDS = ("asset", NATURAL)


@dataclass(frozen=True, kw_only=True)
class BlockShape:
    """A block as the inventory describes it (nominal values; keyword-only).

    Attributes
    ----------
    height_m, width_m : float
        Full height and full base width in the rocking plane [m].
    mu : float
        Friction coefficient [-].
    restitution : float
        The declared angular-velocity restitution [-] (NaN: Housner's value).
    azimuth_deg : float
        Azimuth of the rocking plane [deg clockwise from north] (NaN: unknown, scanned).
    depth_m : float
        Base dimension perpendicular to ``width_m`` [m] (NaN: not given; the planar models take the block as
        infinitely deep).
    kind : ShapeKind
        The kind of body.
    scan : ScannedShape or None
        The settled scan of a ``scanned`` body (its height and width are then its equivalent rectangle's:
        :func:`pipeline.shapes.plane.equivalent_rectangle`).
    stack : StackPlace or None
        The stack the block is a body of, and which body (None: it stands alone on its base).
    """

    height_m: float
    width_m: float
    mu: float
    restitution: float = math.nan
    azimuth_deg: float = math.nan
    depth_m: float = math.nan
    kind: ShapeKind = ShapeKind.box
    scan: ScannedShape | None = field(default=None, compare=False)
    stack: StackPlace | None = field(default=None, compare=False)


@dataclass(frozen=True, kw_only=True)
class Block:
    """A rigid block for the planar simulator (keyword-only), derived from a :class:`BlockShape` by
    :func:`dynamics` (or given directly, for tests and idealised cases).

    Attributes
    ----------
    p : float
        Frequency parameter sqrt(3 g / (4 R)) [rad s-1].
    alpha : float
        Slenderness atan(b / h) [rad].
    e : float
        Restitution, the angular-velocity ratio across an impact [-] (0 for a block too squat to rock).
    R_m : float
        Distance from a base corner to the centre of mass [m].
    mu : float
        Friction coefficient [-].
    g_ms2 : float
        Gravity [m s-2].
    """

    p: float
    alpha: float
    e: float
    R_m: float
    mu: float
    g_ms2: float = G


def dynamics(shapes: list[BlockShape], *, g_ms2: float = G) -> list[Block]:
    """The nominal :class:`Block` of each shape: Housner's geometry and the effective restitution (the declared
    value, else Housner's, clipped to [0, 1]: 0 for a block too squat to rock), computed over all shapes at once."""
    if not shapes:
        return []
    geom = geometry(np.array([s.height_m for s in shapes]), np.array([s.width_m for s in shapes]), g_ms2=g_ms2,
                    cylinder=np.array([s.kind == ShapeKind.cylinder for s in shapes]))
    e = effective_restitution(np.array([s.restitution for s in shapes]), geom.e_housner)
    return [Block(p=float(geom.p[j]), alpha=float(geom.alpha[j]), e=float(e[j]), R_m=float(geom.R[j]),
                  mu=float(s.mu), g_ms2=g_ms2) for j, s in enumerate(shapes)]


@jit
def rigid_block(p, alpha, e, R, mu, g, rest_ratio, linear=False, stop_mu=math.inf) -> RigidBlock:
    """The compiled models' :class:`~.structures.RigidBlock`, its half-width, half-height and inertia derived once.

    Parameters
    ----------
    p : float
        Frequency parameter [rad s-1].
    alpha : float
        Slenderness [rad].
    e : float
        Restitution [-].
    R : float
        Corner distance [m].
    mu : float
        Friction coefficient [-].
    g : float
        Gravity [m s-2].
    rest_ratio : float
        The contact model's rest rule [-].
    linear : bool
        The kernel's linearised equation of motion.
    stop_mu : float
        Where the kernel stops for the contact model (``inf``: never) [-].
    """
    # J = I_G / m of a rectangular block, R^2 / 3: the general contact model takes it for a cylinder too (its own
    # is a^2/4 + h^2/3), while pure rocking takes the cylinder's own p
    return RigidBlock(p=p, alpha=alpha, e=e, R=R, mu=mu, g=g, b=R * math.sin(alpha), h=R * math.cos(alpha),
                      J=R * R / 3.0, rest_ratio=rest_ratio, linear=linear, stop_mu=stop_mu)
