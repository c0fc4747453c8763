"""Verdicts that can be believed: the worst orientation, a planner that never skips motion, free flight,
honest margins (issue 15)."""

from __future__ import annotations

import dataclasses
import math
import shutil

import numpy as np
import pytest

from pipeline.blocks import read_inventory
from pipeline.bodies.planar import overturn_scale_simulated
from pipeline.constants import G
from pipeline.records.listing import find_records
from pipeline.records.side_files import read_declared_units
from pipeline.rocking.block import Block
from pipeline.rocking.orientation import Orientation, Planes, plane_grid, worst_plane
from pipeline.rocking.planner import Physics, Response, plan, simulate_scene
from pipeline.rocking.references.reference import rock_reference
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import slide
from pipeline.run.screening import Context, screen_record

#: Near-field two-component records with known azimuths (Northridge, Kocaeli, Chi-Chi, Duzce, Imperial Valley).
NEAR_FIELD = ("RSN1063_NORTHR_RRS", "RSN1086_NORTHR_SYL", "RSN1176_KOCAELI_YPT", "RSN1505_CHICHI_TCU068",
              "RSN1605_DUZCE_DZC", "RSN182_IMPVALL.H_H-E07")
#: (height, width) [m] of blocks near their overturning thresholds on these records.
GEOMETRIES = ((1.1, 0.2), (2.0, 0.5), (3.0, 0.9), (4.0, 1.2), (1.5, 0.6))


def _block(height_m: float, width_ratio: float) -> dict:
    h, b = height_m / 2, width_ratio * height_m / 2
    alpha = math.atan(b / h)
    R = math.hypot(b, h)
    return {"p": math.sqrt(3 * G / (4 * R)), "alpha": alpha, "e": 1 - 1.5 * math.sin(alpha) ** 2, "R_m": R}


@pytest.fixture(scope="module")
def explicit_planes(tmp_path_factory, records_dir, config):
    """Each geometry with a blank azimuth and in every explicit 5-degree plane, screened on real near-field
    records through the whole screening task."""
    root = tmp_path_factory.mktemp("nf")
    for f in (records_dir / "peer-at2").iterdir():
        if f.name.startswith(NEAR_FIELD):
            shutil.copy(f, root / f.name)
    rows = ["id,height_m,width_m,mu,azimuth_deg"]
    for g, (hgt, wid) in enumerate(GEOMETRIES):
        rows.append(f"G{g}-blank,{hgt},{wid},0.7,")
        rows += [f"G{g}-{az:03d},{hgt},{wid},0.7,{az}" for az in range(0, 180, 5)]
    csv = root / "blocks.csv"
    csv.write_text("\n".join(rows) + "\n")
    inv = read_inventory(csv, default_mu=0.6)
    ctx = Context(str(root), config, inv, read_declared_units(root, config))
    sources, failures = find_records(root, config=config)
    assert not failures and len(sources) == len(NEAR_FIELD)
    results = [screen_record(s, ctx) for s in sources]
    assert all(r.ok for r in results), [r.status for r in results if not r.ok]
    return inv, results, ctx, sources


def test_blank_azimuth_is_never_safer_than_any_explicit_5_degree_plane(explicit_planes):
    inv, results, _, _ = explicit_planes
    ids = list(inv.ids)
    found_overturn = found_stand = 0
    for res in results:
        b = res.blocks
        for g in range(len(GEOMETRIES)):
            blank = ids.index(f"G{g}-blank")
            explicit = [ids.index(f"G{g}-{az:03d}") for az in range(0, 180, 5)]
            assert b["orientation"][blank] == Orientation.scanned
            assert all(b["orientation"][j] == Orientation.given for j in explicit)
            over = b["overturn_simulated"][explicit] == 1
            if over.any():
                assert b["overturn_simulated"][blank] == 1, (res.record_id, GEOMETRIES[g])
                found_overturn += 1
            if b["overturn_simulated"][blank] == 1:
                # the governing plane is a real overturning plane (on the grid: the explicit block agrees)
                az = b["governing_azimuth"][blank]
                if az % 5 == 0:
                    assert b["overturn_simulated"][ids.index(f"G{g}-{int(az):03d}")] == 1
            else:
                found_stand += 1
                # standing everywhere: the reported rotation is the largest of all planes
                assert b["theta_max"][blank] >= np.nanmax(b["theta_max"][explicit]) - 1e-12
    # the check is not vacuous: both outcomes occur on these records
    assert found_overturn >= 5 and found_stand >= 1


