"""The general contact model (rest, slide, rock, slide-rock, free flight) against closed forms and limits.

Independent truths: Housner's restitution of a sticking impact (angular momentum about the corner);
the onset friction of Zhang & Makris (2001, eq. 7); Shenton's (1996) initiation regions; the free
parabola of a body in flight; and the two exact limits the planner relies on (mu -> infinity gives the
pure-rocking kernel, a block that cannot rock gives the Coulomb sliding kernel).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.rocking import codes
from pipeline.rocking.block import Block, rigid_block
from pipeline.rocking.planar import contact, contact_laws, kernel
from pipeline.rocking.planner import ContactMode, Physics, simulate_scene
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import from_rest, rock, slide

REST = contact.ContactState(0.0, codes.REST, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
#: No history, as the simulator's own calls pass it (the compiled model's arguments typed as they are:
#: pipeline.compiled, 'One version per solver'), so that the tests compile no version of their own
NO_HISTORY = kernel.empty_theta()


def contact_block(height_m, width_m, mu, e=None):
    b, h = width_m / 2, height_m / 2
    R, alpha = math.hypot(b, h), math.atan(b / h)
    e = contact_laws.housner_restitution(alpha) if e is None else e
    return rigid_block(math.sqrt(3 * G / (4 * R)), alpha, e, R, mu, G, 1e-6, False, math.inf)


def rocking_block(cb):
    return Block(p=cb.p, alpha=cb.alpha, e=cb.e, R_m=cb.R, mu=cb.mu, g_ms2=cb.g)


def onset_friction(a_ms2, alpha):
    """Friction needed to start rocking without sliding under a pulse at full amplitude a (Zhang & Makris 2001,
    eq. 7, lambda = 1)."""
    r = a_ms2 / (G * math.tan(alpha)) - 1.0
    return (a_ms2 - 0.75 * G * math.sin(alpha) * math.cos(alpha) * r) / (G + 0.75 * G * math.sin(alpha) ** 2 * r)


@pytest.mark.parametrize("aspect", [0.1, 0.2, 0.3, 0.5])
@pytest.mark.parametrize("restitution", [None, 0.8])
def test_sticking_rocking_impact_is_housners_law(aspect, restitution):
    """A rocking impact at theta = 0 whose corner sticks keeps the angular momentum about the corner: the
    rate ratio is 1 - 1.5 sin^2(alpha) (Housner 1963), or the block's e when one is given."""
    cb = contact_block(2.0, 2.0 * aspect, mu=5.0, e=restitution)
    b, h = cb.R * math.sin(cb.alpha), cb.R * math.cos(cb.alpha)
    w = 0.7                                              # rocking about the -x corner, coming back (w > 0)
    rx, ry = contact_laws.corner_offsets(0.0, -1.0, b, h)
    u1, v1, w1, sticks = contact_laws.impact(1.0, 0.0, -ry * w, rx * w, w, cb)
    expected = 1.0 - 1.5 * math.sin(cb.alpha) ** 2 if restitution is None else restitution
    assert sticks
    assert w1 / w == pytest.approx(expected, rel=1e-12)
    rx1, ry1 = contact_laws.corner_offsets(0.0, 1.0, b, h)
    assert u1 + ry1 * w1 == pytest.approx(0.0, abs=1e-12) and v1 - rx1 * w1 == pytest.approx(0.0, abs=1e-12)


def test_impact_that_needs_more_friction_slips_at_the_coulomb_ratio():
    """A squat block's rocking impact needs |P_t / P_n| > mu for a small mu: the corner slips, its normal velocity
    is 0 after the impact, the tangential impulse is mu times the normal one, and the corner slides against it
    (Coulomb's law for impulses)."""
    cb = contact_block(1.0, 1.0, mu=0.05)
    b, h = cb.R * math.sin(cb.alpha), cb.R * math.cos(cb.alpha)
    w = 1.0
    rx, ry = contact_laws.corner_offsets(0.0, -1.0, b, h)
    u0, v0 = -ry * w, rx * w
    u1, v1, w1, sticks = contact_laws.impact(1.0, 0.0, u0, v0, w, cb)
    assert not sticks
    rx1, ry1 = contact_laws.corner_offsets(0.0, 1.0, b, h)
    assert v1 - rx1 * w1 == pytest.approx(0.0, abs=1e-12)
    assert abs(u1 - u0) == pytest.approx(cb.mu * (v1 - v0), rel=1e-12)
    assert (u1 + ry1 * w1) * (u1 - u0) < 0


@pytest.mark.parametrize("a_over_g", [0.2, 0.3, 0.5, 0.8])
@pytest.mark.parametrize("side", [0.97, 1.03])
def test_onset_from_rest_follows_zhang_makris_eq7(a_over_g, side):
    """A ground acceleration at full amplitude from t = 0: the block starts to slide-rock exactly when mu is below
    the onset friction of Zhang & Makris (2001, eq. 7), else it rocks (the modes of the first 0.1 ms)."""
    alpha = math.atan(0.15)
    mu = side * onset_friction(a_over_g * G, alpha)
    cb = contact_block(2.0, 0.3, mu=mu)
    assert mu > math.tan(alpha)
    out = contact.move(np.full(4, a_over_g * G), np.zeros(0), 0.01, cb, REST, True, 1e-4, False, NO_HISTORY)
    expected = ContactMode.slide_rock if side < 1 else ContactMode.rock
    assert out.modes == expected


