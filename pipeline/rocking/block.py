"""One block as the simulator takes it: a typed structure, not a dict of keyword arguments."""

from __future__ import annotations

import math
from typing import NamedTuple

from ..compiled import jit
from ..constants import G
from .structures import RigidBlock


class Block(NamedTuple):
    """A rigid rectangular block for the simulator (from :meth:`pipeline.blocks.Inventory.rocking_blocks`).

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
    return RigidBlock(p=p, alpha=alpha, e=e, R=R, mu=mu, g=g, b=R * math.sin(alpha), h=R * math.cos(alpha),
                      J=R * R / 3.0, rest_ratio=rest_ratio, linear=linear, stop_mu=stop_mu)
