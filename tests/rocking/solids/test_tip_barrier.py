"""What a convex body needs to overturn (pipeline.rocking.solids.tip_barrier): the barrier against the closed forms
of a box, a cylinder's rim and a hexagonal prism rolling onto its next face (G's height over the edge it turns on),
the certificate at its boundaries, and the contact model's runs with it against the same runs followed to their
end (a second run, not a formula): the verdicts equal, the run cut short only once the record has ended."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.rocking.solids.contact3d import overturn_barrier, simulate_contact3d
from pipeline.rocking.solids.convex_body import ConvexBody, box_body, cylinder_body
from pipeline.rocking.solids.tip_barrier import NO_BARRIER, TipBarrier, below_barrier, tip_barrier

DT = 0.002
#: The barrier is a lower bound within the sampling's Lipschitz allowance: within this fraction below the closed form
#: on the bodies here (measured 0.4 % for the box, 0.2 % for the cylinder) [-]
BELOW = 0.01


def _prism(apothem_m: float, length_m: float) -> ConvexBody:
    """A hexagonal prism lying on a side face, its axis along x (G at the apothem's height); its smallest static
    tipping angle is 30 deg, rolling about a long edge onto the next face."""
    circum = apothem_m / math.cos(math.pi / 6.0)
    ring = [(circum * math.cos(a), circum * math.sin(a)) for a in np.radians(np.arange(0.0, 360.0, 60.0))]
    vertices = np.array([[sx * length_m / 2.0, y, z] for sx in (-1.0, 1.0) for y, z in ring])
    inertia = np.array([0.5 * circum ** 2, length_m ** 2 / 12.0 + 0.25 * circum ** 2,
                        length_m ** 2 / 12.0 + 0.25 * circum ** 2])                  # (close enough: speeds only)
    return ConvexBody(vertices, inertia, 0.8, tipping_rad=math.radians(30.0))


@pytest.mark.parametrize("body, exact_m", [
    (box_body(0.5, 0.5, 1.5, mu=0.6), math.hypot(0.25, 0.75)),
    (box_body(0.3, 0.4, 1.2, mu=0.6), math.hypot(0.15, 0.6)),                        # over the narrower base edge
    (cylinder_body(0.4, 1.6, mu=0.6), math.hypot(0.2 * math.cos(math.pi / 32), 0.8)),   # over a side of the rim
    (_prism(0.2, 1.5), 0.2 / math.cos(math.pi / 6.0)),                                 # over the long edge
], ids=["square box", "box", "cylinder", "hexagonal prism"])
def test_the_barrier_is_the_height_over_the_edge_the_body_tips_on_from_below(body, exact_m):
    """G's height balanced over the edge it tips over most easily (closed form), approached from below."""
    barrier = overturn_barrier(body)
    assert exact_m * (1.0 - BELOW) <= barrier.height_m <= exact_m
    assert barrier.low_m <= -np.min(body.vertices[:, 2]) < barrier.height_m       # G's height as it stands


def test_a_still_body_at_rest_is_below_the_barrier_and_one_with_its_energy_or_tilt_is_not():
    body = box_body(0.5, 0.5, 1.5, mu=0.6)
    barrier = overturn_barrier(body)
    at_rest = G * 0.75
    assert below_barrier(at_rest, 0.0, G, 5e-4, barrier, 40_000)
    assert not below_barrier(G * barrier.height_m, 0.0, G, 5e-4, barrier, 0)        # the boundary: not certified
    assert not below_barrier(at_rest, barrier.radius_rad, G, 5e-4, barrier, 0)     # tilted as far as overturning
    assert not below_barrier(at_rest, 0.0, G, 5e-4, NO_BARRIER, 0)                  # no barrier: never
    assert not below_barrier(G * (barrier.height_m - 1e-6), 0.0, G, 5e-4, barrier, 0)   # the ground's overlap


@pytest.mark.parametrize("cap_deg", [30.0, 45.0, 60.0, 89.0])
def test_a_cap_beyond_the_tipping_angle_needs_no_more_than_the_edge(cap_deg):
    """Out of any cap wider than its 30 deg tipping angle the prism may roll over its long edge, G at the
    circumradius: the barrier never exceeds it (a lower bound of the energy needed, whatever the cap)."""
    body = _prism(0.2, 1.5)
    barrier = tip_barrier(body.vertices, body.inertia, math.radians(cap_deg))
    assert isinstance(barrier, TipBarrier) and barrier.height_m <= 0.2 / math.cos(math.pi / 6.0)


@pytest.mark.parametrize("amp_g, overturns", [(0.3, False), (0.4, False), (0.5, True)])
def test_a_run_for_the_verdict_gives_the_verdict_of_the_run_followed_to_its_end(amp_g, overturns):
    """A 0.3 x 0.4 x 1.2 m box under one sine cycle of 0.5 s on two horizontals, the record ending with the cycle:
    at 0.3 g it still rocks at the record's end and the certificate ends the run there; at 0.4 g it rocks to 0.22 rad
    and is cut in the tail once its energy has fallen below the barrier; at 0.5 g it overturns in the tail, which the
    certificate never cuts. The verdict is the full run's each time."""
    body = box_body(0.3, 0.4, 1.2, mu=0.8)
    t = np.arange(0.0, 0.5, DT)
    x = amp_g * G * np.sin(2.0 * np.pi * t / 0.5)
    full = simulate_contact3d(x, 0.3 * x, None, DT, body)
    cut = simulate_contact3d(x, 0.3 * x, None, DT, body, barrier=overturn_barrier(body))
    assert full.overturned == cut.overturned == overturns
    if overturns:
        assert cut.t_overturn == full.t_overturn and cut.steps == full.steps
    else:
        assert t[-1] <= cut.t_end_s < full.t_end_s and cut.integrated_steps < full.integrated_steps
        assert cut.tilt_max_rad <= full.tilt_max_rad