@pytest.mark.parametrize("alpha", [0.1, 0.25, 0.5, 0.8])
@pytest.mark.parametrize("mu", [0.05, 0.15, 0.3, 0.6, 1.2])
@pytest.mark.parametrize("a_over_g", [0.1, 0.4, 1.0])
def test_initiation_regions_of_shenton(alpha, mu, a_over_g):
    """Shenton (1996): from rest under a ground acceleration a, the block rests when a < min(mu, tan alpha) g;
    slides when mu <= tan alpha (or it is too squat to rock); otherwise rocks, or slide-rocks when mu is below
    the onset friction (Zhang & Makris 2001, eq. 7)."""
    H = 2.0
    cb = contact_block(H, H * math.tan(alpha), mu=mu)
    a = a_over_g * G
    out = contact.move(np.full(4, a), np.zeros(0), 0.01, cb, REST, True, 1e-4, False, NO_HISTORY)
    if a <= min(mu, math.tan(alpha)) * G:
        expected = 0
    elif mu <= math.tan(alpha) or alpha >= math.asin(math.sqrt(2 / 3)):
        expected = ContactMode.slide
    elif mu < onset_friction(a, alpha):
        expected = ContactMode.slide_rock
    else:
        expected = ContactMode.rock
    assert out.modes == expected


def test_free_flight_is_a_parabola_with_constant_spin():
    """No contact, a still ground: the centre of mass falls on a parabola and the rotation rate is constant (the
    fourth-order step is exact for it)."""
    cb = contact_block(1.0, 0.4, mu=0.5)
    y0, u0, v0, w0, th0 = 0.5, 0.3, 1.0, 0.8, 0.1
    start = contact.ContactState(0.0, codes.FLIGHT, 1.0, 1.0, 0.0, y0, th0, u0, v0, w0, 0.0)
    t = 0.2
    out = contact.move(np.zeros(1001), np.zeros(0), 0.001, cb, start, False, t, False, NO_HISTORY)
    end = out.end
    assert end.t == pytest.approx(t, abs=1e-12)
    assert end.y == pytest.approx(y0 + v0 * t - 0.5 * G * t * t, abs=1e-12)
    assert end.x == pytest.approx(u0 * t, abs=1e-12)
    assert end.theta == pytest.approx(th0 + w0 * t, abs=1e-12)
    assert end.w == w0 and end.v == pytest.approx(v0 - G * t, abs=1e-12)


