"""Floor motion by the continuous shear-flexural model (Miranda & Taghavi 2005), against its exact limits,
closed forms and an independent discrete model."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import eigh

from pipeline.errors import ParameterError
from pipeline.floors.model import modes
from pipeline.floors.motion import Building, floor_filter, floor_motion, relative_acceleration


def test_pure_flexure_has_the_cantilever_beam_period_ratios():
    """alpha = 0: the modes of a flexural cantilever, 1 + cos(gamma) cosh(gamma) = 0: T1/T2 = 6.267,
    T1/T3 = 17.547, T1/T4 = 34.386, and the roof participation Gamma_1 phi_1(1) = 1.566."""
    m = modes(0.0, at_least=4)
    np.testing.assert_allclose(m.period_ratio[1:4], [6.267, 17.547, 34.386], atol=1e-3)
    assert m.participation[0] == pytest.approx(1.566, abs=1e-3)
    for g in m.gamma[:4]:
        assert 1 + math.cos(g) * math.cosh(g) == pytest.approx(0.0, abs=1e-8 * math.cosh(g))


@pytest.mark.parametrize("alpha, ratios, atol", [(30.0, (3.03, 5.15, 7.41), 0.01), (300.0, (3.0, 5.0, 7.0), 0.01)])
def test_towards_pure_shear_the_ratios_tend_to_3_5_7(alpha, ratios, atol):
    m = modes(alpha, at_least=4)
    np.testing.assert_allclose(m.period_ratio[1:4], ratios, atol=atol)


def test_pure_shear_roof_participation_and_first_mode_mass():
    """A shear cantilever: phi_1 = sin(pi x / 2), Gamma_1 phi_1(1) = 4 / pi, first-mode mass share 8 / pi^2."""
    m = modes(1000.0)
    assert m.participation[0] == pytest.approx(4 / math.pi, rel=2e-3)
    assert m.mass_share[0] == pytest.approx(8 / math.pi ** 2, rel=5e-3)
    x = np.linspace(0, 1, 11)
    np.testing.assert_allclose(m.shape(0, x), np.sin(np.pi * x / 2), atol=3e-3)


@pytest.mark.parametrize("alpha", [0.0, 2.0, 8.0, 30.0])
def test_the_modes_kept_reach_95_percent_of_the_mass(alpha):
    m = modes(alpha)
    assert m.mass_share.sum() >= 0.95 and np.all(np.diff(m.period_ratio) > 0)


def test_a_harmonic_input_gives_the_closed_form_steady_state():
    """u'' of a damped oscillator under A sin(W t) settles to the amplitude A r^2 / sqrt((1 - r^2)^2 +
    (2 zeta r)^2), r = W / w (relative acceleration)."""
    T, zeta, W, A = 0.6, 0.05, 2 * math.pi / 0.8, 1.0
    dt = 0.005
    t = np.arange(0, 60.0, dt)
    acc = relative_acceleration(A * np.sin(W * t), dt, T, zeta)
    r = W / (2 * math.pi / T)
    expected = A * r * r / math.sqrt((1 - r * r) ** 2 + (2 * zeta * r) ** 2)
    assert np.max(np.abs(acc[t > 40])) == pytest.approx(expected, rel=2e-3)


def test_a_block_on_the_ground_of_a_building_feels_the_ground():
    b = Building("museum", 0.6, 0.05, 8.0, 24.0)
    rng = np.random.default_rng(3)
    g = rng.normal(size=(2, 2000))
    np.testing.assert_array_equal(floor_motion(g, 0.01, floor_filter(b, 0.0)), g)


def test_bad_buildings_are_parameter_errors():
    with pytest.raises(ParameterError, match="outside its height"):
        floor_filter(Building("b", 0.6, 0.05, 8.0, 24.0), 30.0)
    with pytest.raises(ParameterError, match="period_s"):
        floor_filter(Building("b", 0.0, 0.05, 8.0, 24.0), 3.0)
    with pytest.raises(ParameterError, match="stiffness_ratio"):
        modes(-1.0)


def shear_building_roof(ground, dt, n_storeys, period_s, zeta):
    """An independent discrete model: a uniform shear building of lumped masses, its modes by eigen-analysis
    (omega_n = 2 sqrt(k/m) sin((2n - 1) pi / (2 (2N + 1)))), each mode integrated by the same exact step,
    the roof's total acceleration."""
    k = np.diag(np.full(n_storeys, 2.0)) - np.diag(np.ones(n_storeys - 1), 1) - np.diag(np.ones(n_storeys - 1), -1)
    k[-1, -1] = 1.0
    w2, vecs = eigh(k)                          # unit stiffness and mass
    scale = (2 * math.pi / period_s) ** 2 / w2[0]
    out = ground.copy()
    ones = np.ones(n_storeys)
    for i in range(n_storeys):
        phi = vecs[:, i]
        gamma = phi @ ones / (phi @ phi)
        out += gamma * phi[-1] * relative_acceleration(ground, dt, 2 * math.pi / math.sqrt(w2[i] * scale), zeta)
    return out, np.sqrt(w2 / w2[0])


