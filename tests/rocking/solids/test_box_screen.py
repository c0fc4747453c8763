"""Boxes with a depth and an azimuth through the screening: simulated in 3D on two horizontals of known azimuth
(orientation given_3d, physics rocking3d), planar elsewhere; a box far deeper than high follows its planar scene in
its own plane (the frames checked against the planar path's own projection); the summary says how many boxes were
not checked about their other axis; the margins and probabilities come from the same 3D model."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

from pipeline.rocking.orientation import Orientation
from pipeline.rocking.scene import Physics
from pipeline.uncertainty.robust import Robustness

INVENTORY = ("id,height_m,width_m,mu,azimuth_deg,depth_m\n"
             "DEEP,1.2,0.15,0.9,60,6.0\n"          # far deeper than high: rocks in its width's plane only
             "DEEP-PLANAR,1.2,0.15,0.9,60,\n"      # the same without a depth: the planar model
             "SQUARE,1.5,0.2,0.9,20,0.2\n"        # a square base at a given azimuth: 3D
             "SQUARE-BLANK,1.5,0.2,0.9,,0.2\n"   # no azimuth: the planar scan
             "CERTIFIED,1.4,0.35,0.9,150,4.0\n")  # rocks a little, its 4 m depth certified: the planar scene


@pytest.fixture(scope="module")
def screened(kocaeli, tmp_path_factory):
    from pipeline.cli import main
    from pipeline.store import open_results

    tmp = tmp_path_factory.mktemp("box-screen")
    inv = tmp / "b.csv"
    inv.write_text(INVENTORY)
    out = tmp / "out"
    assert main(["--records", str(kocaeli), "--blocks", str(inv), "--out", str(out), "-q", "--samples", "24"]) == 0
    ds = open_results(out / "screening.nc")
    return ds, {b: k for k, b in enumerate(ds["block"].values)}, out


def test_a_box_with_a_depth_and_an_azimuth_is_simulated_in_3d(screened):
    ds, idx, _ = screened
    for block, code in (("DEEP", Orientation.given_3d), ("SQUARE", Orientation.given_3d),
                        ("DEEP-PLANAR", Orientation.given), ("SQUARE-BLANK", Orientation.scanned)):
        assert ds["orientation"].values[0, idx[block]] == code, block
    for block in ("DEEP", "SQUARE"):
        # the exact 3D model, or where it stops (a corner of an edge would slip) the 3D contact model
        assert ds["physics"].values[0, idx[block]] in (Physics.rocking3d, Physics.contact3d, Physics.none)
        assert ds["planes_simulated"].values[0, idx[block]] in (0, 1)
        assert ds["sample_simulations"].values[0, idx[block]] > 0            # its probability drew 3D runs
        p, low, high = (float(ds[v].values[0, idx[block]]) for v in ("p_overturn", "p_overturn_low", "p_overturn_high"))
        drawn, unknown = (int(ds[v].values[0, idx[block]]) for v in ("samples_drawn", "samples_without_verdict"))
        # every draw has a verdict: where the exact model stops, the contact model decides it
        assert 0.0 <= low <= p <= high <= 1.0 and unknown == 0 < drawn, block


def test_a_box_far_deeper_than_high_follows_its_planar_scene(screened):
    """DEEP (6 m deep, 1.2 m high) cannot tip about its other axis: its 3D scene equals the planar scene of the same
    box without a depth in the plane of its azimuth (the record projected by the planar path), verdict and peak
    rotation; this checks the 3D frames (the record's azimuth, the second horizontal's sense, the box's azimuth)."""
    ds, idx, _ = screened
    deep, planar = idx["DEEP"], idx["DEEP-PLANAR"]
    # the exact box model, or the contact model where the fall past alpha would slip its edge (handed over)
    assert ds["physics"].values[0, deep] in (Physics.rocking3d, Physics.contact3d)
    assert ds["overturn_simulated"].values[0, deep] == ds["overturn_simulated"].values[0, planar]
    assert ds["theta_max"].values[0, deep] == pytest.approx(ds["theta_max"].values[0, planar], rel=1e-4)
    # both overturn here: the factor on the record at which each first overturns (the margins' scan) is the sharper
    # check, and the 3D box leans along its own plane
    assert ds["overturn_scale_simulated"].values[deep] == pytest.approx(
        ds["overturn_scale_simulated"].values[planar], rel=1e-6)
    # (the contact model's lean at its peak tilt: 0.04 deg off its plane here)
    assert ds["governing_azimuth"].values[0, deep] % 180.0 == pytest.approx(60.0, abs=0.1)


def test_a_box_whose_other_axis_is_certified_keeps_its_planar_scene_which_is_the_3d_one(screened, kocaeli):
    """CERTIFIED rocks (its planar scene) and its 4 m depth cannot lift: orientation given_certified, the planar
    physics, and the 3D model's run of the same scene (a second algorithm) stays on its edges with the same peak."""
    from pipeline.config import Config
    from pipeline.records.listing import find_records
    from pipeline.records.loader import load_record
    from pipeline.rocking.block import BlockShape
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.rocking.solids.solid3d import run, solid_of

    ds, idx, _ = screened
    j = idx["CERTIFIED"]
    assert ds["orientation"].values[0, j] == Orientation.given_certified
    assert ds["physics"].values[0, j] == Physics.rocking_vertical
    assert 0.0 < ds["theta_max"].values[0, j] < 1.0
    assert ds["governing_azimuth"].values[0, j] % 180.0 == pytest.approx(150.0, abs=1e-6)
    sources, _ = find_records(kocaeli, config=Config())
    rec = load_record(sources[0], root=kocaeli, config=Config())
    solid = solid_of(BlockShape(height_m=1.4, width_m=0.35, mu=0.9, azimuth_deg=150.0, depth_m=4.0),
                     record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=True)
    assert solid is not None
    out = run(rec.horizontal_ms2[0], rec.horizontal_ms2[1], rec.vertical_ms2, rec.dt_s, solid,
              settings=SimulationConfig())
    assert out.corner_s == 0.0 and out.flag == 0 and not out.overturned
    assert out.theta_max_rad / solid.alpha == pytest.approx(ds["theta_max"].values[0, j], abs=1e-4)


def test_histories_keep_where_a_3d_scene_leans(screened):
    """histories.nc: a 3D box's lean azimuth at its peak tilt is its governing azimuth; a planar scene's is NaN."""
    import xarray as xr

    from pipeline.store.netcdf import ragged_rows

    ds, idx, out = screened
    with xr.open_dataset(out / "histories.nc") as h:
        rows = ragged_rows(h, "block_id")
        for block in ("SQUARE", "DEEP-PLANAR"):
            assert block in rows, block
        theta, lean = (h[v].values[rows["SQUARE"]].astype(float) for v in ("theta_over_alpha", "lean_azimuth"))
        assert np.all(np.isnan(h["lean_azimuth"].values[rows["DEEP-PLANAR"]]))
    k = int(np.nanargmax(np.where(theta < 1.0, theta, np.nan)))      # the largest tilt before the fall
    assert np.isfinite(lean[k]) and 0.0 <= lean[k] < 360.0
    assert np.all(np.isnan(lean[theta == 0.0]))


def test_the_summary_counts_the_boxes_not_checked_about_their_other_axis(screened):
    _, _, out = screened
    page = (out / "report.html").read_text()
    assert "not checked for 2 of 5" in page and "2 scenes, orientation given_3d" in page
    assert "1 scenes, orientation\ngiven_certified" in page


def test_the_margin_of_a_3d_box_comes_from_its_3d_model(screened, kocaeli):
    """The simulated margin of a box judged in 3D is the 3D scene's (the exact model's, or the contact model's where
    it is handed over): overturning at the margin's factor."""
    from pipeline.config import Config
    from pipeline.records.listing import find_records
    from pipeline.records.loader import load_record
    from pipeline.rocking.block import BlockShape
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.rocking.solids.solid3d import judge_solid, solid_of

    ds, idx, _ = screened
    sources, _ = find_records(kocaeli, config=Config())
    rec = load_record(sources[0], root=kocaeli, config=Config())
    h1, h2 = rec.horizontal_ms2
    checked = 0
    for block, shape in (("SQUARE", BlockShape(height_m=1.5, width_m=0.2, mu=0.9, azimuth_deg=20.0, depth_m=0.2)),
                         ("DEEP", BlockShape(height_m=1.2, width_m=0.15, mu=0.9, azimuth_deg=60.0, depth_m=6.0))):
        scale = float(ds["overturn_scale_simulated"].values[idx[block]])
        if not math.isfinite(scale):
            assert ds["overturn_simulated"].values[0, idx[block]] == -1, block      # only where it has no verdict
            continue
        solid = solid_of(shape, record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=True)
        assert solid is not None
        at = judge_solid(h1, h2, rec.vertical_ms2, rec.dt_s, solid, settings=SimulationConfig(), amplitude=scale)
        assert at.scene.overturned, block
        assert ds["robustness"].values[0, idx[block]] in [m.value for m in Robustness]
        checked += 1
    assert checked == 2


def test_the_3d_box_is_not_used_on_one_horizontal(records_dir, tmp_path):
    from pipeline.cli import main
    from pipeline.store import open_results

    root = tmp_path / "recs"
    (root / "fn-ascii").mkdir(parents=True)
    shutil.copy(records_dir / "fn-ascii" / "rinaldi_fn.dat", root / "fn-ascii" / "rinaldi_fn.dat")
    shutil.copy(records_dir / "units.toml", root / "units.toml")
    inv = tmp_path / "b.csv"
    inv.write_text("id,height_m,width_m,mu,azimuth_deg,depth_m\nSQUARE,1.5,0.3,0.9,20,0.3\n")
    out = tmp_path / "out"
    assert main(["--records", str(root), "--blocks", str(inv), "--out", str(out), "-q", "--samples", "0"]) == 0
    ds = open_results(out / "screening.nc")
    assert ds["orientation"].values[0, 0] == Orientation.single_component
    assert np.all(ds["physics"].values != Physics.rocking3d)
