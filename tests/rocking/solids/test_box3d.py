"""The 3D box (rocking on an edge or a corner) against closed forms, a second algorithm and invariants: the uplift
threshold in every direction, the planar equation when excited along a base axis (the width's plane and the
depth's) and along the diagonal of a square base (the diagonal's own R, alpha, inertia and Housner restitution),
energy conserved on a corner, rotating the record and the box together, the mirror image, and the exact
friction boundary at rest."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.rocking.simulate import rock
from pipeline.rocking.solids.box3d import (
    CORNER,
    FLAG_NONE,
    FLAG_SLIDE,
    Box,
    BoxState,
    box_energy,
    housner_e_box,
    simulate_box,
)

DT = 0.005
STATUE = Box(half_width_m=0.25, half_depth_m=0.4, half_height_m=1.0, mu=10.0)
SQUARE = Box(half_width_m=0.25, half_depth_m=0.25, half_height_m=1.0, mu=10.0)


def _pulse(amplitude_ms2: float, period_s: float, n: int = 1200) -> np.ndarray:
    t = np.arange(n) * DT
    return np.where(t < period_s, amplitude_ms2 * np.sin(2 * np.pi * t / period_s), 0.0)


def _threshold(box: Box, direction: float) -> float:
    """The smallest |a| along ``direction`` [rad, in the box's axes] that lifts the box at rest: the edge whose
    moment balance g b_n / h / (-a_hat . n) is smallest (an independent restatement of the rest condition)."""
    a = np.array([math.cos(direction), math.sin(direction)])
    edges = [((0.0, 1.0), box.half_depth_m), ((-1.0, 0.0), box.half_width_m), ((0.0, -1.0), box.half_depth_m),
             ((1.0, 0.0), box.half_width_m)]
    return min(G * b / box.half_height_m / -(a @ n) for n, b in edges if -(a @ n) > 1e-12)


@pytest.mark.parametrize(("azimuth_deg", "direction_deg"), [(0, 0), (0, 90), (0, 37), (30, 200), (-50, 300)])
def test_the_uplift_threshold_holds_in_every_direction(azimuth_deg, direction_deg):
    """At rest up to the threshold of the edge it tips about (the exact boundary too); above it, the box tilts
    away from the acceleration across that edge."""
    box, n = STATUE, 300
    beta = math.radians(direction_deg)
    limit = _threshold(box, beta - math.radians(azimuth_deg))
    for factor, moves in ((1.0 - 1e-9, False), (1.0, False), (1.02, True)):
        amp = factor * limit
        out = simulate_box(np.full(n, amp * math.cos(beta)), np.full(n, amp * math.sin(beta)), None, DT, box,
                           azimuth_deg=azimuth_deg)
        assert out.flag == FLAG_NONE
        assert (out.theta_max_rad > 0) == moves, factor
        if moves:     # it leans away from the acceleration (the inertial force's side)
            lean = math.radians(out.azimuth_max_deg)
            assert math.cos(lean - beta) < 0.0


def _planar(a: np.ndarray, half: float, h: float, restitution: float):
    big_r = math.hypot(half, h)
    return rock(a, DT, p=math.sqrt(0.75 * G / big_r), alpha=math.atan2(half, h), e=restitution, R_m=big_r,
                history=True)


PULSES = [(0.45, 1.0), (0.35, 0.8), (0.6, 0.5), (0.3, 1.2)]


@pytest.mark.parametrize(("amp_g", "period_s"), PULSES)
@pytest.mark.parametrize("axis", ["width", "depth"])
def test_excited_along_a_base_axis_it_follows_the_planar_kernel(amp_g, period_s, axis):
    """One component along a base axis: the box rocks on an edge, as the planar kernel's block of that plane's
    R and alpha (Housner's restitution of that plane), sample by sample."""
    b_w, b_d, h = (0.25, 2.0, 1.0) if axis == "width" else (2.0, 0.25, 1.0)
    box = Box(b_w, b_d, h, mu=10.0)
    a = _pulse(amp_g * G, period_s)
    zero = np.zeros_like(a)
    out = simulate_box(a, zero, None, DT, box) if axis == "width" else simulate_box(zero, a, None, DT, box)
    half = b_w if axis == "width" else b_d
    ref = _planar(a, half, h, housner_e_box(half, h))
    alpha = math.atan2(half, h)
    assert out.flag == FLAG_NONE and out.corner_s == 0.0
    assert out.overturned == ref.overturned
    both = np.isfinite(out.theta) & np.isfinite(ref.theta)
    assert np.max(np.abs(out.theta[both] - np.abs(ref.theta[both]))) < 1e-5 * alpha


@pytest.mark.parametrize(("amp_g", "period_s"), [(0.5, 1.0), (0.42, 0.8), (0.7, 0.5), (0.6, 0.7)])
def test_a_square_base_excited_along_its_diagonal_rocks_on_corners_as_the_diagonal_plane(amp_g, period_s):
    """A square base excited along its diagonal turns on a corner, as a planar block with the diagonal's
    R_d = sqrt(2 b^2 + h^2), alpha_d = atan(sqrt(2) b / h), I_O = I_G + R_d^2 and Housner's
    e = 1 - 2 R_d^2 sin^2(alpha_d) / I_O."""
    b, h = SQUARE.half_width_m, SQUARE.half_height_m
    big_r, alpha = math.hypot(math.sqrt(2) * b, h), math.atan2(math.sqrt(2) * b, h)
    inertia = (b * b + h * h) / 3 + big_r ** 2
    e = 1 - 2 * big_r ** 2 * math.sin(alpha) ** 2 / inertia
    a = _pulse(amp_g * G, period_s)
    out = simulate_box(a / math.sqrt(2), a / math.sqrt(2), None, DT, SQUARE)
    ref = rock(a, DT, p=math.sqrt(G * big_r / inertia), alpha=alpha, e=e, R_m=big_r, history=True)
    assert out.overturned == ref.overturned and out.corner_s > 0.0
    both = np.isfinite(out.theta) & np.isfinite(ref.theta)
    assert np.max(np.abs(out.theta[both] - np.abs(ref.theta[both]))) < 1e-5 * alpha


@pytest.mark.parametrize("rates", [(0.3, 0.1, 0.2), (-0.2, 0.25, -0.4), (0.0, 0.0, 1.5)])
def test_on_a_corner_without_excitation_energy_is_conserved(rates):
    """Turning on a corner (twist included) with the ground at rest: gravity's potential plus the kinetic energy
    about the corner is constant until a corner lands."""
    axis = np.array([1.0, -1.0, 0.0]) / math.sqrt(2)
    angle = -0.05                                          # corner 0 lowest
    y = BoxState(np.array([math.cos(angle / 2), *(math.sin(angle / 2) * axis)]), np.array(rates), CORNER, 0)
    n = 12
    out = simulate_box(np.zeros(n), np.zeros(n), None, DT, SQUARE, start=y)
    assert out.impacts == 0 and out.flag == FLAG_NONE and out.corner_s > 0.0
    e0, e1 = box_energy(y, SQUARE, pivot=0), box_energy(out.end, SQUARE, pivot=0)
    assert abs(e1 - e0) < 1e-9 * e0


def _two_components(n: int = 1400) -> tuple[np.ndarray, np.ndarray]:
    """Two horizontal pulses of different periods and phases (a motion that leaves any one plane)."""
    t = np.arange(n) * DT
    ax = np.where(t < 1.0, 0.3 * G * np.sin(2 * np.pi * t / 1.0), 0.0)
    ay = np.where((t > 0.2) & (t < 0.9), -0.45 * G * np.sin(2 * np.pi * (t - 0.2) / 0.7), 0.0)
    return ax, ay


@pytest.mark.parametrize("beta_deg", [30.0, 90.0, 217.0])
def test_rotating_the_record_and_the_box_together_changes_nothing(beta_deg):
    ax, ay = _two_components()
    base = simulate_box(ax, ay, None, DT, STATUE)
    c, s = math.cos(math.radians(beta_deg)), math.sin(math.radians(beta_deg))
    turned = simulate_box(c * ax - s * ay, s * ax + c * ay, None, DT, STATUE, azimuth_deg=beta_deg)
    assert base.corner_s > 0.0 and base.impacts > 0
    assert turned.overturned == base.overturned and turned.impacts == base.impacts
    assert np.nanmax(np.abs(turned.theta - base.theta)) < 1e-6 * math.atan2(0.25, 1.0)
    assert abs((turned.azimuth_max_deg - base.azimuth_max_deg - beta_deg + 180) % 360 - 180) < 1e-6


@pytest.mark.parametrize("amplitude_g, frequency_hz", [(0.4, 1.0), (0.4, 2.0), (0.5, 2.0)])
def test_a_box_rolling_from_corner_to_corner_as_the_contact_model_has_it(amplitude_g, frequency_hz):
    """A ground moving in a circle for 3 s turns the demand, and a square base that lifts rolls from corner to corner
    (benchmarks/box_circular.py): where a corner next to the pivot lands and the old pivot rises, the box turns on it
    alone. The exact model follows the whole record and peaks as the contact model (a second algorithm: every vertex a
    Coulomb contact, Moreau-Jean steps) does, within 5 %; PyBullet's, in the benchmark, within 0.003 rad of it."""
    from pipeline.rocking.solids.contact3d import simulate_contact3d

    t = np.arange(0.0, 12.0, 0.01)
    on = amplitude_g * G * (t < 3.0)
    ax, ay = on * np.sin(2 * np.pi * frequency_hz * t), on * np.cos(2 * np.pi * frequency_hz * t)
    box = Box(0.3, 0.3, 1.05, mu=2.0, restitution_ratio=1.0)
    exact = simulate_box(ax, ay, None, 0.01, box)
    alone = simulate_contact3d(ax, ay, None, 0.01, box.convex())
    assert exact.flag == FLAG_NONE and exact.held == FLAG_NONE
    assert exact.overturned == alone.overturned
    assert exact.theta_max_rad == pytest.approx(alone.tilt_max_rad, rel=0.05)


def _kinetic(rate: np.ndarray, corner_from_g: np.ndarray, inertia: np.ndarray) -> float:
    """The kinetic energy per unit mass [J kg-1] of a box turning at ``rate`` [rad s-1] about a corner at rest, the
    corner at ``corner_from_g`` from G [m], ``inertia`` about G per unit mass in the same axes [m2]."""
    v_g = np.cross(rate, -corner_from_g)
    return float(0.5 * v_g @ v_g + 0.5 * rate @ inertia @ rate)


def test_a_corner_taking_over_never_gains_energy():
    """Where a landing corner takes over alone (``box_run._corner_passes``), its impulse stops it dead (a plastic,
    sticking impact at one point), so the kinetic energy cannot grow (Kelvin): checked with the energy computed
    here from the box's own inertia (not the kernel's), on 400 random tilted states and rates."""
    from scipy.spatial.transform import Rotation

    from pipeline.rocking.solids.box_kernel import _params
    from pipeline.rocking.solids.box_run import _corner_passes

    rng = np.random.default_rng(20261203)
    signs = ((1, 1), (-1, 1), (-1, -1), (1, -1))                     # the kernel's corners, counter-clockwise
    passed = 0
    for _ in range(400):
        a, b, c = rng.uniform(0.1, 0.5), rng.uniform(0.1, 0.5), rng.uniform(0.5, 1.5)
        prm = _params(G, a, b, c, 2.0, 1.0, 1e-7, 1e-9)
        rot = Rotation.from_rotvec(np.append(rng.normal(0.0, 0.15, 2), rng.uniform(-np.pi, np.pi)))
        x, y_, z, w = rot.as_quat()
        omega = rng.normal(0.0, 1.0, 3)
        pivot = int(rng.integers(4))
        landing = (pivot + int(rng.choice([1, 3]))) % 4
        state = np.array([w, x, y_, z, *omega])
        m = rot.as_matrix()
        inertia = m @ np.diag([(b * b + c * c) / 3, (a * a + c * c) / 3, (a * a + b * b) / 3]) @ m.T
        corner = [m @ np.array([sx * a, sy * b, -c]) for sx, sy in signs]

        before = _kinetic(omega, corner[pivot], inertia)
        if _corner_passes(state, pivot, landing, prm):
            passed += 1
            assert _kinetic(state[4:], corner[landing], inertia) <= before * (1.0 + 1e-12)
    assert passed >= 20, passed


def test_the_mirror_image_of_the_record_gives_the_mirror_image_of_the_motion():
    """The box is symmetric about its x axis: a_y -> -a_y gives the same tilts and mirrored azimuths."""
    ax, ay = _two_components()
    base = simulate_box(ax, ay, None, DT, STATUE)
    mirror = simulate_box(ax, -ay, None, DT, STATUE)
    assert mirror.overturned == base.overturned and mirror.impacts == base.impacts
    assert np.nanmax(np.abs(mirror.theta - base.theta)) < 1e-6 * math.atan2(0.25, 1.0)
    moving = base.theta > 1e-6
    assert np.allclose(np.sin(mirror.azimuth[moving]), -np.sin(base.azimuth[moving]), atol=1e-6)


def test_at_rest_the_friction_boundary_holds_and_beyond_it_the_scene_is_flagged():
    """|a_h| = mu g exactly holds the box at rest; above it, the box would slide before it rocks: flagged (not
    followed in 3D)."""
    box = STATUE._replace(mu=0.2)                  # 0.2 g < the uplift threshold 0.25 g
    n = 200
    for factor, flag in ((1.0, FLAG_NONE), (1.001, FLAG_SLIDE)):
        a = np.full(n, factor * box.mu * G / math.sqrt(2))
        out = simulate_box(a, a, None, DT, box)
        assert out.flag == flag and out.theta_max_rad == 0.0