def test_a_tall_shear_building_of_lumped_masses_tends_to_the_continuous_shear_model(records_dir):
    """The roof of a 40-storey uniform shear building (lumped masses) against the continuous model with a large
    alpha, under a real record: the discrete frequencies follow their closed form, and the roof histories agree
    to 5 % of their peak."""
    from pipeline.config import Config
    from pipeline.records.loader import iter_records

    rec = next(r for r in iter_records(records_dir / "peer-at2", config=Config()) if r.record_id.startswith("RSN1063"))
    ground, dt = rec.horizontal_ms2[0], rec.dt_s
    roof_discrete, ratios = shear_building_roof(ground, dt, 40, 1.0, 0.05)
    n = np.arange(1, 41)
    closed = np.sin((2 * n - 1) * np.pi / (2 * 81)) / np.sin(np.pi / 162)
    np.testing.assert_allclose(ratios, closed, rtol=1e-10)
    roof = floor_motion(ground, dt, floor_filter(Building("shear", 1.0, 0.05, 1000.0, 120.0), 120.0))[0]
    assert np.max(np.abs(roof - roof_discrete)) < 0.05 * np.max(np.abs(roof_discrete))
    assert np.max(np.abs(roof)) > 2.0 * np.max(np.abs(ground))        # the roof amplifies (3.1x measured)


@pytest.fixture(scope="module")
def rinaldi_dir(tmp_path_factory, records_dir):
    import shutil
    root = tmp_path_factory.mktemp("rinaldi")
    (root / "fn-ascii").mkdir()
    shutil.copy(records_dir / "fn-ascii" / "rinaldi_fn.dat", root / "fn-ascii" / "rinaldi_fn.dat")
    (root / "units.toml").write_text((records_dir / "units.toml").read_text())
    return root


def museum_inventory(tmp_path, rows):
    from pipeline.blocks import read_inventory
    csv = tmp_path / "blocks.csv"
    csv.write_text("id,height_m,width_m,mu,building,floor,floor_height_m\n" + "\n".join(rows) + "\n")
    return read_inventory(csv, default_mu=0.6)


MUSEUM = Building("MUSEUM", 0.6, 0.05, 3.0, 21.0, 6)


def test_a_block_on_the_ground_floor_is_screened_exactly_as_on_the_ground(tmp_path, rinaldi_dir, config):
    """Similitude: z = 0 is the ground (phi_i(0) = 0), so every per-scene value is identical, bit for bit."""
    import dataclasses

    from pipeline.records.listing import find_records
    from pipeline.records.side_files import read_declared_units
    from pipeline.run.screening import Context, screen_record
    from pipeline.schema import PROBABILITY_VARS, PULSE_BLOCK_VARS, SIMULATION_VARS

    inv = museum_inventory(tmp_path, ["A,1.5,0.3,0.6,,,", "B,1.5,0.3,0.6,MUSEUM,0,", "C,1.5,0.3,0.6,MUSEUM,,0"])
    cfg = dataclasses.replace(config, uncertainty=dataclasses.replace(config.uncertainty, samples=3))
    src = find_records(rinaldi_dir, config=cfg)[0][0]
    res = screen_record(src, Context(str(rinaldi_dir), cfg, inv, read_declared_units(rinaldi_dir, cfg), None,
                                     {"MUSEUM": MUSEUM}))
    assert res.ok, res.status
    for name in PULSE_BLOCK_VARS + SIMULATION_VARS + PROBABILITY_VARS:
        v = np.asarray(res.blocks[name], dtype=float)
        np.testing.assert_array_equal(v[1:], [v[0], v[0]], err_msg=name)


def test_the_top_floor_amplifies_and_its_velocity_is_the_integral_of_its_acceleration(rinaldi_dir, config):
    """The floor's velocity comes from the same oscillator states as its acceleration: its derivative matches
    the floor acceleration (to the central difference's error), and the top floor amplifies the ground."""
    from pipeline.floors.standing import floor_record
    from pipeline.records.loader import iter_records

    rec = next(iter_records(rinaldi_dir, config=config))
    top = floor_record(rec, MUSEUM, 17.5)
    acc, vel = top.horizontal_ms2[0], top.velocity_ms[0]
    deriv = (vel[2:] - vel[:-2]) / (2 * rec.dt_s)
    assert np.max(np.abs(deriv - acc[1:-1])) < 0.02 * np.max(np.abs(acc))
    assert top.pga_ms2() > 1.5 * rec.pga_ms2()
    assert top.vertical_ms2 is rec.vertical_ms2                     # the vertical passes unchanged


