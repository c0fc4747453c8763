"""The 3D cylinder (rocking and rolling on its rim) against closed forms, a second algorithm and invariants: the
uplift threshold in every direction, the planar equation when excited in one plane, energy conserved in free
wobbling and at e = 1, and axisymmetry (the record and the cylinder rotated together change nothing)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pipeline.constants import G
from pipeline.rocking.solids.cylinder3d import (
    FLAG_NONE,
    Cylinder,
    CylinderState,
    housner_e,
    planar_inertia,
    simulate_cylinder,
)

COLUMN = Cylinder(radius_m=0.25, half_height_m=1.0, mu=10.0, restitution=housner_e(0.25, 1.0))
DT = 0.005


def _alpha(c: Cylinder) -> float:
    return math.atan2(c.radius_m, c.half_height_m)


def _pulse(amplitude_ms2: float, period_s: float, n: int = 1200) -> np.ndarray:
    t = np.arange(n) * DT
    return np.where(t < period_s, amplitude_ms2 * np.sin(2 * np.pi * t / period_s), 0.0)


@pytest.mark.parametrize("direction_deg", [0.0, 37.0, 90.0, 200.0, 315.0])
def test_the_uplift_threshold_is_g_tan_alpha_in_every_direction(direction_deg):
    """At rest below |a_h| = g tan(alpha) (the exact boundary too); above it, the cylinder tilts away from the
    acceleration (toward the inertial force)."""
    c = COLUMN
    beta = math.radians(direction_deg)
    n = 400
    for factor, moves in ((1.0 - 1e-9, False), (1.0, False), (1.02, True)):
        amp = factor * G * math.tan(_alpha(c))
        out = simulate_cylinder(np.full(n, amp * math.cos(beta)), np.full(n, amp * math.sin(beta)), None, DT, c)
        assert (out.theta_max_rad > 0) == moves, factor
        if moves:
            lean = math.degrees(math.atan2(-math.sin(beta), -math.cos(beta))) % 360.0
            assert abs((out.azimuth_max_deg - lean + 180) % 360 - 180) < 1e-6


def _planar(c: Cylinder, ah: np.ndarray, t_end: float):
    """An independent solution of the planar rocking equation with the cylinder's own inertia, R and alpha
    (Housner 1963 with I_O = I_G + R^2), Housner's cylinder restitution at each impact; signed theta."""
    alpha, big_r = _alpha(c), math.hypot(c.radius_m, c.half_height_m)
    p2 = G * big_r / planar_inertia(c.radius_m, c.half_height_m)
    t_grid = np.arange(ah.size) * DT

    def f(t, y):
        a = np.interp(t, t_grid, ah)
        s = np.sign(y[0]) if y[0] != 0 else -np.sign(a)
        return [y[1], -p2 * (math.sin(s * alpha - y[0]) + a / G * math.cos(s * alpha - y[0]))]

    def landing(t, y):
        return y[0]
    landing.terminal, landing.direction = True, 0

    ts = []
    # at rest until |a_h| > g tan(alpha)
    start = np.argmax(np.abs(ah) > G * math.tan(alpha))
    frac = (G * math.tan(alpha) - abs(ah[start - 1])) / (abs(ah[start]) - abs(ah[start - 1]))
    t = (start - 1 + frac) * DT
    y = [-np.sign(ah[start]) * 1e-12, 0.0]
    while t < t_end:
        sol = solve_ivp(f, (t, t_end), y, method="DOP853", rtol=1e-11, atol=1e-13 * alpha, events=landing,
                        dense_output=True, first_step=1e-6)
        ts.append(sol)
        if sol.status != 1:
            break
        t = sol.t_events[0][0]
        w = sol.y_events[0][0][1] * c.restitution
        y = [np.sign(w) * 1e-12, w]
    return ts


def test_excited_in_one_plane_it_follows_the_planar_equation_of_a_cylinder():
    """A sine pulse along x alone: the tilt stays in the x-z plane and equals a second algorithm's solution of
    the planar equation with the cylinder's inertia, radius and restitution (scipy DOP853, impacts as events)."""
    c = COLUMN
    ah = _pulse(1.5 * G * math.tan(_alpha(c)), 0.6)
    out = simulate_cylinder(ah, np.zeros_like(ah), None, DT, c)
    assert out.flag == FLAG_NONE and not out.overturned and out.impacts >= 2
    t = np.arange(ah.size) * DT
    pieces = _planar(c, ah, t[-1])
    ref = np.zeros_like(t)
    for sol in pieces:
        inside = (t >= sol.t[0]) & (t <= sol.t[-1])
        ref[inside] = sol.sol(t[inside])[0]
    signed = out.theta * np.cos(out.azimuth)
    assert np.nanmax(np.abs(signed - ref)) < 1e-5 * _alpha(c)
    # no wobble: the tilt stays in the plane (to 1e-7 rad: the landings are taken at theta = 1e-9 alpha)
    assert np.nanmax(np.abs(np.sin(out.azimuth[out.theta > 1e-6]))) < 1e-7


