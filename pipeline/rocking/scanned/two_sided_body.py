"""A body's rocking geometry in one vertical plane, one pivot on each side of its centre of mass: what the
two-sided model (:mod:`.two_sided`) and its reference solver (:mod:`pipeline.rocking.references.asymmetric`) rock,
and what :mod:`pipeline.shapes.plane` reads off a scan's hull.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin of the
Seismological Society of America, 53(2), 403-417 (the impact's angular momentum about the new pivot).
"""

from __future__ import annotations

import math
from typing import NamedTuple


class TwoSided(NamedTuple):
    """A body's rocking geometry in one vertical plane, per unit mass.

    Attributes
    ----------
    b_plus_m, b_minus_m : float
        Horizontal distances from G to the pivot on each side [m].
    com_height_m : float
        Height of G above the base [m].
    inertia_g_m2 : float
        Moment of inertia about G's axis normal to the plane, per unit mass [m2].
    """

    b_plus_m: float
    b_minus_m: float
    com_height_m: float
    inertia_g_m2: float

    def side(self, s: float) -> tuple[float, float, float]:
        """(alpha [rad], R [m], I about the pivot per unit mass [m2]) of side ``s`` (+1 or -1)."""
        b = self.b_plus_m if s > 0 else self.b_minus_m
        r = math.hypot(b, self.com_height_m)
        return math.atan2(b, self.com_height_m), r, self.inertia_g_m2 + r * r

    def impact_ratio(self, s: float) -> float:
        """omega+ / omega- at the impact that moves the pivot from side ``s`` to the other [-]."""
        a = self.inertia_g_m2 + self.com_height_m ** 2
        b_from, b_to = (self.b_plus_m, self.b_minus_m) if s > 0 else (self.b_minus_m, self.b_plus_m)
        return (a - b_from * b_to) / (a + b_to * b_to)


def rectangle(width_m: float, height_m: float) -> TwoSided:
    """The :class:`TwoSided` of a rectangular block (I_G = (w^2 + h^2) / 12 per unit mass)."""
    return TwoSided(width_m / 2, width_m / 2, height_m / 2, (width_m ** 2 + height_m ** 2) / 12.0)
