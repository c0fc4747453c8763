"""One block as the simulator takes it: a typed structure, not a dict of keyword arguments."""

from __future__ import annotations

from typing import NamedTuple

from ..constants import G


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