def _energy(c: Cylinder, y: np.ndarray) -> float:
    """Kinetic plus potential energy per unit mass of a state, from the definitions alone."""
    th, ph, _, td, pd, sd = y
    a, h = c.radius_m, c.half_height_m
    e3 = np.array([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
    en = np.array([-math.sin(ph), math.cos(ph), 0.0])
    w = pd * np.array([0, 0, 1.0]) + td * en + sd * e3
    u = np.array([math.cos(th) * math.cos(ph), math.cos(th) * math.sin(ph), -math.sin(th)])
    r = h * e3 - a * u
    i1, i3 = a * a / 4 + h * h / 3, a * a / 2
    inertia = i1 * np.eye(3) + (i3 - i1) * np.outer(e3, e3)
    v = np.cross(w, r)
    return 0.5 * v @ v + 0.5 * w @ inertia @ w + G * r[2]


@pytest.mark.parametrize("state", [(0.15, 0.0, 0.0, 0.0, 6.0, 0.0), (0.2, 1.0, 0.3, -0.5, 4.0, 2.0)])
def test_free_wobbling_conserves_energy(state):
    """No ground motion, the rim rolling on the ground (tilt, precession and spin together): the energy is
    conserved to the step control's tolerance."""
    c = COLUMN
    n = 600
    z = np.zeros(n)
    out = simulate_cylinder(z, z, None, DT, c, start=CylinderState(*state))
    assert out.impacts == 0 and out.flag == FLAG_NONE and not out.overturned
    assert np.nanmin(out.theta) > 0.01 and np.ptp(out.azimuth) > 1.0          # it wobbled: the tilt went round
    e0, e1 = _energy(c, np.array(state)), _energy(c, np.array(out.end))
    assert abs(e1 - e0) < 1e-7 * e0


def test_at_restitution_one_free_rocking_keeps_its_energy_through_impacts():
    c = COLUMN._replace(restitution=1.0)
    n = 2000
    z = np.zeros(n)
    state = (0.6 * _alpha(c), 0.0, 0.0, 0.0, 0.0, 0.0)
    out = simulate_cylinder(z, z, None, DT, c, start=CylinderState(*state))
    assert out.impacts >= 4
    peaks = [np.nanmax(out.theta[k:k + 300]) for k in range(0, n - 300, 300)]       # a peak each half period
    assert max(peaks) == pytest.approx(0.6 * _alpha(c), rel=1e-6)
    assert min(peaks) == pytest.approx(0.6 * _alpha(c), rel=1e-4)      # (the samples straddle the peaks)
    assert abs(_energy(c, np.array(out.end)) - _energy(c, np.array(state))) < 1e-7 * _energy(c, np.array(state))


@pytest.mark.parametrize("beta_deg", [30.0, 135.0, 270.0])
def test_rotating_the_record_rotates_the_motion_and_changes_nothing_else(beta_deg):
    """Axisymmetry: both horizontal components rotated by beta give the same tilt history, its azimuth turned
    by beta."""
    c = COLUMN
    ax = _pulse(2.2 * G * math.tan(_alpha(c)), 0.7)
    ay = np.roll(_pulse(1.6 * G * math.tan(_alpha(c)), 0.45), 40)
    b = math.radians(beta_deg)
    one = simulate_cylinder(ax, ay, None, DT, c)
    two = simulate_cylinder(ax * math.cos(b) - ay * math.sin(b), ax * math.sin(b) + ay * math.cos(b), None, DT, c)
    assert one.overturned == two.overturned and one.impacts == two.impacts
    assert np.nanmax(np.abs(one.theta - two.theta)) < 1e-6 * _alpha(c)
    moving = one.theta > 1e-3 * _alpha(c)
    turn = np.angle(np.exp(1j * (two.azimuth[moving] - one.azimuth[moving] - b)))
    assert np.max(np.abs(turn)) < 1e-5


def test_a_tilt_too_small_to_matter_with_too_little_energy_to_grow_is_set_at_rest():
    """The settle rule (SETTLE_TILT_ALPHA): on a quiet ground, a cylinder at a tilt of 1e-4 alpha turning slowly is
    set at rest at the end of the first sample interval (counted in holds); the same tilt with the contact running
    round the rim fast (kinetic energy above what would raise it to 1e-3 alpha) is followed, not held; and with the
    rule off (0) nothing is held."""
    from pipeline.rocking.solids.cylinder3d import SETTLE_TILT_ALPHA, Cylinder, CylinderState, simulate_cylinder

    c = Cylinder(radius_m=0.13, half_height_m=0.4, mu=0.7, restitution=0.9)
    alpha = math.atan2(c.radius_m, c.half_height_m)
    n, dt = 200, 0.01
    quiet = np.zeros(n)
    slow = [1e-4 * alpha, 0.3, 0.0, 0.0, 1e-3, 0.0]          # theta, phi, psi, and their rates
    held = simulate_cylinder(quiet, quiet, None, dt, c, start=CylinderState(*slow))
    assert held.holds >= 1 and not held.overturned and held.theta_max_rad < SETTLE_TILT_ALPHA * alpha
    assert np.all(held.theta[1:] == 0.0)
    fast = [1e-4 * alpha, 0.3, 0.0, 0.0, 300.0, 0.0]          # precessing at 300 rad/s
    followed = simulate_cylinder(quiet, quiet, None, dt, c, start=CylinderState(*fast))
    assert followed.holds == 0
    off = simulate_cylinder(quiet, quiet, None, dt, c, start=CylinderState(*slow), settle_tilt_alpha=0.0)
    assert off.holds == 0
