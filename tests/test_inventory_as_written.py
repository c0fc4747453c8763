"""Inventories read as users write them: a European spreadsheet's ';' and decimal commas, misspelt columns matched to
the intended ones (and what ignoring them would cost), sizes typed in centimetres named as such, and no "screened as
given" beside an error that stops the run."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from pipeline.blocks import read_inventory
from pipeline.errors import InventoryError

COMMA = "id,height_m,width_m,mu,azimuth_deg\nSTAT-01,1.85,0.55,0.6,30\nTOMB-01,1.10,0.20,0.65,\n"


@pytest.mark.parametrize("text", [
    COMMA.replace(",", ";").replace("1;85", "1,85").replace("0;55", "0,55").replace("0;6", "0,6")
    .replace("1;10", "1,10").replace("0;20", "0,20").replace("0;65", "0,65"),
    COMMA.replace(",", "\t"),
])
def test_semicolons_tabs_and_decimal_commas_read_as_the_comma_table(tmp_path, text):
    (tmp_path / "a.csv").write_text(COMMA)
    (tmp_path / "b.csv").write_text(text)
    a, b = read_inventory(tmp_path / "a.csv", default_mu=0.5), read_inventory(tmp_path / "b.csv", default_mu=0.5)
    assert a.ids == b.ids
    for name in ("height_m", "width_m", "mu", "azimuth_deg"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


def test_a_misspelt_required_column_is_matched_to_the_intended_one(tmp_path):
    (tmp_path / "b.csv").write_text("id,heigth_m,width_m\nA,1.0,0.2\n")
    with pytest.raises(InventoryError, match=r"rename 'heigth_m' to 'height_m'"):
        read_inventory(tmp_path / "b.csv", default_mu=0.5)


def test_a_misspelt_optional_column_says_what_ignoring_it_costs(tmp_path, caplog):
    (tmp_path / "b.csv").write_text("id,height_m,width_m,azimuth\nA,1.0,0.2,30\n")
    with caplog.at_level(logging.WARNING):
        inv = read_inventory(tmp_path / "b.csv", default_mu=0.5)
    assert np.isnan(inv.azimuth_deg[0])
    assert "did you mean 'azimuth_deg'" in caplog.text and "unknown orientation" in caplog.text


def test_sizes_in_centimetres_are_named_and_nothing_claims_to_be_screened(tmp_path, caplog):
    (tmp_path / "b.csv").write_text("id,height_m,width_m\nA,185,55\n")
    with caplog.at_level(logging.WARNING), pytest.raises(InventoryError) as err:
        read_inventory(tmp_path / "b.csv", default_mu=0.5)
    assert "in centimetres? 1.85 m" in str(err.value)
    assert "screened as given" not in caplog.text


@pytest.mark.parametrize("typed, first, second", [
    ("1850", "in millimetres? 1.85 m", "in centimetres? 18.5 m"),      # a statue's height in millimetres
    ("185", "in centimetres? 1.85 m", "in millimetres? 0.185 m"),      # ... in centimetres
])
def test_a_size_in_another_unit_is_offered_in_each_the_likeliest_first(tmp_path, typed, first, second):
    (tmp_path / "b.csv").write_text(f"id,height_m,width_m\nA,{typed},0.55\n")
    with pytest.raises(InventoryError) as err:
        read_inventory(tmp_path / "b.csv", default_mu=0.5)
    message = str(err.value)
    assert first in message and second in message and message.index(first) < message.index(second)


def test_a_size_too_large_in_every_unit_gets_no_unit_hint(tmp_path):
    (tmp_path / "b.csv").write_text("id,height_m,width_m\nA,500000,0.55\n")
    with pytest.raises(InventoryError) as err:
        read_inventory(tmp_path / "b.csv", default_mu=0.5)
    assert "height_m" in str(err.value) and "?" not in str(err.value).split("height_m")[1].split("\n")[0]


def test_the_object_column_takes_asset_or_natural_and_names_a_bad_value(tmp_path):
    (tmp_path / "b.csv").write_text("id,height_m,width_m,object\nA,1.2,0.3,natural\nB,1.2,0.3,\nC,1.2,0.3,Asset\n")
    inv = read_inventory(tmp_path / "b.csv", default_mu=0.5)
    assert inv.extra["object"] == ("natural", "", "Asset")
    (tmp_path / "bad.csv").write_text("id,height_m,width_m,object\nA,1.2,0.3,boulder\n")
    with pytest.raises(InventoryError, match=r"line 2, column 'object': 'boulder'; expected one of asset, natural"):
        read_inventory(tmp_path / "bad.csv", default_mu=0.5)
