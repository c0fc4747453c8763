"""``screen event``: the probability at a real grid node against the closed form, sigma = 0 against the fragility
at the median, the uncertainty field's source, an asset off the grid, the component check, revisions, the
ShakeCast export read back and checked against the format, and the page in a browser."""

from __future__ import annotations

import csv
import dataclasses
import math
import os
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from browser import assert_decision_first, assert_reads_at, chromium

from pipeline.blocks import read_inventory
from pipeline.config import Config
from pipeline.event.assets import Basis, Level
from pipeline.event.shakecast import read_facilities
from pipeline.run.event import EventError, EventRequest, screen_event
from pipeline.schema import FRAGILITY, apply_schema
from pipeline.uncertainty.fragility import FitStatus

SCENARIO = "903_m6p09_se-scenario-grid-cut.xml"
ACTUAL = "us10003yjy-grid-cut.xml"
G = 9.80665


def _phi(x: float) -> float:
    return 0.5 * (1.0 + math.erf(x / math.sqrt(2.0)))


def _node_rows(path: Path) -> list[list[float]]:
    """The grid_data rows of a grid.xml, parsed from its text (independent of the reader)."""
    text = path.read_text()
    data = text.split("<grid_data>")[1].split("</grid_data>")[0]
    return [[float(x) for x in line.split()] for line in data.strip().splitlines()]


@pytest.fixture(scope="module")
def shakemaps(data_dir) -> Path:
    return data_dir / "shakemaps"


def _fragility(path: Path, ids, *, median_g, beta, status=None, component="larger", im="pga",
               levels_g=(0.05, 0.1, 0.2, 0.4, 0.8)) -> Path:
    """A fragility.nc as 'screen fragility' writes it (the fit's variables), from given values: the input of the
    event stage."""
    n = len(ids)
    status = [FitStatus.ok] * n if status is None else status
    median = np.array(median_g, dtype=float) * G
    ds = xr.Dataset({
        "median": (("block",), median), "beta": (("block",), np.array(beta, dtype=float)),
        "median_low": (("block",), median * 0.8), "median_high": (("block",), median * 1.25),
        "fit_status": (("block",), np.array([int(s) for s in status], dtype=np.int8)),
    }, coords={"block": np.array(ids, dtype=object), "im_level": np.array(levels_g) * G})
    ds.attrs.update({"im": im, "im_units": "m s-2", "im_component": component})
    path.mkdir(parents=True, exist_ok=True)
    apply_schema(ds, FRAGILITY).to_netcdf(path / "fragility.nc")
    return path


def _inventory(path: Path, rows: list[tuple]) -> Path:
    lines = ["id,height_m,width_m,mu,azimuth_deg,site,lon,lat"]
    lines += [",".join(str(x) for x in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def _request(tmp_path: Path, grid: Path, inv_csv: Path, frag_dir: Path, config: Config | None = None, **kw
             ) -> EventRequest:
    cfg = config or Config()
    inventory = read_inventory(inv_csv, default_mu=cfg.blocks.default_mu)
    return EventRequest(grid, inventory, frag_dir, tmp_path / "out", cfg, **kw)


def test_the_probability_at_a_real_node_is_the_closed_form(shakemaps, tmp_path):
    """At a node of the real grid with STDPGA, P = Phi(ln(m / theta) / sqrt(beta^2 + sigma^2)) with the node's
    own values, read from the file's text."""
    row = _node_rows(shakemaps / ACTUAL)[37]
    lon, lat, pga_pctg, sd = row[0], row[1], row[2], row[8]
    theta_g, beta = pga_pctg / 100.0 * 1.7, 0.4
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", lon, lat)])
    frag = _fragility(tmp_path / "frag", ["A"], median_g=[theta_g], beta=[beta])
    out = screen_event(_request(tmp_path, shakemaps / ACTUAL, inv, frag))
    expected = _phi(math.log(pga_pctg / 100.0 / theta_g) / math.sqrt(beta ** 2 + sd ** 2))
    assert float(out.dataset.p_overturn_event.values[0]) == pytest.approx(expected, rel=1e-9)
    assert float(out.dataset.shaking_log_sd.values[0]) == pytest.approx(sd)
    assert int(out.dataset.log_sd_source.values[0]) == 0                     # from the grid's STDPGA
    # k sigma: the shaking at its median x exp(k sigma)
    out2 = screen_event(_request(tmp_path, shakemaps / ACTUAL, inv, frag, k_sigma=1.0))
    expected2 = _phi((math.log(pga_pctg / 100.0 / theta_g) + sd) / math.sqrt(beta ** 2 + sd ** 2))
    assert float(out2.dataset.p_overturn_event.values[0]) == pytest.approx(expected2, rel=1e-9)


def test_sigma_zero_is_the_fragility_at_the_median_and_a_missing_field_is_said(shakemaps, tmp_path):
    """The scenario grid has no STD field: the configured default is used, said in a warning and in event.nc;
    with that default at 0, P is the fragility at the node's median."""
    row = _node_rows(shakemaps / SCENARIO)[100]
    lon, lat, pga_pctg = row[0], row[1], row[2]
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", lon, lat)])
    frag = _fragility(tmp_path / "frag", ["A"], median_g=[0.2], beta=[0.5])
    cfg = Config()
    zero = dataclasses.replace(cfg, event=dataclasses.replace(cfg.event, default_log_sd=0.0))
    out = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag, zero))
    assert float(out.dataset.p_overturn_event.values[0]) == pytest.approx(
        _phi(math.log(pga_pctg / 100.0 / 0.2) / 0.5), rel=1e-9)
    assert any("no STDPGA" in w and "default_log_sd" in w for w in out.warnings)
    assert int(out.dataset.log_sd_source.values[0]) == 2
    out = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))    # the default 0.65
    assert float(out.dataset.shaking_log_sd.values[0]) == cfg.event.default_log_sd


