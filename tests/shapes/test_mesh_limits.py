"""A mesh is held to what a body is, before and after it is read: its size on disk and count of faces against the
stated limits (counted as a stream, equal to trimesh's count for each format), finite coordinates, not flat, one
body, and sizes within the columns' 0.01-100 m (a scan exported in millimetres named as such)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from pipeline.errors import MeshError
from pipeline.shapes.mesh_limits import MeshLimits, count_faces
from pipeline.shapes.scan import read_scan


def _box(tmp_path, extents, name="box.obj", *, moved=(0.0, 0.0, 0.0)):
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(np.asarray(moved) + [0.0, 0.0, extents[2] / 2.0])
    path = tmp_path / name
    mesh.export(path)
    return path


@pytest.mark.parametrize("name, kind", [("s.stl", "stl"), ("a.stl", "stl_ascii"), ("p.ply", "ply"), ("o.obj", "obj")])
def test_the_faces_counted_as_a_stream_are_trimeshs(tmp_path, name, kind):
    mesh = trimesh.creation.icosphere(subdivisions=3)
    path = tmp_path / name
    data = mesh.export(file_type=kind)
    path.write_bytes(data if isinstance(data, bytes) else data.encode())
    assert count_faces(path) == len(trimesh.load(path, process=False).faces) == len(mesh.faces)


def test_too_many_faces_are_refused_before_reading_naming_the_setting(tmp_path):
    path = tmp_path / "sphere.obj"
    trimesh.creation.icosphere(subdivisions=3).export(path)                       # 1,280 faces
    with pytest.raises(MeshError, match=r"1,280 faces, more than \[blocks\] max_mesh_faces = 1,000"):
        read_scan(path, limits=MeshLimits(max_faces=1000))
    with pytest.raises(MeshError, match=r"more than \[blocks\] max_mesh_mb = 1e-05"):
        read_scan(path, limits=MeshLimits(max_mb=1e-5))


@pytest.mark.parametrize("extents, match", [
    ((500.0, 500.0, 1500.0), r"1500 m tall, outside the 0.01-100 m.*exported in millimetres\? it would be 1.5 m"),
    ((0.001, 0.001, 100.0), r"0.001 m wide, outside the 0.01-100 m"),
])
def test_a_body_outside_the_columns_sizes_is_refused_with_its_units(tmp_path, extents, match):
    with pytest.raises(MeshError, match=match):
        read_scan(_box(tmp_path, extents))


def test_two_bodies_in_one_mesh_are_refused(tmp_path):
    a = trimesh.creation.box(extents=(0.5, 0.5, 1.5))
    b = trimesh.creation.box(extents=(0.5, 0.5, 1.5))
    b.apply_translation((5.0, 0.0, 0.0))
    path = tmp_path / "two.obj"
    trimesh.util.concatenate([a, b]).export(path)
    with pytest.raises(MeshError, match="2 separate bodies in one mesh"):
        read_scan(path)


def test_a_flat_mesh_and_a_nan_mesh_are_named_as_such(tmp_path):
    flat = tmp_path / "flat.obj"
    flat.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\nf 3 2 1\nf 4 3 1\n")
    with pytest.raises(MeshError, match="flat"):
        read_scan(flat)
    bad = tmp_path / "nan.obj"
    text = _box(tmp_path, (0.5, 0.5, 1.5)).read_text().splitlines()
    first = next(i for i, line in enumerate(text) if line.startswith("v "))
    text[first] = "v nan 0.0 0.0"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(MeshError, match="NaN or infinite"):
        read_scan(bad)


def test_a_box_in_range_reads_with_its_closed_form_volume(tmp_path):
    shape = read_scan(_box(tmp_path, (0.5, 0.4, 1.5)))
    assert shape.volume_m3 == pytest.approx(0.5 * 0.4 * 1.5, rel=1e-9) and shape.com_height_m == pytest.approx(0.75)


def test_a_tall_scan_is_not_warned_about_as_a_typed_column(tmp_path, caplog):
    """A scan's own height (its height_m cell left blank) is held to the columns' range when read; the warning
    'centimetres typed as metres?' is about a typed column, and not given for it."""
    import logging

    from pipeline.blocks import PLAUSIBLE_HEIGHT_M, read_inventory

    height = PLAUSIBLE_HEIGHT_M * 1.5
    _box(tmp_path, (0.4 * height, 0.4 * height, height), name="tall.obj")
    (tmp_path / "blocks.csv").write_text("id,height_m,width_m,mu,mesh\nTALL,,,0.6,tall.obj\n")
    with caplog.at_level(logging.WARNING):
        read_inventory(tmp_path / "blocks.csv", default_mu=0.6)
    assert "typed as metres" not in caplog.text
    (tmp_path / "typed.csv").write_text(f"id,height_m,width_m,mu\nTYPED,{height:g},{0.4 * height:g},0.6\n")
    with caplog.at_level(logging.WARNING):
        read_inventory(tmp_path / "typed.csv", default_mu=0.6)
    assert "typed as metres" in caplog.text
