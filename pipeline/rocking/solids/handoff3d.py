"""Where an exact 3D model hands its scene to the contact model (:mod:`.contact_scene`): the last state it
certified (:class:`BoxHandoff` of :mod:`.box3d`, :class:`CylinderHandoff` of :mod:`.cylinder3d`): a time and the
model's named state (:class:`BoxState`, :class:`CylinderState`), each able to say how the body turns there: its
orientation, its rate and a point of it on the ground that does not slip.

A box turns about its pivot corner (a corner, or either corner of an edge, or the corner an edge turns on while the
other slides); a cylinder rolls on the lowest point of its rim, whose arm from G is ``r`` = ((h sin theta - a cos
theta) cos phi, ... sin phi, h cos theta + a sin theta) in the frame turned by phi, and whose rate is theta' e_n +
phi' e_z + psi' e_3 (:mod:`.cylinder3d`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.spatial.transform import Rotation

from .box_kernel import CORNER, REST

#: The base corners of the kernel, counter-clockwise from above: c_k = (s_x b_x, s_y b_y, -h).
CORNER_SIGNS = ((1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0))


def base_corner(box, k: int) -> np.ndarray:
    """Base corner ``k`` of the box model (:data:`CORNER_SIGNS`) from G, in the box's axes [m]."""
    sx, sy = CORNER_SIGNS[k % 4]
    return np.array([sx * box.half_width_m, sy * box.half_depth_m, -box.half_height_m])


class BoxState(NamedTuple):
    """A state of the box model (:mod:`.box3d`; the kernel's ``y`` and contact, named).

    Attributes
    ----------
    q : ndarray, shape (4,)
        the orientation, a unit quaternion (w, x, y, z), body to world
    rate_rad_s : ndarray, shape (3,)
        the angular velocity in the world's axes [rad s-1]
    mode : int
        REST (flat), CORNER or EDGE (:mod:`.box_kernel`)
    pivot : int
        the corner it turns on (CORNER), the edge's first corner (EDGE); at rest the corner taken as its pivot
    """

    q: np.ndarray
    rate_rad_s: np.ndarray
    mode: int = CORNER
    pivot: int = 0

    def turning(self, box, azimuth_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The orientation, the rate [rad s-1] and the point of the box that does not slip (its pivot corner, in
        its principal axes from G [m]; corner 0 at rest) of this state; ``azimuth_deg``, the box's at rest, is
        already in the quaternion."""
        pivot = base_corner(box, 0 if self.mode == REST else self.pivot)
        return np.asarray(self.q, dtype=float), np.asarray(self.rate_rad_s, dtype=float), pivot


class CylinderState(NamedTuple):
    """A state of the cylinder model (:mod:`.cylinder3d`; the kernel's ``y``, named): the tilt, the azimuth of the
    tilt and the spin (ZYZ Euler angles) [rad] and their rates [rad s-1]."""

    theta: float
    phi: float
    psi: float
    theta_rate: float
    phi_rate: float
    psi_rate: float

    def turning(self, cylinder, azimuth_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The orientation (a unit quaternion (w, x, y, z), its x axis at ``azimuth_deg`` at rest), the rate in the
        world's axes [rad s-1] and the lowest point of the rim (in its principal axes from G [m]) of this state."""
        th, ph = self.theta, self.phi
        a, h = cylinder.radius_m, cylinder.half_height_m
        rot = Rotation.from_euler("ZYZ", [ph, th, self.psi + math.radians(azimuth_deg)])
        e_n, e_3 = np.array([-math.sin(ph), math.cos(ph), 0.0]), rot.apply([0.0, 0.0, 1.0])
        rate = self.theta_rate * e_n + np.array([0.0, 0.0, self.phi_rate]) + self.psi_rate * e_3
        lever, up = h * math.sin(th) - a * math.cos(th), h * math.cos(th) + a * math.sin(th)
        pivot = rot.inv().apply(-np.array([lever * math.cos(ph), lever * math.sin(ph), up]))
        x, y, z, w = rot.as_quat()
        return np.array([w, x, y, z]), rate, pivot


class BoxHandoff(NamedTuple):
    """The last state the box model certified before it first stopped or held (the start of the step whose contact
    force left the cone, or the instant at rest it would slide): where the 3D contact model goes on."""

    #: when [s] (from the record's first sample)
    t_s: float
    state: BoxState


class CylinderHandoff(NamedTuple):
    """The last state the cylinder model certified before the base would first slide or lift off (the start of
    that step): where the 3D contact model goes on."""

    #: when [s] (from the record's first sample)
    t_s: float
    state: CylinderState