def test_an_asset_off_the_grid_is_an_error_naming_it(shakemaps, tmp_path):
    inv = _inventory(tmp_path / "b.csv", [("ON", 1.0, 0.2, 0.6, "", "s", -105.9, 31.37),
                                          ("FAR-01", 1.0, 0.2, 0.6, "", "s", -90.0, 31.0)])
    frag = _fragility(tmp_path / "frag", ["ON", "FAR-01"], median_g=[0.2, 0.2], beta=[0.5, 0.5])
    with pytest.raises(Exception, match=r"FAR-01 \(lon -90.0, lat 31.0\)"):
        screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    assert not (tmp_path / "out" / "event.nc").exists()


def test_an_asset_without_coordinates_is_an_error_with_the_fix_and_sites_give_them(shakemaps, tmp_path):
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "chapel", "", "")])
    frag = _fragility(tmp_path / "frag", ["A"], median_g=[0.2], beta=[0.5])
    with pytest.raises(EventError, match="A: lon '', lat ''.*--sites"):
        screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    sites = tmp_path / "sites.csv"
    sites.write_text("site,lon,lat\nchapel,-105.9,31.37\n")
    out = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag, sites=sites))
    assert float(out.dataset.lon.values[0]) == -105.9


def test_the_component_definitions_must_match_or_a_conversion_is_stated(shakemaps, tmp_path):
    row = _node_rows(shakemaps / SCENARIO)[100]
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", row[0], row[1])])
    frag = _fragility(tmp_path / "frag", ["A"], median_g=[0.2], beta=[0.5], component="rotd100")
    with pytest.raises(EventError, match="--im-component larger, or state the conversion with --shakemap-scale"):
        screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    out = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag, shakemap_scale=1.1))
    assert float(out.dataset.shaking_median.values[0]) == pytest.approx(row[2] / 100.0 * G * 1.1, rel=1e-9)
    assert "x 1.1" in out.dataset.attrs["component"]