def test_the_scan_finds_overturnings_the_pulse_axis_misses(explicit_planes, tmp_path):
    # the old behaviour simulated a blank-azimuth block along the pulse axis only; on these records that
    # misses overturnings which the scan finds (and the scan never loses one the axis finds)
    from pipeline.run.screening import simulate_scenes

    inv, results, ctx, sources = explicit_planes
    blank = np.array([bid.endswith("blank") for bid in inv.ids])
    missed_by_axis = 0
    for res, src in zip(results, sources):
        rec = ctx.load(src)
        axis = simulate_scenes(rec, res.blocks["block_pulse_azimuth"], ctx, blank, scan=False)
        scanned = res.blocks["overturn_simulated"][blank]
        along_axis = axis.overturn_simulated[blank]
        assert not np.any((along_axis == 1) & (scanned != 1))
        missed_by_axis += int(np.sum((along_axis == 0) & (scanned == 1)))
    assert missed_by_axis >= 1


def test_worst_plane_of_a_synthetic_oblique_pulse():
    # a one-sine pulse along N30E only: planes far from 30 deg cannot lift the block; the scan finds 30 deg
    blk = _block(1.0, 0.15)
    dt = 0.005
    t = np.arange(0, 4, dt)
    pulse = np.where((t > 0.5) & (t < 1.5), np.sin(2 * math.pi * (t - 0.5)), 0.0) * 3.0 * G * math.tan(blk["alpha"])
    az = math.radians(30.0)
    h = np.vstack([pulse * math.cos(az), pulse * math.sin(az)])       # N and E components
    planes = Planes(h, 0.0, None)
    assert planes.vector_ratio() == pytest.approx(np.max(np.abs(pulse)) / G)
    res = worst_plane(planes, [90.0, *plane_grid(5.0)], dt, block=Block(mu=0.7, **blk))
    assert res.scene.overturned and abs(res.azimuth_deg - 30.0) <= 25.0
    # the plane at 120 deg sees nothing: a block given that plane is proven at rest without integration
    at_rest = worst_plane(planes, [120.0], dt, block=Block(mu=0.7, **blk))
    assert at_rest.planes_simulated == 0 and at_rest.scene.physics == Physics.none


@pytest.mark.parametrize("height_m", [0.8, 1.6, 3.0])
def test_a_small_vertical_under_a_plateau_is_never_planned_away(height_m):
    # a 6.5 s plateau of 0.99 g tan(alpha) with 4.9 % g of vertical at 0.75 Hz: the vertical brings
    # (g + a_v) tan(alpha) under the horizontal. The old planner called this 'none'.
    blk = _block(height_m, 0.2)
    dt = 0.005
    t = np.arange(0, 9, dt)
    plateau = np.clip(np.minimum((t - 0.5) / 0.25, (7.25 - t) / 0.25), 0, 1)
    ah = 0.99 * G * math.tan(blk["alpha"]) * plateau
    av = 0.049 * G * np.sin(2 * math.pi * 0.75 * t)
    # no fraction of g decides that the scene stays still, not even the approximation's
    for fraction in (0.0, 0.05):
        assert plan(ah, av, alpha=blk["alpha"], mu=0.6, vertical_fraction=fraction) != Physics.none
    sc = simulate_scene(ah, av, dt, block=Block(mu=0.6, **blk))
    ref = rock_reference(ah, dt, av=av, **{k: v for k, v in blk.items() if k != "R_m"})   # solve_ivp, independent
    assert sc.physics == Physics.rocking_vertical
    assert sc.overturned and ref.overturned
    # without the vertical nothing moves at all
    assert plan(ah, None, alpha=blk["alpha"], mu=0.6) == Physics.none


#: The simulator without the general contact model: free flight stops the kernels (no verdict).
NO_CONTACT_MODEL = dataclasses.replace(SimulationConfig(), contact_model=False)


def test_free_flight_is_not_a_verdict_without_the_contact_model_and_is_simulated_with_it():
    # h = 0.23 m, b/h = 0.05 under 1.2 g of vertical at 5 Hz and 0.01 g of horizontal: the ground falls
    # faster than gravity at t_f = (pi + asin(1/1.2)) / (2 pi 5) (closed form), before anything else happens
    blk = _block(0.23, 0.05)
    dt = 0.001
    t = np.arange(0, 2, dt)
    av = 1.2 * G * np.sin(2 * math.pi * 5 * t)
    ah = 0.01 * G * np.sin(2 * math.pi * 5 * t + 0.3)
    t_flight = (math.pi + math.asin(1 / 1.2)) / (2 * math.pi * 5)
    sc = simulate_scene(ah, av, dt, block=Block(mu=0.6, **blk), settings=NO_CONTACT_MODEL)
    assert sc.response == Response.free_flight and sc.verdict == -1 and not sc.overturned
    assert sc.free_flight == 1
    assert sc.t_flight == pytest.approx(t_flight, abs=dt / 10)     # the sine against its linear interpolant
    # with the general contact model (the default) the block flies, lands and gets a verdict
    sc = simulate_scene(ah, av, dt, block=Block(mu=0.6, **blk))
    assert sc.physics == Physics.general and sc.verdict in (0, 1) and sc.free_flight == 1
    assert sc.t_flight == pytest.approx(t_flight, abs=dt / 10)
    # a block that slides (mu < tan alpha) under the same vertical and no horizontal at all: no slip,
    # and no slide verdict without the contact model; with it, it flies flat, lands flat and stands
    sc = simulate_scene(np.zeros_like(t), av, dt, block=Block(mu=0.03, **blk), settings=NO_CONTACT_MODEL)
    assert sc.response == Response.free_flight and sc.sliding_max_m == 0.0
    sc = simulate_scene(np.zeros_like(t), av, dt, block=Block(mu=0.03, **blk))
    assert sc.physics == Physics.general and sc.verdict == 0 and sc.sliding_max_m <= 1e-12
    assert sc.theta_max == 0.0
    # the Coulomb kernel with zero horizontal input never slips (it used to, with friction of the wrong sign)
    for scale in (0.9, 1.2):
        assert slide(np.zeros_like(t), dt, mu=0.3, av_ms2=scale / 1.2 * av).sliding_max_m == 0.0