def test_placements_name_every_problem(tmp_path):
    from pipeline.errors import InventoryError
    from pipeline.floors.buildings import place_blocks

    inv = museum_inventory(tmp_path, ["A,1.5,0.3,0.6,LIBRARY,2,", "B,1.5,0.3,0.6,MUSEUM,,30",
                                      "C,1.5,0.3,0.6,MUSEUM,,", "D,1.5,0.3,0.6,MUSEUM,6,"])
    with pytest.raises(InventoryError) as err:
        place_blocks(inv, {"MUSEUM": MUSEUM})
    text = str(err.value)
    assert "block A: building 'LIBRARY' is not in the buildings file; buildings: MUSEUM" in text
    assert "block B: floor at 30 m is outside building 'MUSEUM'" in text
    assert "block C: in building 'MUSEUM' but no floor_height_m" in text
    placed = place_blocks(museum_inventory(tmp_path, ["D,1.5,0.3,0.6,MUSEUM,6,"]), {"MUSEUM": MUSEUM})
    assert placed[0].height_m == pytest.approx(21.0)


def test_bad_buildings_files_name_the_line_and_column(tmp_path):
    from pipeline.errors import InventoryError
    from pipeline.floors.buildings import read_buildings

    path = tmp_path / "buildings.csv"
    path.write_text("id,period_s,damping,stiffness_ratio,height_m,n_stories\nM,0.6,0.05,3,21,6\nL,-1,0.05,3,21,\n"
                    "K,0.5,1.5,3,21,2.5\n")
    with pytest.raises(InventoryError) as err:
        read_buildings(path)
    text = str(err.value)
    assert "line 3, column 'period_s'" in text and "line 4, column 'damping'" in text
    assert "line 4, column 'n_stories'" in text
    for header, message in (("id,period_s,damping,height_m", r"line 1: missing required column.*'stiffness_ratio'"),
                            ("id,period_s,damping,stiffness_ratio,height_m,height_m", "appear more than once")):
        path.write_text(header + "\n")
        with pytest.raises(InventoryError, match=message):
            read_buildings(path)


def test_fragility_on_a_floor_is_against_the_ground_im(tmp_path, rinaldi_dir, config):
    """The stripes scale the ground record; a block on the ground floor gets the fit of the same block on the
    ground, and the same block on the top floor overturns at a lower ground level."""
    import dataclasses

    from pipeline.run.executors import SerialExecutor
    from pipeline.run.fragility_stripes import run_stripes

    inv = museum_inventory(tmp_path, ["A,1.5,0.3,0.6,,,", "B,1.5,0.3,0.6,MUSEUM,0,", "T,1.5,0.3,0.6,MUSEUM,,17.5"])
    cfg = dataclasses.replace(config, uncertainty=dataclasses.replace(config.uncertainty, samples=0))
    levels = np.array([0.05, 0.1, 0.2, 0.4, 0.8]) * 9.80665
    with SerialExecutor() as ex:
        results, failures, _ = run_stripes(rinaldi_dir, inv, cfg, im="pga", levels=levels, executor=ex,
                                           buildings={"MUSEUM": MUSEUM})
    assert not failures and len(results) == 1
    verdict = results[0]["verdict"]
    np.testing.assert_array_equal(verdict[:, 1], verdict[:, 0])
    np.testing.assert_array_equal(results[0]["factor"][:, 2], results[0]["factor"][:, 0])   # the ground IM
    first = [int(np.argmax(verdict[:, k] == 1)) if np.any(verdict[:, k] == 1) else len(levels) for k in (0, 2)]
    assert first[1] <= first[0]