def test_a_fragility_that_bounds_nothing_gives_bounds_not_a_number(shakemaps, tmp_path):
    """Nothing overturned at the levels tested: p is not given; its upper bound is P(shaking > top level)."""
    row = _node_rows(shakemaps / SCENARIO)[100]
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", row[0], row[1]),
                                          ("CRATE", 0.6, 1.2, 0.25, "", "s", row[0], row[1])])
    frag = _fragility(tmp_path / "frag", ["A", "CRATE"], median_g=[math.inf, math.inf], beta=[math.nan] * 2,
                      status=[FitStatus.none_overturn] * 2, levels_g=(0.05, 0.1))
    ds = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag)).dataset
    assert math.isnan(float(ds.p_overturn_event.values[0]))
    assert int(ds.basis.values[0]) == Basis.bounds_only
    sd = Config().event.default_log_sd
    assert float(ds.p_overturn_event_high.values[0]) == pytest.approx(
        _phi(math.log(row[2] / 100.0 / 0.1) / sd), rel=1e-9)
    assert float(ds.p_overturn_event_low.values[0]) == 0.0
    assert int(ds.basis.values[1]) == Basis.cannot_rock and float(ds.p_overturn_event.values[1]) == 0.0
    # the page and the list say it in words: no raw "inf" or "nan" (the fragility median is inf, beta NaN)
    out = tmp_path / "out"
    text = re.sub(r"<[^>]+>", " ", re.sub(r"data:image/[^\"]+", "", (out / "event.html").read_text()))
    assert not re.findall(r"\b(?:nan|inf)\b", text, flags=re.I)
    assert "none overturn" in text and re.search(r"\bnone\b", text.split("fragility median")[-1])
    cells = [c for line in (out / "inspection.csv").read_text().splitlines() for c in line.split(",")]
    assert not [c for c in cells if c.strip().lower() in ("nan", "inf", "-inf")], cells


def _with_version(src: Path, dest: Path, version: int, factor: float = 1.0) -> Path:
    """The grid with another shakemap_version, its PGA multiplied by ``factor`` (a revised map)."""
    text = src.read_text()
    text = re.sub(r'shakemap_version="\d+"', f'shakemap_version="{version}"', text)
    head, data = text.split("<grid_data>")
    data, tail = data.split("</grid_data>")
    rows = []
    for line in data.strip().splitlines():
        v = line.split()
        v[2] = f"{float(v[2]) * factor:.4f}"
        rows.append(" ".join(v))
    dest.write_text(head + "<grid_data>\n" + "\n".join(rows) + "\n</grid_data>" + tail)
    return dest


def test_a_newer_version_replaces_an_older_and_an_older_never_overwrites(shakemaps, tmp_path):
    rows = _node_rows(shakemaps / SCENARIO)
    inv = _inventory(tmp_path / "b.csv", [(f"A{k}", 1.0, 0.2, 0.6, "", "s", rows[k][0], rows[k][1])
                                          for k in (90, 100, 110)])
    frag = _fragility(tmp_path / "frag", [f"A{k}" for k in (90, 100, 110)],
                      median_g=[0.1, 0.1, 0.1], beta=[0.3] * 3)
    v3 = _with_version(shakemaps / SCENARIO, tmp_path / "v3.xml", 3)
    first = screen_event(_request(tmp_path, v3, inv, frag)).dataset
    assert (first.level_previous.values == -1).all()
    v4 = _with_version(shakemaps / SCENARIO, tmp_path / "v4.xml", 4, factor=8.0)      # much stronger shaking
    out = screen_event(_request(tmp_path, v4, inv, frag))
    assert out.replaced_version == "3"
    ds = xr.open_dataset(tmp_path / "out" / "event.nc")
    assert ds.attrs["shakemap_version"] == "4" and ds.attrs["previous_version"] == "3"
    assert (ds.level_previous.values == first.level.values).all()
    assert out.changed and all(now == Level.high.name for _, _, now in out.changed)
    page = (tmp_path / "out" / "event.html").read_text()
    assert "ShakeMap version 4" in page and "replaces version 3" in page and 'id="changes"' in page
    ds.close()
    before = (tmp_path / "out" / "event.nc").read_bytes()
    with pytest.raises(EventError, match="version 3 .* is older and never overwrites it"):
        screen_event(_request(tmp_path, v3, inv, frag))
    assert (tmp_path / "out" / "event.nc").read_bytes() == before
    other = tmp_path / "other.xml"
    other.write_text(v4.read_text().replace('event_id="903_m6p09_se"', 'event_id="us9999"'))
    with pytest.raises(EventError, match="holds the results of event 903_m6p09_se"):
        screen_event(_request(tmp_path, other, inv, frag))


