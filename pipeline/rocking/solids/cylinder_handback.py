"""The cylinder's exact model (:mod:`.cylinder3d`) as the alternation (:mod:`.alternate`) takes it: the contact model
hands a cylinder back to it wherever the cylinder rolls on its base's rim, the one rim point it turns on (or the two
neighbours of the side between them) sticking and no other point loaded.

The exact model's state is the contact model's orientation and rate in its Euler angles (:func:`rim_state`): with the
axis ``e3`` and the line of nodes ``e_n`` = (-sin phi, cos phi, 0), the rate is
``omega = phi' e_z + theta' e_n + psi' e3`` (:mod:`.cylinder3d`), so ``theta' = omega . e_n`` and phi', psi' solve::

    phi' + psi' cos theta = omega . e_z,    phi' cos theta + psi' = omega . e3

whose determinant is sin^2 theta: the difference phi' - psi' is taken as omega . (e_z - e3) / (1 - cos theta) with
``1 - cos theta = 2 sin^2(theta / 2)``, so that it keeps its digits at a small tilt. The contact model's body is the
cylinder's rim as a polygon of 32 points (:func:`~.convex_body.cylinder_body`), the exact model's a circle: the
state is carried over whole, and the place of the contact on the rim follows from it in each model.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from .alternate import ExactModel
from .contact3d import Contact3DOutcome
from .cylinder3d import Cylinder, WobbleOutcome, housner_e, simulate_cylinder
from .handoff3d import CylinderState


def cylinder_model(cylinder: Cylinder, azimuth_deg: float, *, dt_s: float, g_ms2: float, rtol: float,
                   atol_alpha: float) -> ExactModel:
    """The cylinder's exact model on the ground sampled at ``dt_s`` [s] (tolerances ``rtol``, ``atol_alpha``) for
    :func:`~.alternate.alternate` (its x axis at ``azimuth_deg`` at rest), with Housner's restitution (the contact
    model's plastic impacts at a pivot)."""
    housner = cylinder._replace(restitution=housner_e(cylinder.radius_m, cylinder.half_height_m))
    body = cylinder.convex()

    def run(ax, ay, az, state: CylinderState) -> WobbleOutcome:
        """The exact model from ``state`` at the first sample of the ground (ax, ay, az) [m s-2]."""
        return simulate_cylinder(ax, ay, az, dt_s, housner, g_ms2=g_ms2, rtol=rtol, atol_alpha=atol_alpha,
                                 start=state)

    def turning(state: CylinderState):
        """How the cylinder turns at ``state`` (:meth:`~.handoff3d.CylinderState.turning`)."""
        return state.turning(cylinder, azimuth_deg)

    return ExactModel(body=body, edges=rim_edges(len(body.vertices) // 2), run=run,
                      state_at=lambda out: rim_state(out, azimuth_deg), turning=turning,
                      ending=lambda exact: turning(exact.end), at_rest=_at_rest,
                      barrier_m=math.hypot(cylinder.radius_m, cylinder.half_height_m))


def rim_edges(rim_points: int) -> np.ndarray:
    """Where the cylinder turns on its base's rim (the contact model's vertices 0 to ``rim_points`` - 1, in order
    round it): each point alone, and each with the next (the side between them) [-]."""
    i = np.arange(rim_points, dtype=np.int64)
    return np.concatenate([np.column_stack([i, i]), np.column_stack([i, (i + 1) % rim_points])])


def rim_state(out: Contact3DOutcome, azimuth_deg: float) -> CylinderState:
    """The exact model's state where the contact model stopped on the rim (its ``q_end``, ``rate_end_rad_s``), the
    cylinder's x axis at ``azimuth_deg`` at rest (see the module)."""
    w, x, y, z = (float(v) for v in np.asarray(out.q_end, dtype=float))
    attitude = Rotation.from_quat([x, y, z, w])
    phi, theta, spin = attitude.as_euler("ZYZ")
    e3 = attitude.apply([0.0, 0.0, 1.0])
    omega = np.asarray(out.rate_end_rad_s, dtype=float)
    theta_rate = float(omega @ np.array([-math.sin(phi), math.cos(phi), 0.0]))
    along_z, along_axis = float(omega[2]), float(omega @ e3)
    total = (along_z + along_axis) / (1.0 + math.cos(theta))                          # phi' + psi'
    difference = float(omega @ (np.array([0.0, 0.0, 1.0]) - e3)) / (2.0 * math.sin(0.5 * theta) ** 2)
    return CylinderState(float(theta), float(phi), float(spin) - math.radians(azimuth_deg), theta_rate,
                         0.5 * (total + difference), 0.5 * (total - difference))


def _at_rest(exact: WobbleOutcome) -> bool:
    """The exact segment ran to the record's end and ended at rest, flat and still."""
    end = exact.end
    return end.theta == 0.0 and end.theta_rate == 0.0 and end.phi_rate == 0.0 and end.psi_rate == 0.0 \
        and exact.theta[-1] == 0.0
