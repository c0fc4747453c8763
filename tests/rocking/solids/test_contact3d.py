"""The 3D contact model of a convex body (Moreau-Jean time stepping) against independent truth: Newmark's closed-form
sliding displacement, the planar rocking kernel (Housner's impacts) for a box far deeper than wide, the planar
Coulomb sliding model for a squat drum, the invariance of a scene turned about the vertical with its record,
and no energy gained through contacts once the ground is still."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.rocking.block import BlockShape, dynamics
from pipeline.rocking.planner import simulate_scene
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import slide
from pipeline.rocking.solids.contact3d import FLAG_TAIL_CAP, simulate_contact3d
from pipeline.rocking.solids.convex_body import box_body, cylinder_body

DT = 0.005
T = np.arange(0.0, 6.0, DT)


@pytest.mark.parametrize("a0_g, mu, duration_s", [(0.5, 0.3, 0.5), (0.8, 0.5, 0.3)])
def test_a_squat_block_slides_newmarks_distance_and_stays_flat(a0_g, mu, duration_s):
    """A rectangular pulse a0 > mu g for t_d: the block slides V^2 / (2 mu g) (1 - mu g / a0), V = a0 t_d
    (Newmark 1965), without tilting (tan alpha = 5 > mu)."""
    dt = 0.001
    t = np.arange(0.0, 3.0, dt)
    a0 = a0_g * G
    got = simulate_contact3d(np.where(t < duration_s, a0, 0.0), np.zeros_like(t), None, dt,
                             box_body(1.0, 1.0, 0.2, mu=mu))
    v = a0 * duration_s
    newmark = v * v / (2.0 * mu * G) * (1.0 - mu * G / a0)
    assert got.slide_max_m == pytest.approx(newmark, rel=0.01)
    assert got.tilt_max_rad < 1e-6 and not got.overturned


@pytest.mark.parametrize("amp_g, period_s", [(0.3, 0.5), (0.25, 0.8), (0.5, 0.3), (0.45, 1.0), (0.4, 0.8)])
def test_a_deep_box_rocks_as_the_planar_kernel_in_the_plane_of_its_width(amp_g, period_s):
    """A 0.4 x 4 x 2 m box (depth ten times its width, no slip at mu 0.8) under one sine pulse along its width:
    the peak tilt of the planar kernel (Housner's impacts) within 1 %, the same verdict. The plastic impact at a new
    sticking contact is Housner's rule."""
    ah = np.where(T < period_s, amp_g * G * np.sin(2 * np.pi * T / period_s), 0.0)
    block = dynamics([BlockShape(height_m=2.0, width_m=0.4, mu=0.8)])[0]
    planar = simulate_scene(ah, None, DT, block=block, settings=SimulationConfig(contact_model=False))
    got = simulate_contact3d(ah, np.zeros_like(ah), None, DT, box_body(0.4, 4.0, 2.0, mu=0.8))
    assert got.overturned == planar.overturned
    if not planar.overturned:
        assert got.tilt_max_rad / block.alpha == pytest.approx(planar.theta_max, rel=0.01)
        assert got.capped_steps == 0


@pytest.mark.parametrize("amp_g, period_s", [(0.3, 0.5), (0.5, 0.3), (0.45, 1.0)])
@pytest.mark.parametrize("body", [box_body(0.4, 4.0, 2.0, mu=0.8), box_body(0.4, 0.6, 1.6, mu=0.5),
                                  cylinder_body(0.4, 1.6, mu=0.6)], ids=["deep box", "box", "cylinder"])
def test_rocking_on_a_horizontal_pulse_is_no_flight_as_in_the_planar_general_model(body, amp_g, period_s):
    """A sine pulse along x and no vertical: the planar general contact model (event-driven: a lift-off where the
    pivot's normal force reaches 0) rocks the 0.4 x 2 m block without any lift-off, standing and overturning; nor
    does the contact model's body ever rise clear of the ground, though single steps without a contact come with
    the stepping at a pivot."""
    ah = np.where(T < period_s, amp_g * G * np.sin(2 * np.pi * T / period_s), 0.0)
    block = dynamics([BlockShape(height_m=2.0, width_m=0.4, mu=0.8)])[0]
    planar = simulate_scene(ah, None, DT, block=block, settings=SimulationConfig(contact_model=True))
    got = simulate_contact3d(ah, np.zeros_like(ah), None, DT, body)
    assert planar.free_flight == 0 and planar.theta_max > 0.1
    assert got.tilt_max_rad > 0.01 and not got.flight


@pytest.mark.parametrize("av_g, flies", [(-1.3, True), (-1.0, False), (-0.9, False)])
def test_the_body_flies_where_the_ground_falls_faster_than_gravity(av_g, flies):
    """The ground falling at a_v for 0.3 s: below -g nothing can hold the body down, and it rises clear of the ground
    (g + a_v < 0); at -g exactly it is weightless and still, and nothing lifts it; above -g it stays on its base."""
    av = np.where(T < 0.3, av_g * G, 0.0)
    for body in (box_body(0.4, 4.0, 2.0, mu=0.8), cylinder_body(0.4, 1.6, mu=0.6)):
        got = simulate_contact3d(np.zeros_like(T), np.zeros_like(T), av, DT, body)
        assert got.flight == flies and not got.overturned


def test_a_squat_drum_slides_as_the_planar_coulomb_model():
    """A 2 x 2 m drum (mu 0.3 < tan alpha = 1) under a 0.35 g sine slides, never tips: the planar Coulomb
    stick-slip model's distance."""
    ah = 0.35 * G * np.sin(2 * np.pi * T) * (T < 4.0)
    got = simulate_contact3d(ah, np.zeros_like(ah), None, DT, cylinder_body(2.0, 2.0, mu=0.3))
    assert got.slide_max_m == pytest.approx(slide(ah, DT, mu=0.3).sliding_max_m, rel=1e-3)
    assert got.tilt_max_rad < 1e-6


@pytest.mark.parametrize("turn_deg", [30.0, 90.0, 180.0])
@pytest.mark.parametrize("size, mu", [((0.5, 0.5, 1.5), 0.8), ((1.0, 0.8, 0.3), 0.3)])
def test_a_scene_turned_about_the_vertical_with_its_record_is_the_same_scene(turn_deg, size, mu):
    """A square statue tipped by one half-sine pulse on two horizontals (its peak before any impact), and a squat
    box sliding under two components; the record and the body turned together (180 deg: the record reflected
    through the vertical axis). The same to 1e-3 (the contact problems are solved to a relative 1e-8, and the turned
    record rounds differently; an error of frame would differ at order 1)."""
    x = 0.5 * G * np.sin(2 * np.pi * T / 1.2) * (T < 0.6)
    y = 0.25 * G * np.sin(2 * np.pi * T / 1.2) * (T < 0.6) + 0.2 * G * np.sin(2 * np.pi * T / 0.5) * (T < 1.0)
    body = box_body(*size, mu=mu)
    base = simulate_contact3d(x, y, None, DT, body, yaw_deg=10.0)
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))
    turned = simulate_contact3d(c * x - s * y, s * x + c * y, None, DT, body, yaw_deg=10.0 + turn_deg)
    assert base.tilt_max_rad > 0.01 or base.slide_max_m > 0.01                  # it moves
    assert turned.overturned == base.overturned
    assert turned.tilt_max_rad == pytest.approx(base.tilt_max_rad, rel=1e-3, abs=1e-9)
    assert turned.slide_max_m == pytest.approx(base.slide_max_m, rel=1e-3, abs=1e-9)