def test_the_inspection_list_is_ranked_and_levels_follow_the_configured_thresholds(shakemaps, tmp_path):
    rows = _node_rows(shakemaps / SCENARIO)
    pga = [rows[k][2] / 100.0 for k in (90, 100, 110)]
    inv = _inventory(tmp_path / "b.csv", [(f"A{k}", 1.0, 0.2, 0.6, "", "s", rows[k][0], rows[k][1])
                                          for k in (90, 100, 110)])
    frag = _fragility(tmp_path / "frag", [f"A{k}" for k in (90, 100, 110)],
                      median_g=[pga[0] * 3, pga[1], pga[2] / 3], beta=[0.3] * 3)
    ds = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag)).dataset
    p = ds.p_overturn_event.values
    assert list(ds.priority.values[np.argsort(-p)]) == [1, 2, 3]
    cfg = Config().event
    for pk, lv in zip(p, ds.level.values):
        want = 3 if pk >= cfg.level_high else 2 if pk >= cfg.level_medium else 1 if pk >= cfg.level_low else 0
        assert lv == want
    table = (tmp_path / "out" / "inspection.csv").read_text().splitlines()
    assert table[0].startswith("priority,block,") and "shaking_median_g" in table[0]
    assert [line.split(",")[1] for line in table[1:]] == list(ds.block.values[np.argsort(-p)])


def _check_against_the_format(path: Path) -> int:
    """A parser written from the ShakeCast facility format (FacilityTable/FacilityRow, the row's fields, FEATURE,
    FRAGILITY of damage levels with METRIC, ALPHA, BETA), not from rockscreen's reader: the number of rows."""
    root = ET.parse(path).getroot()
    assert root.tag == "FacilityTable"
    n = 0
    for row in root:
        assert row.tag == "FacilityRow"
        children = [c.tag for c in row]
        for required in ("EXTERNAL_FACILITY_ID", "FACILITY_TYPE", "COMPONENT_CLASS", "COMPONENT", "FACILITY_NAME",
                         "FEATURE", "FRAGILITY"):
            assert required in children, (required, children)
        vertices = [v.split(",") for v in row.find("FEATURE/GEOM").text.split(";")]     # lon,lat,depth;...
        assert row.find("FEATURE/GEOM_TYPE").text in ("POINT", "POLYGON")
        assert all(len(v) == 3 and all(float(x) == float(x) for x in v) for v in vertices)
        for level in row.find("FRAGILITY"):
            assert level.tag in ("GREEN", "YELLOW", "ORANGE", "RED", "GREY")
            assert level.find("METRIC").text in ("MMI", "PGA", "PGV", "PSA03", "PSA10", "PSA30")
            assert float(level.find("ALPHA").text) > 0 and float(level.find("BETA").text) > 0
        n += 1
    return n


def test_the_shakecast_export_reads_back_with_the_same_medians_and_follows_the_format(shakemaps, tmp_path):
    rows = _node_rows(shakemaps / SCENARIO)
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", rows[90][0], rows[90][1]),
                                          ("B", 2.0, 0.5, 0.3, "", "s", rows[100][0], rows[100][1])])
    frag = _fragility(tmp_path / "frag", ["A", "B"], median_g=[0.15, 0.3], beta=[0.35, 0.5])
    screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    path = tmp_path / "out" / "shakecast-facilities.xml"
    assert _check_against_the_format(path) == 2
    back = {f.facility_id: f for f in read_facilities(path)}
    red = {k: next(lv for lv in f.levels if lv.name == "RED") for k, f in back.items()}
    assert red["A"].metric == "PGA" and red["A"].alpha == pytest.approx(15.0, rel=1e-5) and red["A"].beta == 0.35
    assert red["B"].alpha == pytest.approx(30.0, rel=1e-5) and red["B"].beta == 0.5
    yellow = {k: next(lv for lv in f.levels if lv.name == "YELLOW") for k, f in back.items()}
    assert yellow["A"].alpha == pytest.approx(100 * 0.2 / 1.0, rel=1e-5)      # tan alpha = 0.2 < mu 0.6: uplift
    assert yellow["B"].alpha == pytest.approx(100 * 0.25, rel=1e-5)           # mu 0.3 > tan alpha 0.25: uplift
    assert (back["A"].lon, back["A"].lat) == pytest.approx((rows[90][0], rows[90][1]))
    # ShakeCast's own example file passes the same format check and reader
    example = shakemaps / "shakecast-facility-example.xml"
    assert _check_against_the_format(example) == 3
    assert [lv.alpha for lv in read_facilities(example)[1].levels] == [21, 35, 70, 137, 0.01]


