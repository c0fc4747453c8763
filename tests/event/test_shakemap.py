"""ShakeMap grids (issue 42, the library part): reading both unit conventions, the shaking at a site against hand
values at real nodes of the bundled grids, and the event probability against its closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from pipeline.constants import G
from pipeline.event.shakemap import ShakeMapError, field_for, p_overturn_event, read_grid, site_shaking
from pipeline.uncertainty.fragility import fragility_curve

SCENARIO = "903_m6p09_se-scenario-grid-cut.xml"        # ShakeMap 3.5, pctg / cms, no STD field
ACTUAL = "us10003yjy-grid-cut.xml"                     # ShakeMap 3.5 with STDPGA in ln(pctg)


@pytest.fixture(scope="module")
def shakemaps(data_dir):
    return data_dir / "shakemaps"


def _rows(path, n):
    """The first ``n`` data rows of a grid, as the file writes them (hand values)."""
    text = path.read_text()
    body = text.split("<grid_data>")[1].split("</grid_data>")[0].split("\n")
    return [[float(x) for x in line.split()] for line in body if line.strip()][:n]


@pytest.mark.parametrize("name", [SCENARIO, ACTUAL])
def test_the_shaking_at_a_real_node_is_the_nodes_value(shakemaps, name):
    grid = read_grid(shakemaps / name)
    for lon, lat, pga_pctg, pgv_cms, *_ in _rows(shakemaps / name, 5):
        at = site_shaking(grid, "PGA", lon, lat)
        assert at.median == pytest.approx(pga_pctg / 100 * G, rel=1e-9)
        assert site_shaking(grid, "PGV", lon, lat).median == pytest.approx(pgv_cms / 100, rel=1e-9)


def test_between_nodes_the_log_of_the_median_is_bilinear(shakemaps):
    """At the centre of four nodes, ln IM is their mean (the geometric mean of the medians); a quarter of the way
    along a row, ln IM is 3/4 and 1/4 of its two ends."""
    grid = read_grid(shakemaps / SCENARIO)
    rows = _rows(shakemaps / SCENARIO, 2 * grid.lon.size)
    nlon = grid.lon.size
    a, b = rows[0], rows[1]                    # neighbours along a row (north row first in the file)
    c, d = rows[nlon], rows[nlon + 1]          # the row below
    centre = site_shaking(grid, "PGA", (a[0] + b[0]) / 2, (a[1] + c[1]) / 2).median
    assert centre == pytest.approx((a[2] * b[2] * c[2] * d[2]) ** 0.25 / 100 * G, rel=1e-9)
    quarter = site_shaking(grid, "PGA", a[0] + 0.25 * (b[0] - a[0]), a[1]).median
    assert quarter == pytest.approx(a[2] ** 0.75 * b[2] ** 0.25 / 100 * G, rel=1e-9)


def test_shakemap_4_unit_strings_give_the_same_values(shakemaps, tmp_path):
    text = (shakemaps / ACTUAL).read_text()
    v4 = tmp_path / "grid.xml"
    v4.write_text(text.replace('units="pctg"', 'units="%g"').replace('units="cms"', 'units="cm/s"')
                  .replace('units="ln(pctg)"', 'units="ln(g)"'))
    a, b = read_grid(shakemaps / ACTUAL), read_grid(v4)
    for im in a.medians:
        np.testing.assert_array_equal(a.medians[im], b.medians[im])
    np.testing.assert_array_equal(a.log_sd["PGA"], b.log_sd["PGA"])
    assert b.units["PGA"] == "%g" and b.units["STDPGA"] == "ln(g)"


def test_a_missing_uncertainty_field_is_nan_never_zero(shakemaps):
    grid = read_grid(shakemaps / SCENARIO)
    lon, lat = float(grid.lon[3]), float(grid.lat[2])
    assert "PGA" not in grid.log_sd and math.isnan(site_shaking(grid, "PGA", lon, lat).log_sd)
    actual = read_grid(shakemaps / ACTUAL)
    sd = site_shaking(actual, "PGA", float(actual.lon[3]), float(actual.lat[1])).log_sd
    assert sd == pytest.approx(float(actual.log_sd["PGA"][1, 3]))


def test_a_site_off_the_grid_is_an_error_naming_it(shakemaps):
    grid = read_grid(shakemaps / SCENARIO)
    with pytest.raises(ShakeMapError, match=r"outside ShakeMap 903_m6p09_se's grid .*: TOMB-07 \(lon -90.0, lat "
                                            r"31.0\)"):
        site_shaking(grid, "PGA", -90.0, 31.0, site="TOMB-07")


@pytest.mark.parametrize("bad, message", [('units="pctg"', "unit 'furlongs'"), ("<grid_data>", "not a ShakeMap")])
def test_bad_files_are_errors_naming_the_file(shakemaps, tmp_path, bad, message):
    path = tmp_path / "grid.xml"
    text = (shakemaps / SCENARIO).read_text()
    path.write_text(text.replace(bad, 'units="furlongs"' if bad.startswith("units") else "<data>", 1))
    with pytest.raises(ShakeMapError, match=message):
        read_grid(path)


@pytest.mark.parametrize("median, sigma, theta, beta", [(0.3, 0.6, 0.4, 0.45), (0.5, 0.0, 0.4, 0.3),
                                                        (0.05, 0.65, 0.4, 0.5)])
def test_the_event_probability_is_the_lognormal_convolution(median, sigma, theta, beta):
    expected = norm.cdf(math.log(median / theta) / math.hypot(beta, sigma))
    assert p_overturn_event(median, sigma, theta, beta) == pytest.approx(expected, rel=1e-12)
    if sigma == 0.0:                                     # the fragility at the median shaking
        assert p_overturn_event(median, sigma, theta, beta) == pytest.approx(
            float(fragility_curve(np.array([median]), theta, beta)[0]), rel=1e-12)
    # the median times exp(k sigma), as regulators ask for
    shifted = norm.cdf(math.log(median * math.exp(sigma) / theta) / math.hypot(beta, sigma))
    assert p_overturn_event(median, sigma, theta, beta, k_sigma=1.0) == pytest.approx(shifted, rel=1e-12)


def test_the_psa_field_nearest_a_blocks_period():
    assert field_for("sa", 0.25) == "PSA03" and field_for("sa", 0.8) == "PSA10" and field_for("sa", 5.0) == "PSA30"
    assert field_for("pga") == "PGA" and field_for("pgv") == "PGV"
    with pytest.raises(ShakeMapError, match="arias"):
        field_for("arias")


#: A billion-laughs entity bomb and an external entity (XXE), each placed before a real grid's root element.
ENTITY_BOMB = ('<!DOCTYPE shakemap_grid [<!ENTITY a "aaaaaaaaaa">' + "".join(
    f'<!ENTITY {chr(98 + k)} "{("&" + chr(97 + k) + ";") * 10}">' for k in range(8)) + "]>\n")
EXTERNAL_ENTITY = '<!DOCTYPE shakemap_grid [<!ENTITY secret SYSTEM "file:///etc/passwd">]>\n'


@pytest.mark.parametrize("doctype", [ENTITY_BOMB, EXTERNAL_ENTITY], ids=["billion-laughs", "xxe"])
def test_xml_entities_are_refused_by_name_not_expanded(shakemaps, tmp_path, doctype):
    text = (shakemaps / SCENARIO).read_text()
    start = text.index("<shakemap_grid")
    path = tmp_path / "grid.xml"
    path.write_text(text[:start] + doctype + text[start:].replace('event_id="', 'event_id="&secret;', 1)
                    if "secret" in doctype else text[:start] + doctype + text[start:])
    with pytest.raises(ShakeMapError, match="declares a DTD or XML entities.*refused"):
        read_grid(path)


def test_malformed_xml_is_a_named_refusal(shakemaps, tmp_path):
    text = (shakemaps / SCENARIO).read_text()
    path = tmp_path / "grid.xml"
    path.write_text(text.replace("<event ", "<event <", 1))
    with pytest.raises(ShakeMapError, match="not well-formed XML"):
        read_grid(path)


def test_a_decompression_bomb_is_refused_without_being_decompressed(tmp_path, monkeypatch):
    import gzip

    from pipeline.event import shakemap

    monkeypatch.setattr(shakemap, "MAX_GRID_BYTES", 2**20)      # the limit, scaled down with the bomb
    path = tmp_path / "grid.xml.gz"
    with gzip.open(path, "wb", compresslevel=9) as fh:
        for _ in range(8):
            fh.write(b" " * 2**20)                                 # 8 MiB of blanks in a few kB
    assert path.stat().st_size < 2**16
    with pytest.raises(ShakeMapError, match="more than 1 MiB once decompressed.*refused"):
        read_grid(path)