@pytest.mark.parametrize("restitution", [0.0, 0.5])
def test_no_energy_is_gained_through_the_contacts_once_the_ground_stands_still(restitution):
    x = 0.4 * G * np.sin(2 * np.pi * T / 0.6) * (T < 1.2)
    y = 0.2 * G * np.sin(2 * np.pi * T / 0.4) * (T < 1.2)
    got = simulate_contact3d(x, y, None, DT, box_body(0.4, 0.6, 1.6, mu=0.5, restitution=restitution))
    assert got.tilt_max_rad > 0.01
    assert got.energy_gain_max <= 1e-9


@pytest.mark.parametrize("body, amp_g", [(box_body(0.4, 0.6, 1.6, mu=0.5), 0.3),
                                         (box_body(1.0, 1.0, 0.3, mu=0.3), 0.45),
                                         (cylinder_body(0.5, 1.5, mu=0.6), 0.35)], ids=["rocks", "slides", "drum"])
def test_a_quiet_minute_after_the_motion_is_held_at_rest_and_changes_nothing(body, amp_g):
    """The body moved by a pulse on two horizontals comes to rest flat on its base within 20 s; a minute of ground
    motion below its at-rest threshold min(mu, tan alpha) follows. The body found at rest again is held there: the
    minute integrates no step (the same integrated steps as the record without it), and every peak is the same."""
    t = np.arange(0.0, 20.0, DT)
    x = amp_g * G * np.sin(2 * np.pi * t / 0.8) * (t < 0.8)
    y = 0.5 * amp_g * G * np.sin(2 * np.pi * t / 0.5) * (t < 0.5)
    short = simulate_contact3d(x, y, None, DT, body)
    calm = 0.04 * G * np.sin(2 * np.pi * np.arange(0.0, 60.0, DT) / 0.7)     # |a_h| <= 0.045 g: held
    longer = simulate_contact3d(np.concatenate([x, calm]), np.concatenate([y, 0.5 * calm]), None, DT, body)
    assert short.tilt_max_rad > 1e-3 or short.slide_max_m > 1e-3                # it moved
    assert not short.overturned and not short.flags & FLAG_TAIL_CAP
    assert longer.integrated_steps == short.integrated_steps
    assert longer.steps >= short.steps + 60.0 / DT - 1                               # the minute was there
    assert (longer.tilt_max_rad, longer.slide_max_m, longer.twist_max_rad) == (
        short.tilt_max_rad, short.slide_max_m, short.twist_max_rad)