@pytest.mark.browser
def test_the_event_page_in_headless_chromium(shakemaps, tmp_path):
    """The page opens with the list and the map; the map renders, every link has its target, and the page fits
    a 1400 px window."""
    rows = _node_rows(shakemaps / SCENARIO)
    ids = [f"A{k}" for k in range(0, 300, 25)]
    inv = _inventory(tmp_path / "b.csv", [(f"A{k}", 1.0, 0.2, 0.6, "", "s", rows[k][0], rows[k][1])
                                          for k in range(0, 300, 25)])
    frag = _fragility(tmp_path / "frag", ids, median_g=[0.05 + 0.02 * k for k in range(len(ids))],
                      beta=[0.4] * len(ids))
    screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    page = tmp_path / "out" / "event.html"
    source = page.read_text()
    assert source.index('id="priority"') < source.index('id="map"') < source.index('id="curves"')
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", source), "the page must not load anything remotely"
    browser = chromium()
    common = [browser, "--headless=new", "--no-sandbox", "--disable-gpu", f"--user-data-dir={tmp_path / 'p'}",
              "--virtual-time-budget=10000", "--window-size=1400,1000"]
    env = dict(os.environ, HOME=str(tmp_path))
    dom = subprocess.run([*common, "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120,
                         env=env)
    assert dom.returncode == 0, dom.stderr[-2000:]
    got = dict(re.findall(r'data-(map-rendered|page-width|list-right|dead-links)="([^"]+)"', dom.stdout))
    assert got.get("map-rendered") == "yes" and got.get("dead-links") == "0", got
    assert int(got["page-width"]) <= 1400 and int(got["list-right"]) <= 1400, got
    assert dom.stdout.count('<figure id="curve-') == len(ids)
    assert_reads_at(page, tmp_path)                               # a phone (390 px) and a laptop (1400 px)
    with open(tmp_path / "out" / "inspection.csv") as f:
        first = next(csv.DictReader(f))
    assert first["recommendation"].startswith(("inspect", "no inspection")), first["recommendation"]
    assert_decision_first(page, tmp_path / "out" / "inspection.csv")   # the top asset's decision, first screen


def test_event_nc_follows_the_schema_and_names_a_more_efficient_im(shakemaps, tmp_path):
    """Every variable has its schema entry; where the fragility run found PGV more efficient than the fit's PGA
    (its beta_im), event.nc and a warning say so."""
    from pipeline import schema

    rows = _node_rows(shakemaps / SCENARIO)
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", rows[90][0], rows[90][1]),
                                          ("B", 2.0, 0.5, 0.3, "", "s", rows[100][0], rows[100][1])])
    frag = _fragility(tmp_path / "frag", ["A", "B"], median_g=[0.15, 0.3], beta=[0.35, 0.5])
    with xr.open_dataset(frag / "fragility.nc") as ds:
        ds = ds.load()
    ds = ds.assign_coords(im=np.array(["pga", "pgv", "arias"], dtype=object))
    ds["beta_im"] = (("block", "im"), np.array([[0.6, 0.4, 0.1], [0.5, np.inf, 0.2]]))
    ds.to_netcdf(frag / "fragility.nc")
    out = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    assert list(out.dataset.most_efficient_im.values) == ["pgv", "pga"]      # arias is not a ShakeMap IM
    assert list(out.dataset.most_efficient_beta.values) == [0.4, 0.5]
    assert any("1 asset(s) (A)" in w and "more efficient than pga" in w for w in out.warnings)
    with xr.open_dataset(tmp_path / "out" / "event.nc") as written:
        assert schema.check(written, schema.EVENT) == []
        assert set(written.data_vars) <= set(schema.EVENT)


def _grid_around(src: Path, dest: Path, lon0: float, lat0: float, pga_pctg: float) -> Path:
    """A grid.xml with the header of a real ShakeMap 3.5 file and a uniform 0.5 deg square of nodes around
    (lon0, lat0): the input of a test whose stations lie elsewhere than the bundled grids."""
    head = src.read_text().split("<grid_data>")[0]
    lons, lats = np.round(lon0 + np.arange(-3, 4) * 0.1, 4), np.round(lat0 + np.arange(-3, 4) * 0.1, 4)
    rows = [f"{x:.4f} {y:.4f} {pga_pctg} 20.0 6.0 {pga_pctg * 2} {pga_pctg} {pga_pctg / 4}"
            for y in lats[::-1] for x in lons]
    dest.write_text(head + "<grid_data>\n" + "\n".join(rows) + "\n</grid_data>\n</shakemap_grid>\n")
    return dest