def test_flight_relative_to_a_moving_ground_integrates_it_exactly():
    """In the ground's frame a flying block feels -a_h: with a ground acceleration linear in time the relative
    displacement is the exact cubic."""
    cb = contact_block(1.0, 0.4, mu=0.5)
    dt, k = 0.001, 3.0
    ah = k * np.arange(1001) * dt                      # a_h = k t
    start = contact.ContactState(0.0, codes.FLIGHT, 1.0, 1.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    t = 0.3
    end = contact.move(ah, np.zeros(0), dt, cb, start, False, t, False, NO_HISTORY).end
    assert end.x == pytest.approx(-k * t ** 3 / 6, abs=1e-12)
    assert end.u == pytest.approx(-k * t ** 2 / 2, abs=1e-12)


def half_sine(amplitude_ms2, period_s, dt=0.002, duration=6.0):
    t = np.arange(0.0, duration, dt)
    return np.where(t < period_s / 2, amplitude_ms2 * np.sin(2 * np.pi / period_s * t), 0.0), dt


@pytest.mark.parametrize("amplitude_g", [0.2, 0.3, 0.45])
def test_general_model_with_ample_friction_matches_the_rocking_kernel(amplitude_g):
    """A second algorithm: with mu large the general model (fourth-order Runge-Kutta, its own impact law) and the
    rocking kernel (Dormand-Prince, Housner's impact) give the same response."""
    cb = contact_block(2.0, 0.3, mu=100.0)
    ah, dt = half_sine(amplitude_g * G, 0.8)
    general = contact.move(ah, np.zeros(0), dt, cb, REST, True, math.inf, False, NO_HISTORY)
    pure = rock(ah, dt, p=cb.p, alpha=cb.alpha, e=cb.e, R_m=cb.R)
    assert general.overturned == pure.overturned
    assert general.theta_max_rad / cb.alpha == pytest.approx(pure.theta_max, rel=1e-4)
    if not pure.overturned:
        assert general.n_impacts == pure.n_impacts


def test_planner_with_infinite_friction_is_pure_rocking_exactly():
    """mu -> infinity: the friction demand never exceeds mu, the planner never hands off, and the scene is the
    pure-rocking kernel's, field by field."""
    cb = contact_block(2.0, 0.3, mu=1e9)
    ah, dt = half_sine(0.3 * G, 0.8)
    block = rocking_block(cb)
    on = simulate_scene(ah, None, dt, block=block)
    off = simulate_scene(ah, None, dt, block=block, settings=dataclasses.replace(SimulationConfig(),
                                                                               contact_model=False))
    assert on.physics == Physics.rocking
    for name in (f.name for f in dataclasses.fields(on)):
        np.testing.assert_array_equal(getattr(on, name), getattr(off, name), err_msg=name)


def test_block_that_cannot_rock_slides_as_coulomb_exactly():
    """alpha above 54.7 deg with a ground that never flies: the planner's Coulomb sliding, unchanged; and the
    general model's slide mode gives the same slip (the Runge-Kutta step is exact for the cubic slip)."""
    cb = contact_block(0.5, 1.5, mu=0.3)
    ah, dt = half_sine(0.6 * G, 0.6)
    block = rocking_block(cb)
    scene = simulate_scene(ah, None, dt, block=block)
    coulomb = slide(ah, dt, mu=cb.mu)
    assert scene.physics == Physics.sliding and scene.sliding_max_m == coulomb.sliding_max_m
    general = from_rest(ah, None, dt, block=block)
    assert general.modes == ContactMode.slide and not general.overturned
    assert general.slip_max_m == pytest.approx(coulomb.sliding_max_m, rel=1e-9)
    assert general.slip_end_m == pytest.approx(coulomb.sliding_end_m, rel=1e-9)


def test_friction_exceedance_is_continued_not_restarted():
    """A scene whose pure rocking needs more friction than mu is continued by the general model from the start of
    the step where that happened; the result equals the general model run from rest (same physics throughout)."""
    cb = contact_block(2.0, 0.6, mu=0.33)
    ah, dt = half_sine(0.5 * G, 0.5)
    block = rocking_block(cb)
    scene = simulate_scene(ah, None, dt, block=block)
    whole = from_rest(ah, None, dt, block=block)
    assert scene.physics == Physics.general and scene.friction_exceeded == 1
    assert scene.contact_modes & ContactMode.slide_rock
    assert scene.overturned == whole.overturned
    assert scene.sliding_max_m == pytest.approx(whole.slip_max_m, rel=1e-3, abs=1e-6)


def test_ground_free_flight_now_has_a_verdict():
    """Where the ground falls faster than gravity the block flies and lands: the scene gets a verdict (physics
    general, the flight mode recorded), where pure rocking stopped with none."""
    cb = contact_block(1.0, 0.3, mu=0.6)
    dt = 0.002
    t = np.arange(0.0, 4.0, dt)
    ah = np.where(t < 0.5, 0.6 * G * np.sin(2 * np.pi * t), 0.0)
    av = np.where((t > 0.1) & (t < 0.14), -1.5 * G, 0.0)
    block = rocking_block(cb)
    scene = simulate_scene(ah, av, dt, block=block)
    off = simulate_scene(ah, av, dt, block=block, settings=dataclasses.replace(SimulationConfig(),
                                                                             contact_model=False))
    assert off.verdict == -1
    assert scene.physics == Physics.general and scene.verdict in (0, 1)
    assert scene.contact_modes & ContactMode.free_flight


def test_a_block_that_slides_farther_than_its_base_margin_slides_off(tmp_path, records_dir, config):
    """The inventory's base_margin_m against the simulated slip: a squat crate that slides on Rinaldi goes off a
    base with no margin and stays on one 100 m wide; a rocking block does not slip; no margin, no verdict (-1)."""
    import shutil

    from pipeline.blocks import read_inventory
    from pipeline.records.listing import find_records
    from pipeline.records.side_files import read_declared_units
    from pipeline.run.screening import Context, assemble, screen_record

    (tmp_path / "fn-ascii").mkdir()
    shutil.copy(records_dir / "fn-ascii" / "rinaldi_fn.dat", tmp_path / "fn-ascii" / "rinaldi_fn.dat")
    (tmp_path / "units.toml").write_text((records_dir / "units.toml").read_text())
    csv = tmp_path / "blocks.csv"
    csv.write_text("id,height_m,width_m,mu,base_margin_m\nCRATE-0,0.5,1.0,0.3,0\nCRATE-100,0.5,1.0,0.3,100\n"
                   "CRATE-none,0.5,1.0,0.3,\nCOLUMN,2.0,0.4,0.8,0.01\n")
    inv = read_inventory(csv, default_mu=0.6)
    cfg = dataclasses.replace(config, uncertainty=dataclasses.replace(config.uncertainty, samples=0))
    sources, failures = find_records(tmp_path, config=cfg)
    assert not failures and len(sources) == 1
    results = [screen_record(s, Context(str(tmp_path), cfg, inv, read_declared_units(tmp_path, cfg)))
               for s in sources]
    ds = assemble(results, inv, cfg)
    assert results[0].ok, results[0].status
    off = ds["slides_off_base"].values[0]
    assert ds["sliding_max"].values[0, 0] > 0 and ds["physics"].values[0, 0] == Physics.sliding
    assert off.tolist() == [1, 0, -1, 0]
    assert ds["base_margin"].values[1] == 100.0