def test_a_block_overturned_before_the_flight_keeps_its_verdict():
    blk = _block(1.0, 0.1)
    dt = 0.005
    t = np.arange(0, 6, dt)
    ah = np.where(t < 2.0, 4.0 * G * math.tan(blk["alpha"]) * np.sin(2 * math.pi * 0.5 * t), 0.0)
    av = np.where(t > 4.0, -1.5 * G * np.sin(math.pi * (t - 4.0)) ** 2, 0.0)
    sc = simulate_scene(ah, av, dt, block=Block(mu=0.7, **blk))
    assert sc.overturned and sc.t_overturn < 4.0 and sc.verdict == 1


def test_a_standing_scene_can_have_a_margin_below_one():
    # WSH20 (a public MATLAB rocking study, 2020; its critical 0.315034 g): p = 2, alpha = 15 deg,
    # a_p cos(pi t) for 2 s. 0.3151 g
    # overturns and 0.33 g stands: on the 0.33 g record the upward scan finds the smaller factor
    alpha, p = math.radians(15.0), 2.0
    R = 3 * G / (4 * p * p)
    dt = 0.001
    t = np.arange(0, 6, dt)
    ah = np.where(t <= 2.0, 0.33 * G * np.cos(math.pi * t), 0.0)
    kw = dict(p=p, alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2, R_m=R, mu=0.9, g_ms2=G)
    from pipeline.config import SimulationConfig

    settings = SimulationConfig(margin_step=0.002)
    assert simulate_scene(ah, None, dt, settings=settings, block=Block(**kw)).verdict == 0
    scale, runs = overturn_scale_simulated(ah, None, dt, settings=settings, block=Block(**kw))
    assert scale < 1.0 and runs > 1
    assert simulate_scene(scale * ah, None, dt, settings=settings, block=Block(**kw)).overturned


@pytest.mark.parametrize("width_ratio", [1e-4, 0.01, 1.40, 1.4142])
def test_extreme_slenderness_stays_finite(width_ratio, records_dir, config):
    from pipeline.records.loader import iter_records

    rec = next(r for r in iter_records(records_dir / "peer-at2", config=config)
               if r.record_id.startswith("RSN1063"))
    blk = _block(1.0, width_ratio)
    blk["e"] = max(blk["e"], 0.0)
    res = worst_plane(Planes(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2), [0.0], rec.dt_s,
                      block=Block(mu=0.6, **blk))
    assert np.isfinite(res.scene.theta_max) and res.scene.response in set(Response)


@pytest.mark.parametrize("azimuth", ["400", "-10", "nan"])
def test_azimuth_outside_0_360_is_rejected_with_line_and_column(tmp_path, azimuth):
    from pipeline.errors import InventoryError

    csv = tmp_path / "inv.csv"
    csv.write_text(f"id,height_m,width_m,azimuth_deg\nA,1.0,0.2,30\nB,1.0,0.2,{azimuth}\n")
    with pytest.raises(InventoryError, match=r"inv.csv.*line 3.*azimuth_deg"):
        read_inventory(csv, default_mu=0.6)


def test_all_zero_horizontals_get_a_clear_status(tmp_path, records_dir, blocks_csv, config):
    # a real AT2 pair with every sample replaced by zero: a failure that says why, not a silent 'rest'
    for comp in ("228", "318"):
        lines = (records_dir / "peer-at2" / f"RSN1063_NORTHR_RRS{comp}.AT2").read_text().splitlines()
        body = [" ".join("0.0" for _ in line.split()) for line in lines[4:]]
        (tmp_path / f"RSN1063_NORTHR_RRS{comp}.AT2").write_text("\n".join(lines[:4] + body) + "\n")
    inv = read_inventory(blocks_csv, default_mu=0.6)
    ctx = Context(str(tmp_path), config, inv, {})
    sources, _ = find_records(tmp_path, config=config)
    res = screen_record(sources[0], ctx)
    assert not res.ok and "every horizontal sample" in res.status and "zero" in res.status
