"""Bodies from a scan (pipeline.shapes.scan): a rectangle or a cylinder given as a mesh has the rocking geometry of
its closed forms (alpha, R, the inertia about the pivot, the tipping angle), in any file format, position and turn
about the vertical; bad meshes are refused with the fix; and the granite rocks' scans give the numbers computed
independently in the dataset's own README (its build script: divergence theorem, hull settling)."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

from pipeline.errors import MeshError  # noqa: E402
from pipeline.shapes.scan import pivots, read_scan  # noqa: E402

GRANITE = Path(__file__).resolve().parents[3] / "shared" / "experiments" / "granite-pbr" / "geometry"


def _box_file(tmp_path, w, d, h, *, suffix=".stl", turn_deg=0.0, shift=(0.0, 0.0, 0.0)):
    box = trimesh.creation.box(extents=(w, d, h))
    box.apply_transform(trimesh.transformations.rotation_matrix(math.radians(turn_deg), (0, 0, 1)))
    box.apply_translation(np.asarray(shift) + (0.0, 0.0, h / 2))
    path = tmp_path / f"box{suffix}"
    box.export(path)
    return path


@pytest.mark.parametrize("suffix", [".stl", ".obj", ".ply"])
@pytest.mark.parametrize("w,d,h", [(0.4, 0.9, 1.6), (1.0, 1.0, 1.2), (0.3, 2.0, 3.0)])
def test_a_rectangle_as_a_mesh_has_the_rectangles_geometry(tmp_path, suffix, w, d, h):
    shape = read_scan(_box_file(tmp_path, w, d, h, suffix=suffix, shift=(3.0, -7.0, 2.0)))
    assert shape.com_height_m == pytest.approx(h / 2, rel=1e-6)
    assert shape.volume_m3 == pytest.approx(w * d * h, rel=1e-6)
    assert shape.settle_deg == pytest.approx(0.0, abs=1e-6) and not shape.from_points
    for az, b in ((0.0, w / 2), (90.0, d / 2), (180.0, w / 2)):
        p = pivots(shape, az)
        alpha, R = math.atan2(b, h / 2), math.hypot(b, h / 2)
        for got in (p.alpha_plus, p.alpha_minus, p.tipping_plus, p.tipping_minus):
            assert got == pytest.approx(alpha, rel=1e-6)
        assert p.R_plus_m == pytest.approx(R, rel=1e-6) and p.R_minus_m == pytest.approx(R, rel=1e-6)
        assert p.inertia_plus_m2 == pytest.approx(4.0 * R * R / 3.0, rel=1e-6)     # (b^2 + h^2) / 3 in full sizes


@pytest.mark.parametrize("turn_deg", [30.0, 115.0])
def test_turning_the_scan_about_the_vertical_turns_its_planes(tmp_path, turn_deg):
    base = pivots(read_scan(_box_file(tmp_path, 0.4, 0.9, 1.6)), 0.0)
    turned = pivots(read_scan(_box_file(tmp_path, 0.4, 0.9, 1.6, turn_deg=turn_deg)), turn_deg)
    for a, b in zip(base[1:], turned[1:]):
        assert b == pytest.approx(a, rel=1e-5)


def test_a_cylinder_as_a_mesh_rocks_about_its_rim(tmp_path):
    radius, height = 0.3, 2.0
    cyl = trimesh.creation.cylinder(radius=radius, height=height, sections=512)
    cyl.apply_translation((0.0, 0.0, height / 2))
    path = tmp_path / "cylinder.stl"
    cyl.export(path)
    shape = read_scan(path)
    alpha = math.atan2(radius, height / 2)
    for az in (0.0, 37.0, 90.0):
        p = pivots(shape, az)
        assert p.alpha_plus == pytest.approx(alpha, rel=1e-4) and p.tipping_minus == pytest.approx(alpha, rel=1e-4)
        # a solid cylinder: I_G across its axis = a^2/4 + h^2/3 per unit mass (h the half-height), plus R^2
        assert p.inertia_plus_m2 == pytest.approx(radius ** 2 / 4 + (height / 2) ** 2 / 3 + radius ** 2
                                                  + (height / 2) ** 2, rel=1e-4)


def test_an_open_mesh_is_refused_with_the_fix(tmp_path):
    box = trimesh.creation.box(extents=(1, 1, 1))
    box.update_faces(np.arange(len(box.faces)) != 0)                  # one triangle removed: a hole
    path = tmp_path / "open.stl"
    box.export(path)
    with pytest.raises(MeshError, match="not closed.*close its holes"):
        read_scan(path)


def test_a_scan_not_posed_as_it_stands_is_refused(tmp_path):
    box = trimesh.creation.box(extents=(0.4, 0.4, 1.6))
    box.apply_transform(trimesh.transformations.rotation_matrix(math.radians(30.0), (1, 0, 0)))
    path = tmp_path / "leaning.obj"
    box.export(path)
    with pytest.raises(MeshError, match="centre of mass is not above the base.*pose the mesh"):
        read_scan(path)


def test_other_files_are_refused_with_the_formats(tmp_path):
    bad = tmp_path / "rock.xyz"
    bad.write_text("0 0 0\n")
    with pytest.raises(MeshError, match="OBJ, PLY or STL"):
        read_scan(bad)


def test_a_point_cloud_is_meshed_by_its_hull_with_a_warning(tmp_path, caplog):
    rng = np.random.default_rng(3)
    pts = rng.uniform(-0.5, 0.5, size=(400, 3)) * (0.6, 0.6, 1.8) + (0, 0, 0.9)
    pts = np.vstack([pts, trimesh.creation.box(extents=(0.6, 0.6, 1.8)).vertices + (0, 0, 0.9)])
    path = tmp_path / "cloud.ply"
    trimesh.PointCloud(pts).export(path)
    with caplog.at_level(logging.WARNING):
        shape = read_scan(path)
    assert shape.from_points and "convex hull" in caplog.text
    assert shape.volume_m3 == pytest.approx(0.6 * 0.6 * 1.8, rel=1e-6)         # the hull of a box's corners


@pytest.mark.skipif(not GRANITE.is_dir(), reason="the granite shake-table data (../shared/experiments) is absent")
def test_the_granite_rock_sp2_matches_the_datasets_own_computation():
    """final_sp2_1.obj, as the published simulation poses it (the dataset README's table): settles by 0.38 deg, its
    centre of mass 292.0 mm up, static tipping 54.7 / 15.6 deg along x, the 2 mm footprint [-186, +62] mm."""
    shape = read_scan(GRANITE / "final_sp2_1.obj", mass_kg=353.802)
    assert shape.volume_m3 == pytest.approx(0.12407, abs=1e-5)
    assert shape.settle_deg == pytest.approx(0.38, abs=0.01)
    assert shape.com_height_m * 1e3 == pytest.approx(292.0, abs=0.1)
    p = pivots(shape, 0.0, footprint_tol_m=0.002)
    assert math.degrees(p.tipping_minus) == pytest.approx(54.7, abs=0.05)
    assert math.degrees(p.tipping_plus) == pytest.approx(15.6, abs=0.05)
    assert p.b_minus_m * 1e3 == pytest.approx(186, abs=1) and p.b_plus_m * 1e3 == pytest.approx(62, abs=1)
    assert math.degrees(p.alpha_minus) == pytest.approx(32.5, abs=0.05)
    assert math.degrees(p.alpha_plus) == pytest.approx(12.0, abs=0.05)
    y = pivots(shape, 90.0)
    assert math.degrees(y.tipping_minus) == pytest.approx(57.4, abs=0.05)
    assert math.degrees(y.tipping_plus) == pytest.approx(56.1, abs=0.05)


@pytest.mark.skipif(not GRANITE.is_dir(), reason="the granite shake-table data (../shared/experiments) is absent")
def test_the_raw_scans_of_both_rocks_are_read():
    """SP1.obj (inward faces, two non-manifold edges) and SP2.obj (a point cloud): the volume and the tipping along
    x as the dataset README gives them (SP1: 0.12386 m3, 294.3 mm, 56.0 / 14.8 deg; SP2: the hull's 0.13442 m3)."""
    sp1 = read_scan(GRANITE / "SP1.obj")
    assert sp1.volume_m3 == pytest.approx(0.12386, abs=1e-5)
    assert sp1.com_height_m * 1e3 == pytest.approx(294.3, abs=0.1)
    p = pivots(sp1, 0.0)
    assert math.degrees(p.tipping_minus) == pytest.approx(56.0, abs=0.1)
    assert math.degrees(p.tipping_plus) == pytest.approx(14.8, abs=0.1)
    sp2 = read_scan(GRANITE / "SP2.obj")
    assert sp2.from_points and sp2.volume_m3 == pytest.approx(0.13442, abs=1e-5)
