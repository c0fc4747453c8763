"""The hand-back to the cylinder's exact model (:mod:`pipeline.rocking.solids.cylinder_handback` through
:mod:`pipeline.rocking.solids.alternate`) against the contact model alone, a second algorithm for the same physics;
the exact model's state against the forward map it inverts; the end-of-record certificate against the closed form of
free rocking."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from support.alternation import DT_S, handed_and_alone, sine_then_still
from support.spies import count_calls

import pipeline.rocking.solids.cylinder_handback as cylinder_handback
from pipeline.constants import G
from pipeline.rocking.solids.alternate import cannot_tip_over
from pipeline.rocking.solids.contact3d import Contact3DOutcome, simulate_contact3d
from pipeline.rocking.solids.contact_scene import handoff
from pipeline.rocking.solids.contact_start import Start
from pipeline.rocking.solids.cylinder3d import Cylinder, housner_e, planar_inertia, simulate_cylinder
from pipeline.rocking.solids.cylinder_handback import cylinder_model, rim_edges, rim_state
from pipeline.rocking.solids.handoff3d import CylinderState

#: tan alpha 0.33 and mu 0.35: under these sines the base slides, then the vase rocks and rolls on its rim
VASE = Cylinder(0.2, 0.6, 0.35, housner_e(0.2, 0.6))


def _model(cylinder: Cylinder = VASE):
    return cylinder_model(cylinder, 0.0, dt_s=DT_S, g_ms2=G, rtol=1e-7, atol_alpha=1e-9)


@pytest.fixture
def exact_calls(monkeypatch) -> list[int]:
    """The exact model's runs the alternation makes (a spy on its calls)."""
    return count_calls(monkeypatch, cylinder_handback, "simulate_cylinder")


@pytest.mark.parametrize("amplitude_g, frequency_hz, azimuth_deg", [
    (0.4, 2.0, 30.0), (0.5, 1.0, 30.0), (0.6, 1.0, 0.0), (0.6, 2.0, 0.0), (0.45, 1.5, 10.0), (0.5, 2.0, 60.0)])
def test_as_the_contact_model_alone(amplitude_g, frequency_hz, azimuth_deg, exact_calls):
    """The verdicts of the contact model alone, from the state where the exact model's base would first slip, at a
    fraction of its steps (the peaks are not compared: where the exact model's circular rim rolls, the contact
    model's rim of 32 points can land and rock in its plane; the alternation keeps only the verdict)."""
    ax, ay = sine_then_still(amplitude_g, frequency_hz, azimuth_deg)
    exact = simulate_cylinder(ax, ay, None, DT_S, VASE)
    assert exact.flag != 0                                       # the exact model stops: its base would slide
    handed, alone = handed_and_alone(ax, ay, VASE, exact, _model())
    assert exact_calls                                           # handed back at least once
    assert handed.overturned == alone.overturned
    assert handed.integrated_steps < alone.integrated_steps


@pytest.mark.parametrize("seed", range(4))
def test_the_exact_state_is_the_one_that_turns_as_the_contact_model_left_it(seed):
    """:func:`rim_state` inverts the exact model's own map from its state to an orientation and rate
    (:meth:`CylinderState.turning`, through scipy's Euler angles) at tilts from 1e-3 rad to past alpha."""
    rng = np.random.default_rng(seed)
    for _ in range(25):
        theta = 10.0 ** rng.uniform(-3.0, 0.1)
        state = CylinderState(theta, rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), *rng.normal(size=3))
        azimuth_deg = rng.uniform(0.0, 180.0)
        q, rate, _ = state.turning(VASE, azimuth_deg)
        back = rim_state(Contact3DOutcome(False, math.nan, 0.0, 0.0, 0.0, False, 0, 0, 0, 0.0, 0, 0, q_end=q,
                                          rate_end_rad_s=rate), azimuth_deg)
        assert back.theta == pytest.approx(state.theta, abs=1e-12)
        for name in ("phi", "psi"):
            turn = getattr(back, name) - getattr(state, name)
            assert math.remainder(turn, 2.0 * math.pi) == pytest.approx(0.0, abs=1e-9)
        for name in ("theta_rate", "phi_rate", "psi_rate"):
            assert getattr(back, name) == pytest.approx(getattr(state, name), abs=1e-8)


def test_the_contact_model_stops_on_one_point_of_the_rim():
    """With the rim's points as its ``edges``, the contact model stops where one point (or two neighbours) alone
    carries the vase without slipping; there the exact state leans toward that point of the rim, within the angle
    between two of its points."""
    ax, ay = sine_then_still(0.4, 2.0, 30.0)
    start = handoff(simulate_cylinder(ax, ay, None, DT_S, VASE), VASE, 0.0, DT_S)
    body = VASE.convex()
    out = simulate_contact3d(ax, ay, None, DT_S, body, start=start, edges=rim_edges(32))
    assert out.edge >= 0 and out.t_end_s == pytest.approx(round(out.t_end_s / DT_S) * DT_S)
    assert out.q_end is not None
    state = rim_state(out, 0.0)
    assert state.theta > 0.0
    rot = Rotation.from_quat([*out.q_end[1:], out.q_end[0]])
    points = rot.apply(body.vertices[rim_edges(32)[out.edge]])
    lean = np.array([math.cos(state.phi), math.sin(state.phi)])
    for point in points:                                         # each loaded point lies on the side it leans to
        cosine = float(point[:2] @ lean) / float(np.linalg.norm(point[:2]))
        assert cosine >= math.cos(2.0 * math.pi / 32) - 1e-12


@pytest.mark.parametrize("share", [0.98, 1.02])
def test_the_end_of_record_certificate_is_housners_free_rocking_threshold(share):
    """A cylinder upright (its tilt 1e-9 rad) turning about a point of its rim at ``share`` of the rate whose kinetic
    energy lifts G from ``R cos(alpha)`` to ``R`` (Housner 1963: ``(I_G + R^2) w^2 / 2 = g R (1 - cos alpha)``) cannot
    tip over below it and can above it; the contact model, the ground still, stands and overturns likewise."""
    a, h = VASE.radius_m, VASE.half_height_m
    big_r, alpha = math.hypot(a, h), math.atan2(a, h)
    rate = share * math.sqrt(2.0 * G * big_r * (1.0 - math.cos(alpha)) / planar_inertia(a, h))   # I_G + R^2
    state = CylinderState(1e-9, 0.0, 0.0, rate, 0.0, 0.0)
    turning = state.turning(VASE, 0.0)
    assert cannot_tip_over(turning, _model(), G) == (share < 1.0)
    still = np.zeros(400)
    q, w, pivot = turning
    out = simulate_contact3d(still, still, None, DT_S, VASE.convex(), start=Start(0.0, q, w, pivot))
    assert out.overturned == (share > 1.0)