def test_pulses_nc_holds_each_floors_pulses_apart_from_the_grounds(tmp_path, rinaldi_dir, config):
    """Group ``floors`` of pulses.nc: one series per (record, floor in use), the pulse of that floor's motion
    (extracted again here from :func:`floor_record`), written from the scene cache identical to the series in
    memory; the ground's group is the ground-only run's, untouched by the floors."""
    import dataclasses

    import xarray as xr

    from pipeline.floors.standing import floor_record
    from pipeline.pulses import analyze
    from pipeline.records.loader import iter_records
    from pipeline.run.batch import run
    from pipeline.store import FLOOR_GROUP, open_results, write_atomic

    cfg = dataclasses.replace(config, uncertainty=dataclasses.replace(config.uncertainty, samples=0))
    rows = ["G,1.5,0.3,0.6,,,", "T,1.5,0.3,0.6,MUSEUM,,17.5", "U,1.2,0.3,0.6,MUSEUM,,17.5", "M,1.5,0.3,0.6,MUSEUM,3,"]
    inv = museum_inventory(tmp_path, rows)
    buildings = {"MUSEUM": MUSEUM}
    memory = run(rinaldi_dir, inv, cfg, buildings=buildings).pulses
    cached = run(rinaldi_dir, inv, cfg, buildings=buildings, out_dir=tmp_path / "out").pulses
    path = cached.write(tmp_path / "pulses.nc")
    with xr.open_dataset(path, group=FLOOR_GROUP) as f:
        floors = f.load()
    assert floors.series_id.values.tolist() == ["rinaldi_fn MUSEUM@10.5 m", "rinaldi_fn MUSEUM@17.5 m"]
    xr.testing.assert_identical(floors, open_results(write_atomic(memory.floor_dataset(), tmp_path / "f.nc")))
    rec = next(iter_records(rinaldi_dir, config=cfg))
    for k, z in enumerate((10.5, 17.5)):
        pulse = analyze(floor_record(rec, MUSEUM, z), method=cfg.pulses.method, tp_min_s=cfg.pulses.tp_min_s,
                        tp_max_s=cfg.pulses.tp_max_s)
        sl = slice(int(floors.row_size.values[:k].sum()), int(floors.row_size.values[:k + 1].sum()))
        np.testing.assert_allclose(floors.pulse.values[sl], pulse.result.best.pulse_cms / 100, rtol=1e-6, atol=1e-7)
        assert floors.pulse_period.values[k] == pytest.approx(pulse.result.tp_s, rel=1e-12)
        assert floors.floor_height.values[k] == z
    ground_only = run(rinaldi_dir, museum_inventory(tmp_path, rows[:1]), cfg).pulses
    xr.testing.assert_identical(open_results(path), open_results(write_atomic(ground_only.dataset(),
                                                                              tmp_path / "g.nc")))


def test_the_report_shows_each_upper_floor_assets_floor_motion(tmp_path, rinaldi_dir):
    """One floor figure per (governing record, floor) of the assets on upper floors, linked from each of them;
    none for the assets on the ground or the ground floor, whose motion is the ground's."""
    import re

    from pipeline.cli import main

    (tmp_path / "b.csv").write_text("id,period_s,damping,stiffness_ratio,height_m,n_stories\nMUSEUM,0.6,0.05,3,21,6\n")
    inv = tmp_path / "blocks.csv"
    inv.write_text("id,height_m,width_m,mu,building,floor,floor_height_m\nG,1.5,0.3,0.6,MUSEUM,0,\n"
                   "T,1.5,0.3,0.6,MUSEUM,5,\nU,1.2,0.3,0.6,MUSEUM,,17.5\nM,1.5,0.3,0.6,MUSEUM,3,\n")
    out = tmp_path / "out"
    assert main(["--records", str(rinaldi_dir), "--blocks", str(inv), "--buildings", str(tmp_path / "b.csv"),
                 "--out", str(out), "--samples", "0", "-q"]) == 0
    html = (out / "report.html").read_text()
    captions = re.findall(r"<figcaption>MUSEUM, floor at ([\d.]+) m, under rinaldi_fn: ([^<]*)</figcaption>", html)
    assert sorted((z, sorted(blocks.split(", "))) for z, blocks in captions) == [("10.5", ["M"]), ("17.5", ["T", "U"])]
    assert html.count("the floor's motion</a>") == 3


def test_a_block_added_on_a_new_floor_keeps_the_other_floors_pulses(tmp_path, rinaldi_dir, config):
    """A second run into the same output with one block added on another floor screens only that block; the
    floors of the first run keep their series (read back from the scene cache), so pulses.nc equals a fresh
    run's."""
    import dataclasses

    import xarray as xr

    from pipeline.run.batch import run
    from pipeline.store import FLOOR_GROUP

    cfg = dataclasses.replace(config, uncertainty=dataclasses.replace(config.uncertainty, samples=0))
    rows = ["T,1.5,0.3,0.6,MUSEUM,,17.5", "M,1.5,0.3,0.6,MUSEUM,3,"]
    buildings, out = {"MUSEUM": MUSEUM}, tmp_path / "out"
    run(rinaldi_dir, museum_inventory(tmp_path, rows[:1]), cfg, buildings=buildings, out_dir=out)
    second = run(rinaldi_dir, museum_inventory(tmp_path, rows), cfg, buildings=buildings, out_dir=out)
    assert second.counts["scenes_computed"] == 1
    fresh = run(rinaldi_dir, museum_inventory(tmp_path, rows), cfg, buildings=buildings)
    with xr.open_dataset(second.pulses.write(tmp_path / "second.nc"), group=FLOOR_GROUP) as f:
        written = f.load()
    assert written.sizes["station"] == 2 and not np.isnan(written.velocity.values).any()
    xr.testing.assert_identical(written, fresh.pulses.floor_dataset())
