"""Bodies given by their scans through the screening (inventory column ``mesh``): a rectangle given as a mesh gets
the verdicts, peaks, probabilities and margins of the same rectangle given by its width and height (a second path:
the planar registry); a body's orientation codes and planes; the inventory's equivalent rectangle (closed form)
and its errors, each naming the file, the line and the fix."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from pipeline.rocking.orientation import Orientation
from pipeline.rocking.scene import Physics

RECORDS = ("RSN1063_NORTHR_RRS-UP.AT2", "RSN1063_NORTHR_RRS228.AT2", "RSN1063_NORTHR_RRS318.AT2",
           "RSN1086_NORTHR_SYL-UP.AT2", "RSN1086_NORTHR_SYL090.AT2", "RSN1086_NORTHR_SYL360.AT2",
           "RSN1176_KOCAELI_YPT-UP.AT2", "RSN1176_KOCAELI_YPT060.AT2", "RSN1176_KOCAELI_YPT150.AT2",
           "RSN1106_KOBE_KJM000.AT2")
INVENTORY = ("id,height_m,width_m,mu,azimuth_deg,mesh,mass_kg\n"
             "BOX-MESH,,,1.0,30,box-0.3x3.0x1.5.obj,\n"
             "BOX,1.5,0.3,1.0,30,,\n"
             "STAT,,,0.6,,leaning-statue.obj,350\n"
             "STAT-N,,,0.6,200,leaning-statue.obj,\n")
#: Draws of the probabilities (the default's 40 is the suite's cost; 24 keep the comparison's resolution)
SAMPLES = 24


#: Each model of a scanned body ([simulation] scanned_model) and the physics code it stores
MODELS = {"rolling": Physics.rolling, "two_sided": Physics.two_sided}


@pytest.fixture(scope="module", params=sorted(MODELS))
def screened(request, records_dir, scans_dir, tmp_path_factory):
    from pipeline.cli import main
    from pipeline.store import open_results

    tmp = tmp_path_factory.mktemp("scanned")
    root = tmp / "records"
    root.mkdir()
    for name in RECORDS:
        shutil.copy(records_dir / "peer-at2" / name, root / name)
    shutil.copy(records_dir / "units.toml", root / "units.toml")
    for name in ("box-0.3x3.0x1.5.obj", "leaning-statue.obj"):
        shutil.copy(scans_dir / name, tmp / name)
    inv = tmp / "blocks.csv"
    inv.write_text(INVENTORY)
    out = tmp / "out"
    config = tmp / "screen.toml"
    config.write_text(f'[simulation]\nscanned_model = "{request.param}"\n')
    assert main(["--records", str(root), "--blocks", str(inv), "--out", str(out), "-q", "--samples",
                 str(SAMPLES), "--config", str(config)]) == 0
    ds = open_results(out / "screening.nc")
    return ds, {b: k for k, b in enumerate(ds["block"].values)}, MODELS[request.param]


def test_a_rectangle_given_as_a_mesh_is_the_rectangle(screened):
    """The rolling model: a box is a uniform rectangle in its width plane, the planar registry's block, so every
    scene has the block's physics, verdict, peak and governing plane, the same draws and the same margin. The
    two-sided model: the same verdict, peak and governing plane in every scene the planar model keeps in pure
    rocking; the same probabilities to within the draws a chaotic scene flips by rounding; the same margins."""
    ds, idx, physics = screened
    mesh, box = idx["BOX-MESH"], idx["BOX"]
    if physics == Physics.rolling:
        same = np.ones(ds.sizes["record"], dtype=bool)
        np.testing.assert_array_equal(ds["physics"].values[:, mesh], ds["physics"].values[:, box])
        np.testing.assert_array_equal(ds["samples_overturned"].values[:, mesh], ds["samples_overturned"].values[:, box])
        np.testing.assert_array_equal(ds["samples_drawn"].values[:, mesh], ds["samples_drawn"].values[:, box])
    else:
        assert (ds["physics"].values[:, mesh] == Physics.two_sided).all()
        same = np.isin(ds["physics"].values[:, box], (Physics.rocking, Physics.rocking_vertical, Physics.none))
        assert same.sum() >= 3
        k_mesh, k_box = ds["samples_overturned"].values[:, mesh], ds["samples_overturned"].values[:, box]
        assert np.abs(k_mesh - k_box).max() <= 2
        assert np.sum(k_mesh == k_box) >= len(k_box) - 1
    for i in np.flatnonzero(same):
        assert ds["overturn_simulated"].values[i, mesh] == ds["overturn_simulated"].values[i, box]
        assert ds["theta_max"].values[i, mesh] == pytest.approx(ds["theta_max"].values[i, box], rel=1e-6, abs=1e-12)
        assert ds["governing_azimuth"].values[i, mesh] % 180 == pytest.approx(ds["governing_azimuth"].values[i, box])
    assert ds["overturn_scale_simulated"].values[mesh] == pytest.approx(ds["overturn_scale_simulated"].values[box],
                                                                        rel=1e-6)


def test_scanned_bodies_are_judged_in_their_planes(screened):
    """A given azimuth on two horizontals: the body's 72 planes; a blank one: every body plane facing the pulse
    axis, then the worst facing the record's 72 directions (one of them may be the pulse axis); one horizontal:
    every body plane facing it."""
    ds, idx, physics = screened
    n_body = 72
    single = ds["n_horizontal"].values == 1
    for block, code, planes in (("STAT", Orientation.scanned, (n_body + 71, n_body + 72)),
                                ("STAT-N", Orientation.given, (72, 72))):
        j = idx[block]
        assert (ds["orientation"].values[~single, j] == code).all()
        assert ((planes[0] <= ds["planes_simulated"].values[~single, j])
                & (ds["planes_simulated"].values[~single, j] <= planes[1])).all()
        assert (ds["orientation"].values[single, j] == Orientation.single_component).all()
        assert (ds["planes_simulated"].values[single, j] == n_body).all()
        assert (ds["p_overturn"].values[:, j] >= 0).all()
        assert (ds["physics"].values[:, j] == physics).all()


def test_the_inventory_reads_a_mesh_its_equivalent_rectangle_and_its_azimuth(scans_dir, tmp_path):
    from pipeline.blocks import read_inventory
    from pipeline.rocking.block import ShapeKind

    inv_path = tmp_path / "b.csv"
    shutil.copy(scans_dir / "box-0.3x3.0x1.5.obj", tmp_path / "box.obj")
    inv_path.write_text("id,height_m,width_m,mu,azimuth_deg,mesh,density_kg_m3\nB,,,0.8,200,box.obj,2500\n")
    inv = read_inventory(inv_path, default_mu=0.6)
    shape = inv.shape(0)
    assert shape.kind == ShapeKind.scanned and shape.scan is not None
    assert shape.height_m == pytest.approx(1.5) and shape.width_m == pytest.approx(0.3)    # 2 z_G, 2 b of its width
    assert shape.azimuth_deg == 200.0                    # a body's two sides differ: its azimuth runs over 360 deg
    assert shape.scan.mass_kg == pytest.approx(2500 * 0.3 * 3.0 * 1.5)


@pytest.mark.parametrize("row,expected", [
    ("B,,,0.8,,missing.obj,", ["line 2", "column 'mesh'", "missing.obj"]),
    ("B,,,0.8,,open.obj,", ["line 2", "open.obj", "not closed"]),
    ("B,,,0.8,,box.obj,-3", ["line 2", "mass_kg", "-3"]),
    ("B,1.5,0.3,0.8,,,", None),
])
def test_a_bad_mesh_row_names_the_file_line_and_fix(scans_dir, tmp_path, row, expected):
    import trimesh

    from pipeline.blocks import read_inventory
    from pipeline.errors import InventoryError

    shutil.copy(scans_dir / "box-0.3x3.0x1.5.obj", tmp_path / "box.obj")
    open_box = trimesh.creation.box(extents=(0.3, 0.3, 1.0))
    open_box.update_faces(np.arange(len(open_box.faces)) != 0)        # one face removed: not closed
    open_box.export(tmp_path / "open.obj")
    inv_path = tmp_path / "b.csv"
    inv_path.write_text(f"id,height_m,width_m,mu,azimuth_deg,mesh,mass_kg\n{row}\n")
    if expected is None:
        assert read_inventory(inv_path, default_mu=0.6).scan_of(0) is None
        return
    with pytest.raises(InventoryError) as err:
        read_inventory(inv_path, default_mu=0.6)
    for part in expected:
        assert part in str(err.value)


@pytest.mark.parametrize("model", sorted(MODELS))
def test_the_inference_grid_of_a_rectangle_given_as_a_mesh_is_the_rectangles(scans_dir, tmp_path, model):
    """screen infer simulates a body given by its scan by the configured model in its weakest plane: a rectangle as
    a mesh overturns at the same grid points (idealized pulses of 0.5-20 times its uplift) as by its sizes."""
    import dataclasses

    from pipeline.blocks import read_inventory
    from pipeline.config import Config
    from pipeline.run.infer import grid, simulated_overturns

    shutil.copy(scans_dir / "box-0.3x3.0x1.5.obj", tmp_path / "box.obj")
    inv_path = tmp_path / "b.csv"
    inv_path.write_text("id,height_m,width_m,mu,mesh\nBOX-MESH,,,1.0,box.obj\nBOX,1.5,0.3,1.0,\n")
    inv = read_inventory(inv_path, default_mu=0.6)
    base = Config()
    config = dataclasses.replace(base, infer=dataclasses.replace(base.infer, n_durations=6, n_accelerations=8),
                                 simulation=dataclasses.replace(base.simulation, scanned_model=model))
    tp, ap, az = grid(inv, shape="half-sine", config=config, oriented=False)
    got, _offsets, _runs = simulated_overturns(inv, tp, ap, az, shape="half-sine", config=config)
    assert got[1].any() and not got[1].all()                  # the grid spans standing and overturning
    assert (got[0] == got[1]).all()