def test_small_rocking_on_a_real_record_follows_the_exact_cylinder_model_while_it_holds(kocaeli):
    """Kocaeli at Yarimca x a 0.4 x 1.6 m cylinder (mu 0.6): the exact cylinder model (smooth rim, event-driven)
    holds until its base would slip at 12.2 s; through 9.9-12 s the cylinder rocks at 0.004-0.28 alpha, with
    impacts about 60 ms apart at the smallest tilts (Housner's period). Over that window the contact model's peak
    tilt is the exact model's to 10 % (with every step 0.5 ms it was 0.008 alpha against 0.28: the coarse steps
    damped the small rocking away)."""
    from pipeline.config import Config
    from pipeline.records.listing import find_records
    from pipeline.records.loader import load_record
    from pipeline.rocking.solids.cylinder3d import Cylinder, housner_e, simulate_cylinder

    sources, _ = find_records(kocaeli, config=Config())
    rec = load_record(sources[0], root=kocaeli, config=Config())
    bx, by = rec.horizontal_ms2[0], -rec.horizontal_ms2[1]         # y counter-clockwise from x, seen from above
    exact = simulate_cylinder(bx, by, rec.vertical_ms2, rec.dt_s, Cylinder(0.2, 0.8, 0.6, housner_e(0.2, 0.8)))
    held = np.isfinite(exact.theta)
    assert exact.flag != 0 and 2000 < held.sum() < exact.theta.size     # it holds for a while, then stops
    got = simulate_contact3d(bx, by, rec.vertical_ms2, rec.dt_s, cylinder_body(0.4, 1.6, mu=0.6), history=True)
    peak_exact = np.max(exact.theta[held])
    assert 0.2 < peak_exact / math.atan(0.25) < 0.4
    assert np.max(got.tilt_rad[held]) == pytest.approx(peak_exact, rel=0.1)


@pytest.mark.parametrize("factor", [0.98, 1.0])
def test_a_cylinder_that_flies_on_a_real_record_overturns_as_both_engines_have_it(make_records, factor):
    """El Centro Array 6 (its vertical reaches -g) x a 0.6 x 1.5 m cylinder (mu 0.5): it flies and lands flat, and
    PyBullet and MuJoCo both overturn it at 0.98 and 1 times the record (benchmarks/contact3d_peer.py,
    contact3d_second_engine.py). With every step 0.5 ms the contact model stood at 1; taken finely while it flies
    and for AFTER_FLIGHT_S after, it overturns, as it does with every step at 50 or 20 us."""
    from pipeline.config import Config
    from pipeline.records.listing import find_records
    from pipeline.records.loader import load_record

    root = make_records(*(f"peer-at2/RSN181_IMPVALL.H_H-E06{c}.AT2" for c in ("140", "230", "-UP")))
    sources, _ = find_records(root, config=Config())
    rec = load_record(sources[0], root=root, config=Config())
    got = simulate_contact3d(factor * rec.horizontal_ms2[0], -factor * rec.horizontal_ms2[1],
                             factor * rec.vertical_ms2, rec.dt_s, cylinder_body(0.6, 1.5, mu=0.5))
    assert got.flight and got.overturned