def test_the_events_records_screen_the_assets_near_their_station(shakemaps, records_dir, tmp_path):
    """An asset 1 km from the station of a bundled DMG record (its coordinates from the file's header) is screened
    on that record; one 50 km away is not. The larger probability governs the level."""
    records = tmp_path / "records"
    records.mkdir()
    shutil.copy(records_dir / "dmg" / "CICLC.v1", records / "CICLC.v1")            # Station Id. CLC 35.816N, 117.598W
    shutil.copy(records_dir / "peer-at2" / "RSN77_SFERN_PUL164.AT2", records / "RSN77_SFERN_PUL164.AT2")
    grid = _grid_around(shakemaps / SCENARIO, tmp_path / "grid.xml", -117.6, 35.8, 2.0)   # weak: 2 %g
    near_lat = 35.816 + 1.0 / 111.195                                                       # 1 km north
    inv = _inventory(tmp_path / "b.csv", [("NEAR", 0.5, 0.055, 0.5, "", "s", -117.598, near_lat),
                                          ("FAR", 0.5, 0.055, 0.5, "", "s", -117.598 + 0.25, 35.816 - 0.25)])
    frag = _fragility(tmp_path / "frag", ["NEAR", "FAR"], median_g=[0.3, 0.3], beta=[0.4, 0.4])
    out = screen_event(_request(tmp_path, grid, inv, frag, records=records))
    ds = out.dataset
    assert list(ds.station_record.values) == ["CICLC", ""]
    assert float(ds.station_distance.values[0]) == pytest.approx(1.0, abs=0.01)
    assert any("RSN77_SFERN_PUL164" in w and "carry no coordinates" in w for w in out.warnings)
    with xr.open_dataset(tmp_path / "out" / "records" / "screening.nc") as sc:
        assert list(sc.block.values) == ["NEAR"]                              # only the asset near a station
        i = list(sc.record.values).index("CICLC")
        assert float(ds.p_overturn_record.values[0]) == float(sc.p_overturn.values[i, 0])
    p_map, p_rec = float(ds.p_overturn_event.values[0]), float(ds.p_overturn_record.values[0])
    assert int(ds.governed_by.values[0]) == int(p_rec > p_map)
    # the column model at 2 %g from the map hardly moves, but under the M 7.1 Ridgecrest record 1 km away it
    # overturns: the record governs, and the level follows it
    assert p_map < 0.01 and p_rec > 0.9 and int(ds.governed_by.values[0]) == 1
    assert int(ds.level.values[0]) == Level.high and int(ds.priority.values[0]) == 1
    assert math.isnan(float(ds.p_overturn_record.values[1])) and int(ds.governed_by.values[1]) == 0
    assert "station_record" in (tmp_path / "out" / "inspection.csv").read_text().splitlines()[0]


