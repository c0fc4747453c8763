"""Hard cases end: every tie rule of :mod:`pipeline.rocking.rules` on exact boundaries, each scene under a
wall-clock budget, the verdicts checked against what each boundary implies.

The regression behind these tests: a 3 m x 1.5 m block with mu = 0.5 (tan alpha = 0.49999999999999994)
under Rinaldi (RSN1063) never finished: the rocking kernel and the general contact model handed the scene back
and forth at one instant.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from boundary_scenes import ALPHA_MAX, SCENE_BUDGET_S, G, block, motions, mu_ties, run_scene, sampled_verdict, verdict

from pipeline.cli import main
from pipeline.errors import ParameterError
from pipeline.rocking import codes, rules
from pipeline.rocking.block import rigid_block
from pipeline.rocking.numerics.ground import NO_QUIET
from pipeline.rocking.orientation import Planes, plane_grid, worst_plane
from pipeline.rocking.planar import contact, contact_laws, handoff, kernel
from pipeline.rocking.planner import FreeFlight, Guard, Physics, simulate_scene
from pipeline.rocking.simulate import rock, slide
from pipeline.rocking.structures import ContactState

#: every scene here is timed against its budget: the simulator is compiled first
pytestmark = pytest.mark.usefixtures("compiled_simulator")

TRANSFORMER = (3.0, 1.5, 0.5)          # height, width [m], mu: mu = tan(alpha) to one rounding
#: A block at rest for the general contact model, its fields typed as the simulator's own calls type them
#: (pipeline.compiled, 'One version per solver': a version of the model of its own is not compiled for the tests)
AT_REST = ContactState(0.0, codes.REST, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@pytest.fixture(scope="module")
def rinaldi(real_records):
    return next(r for r in real_records if r.record_id == "RSN1063_NORTHR_RRS")


@pytest.fixture(scope="module")
def real_records(records_dir):
    from pipeline.config import Config
    from pipeline.records.loader import iter_records

    return [r for r in iter_records(records_dir, config=Config()) if r.record_id.startswith("RSN1063")]


def transformer(mu: float):
    h, w, _ = TRANSFORMER
    return block(h, math.atan2(w / 2, h / 2), mu)


@pytest.mark.parametrize("mu", [0.49, 0.5, 0.51, math.tan(math.atan2(0.75, 1.5)),
                                math.nextafter(0.5, 1.0), 0.5 * (1 + 2 * rules.TIE_RTOL)])
def test_rinaldi_transformer_ends_in_every_plane_with_a_verdict(rinaldi, mu):
    """The regression: every plane of the grid, the vertical included, ends within the budget with a verdict."""
    planes = Planes(rinaldi.horizontal_ms2, rinaldi.azimuths_deg[0], rinaldi.vertical_ms2, g_ms2=G)
    blk = transformer(mu)
    for az in plane_grid(5.0):
        res = worst_plane(planes, [float(az)], rinaldi.dt_s, block=blk)
        assert res.scene.verdict in (0, 1)
    res = worst_plane(planes, [0.0, *plane_grid(5.0).tolist()], rinaldi.dt_s, block=blk, refine_span_deg=5.0,
                      refine_deg=1.0)
    assert res.scene.verdict == 0                 # neighbours 0.49 and 0.51 both stand (slide, slide-rock)
    assert res.scene.guard == 0


def test_rinaldi_transformer_screens_like_its_neighbours(make_records, tmp_path):
    """The whole command with the default (sampled) settings: the tie's verdict is one of its neighbours'."""
    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2",
                        "peer-at2/RSN1063_NORTHR_RRS-UP.AT2")
    inv = tmp_path / "inv.csv"
    inv.write_text("id,height_m,width_m,mu,azimuth_deg\nbelow,3.0,1.5,0.49,\ntie,3.0,1.5,0.5,\nabove,3.0,1.5,0.51,\n"
                   "tie-40,3.0,1.5,0.5,40\n")
    out = tmp_path / "out"
    assert main(["--records", str(root), "--blocks", str(inv), "--out", str(out), "-q"]) == 0
    ds = xr.open_dataset(out / "screening.nc")
    over = dict(zip(ds["block"].values.tolist(), ds["overturn_simulated"].values[0].tolist()))
    p = dict(zip(ds["block"].values.tolist(), ds["p_overturn"].values[0].tolist()))
    assert over["tie"] in (over["below"], over["above"]) and over["tie-40"] in (over["below"], over["above"])
    assert min(p["below"], p["above"]) <= p["tie"] <= max(p["below"], p["above"])
    assert np.all(ds["simulation_guard"].values == 0)


# --- tie rule 1: mu = tan(alpha) -----------------------------------------------------------------------------

@pytest.mark.parametrize("alpha_deg", [1.0, 5.0, 11.3, 26.565051177077994, 40.0, 54.0])
def test_tie_rule_1_mu_at_tan_alpha_slides_and_beyond_the_tolerance_rocks(alpha_deg):
    alpha = math.radians(alpha_deg)
    ties = mu_ties(alpha)
    for name in ("tie", "tie_up", "tie_down", "below"):
        assert not rules.rocks(alpha, ties[name]), name
    assert rules.rocks(alpha, ties["above"])
    # the compiled twin and the contact model's onset say the same
    assert rules.rocks_compiled(alpha, ties["tie_up"]) is False
    blk = rigid_block(3.0, alpha, 0.9, 1.0, ties["tie_up"], G, 1e-6, False, math.inf)
    assert contact_laws._onset(0.9 * G, G, blk)[0] == codes.SLIDE
    blk = rigid_block(3.0, alpha, 0.9, 1.0, ties["above"], G, 1e-6, False, math.inf)
    assert contact_laws._onset(math.tan(alpha) * G * 1.0000001, G, blk)[0] in (codes.ROCK, codes.SLIDE_ROCK)


@pytest.mark.parametrize("alpha_deg", [2.0, 15.0, 26.565051177077994, 45.0])
@pytest.mark.parametrize("height_m", [0.03, 1.0, 30.0])
def test_verdict_at_the_tie_is_one_of_its_neighbours(alpha_deg, height_m):
    """Continuity: at mu = tan(alpha) (and a double either side) the verdict is one of the verdicts just above
    and just below the tie, on every excitation family, with the level at and above the threshold."""
    alpha = math.radians(alpha_deg)
    rng = np.random.default_rng(int(alpha_deg * 100 + height_m * 10))
    ties = mu_ties(alpha)
    for factor in (1.0, 1.5, 4.0):
        for m in motions(factor * math.tan(alpha) * G, ulps=0, n=400, dt=0.01, rng=rng):
            out = {}
            for name, mu in ties.items():
                timed = run_scene(m, block(height_m, alpha, mu))
                assert timed.seconds < SCENE_BUDGET_S, (m.name, name, timed.seconds)
                out[name] = verdict(timed.scene)
            for name in ("tie", "tie_up", "tie_down"):
                assert out[name] in (out["above"], out["below"]), (m.name, factor, out)


# --- tie rule 2: a demand exactly at a threshold leaves the block at rest --------------------------------------

@pytest.mark.parametrize("alpha_deg", [3.0, 20.0, 45.0])
@pytest.mark.parametrize("which", ["slip", "uplift"])
def test_tie_rule_2_exactly_at_the_threshold_rests_and_one_double_above_moves(alpha_deg, which):
    alpha = math.radians(alpha_deg)
    t = math.tan(alpha)
    mu = 0.5 * t if which == "slip" else 2.0 * t
    level = (mu if which == "slip" else t) * G
    blk = block(1.0, alpha, mu)
    rng = np.random.default_rng(7)
    for m in motions(level, ulps=0, n=300, dt=0.01, rng=rng)[:4]:       # without a vertical
        sc = run_scene(m, blk).scene
        assert not sc.overturned and sc.theta_max == 0.0, m.name
        assert math.isnan(sc.sliding_max_m) or sc.sliding_max_m == 0.0, m.name
    for m in motions(level, ulps=8, n=300, dt=0.01, rng=rng)[:1]:       # constant, a few doubles above
        sc = run_scene(m, blk).scene
        assert sc.physics != Physics.none
        if which == "slip":
            assert sc.sliding_max_m > 0.0
        else:
            assert sc.theta_max > 0.0 or sc.sliding_max_m > 0.0


def test_tie_rule_2_the_sliding_kernel_and_the_general_model_agree_at_the_threshold():
    a = np.full(200, 0.3 * G)
    assert slide(a, 0.01, mu=0.3, g_ms2=G).sliding_max_m == 0.0
    cb = rigid_block(3.0, math.radians(40.0), 0.5, 1.0, 0.3, G, 1e-6, False, math.inf)
    out = contact.move(a, np.zeros(0), 0.01, cb, AT_REST, True, math.inf, False, kernel.empty_theta())
    assert out.slip_max == 0.0 and out.modes == 0


# --- tie rule 3: g + a_v = 0 -----------------------------------------------------------------------------------

@pytest.mark.parametrize("mu_factor", [0.5, 2.0])
def test_tie_rule_3_a_vertical_reaching_exactly_minus_g_is_free_flight(mu_factor):
    alpha = math.radians(15.0)
    blk = block(1.5, alpha, mu_factor * math.tan(alpha))
    ah = np.full(300, 0.05 * G)                          # below both thresholds: nothing moves but the vertical
    av = np.zeros(300)
    ah[150] = 0.0
    av[150] = -G
    timed = run_scene(type("M", (), {"ah": ah, "av": av, "dt": 0.01})(), blk)
    assert timed.scene.free_flight == FreeFlight.ground_flight
    assert timed.scene.verdict in (0, 1)
    av[150] = math.nextafter(-G, 0.0)                    # one double short of -g: contact holds, nothing moves
    sc = simulate_scene(ah, av, 0.01, block=blk)
    assert sc.physics == Physics.none and sc.free_flight == FreeFlight.none


# --- tie rule 4: theta = 0 with omega = 0 is rest --------------------------------------------------------------

def test_tie_rule_4_theta_and_omega_zero_is_rest():
    res = rock(np.zeros(100), 0.01, p=3.0, alpha=0.2, e=0.9, R_m=1.0, theta0=0.0, omega0=0.0)
    assert res.mode_end == kernel.REST and res.theta_max == 0.0 and res.n_impacts == 0


# --- tie rule 5: the e = 0 limit -------------------------------------------------------------------------------

def test_tie_rule_5_at_the_restitution_limit_the_block_slides():
    below, above = math.nextafter(ALPHA_MAX, 0.0), math.nextafter(ALPHA_MAX, math.inf)
    for alpha in (ALPHA_MAX, above):
        assert not rules.rocks(alpha, 100.0)
        blk = block(1.0, alpha, 100.0)
        sc = simulate_scene(np.full(200, 2.0 * G), None, 0.01, block=blk)
        assert sc.physics == Physics.sliding and not sc.overturned
    assert rules.rocks(below, 100.0)
    sc = run_scene(type("M", (), {"ah": np.full(200, 2.0 * G), "av": None, "dt": 0.01})(), block(1.0, below, 100.0))
    assert sc.scene.physics in (Physics.rocking, Physics.general) and sc.seconds < SCENE_BUDGET_S


# --- tie rule 6 and the caps: every loop ends ------------------------------------------------------------------

def test_steps_advance_a_clock_far_beyond_128_s():
    """A fixed 1e-14 s step no longer moves a double past t = 128 s; the smallest step grows with t."""
    for t in (0.0, 1.0, 127.0, 129.0, 1000.0, 1e5):
        assert t + rules.min_advance(t) > t


def test_the_handoff_ends_where_the_contact_model_met_a_cap(rinaldi, monkeypatch):
    """A general-model segment that ends at a cap ends the scene: the plain-Python handoff, with a contact model
    allowed one event, calls it once and returns the cap (before the fix it handed the scene back to the kernel,
    which stopped at once, up to 100,000 times)."""
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.rocking.simulate import contact_block, step_control

    blk = transformer(0.51)
    planes = Planes(rinaldi.horizontal_ms2, rinaldi.azimuths_deg[0], rinaldi.vertical_ms2, g_ms2=G)
    ah, av = np.asarray(planes.along(40.0)), np.asarray(rinaldi.vertical_ms2)
    first = rock(ah, rinaldi.dt_s, p=blk.p, alpha=blk.alpha, e=blk.e, R_m=blk.R_m, av_ms2=av, stop_mu=blk.mu).outcome
    assert handoff.stopped_short(first)                   # the friction demand stops pure rocking: a handoff
    calls = []
    move_py = contact.move.py_func

    def counted(*args):
        calls.append(args[4].t)
        return move_py(*args)

    monkeypatch.setattr(contact, "move", counted)
    monkeypatch.setattr(contact, "MAX_EVENTS", 1)
    if hasattr(contact._move, "py_func"):               # the loop too, so that it reads the patched cap (compiled, it
        monkeypatch.setattr(contact, "_move", contact._move.py_func)   # keeps the one it was compiled or cached with)
    out = handoff.continue_rocking.py_func(first, ah, av, rinaldi.dt_s, contact_block(blk, SimulationConfig()),
                                           step_control(SimulationConfig()),
                                           True)
    assert out.status & codes.STATUS_EVENT_CAP and len(calls) == 1


def test_a_scene_at_its_step_budget_ends_with_the_verdict_of_its_state(monkeypatch):
    """The plain-Python path with a budget of a few steps: ended, flagged, a verdict from the state."""
    monkeypatch.setattr(kernel, "MAX_STEPS_PER_SAMPLE", 0)
    monkeypatch.setattr(kernel, "MAX_STEPS_FIXED", 5)
    rock_py = kernel.rock.py_func if hasattr(kernel.rock, "py_func") else kernel.rock
    if hasattr(kernel._rock, "py_func"):                # the loop too, so that it reads the patched budget
        monkeypatch.setattr(kernel, "_rock", kernel._rock.py_func)
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.rocking.simulate import step_control
    from pipeline.rocking.structures import RockingOutput, RockingState

    a = np.full(400, 0.5 * G)
    o = rock_py(a, np.zeros(0), 0.01, 3.99, rigid_block(3.0, 0.2, 0.9, 1.0, math.inf, G, 1e-6, False, math.inf),
                step_control(SimulationConfig()), RockingState(0.0, 0.0, 0.0), True,
                RockingOutput(np.zeros(0), np.zeros((0, 3))), NO_QUIET)
    assert o.status & kernel.STATUS_STEP_CAP and o.t_stop < 3.99
    # a few steps after the uplift the block is barely tilted and slow: its free rocking from there cannot reach
    # the saddle (Housner 1963: energy is only lost after the record), so the state's verdict is to stand
    assert 0.0 < abs(o.theta_end) < 0.01 * 0.2 and not o.overturned and o.theta_max_rad < 0.2


@pytest.mark.parametrize("n", [0, 1])
def test_empty_and_one_sample_records_are_refused_by_name(n):
    with pytest.raises(ParameterError, match="at least 2 samples"):
        rock(np.zeros(n), 0.01, p=3.0, alpha=0.2, e=0.9, R_m=1.0)
    with pytest.raises(ParameterError, match="at least 2 samples"):
        slide(np.zeros(n), 0.01, mu=0.3)


@pytest.mark.parametrize("n", [0, 1, 2])
def test_the_compiled_kernels_end_on_empty_and_one_sample_records(n):
    """Below the wrappers' checks, the kernels themselves end on records of 0, 1 and 2 samples."""
    a = np.full(n, 3.0 * G)
    m = type("M", (), {"ah": a, "av": None, "dt": 0.01})()
    for mu in (0.1, 2.0):
        assert sampled_verdict(m, block(1.0, 0.2, mu)) in (0, 1)
    cb = rigid_block(3.0, 0.2, 0.9, 1.0, 2.0, G, 1e-6, False, math.inf)
    out = contact.move(a, np.zeros(0), 0.01, cb, AT_REST, True, math.inf, False, kernel.empty_theta())
    assert not out.overturned or n == 2


