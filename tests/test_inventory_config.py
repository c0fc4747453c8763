"""Inventory validation and configuration (one source of truth)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pipeline.blocks import geometry, read_inventory
from pipeline.config import Config, config_from_dict, load_config
from pipeline.errors import BlockParameterError, ConfigError, InventoryError

PROJECT = Path(__file__).resolve().parents[1]


def test_sample_inventory_reads(blocks_csv):
    inv = read_inventory(blocks_csv, default_mu=0.6)
    assert len(inv) >= 12
    assert {"COL-0.5", "COL-1", "COL-20", "PBR-01", "TRAF-01"} <= set(inv.ids)
    cols = [inv.ids.index(c) for c in ("COL-0.5", "COL-1", "COL-20")]
    assert np.allclose(inv.width_m[cols] / inv.height_m[cols], 0.11)


BAD_ROWS = [
    ("id,height_m,width_m\nA,1.0\n", r"line 2: 2 fields, expected 3"),
    ("id,height_m,width_m\nA,abc,0.2\n", r"line 2, column 'height_m': 'abc' is not a number"),
    ("id,height_m,width_m\nA,0,0.2\n", r"line 2, column 'height_m': '0' is out of range"),
    ("id,height_m,width_m\nA,1,-0.2\n", r"line 2, column 'width_m': '-0.2' is out of range"),
    ("id,height_m,width_m\nA,1,0.2\nA,2,0.3\n", r"line 3, column 'id': duplicate id 'A' \(first on line 2\)"),
    ("id,height_m,width_m\nA,1e9,0.2\n", r"line 2, column 'height_m': '1e9' is out of range; expected a size in "
                                        r"metres between 0.01 and 100"),
    ("id,height_m\nA,1\n", r"line 1: missing required column\(s\) \['width_m'\]"),
    ("id,height_m,width_m,mu\nA,1,0.2,0\n", r"line 2, column 'mu': '0' is out of range"),
    ("id,height_m,width_m\nA,,0.2\n", r"line 2, column 'height_m': missing"),
    ("id,height_m,width_m\nA,nan,0.2\n", r"line 2, column 'height_m': 'nan' is out of range"),
    ("", r"empty file"),
]


@pytest.mark.parametrize("text,message", BAD_ROWS)
def test_bad_inventory_rows_name_file_line_column(tmp_path, text, message):
    path = tmp_path / "inv.csv"
    path.write_text(text)
    with pytest.raises(InventoryError, match=message) as info:
        read_inventory(path, default_mu=0.6)
    assert "inv.csv" in str(info.value)


def test_every_bad_row_is_reported_at_once(tmp_path):
    path = tmp_path / "inv.csv"
    path.write_text("id,height_m,width_m,mu\nA,abc,0.2,0.5\nB,1,0.2\nC,1,0.2,-1\nA,2,0.3,0.5\n")
    with pytest.raises(InventoryError) as info:
        read_inventory(path, default_mu=0.6)
    text = str(info.value)
    assert "4 problem(s)" in text
    for expected in ("line 2, column 'height_m'", "line 3: 3 fields", "line 4, column 'mu'",
                     "line 5, column 'id': duplicate id 'A'"):
        assert expected in text


def test_extra_columns_are_kept_and_unknown_ones_warn(tmp_path, caplog):
    path = tmp_path / "inv.csv"
    path.write_text("id,height_m,width_m,value,floor,colour\nA,1,0.2,120000,2,red\nB,2,0.4,,G,blue\n")
    inv = read_inventory(path, default_mu=0.6)
    assert inv.extra == {"value": ("120000", ""), "floor": ("2", "G"), "colour": ("red", "blue")}
    assert "['colour'] are not inventory columns" in caplog.text and "value" not in caplog.text.split("[")[1]
    assert inv.take([1]).extra == {"value": ("",), "floor": ("G",), "colour": ("blue",)}


def test_blank_optional_fields_take_defaults(tmp_path):
    path = tmp_path / "inv.csv"
    path.write_text("id,height_m,width_m,mu,azimuth_deg\nA,1,0.2,,\nB,1,0.2,0.4,200\n")
    inv = read_inventory(path, default_mu=0.55)
    assert inv.mu.tolist() == [0.55, 0.4]
    assert math.isnan(inv.azimuth_deg[0]) and inv.azimuth_deg[1] == 20.0  # an axis: mod 180


def test_geometry_closed_forms():
    # h = 1, b = 0.2: a worked-example block whose published numbers use g = 9.81
    g = geometry(2.0, 0.4, g_ms2=9.81)
    assert g.alpha == pytest.approx(0.197396, abs=1e-6)
    assert g.p == pytest.approx(2.686005, abs=1e-6)
    assert g.e_housner == pytest.approx(0.942308, abs=1e-6)
    assert g.e_housner ** 2 == pytest.approx(0.887944, abs=1e-6)  # energy ratio r = e^2


@pytest.mark.parametrize("h,w", [(0, 1), (-1, 1), (1, 0), (float("inf"), 1)])
def test_geometry_rejects_impossible_sizes(h, w):
    with pytest.raises(BlockParameterError, match="positive, finite size"):
        geometry(h, w)


def test_shipped_config_equals_builtin_defaults():
    assert load_config(PROJECT / "configs" / "screen.toml") == Config()


@pytest.mark.parametrize("data,message", [
    ({"recrods": {}}, r"unknown section\(s\) \['recrods'\]; valid"),
    ({"records": {"gee": 9.8}}, r"unknown key\(s\) \['gee'\] in \[records\]; valid: .*g_ms2"),
    ({"records": {"g_ms2": -1}}, r"g_ms2 = -1: expected a positive number"),
    ({"processing": {"corrected": [{"step": "smooth"}]}}, r"unknown step 'smooth'; valid steps"),
    ({"processing": {"corrected": [{"step": "demean"}]}}, r"must end with exactly one 'integrate'"),
    ({"processing": {"corrected": [{"step": "integrate", "method": "simpson"}]}}, r"integrate method 'simpson'"),
    ({"processing": {"corrected": [{"step": "highpass", "freq": "x"}, {"step": "integrate"}]}},
     r"freq = 'x' must be float"),
])
def test_config_errors_name_key_and_valid_values(data, message):
    with pytest.raises(ConfigError, match=message):
        config_from_dict(data)


def test_config_file_errors(tmp_path):
    with pytest.raises(ConfigError, match="not found"):
        load_config(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[records\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_config(bad)


@pytest.mark.parametrize("row, expected", [
    ("vase,80,0.3,0.5", r"line 2 \(vase\): height_m 80 m is above 30 m"),
    ("b,1,0.3,5", r"line 2 \(b\): mu 5 is above 1.5"),
    ("c,0.3,1,0.5", r"line 2 \(c\): width_m/height_m 3.33 gives slenderness 73.3 deg.*cannot rock"),
    ("d,2,0.04,0.5", r"line 2 \(d\): height_m/width_m 50 is above 40"),
])
def test_implausible_values_are_screened_with_a_warning_naming_line_and_value(tmp_path, caplog, row, expected):
    path = tmp_path / "inv.csv"
    path.write_text("id,height_m,width_m,mu\n" + row + "\n")
    inv = read_inventory(path, default_mu=0.5)
    assert len(inv) == 1
    assert any(__import__("re").search(expected, r.getMessage()) for r in caplog.records), caplog.text


def test_plausible_values_give_no_warning(tmp_path, caplog):
    path = tmp_path / "inv.csv"
    path.write_text("id,height_m,width_m,mu\nstatue,1.8,0.5,0.6\ncolumn,12,1.4,0.7\n")
    read_inventory(path, default_mu=0.5)
    assert "outside what real objects have" not in caplog.text


def test_a_command_about_one_block_warns_about_that_block_alone(tmp_path, caplog):
    import logging

    from pipeline.blocks import read_inventory

    inv = tmp_path / "inv.csv"
    inv.write_text("id,height_m,width_m,mu\nOK,1.0,0.2,0.6\nCRATE,0.6,1.2,0.25\n")
    with caplog.at_level(logging.WARNING):
        read_inventory(inv, default_mu=0.6, warn_for="OK")
    assert "CRATE" not in caplog.text
    with caplog.at_level(logging.WARNING):
        read_inventory(inv, default_mu=0.6)
    assert "CRATE" in caplog.text