def test_the_map_names_its_assets_beside_it_with_leader_lines_and_its_legend_below(shakemaps, tmp_path,
                                                                                    monkeypatch):
    """Assets clustered at the epicentre: their names stand in a column beside the map, none over another, none
    over the map; the legend is below the axes; the curves' tick labels have no exponent."""
    from figure_checks import legend_boxes_clear
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from pipeline.report import event_html

    drawn = []

    def capture(ds, grid, inv, order):
        fig = event_html.map_figure(ds, grid, inv, order)
        drawn.append(fig)
        from pipeline.report.mpl import png_bytes
        return png_bytes(fig)

    monkeypatch.setattr(event_html, "map_png", capture)
    rows = _node_rows(shakemaps / SCENARIO)
    lon0 = float(np.median([r[0] for r in rows]))                        # the assets in a cluster mid-grid
    lat0 = float(np.median([r[1] for r in rows]))
    ids = [f"A{k}" for k in range(10)]
    inv = _inventory(tmp_path / "b.csv", [(f"A{k}", 1.0, 0.2, 0.6, "", "s", lon0 + 0.001 * k, lat0 + 0.0005 * k)
                                          for k in range(10)])
    frag = _fragility(tmp_path / "frag", ids, median_g=[0.05 + 0.3 * k for k in range(10)], beta=[0.4] * 10)
    screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    fig = drawn[0]
    FigureCanvasAgg(fig)
    assert legend_boxes_clear(fig) == []
    ax = fig.axes[0]
    box = ax.get_window_extent()
    assert len(fig.legends) == 1 and not fig.legends[0].get_window_extent().overlaps(box)
    from matplotlib.text import Text

    renderer = fig.canvas.get_renderer()
    labels = [Text.get_window_extent(t, renderer) for t in ax.texts]     # the text alone, not its leader line
    assert len(labels) == min(10, event_html.MAP_LABELS)
    assert all(box.x1 <= lb.x0 and lb.x1 <= fig.bbox.x1 for lb in labels)   # beside the map, within the figure
    assert not any(a.overlaps(b) for i, a in enumerate(labels) for b in labels[i + 1:])
    bar = fig.axes[-1]                                                    # the colour bar: its labels apart, plain
    shown = [t for t in bar.get_xticklabels(minor=False) + bar.get_xticklabels(minor=True) if t.get_text()]
    boxes = [t.get_window_extent(renderer) for t in shown]
    assert shown and not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert not [t.get_text() for t in shown if "times" in t.get_text() or "^" in t.get_text()]
    page = (tmp_path / "out" / "event.html").read_text()
    ticks = re.findall(r'text-anchor="(?:start|middle|end)">([^<]+)</text>', page)
    assert ticks and not [t for t in ticks if "e+" in t or "e-" in t]
    # the terms of the details table are explained above it, on the rendered page
    terms = page[page.index('id="terms"'):page.index('id="detail-table"')]
    for word in ("P bounds", "basis", "fitted", "extrapolated", "bounds only", "cannot rock", "no fragility"):
        assert word in terms, word


def test_records_without_a_verdict_and_sliding_are_never_level_none(shakemaps, tmp_path):
    """A: its judged records put the median at 20 times the site's shaking (P ~ 0), but its fragility run had
    records without a verdict, and counted as overturning they put it at half the shaking: P's upper bound, its rank
    and its level come from that fit (the closed form), and the run says so with the count. CRATE cannot rock (P = 0)
    but slid in the stripes at a level below the site's shaking: never level none."""
    row = _node_rows(shakemaps / SCENARIO)[100]
    site_g = row[2] / 100.0
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", row[0], row[1]),
                                          ("CRATE", 0.6, 1.2, 0.25, "", "s", row[0], row[1])])
    levels_g = (0.05, 0.1, 0.2, 0.4, 0.8)
    frag = _fragility(tmp_path / "frag", ["A", "CRATE"], median_g=[20 * site_g, math.inf], beta=[0.4, math.nan],
                      status=[FitStatus.ok, FitStatus.none_overturn], levels_g=levels_g)
    with xr.open_dataset(frag / "fragility.nc") as f:
        ds = f.load()
    ds["median_unjudged_overturn"] = (("block",), np.array([0.5 * site_g * G, math.nan]))
    ds["beta_unjudged_overturn"] = (("block",), np.array([0.4, math.nan]))
    ds["n_unjudged"] = (("block", "im_level"), np.array([[0, 0, 1, 2, 3], [0, 0, 0, 0, 0]], dtype=float))
    ds["n_sliding"] = (("block", "im_level"), np.array([[0] * 5, [1, 1, 2, 2, 2]], dtype="i4"))
    (frag / "fragility.nc").unlink()
    ds.to_netcdf(frag / "fragility.nc")
    result = screen_event(_request(tmp_path, shakemaps / SCENARIO, inv, frag))
    out = result.dataset
    sd = float(out.shaking_log_sd.values[0])
    assert float(out.p_overturn_event.values[0]) < 0.01
    expected = _phi(math.log(2.0) / math.sqrt(0.4 ** 2 + sd ** 2))            # shaking / median = 2
    assert float(out.p_overturn_event_high.values[0]) == pytest.approx(expected, rel=1e-9)
    assert int(out.basis.values[0]) == Basis.unjudged and int(out.level.values[0]) != Level.none
    assert any(w.startswith("A: 6 scaled record-levels") for w in result.warnings), result.warnings
    assert site_g >= 0.05, "the node chosen must shake above the level at which CRATE slid"
    assert int(out.sliding_risk.values[1]) == 1 and int(out.level.values[1]) == Level.low
    assert float(out.p_overturn_event.values[1]) == 0.0
    page = (tmp_path / "out" / "event.html").read_text()
    assert "it slides at this shaking" in page and "records not judged" in page