def test_each_guard_is_its_own_bit_and_the_file_decodes_it():
    from pipeline.rocking.planner import guard_names
    from pipeline.schema import SCHEMA

    values = [int(g) for g in Guard]
    assert all(v & (v - 1) == 0 for v in values) and len(set(values)) == len(values)    # distinct powers of two
    attrs = SCHEMA["simulation_guard"][3]
    assert attrs["flag_masks"].tolist() == values and attrs["flag_meanings"].split() == [g.name for g in Guard]
    assert guard_names(Guard.tie_hold | Guard.step_cap) == "tie_hold, step_cap"


def test_a_slip_a_rounding_started_at_the_threshold_stops_at_once():
    """Found by the threshold property test: noise whose peak is exactly mu g started a slip a few ulps before a
    sample, and the slip velocity left at 1.6e-33 m/s was never seen to stop (its root, 1e-33 s away, was
    discarded as the slip's own start), so the block slid 5.66 m the wrong way under a demand at the threshold."""
    alpha = 0.7544114883954032
    mu = 0.5 * math.tan(alpha)
    noise = next(m for m in motions(mu * G, ulps=0, n=400, dt=0.01, rng=np.random.default_rng(0)) if m.name == "noise")
    assert np.max(np.abs(noise.ah)) == mu * G
    assert slide(noise.ah, noise.dt, mu=mu, g_ms2=G).sliding_max_m < 1e-12
