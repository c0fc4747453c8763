"""Cylinders through the inventory and the screening: the shape column, the planar model with the cylinder's own
inertia on one horizontal, the 3D model on two (no orientation scan), and the measured case that the planar scan
called robust_stand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.blocks import read_inventory
from pipeline.constants import G
from pipeline.errors import InventoryError
from pipeline.rocking.block import ShapeKind
from pipeline.rocking.orientation import Orientation
from pipeline.rocking.scene import Guard, Physics
from pipeline.rocking.solids.cylinder3d import housner_e, planar_inertia
from pipeline.uncertainty.robust import Robustness


def _inventory(tmp_path, text: str):
    path = tmp_path / "b.csv"
    path.write_text(text)
    return read_inventory(path, default_mu=0.6)


def test_the_shape_column_makes_a_cylinder_with_its_own_dynamics(tmp_path):
    inv = _inventory(tmp_path, "id,height_m,width_m,shape,depth_m\nC,2.0,0.5,cylinder,\nB,2.0,0.5,,0.8\n"
                               "D,2.0,0.5,Box,\n")
    assert [s.kind for s in inv.shapes()] == [ShapeKind.cylinder, ShapeKind.box, ShapeKind.box]
    assert math.isnan(inv.shape(0).depth_m) and inv.shape(1).depth_m == 0.8
    geo = inv.geometry()
    a, h = 0.25, 1.0
    big_r = math.hypot(a, h)
    assert geo.p[0] == pytest.approx(math.sqrt(G * big_r / planar_inertia(a, h)), rel=1e-12)
    assert geo.e_housner[0] == pytest.approx(housner_e(a, h), rel=1e-12)
    assert geo.p[1] == pytest.approx(math.sqrt(3 * G / (4 * big_r)), rel=1e-12)       # the box: Housner's
    assert len(set(inv.digests())) == 3                   # the shape and the depth enter the results' keys


@pytest.mark.parametrize("row, message", [
    ("C,2.0,0.5,cone,", r"line 2, column 'shape': 'cone'; expected one of box, cylinder"),
    ("C,2.0,0.5,cylinder,0.5", r"line 2, column 'depth_m': '0.5' for a cylinder"),
    ("C,2.0,0.5,box,-1", r"line 2, column 'depth_m'"),
])
def test_a_bad_shape_or_depth_is_named(tmp_path, row, message):
    with pytest.raises(InventoryError, match=message):
        _inventory(tmp_path, "id,height_m,width_m,shape,depth_m\n" + row + "\n")


@pytest.fixture(scope="module")
def el_centro_6(tmp_path_factory, records_dir):
    """RSN181 (El Centro Array #6, 1979 Imperial Valley): two horizontals and the vertical."""
    from bundled import copy_bundled

    return copy_bundled(records_dir, tmp_path_factory.mktemp("rsn181"), "RSN181_IMPVALL.H_H-E06140.AT2",
                        "RSN181_IMPVALL.H_H-E06230.AT2", "RSN181_IMPVALL.H_H-E06-UP.AT2")


def test_a_cylinder_on_two_horizontals_is_judged_in_3d_and_never_falsely_robust(el_centro_6, tmp_path, capsys):
    """The measured case: El Centro #6 x a solid cylinder 1.0 m high, 0.333 m across, mu 0.7. The planar scan of
    its 37 planes said robust_stand, p = 0.00, where a 3D rigid-body engine overturns it; in 3D its base would
    slide under the record's vertical (-0.97 g at 2.3 s), where the exact model stops: the 3D contact model decides
    the scene, and overturns it, as the engine does; never robust_stand. A box of the same size on the same record
    is still scanned in planes."""
    from pipeline.cli import main
    from pipeline.store import open_results

    inv = tmp_path / "b.csv"
    inv.write_text("id,height_m,width_m,mu,shape,depth_m\nCYL,1.0,0.333,0.7,cylinder,\nBOX,1.0,0.333,0.7,,0.5\n")
    out = tmp_path / "out"
    assert main(["--records", str(el_centro_6), "--blocks", str(inv), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "other base axis: not checked for 1 of 2 blocks" in err
    assert "boxes with both on two horizontals, 0 were simulated in 3D" in err
    assert "not checked for 1 of 2" in (out / "report.html").read_text()
    ds = open_results(out / "screening.nc")
    cyl, box = (list(ds["block"].values).index(b) for b in ("CYL", "BOX"))
    assert ds["orientation"].values[0, cyl] == Orientation.axisymmetric
    assert ds["orientation"].values[0, box] == Orientation.scanned
    assert ds["physics"].values[0, cyl] == Physics.contact3d
    assert ds["planes_simulated"].values[0, cyl] == 1
    assert not ds["simulation_guard"].values[0, cyl] & Guard.model_limit
    assert ds["overturn_simulated"].values[0, cyl] == 1
    assert ds["robustness"].values[0, cyl] != Robustness.robust_stand
    assert 0.0 <= ds["governing_azimuth"].values[0, cyl] < 360.0
    assert list(ds["shape"].values) == [ShapeKind.cylinder, ShapeKind.box]
    assert math.isnan(ds["depth"].values[cyl]) and ds["depth"].values[box] == 0.5


def test_without_the_vertical_the_cylinder_overturns(el_centro_6):
    """The same scene on the two horizontals alone: the 3D cylinder rocks and rolls past alpha, its base would
    slide while it falls (held: the fall kept), and it overturns at 8.7 s, where the planar scan's worst plane
    reached 0.016 alpha."""
    from pipeline.config import Config
    from pipeline.records.listing import find_records
    from pipeline.records.loader import load_record
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.rocking.solids.cylinder3d import FLAG_NONE, FLAG_SLIDE, Cylinder
    from pipeline.rocking.solids.cylinder_scene import run_on_record

    sources, _ = find_records(el_centro_6, config=Config())
    rec = load_record(sources[0], root=el_centro_6, config=Config())
    c = Cylinder(radius_m=0.1665, half_height_m=0.5, mu=0.7, restitution=housner_e(0.1665, 0.5))
    out = run_on_record(rec.horizontal_ms2[0], rec.horizontal_ms2[1], None, rec.dt_s, c,
                        settings=SimulationConfig())
    assert out.overturned and out.flag == FLAG_NONE and out.held == FLAG_SLIDE
    assert np.nanmax(np.abs(np.diff(np.unwrap(out.azimuth[np.isfinite(out.azimuth)])))) > 0     # it rolled
    # a fall followed with the rim held is handed to the 3D contact model (the default), which lets the rim slip:
    # it overturns too, with its own peak, history and lean; with the hand-off off the held fall is kept, flagged
    from pipeline.rocking.block import BlockShape, ShapeKind
    from pipeline.rocking.solids.solid3d import judge_solid, solid_of

    solid = solid_of(BlockShape(height_m=1.0, width_m=0.333, mu=0.7, kind=ShapeKind.cylinder),
                     record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=True)
    kept = judge_solid(rec.horizontal_ms2[0], rec.horizontal_ms2[1], None, rec.dt_s, solid,
                       settings=SimulationConfig(contact3d=False)).scene
    assert kept.physics == Physics.wobbling and kept.guard & Guard.held_past_alpha and kept.verdict == 1
    handed = judge_solid(rec.horizontal_ms2[0], rec.horizontal_ms2[1], None, rec.dt_s, solid,
                         settings=SimulationConfig(), history=True)
    assert handed.scene.physics == Physics.contact3d and handed.scene.verdict == 1
    assert not handed.scene.guard & (Guard.held_past_alpha | Guard.model_limit)
    assert handed.scene.theta_max == pytest.approx(0.5 * np.pi / solid.alpha)
    theta, lean = handed.scene.theta_over_alpha, handed.lean_history_deg
    assert theta.shape == lean.shape == rec.horizontal_ms2[0].shape
    assert np.all(np.isnan(lean[theta == 0.0])) and np.all(np.isfinite(lean[theta > 0.0]))
    assert theta[-1] == pytest.approx(0.5 * np.pi / solid.alpha)            # lying on its side from its fall on
    assert 0.0 <= handed.lean_deg < 360.0


def test_a_cylinder_on_one_horizontal_rocks_in_its_plane_with_its_own_inertia(records_dir, tmp_path):
    import shutil

    from pipeline.cli import main
    from pipeline.store import open_results

    root = tmp_path / "recs"
    root.mkdir()
    (root / "fn-ascii").mkdir()
    shutil.copy(records_dir / "fn-ascii" / "rinaldi_fn.dat", root / "fn-ascii" / "rinaldi_fn.dat")
    shutil.copy(records_dir / "units.toml", root / "units.toml")
    inv = tmp_path / "b.csv"
    inv.write_text("id,height_m,width_m,mu,shape\nCYL,1.0,0.2,0.7,cylinder\n")
    out = tmp_path / "out"
    assert main(["--records", str(root), "--blocks", str(inv), "--out", str(out), "-q", "--samples", "0"]) == 0
    ds = open_results(out / "screening.nc")
    assert ds["orientation"].values[0, 0] == Orientation.single_component
    assert ds["physics"].values[0, 0] in (Physics.rocking, Physics.rocking_vertical, Physics.general)


@pytest.mark.parametrize("overturned, flag, held, verdict, guard", [
    (True, 0, 0, 1, 0),
    (False, 0, 0, 0, 0),
    (True, 0, 1, 1, Guard.held_past_alpha),          # a fall under way, followed with the rim held: kept
    (False, 1, 1, -1, Guard.model_limit | Guard.held_past_alpha),     # held, then it came back: no verdict
    (False, 2, 0, -1, Guard.model_limit),            # it would slide before alpha: no verdict
    (False, 3, 0, -1, Guard.model_limit | Guard.step_cap),     # the step cap: no verdict either
])
def test_what_a_3d_run_becomes_in_the_results(overturned, flag, held, verdict, guard):
    from pipeline.rocking.solids.cylinder3d import Cylinder, WobbleOutcome
    from pipeline.rocking.solids.solid3d import Solid, scene_of

    z = np.zeros(3)
    out = WobbleOutcome(overturned, 1.0 if overturned else math.nan, 0.5, 10.0, flag, 2, z, z, np.zeros(6), 0.3,
                        held)
    sc = scene_of(out, Solid(Cylinder(0.25, 1.0, 0.7, 0.8), 0.0, 0.3))
    assert sc.verdict == verdict and sc.guard == guard and sc.physics == Physics.wobbling


def test_screen_bench_compares_the_3d_cylinders_with_their_planar_scan(el_centro_6, tmp_path):
    from types import SimpleNamespace

    from pipeline.config import Config
    from pipeline.records.listing import find_records
    from pipeline.records.loader import load_record
    from pipeline.run.bench_solids import solid_rows

    cfg = Config()
    sources, _ = find_records(el_centro_6, config=cfg)
    rec = load_record(sources[0], root=el_centro_6, config=cfg)
    inv = _inventory(tmp_path, "id,height_m,width_m,mu,shape\nCYL,1.0,0.333,0.7,cylinder\nBOX,1.0,0.333,0.7,\n")
    three_d, planar = solid_rows([SimpleNamespace(record=rec)], inv, cfg)
    assert three_d["section"] == planar["section"] == "cylinders" and three_d["scenes"] == planar["scenes"] == 1
    assert three_d["time_s"] > 0 and planar["time_s"] > 0
    assert three_d["scenes_simulated"] == 1                  # decided in 3D by the contact model: it overturns
    assert planar["misses"] == 1 and planar["false_alarms"] == 0      # where the planar scan stands
    assert solid_rows([SimpleNamespace(record=rec)], inv.take([1]), cfg) == []       # no 3D scene: no rows
    from pipeline.run.accuracy import markdown

    table = markdown([three_d, planar])                       # bench.md takes rows without the pulse split
    assert "| cylinders | planar scan of the same cylinders" in table
