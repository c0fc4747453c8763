"""Fragility curves written for the risk engines: OpenQuake NRML and pelicun's damage-model CSV.

Independent truths: the lognormal's moments (the example OpenQuake's documentation of continuous fragility
functions works: theta 0.507572 g, beta 0.281977 -> mean 0.528157, stddev 0.151938), their inverse, and where
installed the engines' own parsers (OpenQuake's nrml.to_python, pelicun's damage model). Those two are optional:
openquake-engine needs GDAL from its own wheels, and pelicun 3.10 pins pandas < 3 and scipy < 1.16, so neither
installs beside this project from the package index; the check made with them in their own environments is in
docs/validation.md.
"""

from __future__ import annotations

import csv
import io
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import xarray as xr
from scipy.stats import norm

from pipeline.constants import G
from pipeline.store.exports import ids_csv, lognormal_moments, openquake_nrml, pelicun_csv, pelicun_id

NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}


def fits(im="pga", component="rotd50"):
    blocks = ["STAT-01", "COL-0.5", "CRATE-01"]
    return xr.Dataset({"median": (("block",), np.array([0.5 * G, 0.12 * G, np.nan]) if im != "pgv"
                                  else np.array([0.35, 0.8, np.nan])),
                       "beta": (("block",), np.array([0.4, 0.25, np.nan])),
                       "block_period": (("block",), np.array([1.9, 1.2, 2.5]))},
                      coords={"block": np.array(blocks, dtype=object)},
                      attrs={"im": im, "im_component": component})


def test_lognormal_moments_match_the_documented_example():
    m = lognormal_moments(0.507572, 0.281977)
    assert m.mean == pytest.approx(0.528157, abs=1e-6) and m.stddev == pytest.approx(0.151938, abs=1e-6)


@pytest.mark.parametrize("im, unit_factor", [("pga", 1 / G), ("pgv", 100.0), ("sa", 1 / G)])
def test_the_nrml_file_gives_back_each_median_and_beta(im, unit_factor):
    """Inverting OpenQuake's mean and stddev (beta^2 = ln(1 + (stddev/mean)^2), theta = mean exp(-beta^2/2))
    recovers every fit, in OpenQuake's units; a block without a fit has no function."""
    ds = fits(im)
    root = ET.fromstring(openquake_nrml(ds))
    functions = root.findall(".//n:fragilityFunction", NS)
    assert [f.get("id") for f in functions] == ["STAT-01", "COL-0.5"]
    for f, j in zip(functions, (0, 1)):
        p = f.find("n:params", NS)
        mean, sd = float(p.get("mean")), float(p.get("stddev"))
        beta = math.sqrt(math.log1p((sd / mean) ** 2))
        assert beta == pytest.approx(float(ds["beta"].values[j]), rel=1e-8)
        assert mean * math.exp(-beta * beta / 2) == pytest.approx(float(ds["median"].values[j]) * unit_factor,
                                                                   rel=1e-8)
        imt = f.find("n:imls", NS).get("imt")
        assert imt == {"pga": "PGA", "pgv": "PGV", "sa": f"SA({ds['block_period'].values[j]:.2f})"}[im]


def test_the_pelicun_file_names_its_demand_and_asks_for_no_multiplier():
    rows = list(csv.DictReader(io.StringIO(pelicun_csv(fits("pga")))))
    assert list(rows[0]) == ["ID", "Incomplete", "Demand-Type", "Demand-Unit", "Demand-Offset", "Demand-Directional",
                             "LS1-Family", "LS1-Theta_0", "LS1-Theta_1"]
    assert [r["ID"] for r in rows] == ["RS.STAT_01", "RS.COL_0.5"] and "-" not in pelicun_id("A-B-C")[3:]
    assert {r["Demand-Directional"] for r in rows} == {"1"} and {r["Demand-Offset"] for r in rows} == {"0"}
    assert rows[0]["Demand-Type"] == "Peak Ground Acceleration" and rows[0]["Demand-Unit"] == "g"
    assert float(rows[0]["LS1-Theta_0"]) == pytest.approx(0.5, rel=1e-9)
    assert float(rows[1]["LS1-Theta_1"]) == pytest.approx(0.25, rel=1e-9)


def test_openquake_reads_the_nrml_as_the_fitted_lognormal(tmp_path):
    try:
        import openquake.risklib.read_nrml  # noqa: F401  (registers the fragility converters)
        from openquake.hazardlib import nrml
    except ImportError:
        print("\n*** openquake-engine is not installed: the NRML file is not checked with OpenQuake's parser "
              "(docs/validation.md has the check made in its own environment) ***")
        pytest.skip("openquake-engine not installed")
    ds = fits("pga")
    path = tmp_path / "fragility_openquake.xml"
    path.write_text(openquake_nrml(ds))
    model = nrml.to_python(str(path))
    for j, block in enumerate(["STAT-01", "COL-0.5"]):
        ff = model[("PGA", block)].build(model.limitStates)[0]
        theta, beta = float(ds["median"].values[j]) / G, float(ds["beta"].values[j])
        x = theta * np.exp(beta * np.linspace(-2.5, 2.5, 11))
        np.testing.assert_allclose(ff(x), norm.cdf(np.log(x / theta) / beta), atol=1e-6)


def test_pelicun_reads_the_damage_model_as_the_fitted_lognormal(tmp_path):
    try:
        from pelicun import uq
        from pelicun.assessment import Assessment
    except ImportError:
        print("\n*** pelicun is not installed: the damage-model CSV is not checked with pelicun "
              "(docs/validation.md has the check made in its own environment) ***")
        pytest.skip("pelicun not installed")
    path = tmp_path / "fragility_pelicun.csv"
    path.write_text(pelicun_csv(fits("pga")))
    ids = ["RS.STAT_01", "RS.COL_0.5"]
    asmnt = Assessment({"PrintLog": False, "Verbose": False})
    asmnt.damage.load_model_parameters([str(path)], ids)
    params = asmnt.damage.ds_model.damage_params
    for cid, theta_g, beta in zip(ids, (0.5, 0.12), (0.4, 0.25)):
        p = params.loc[cid]
        rv = uq.LogNormalRandomVariable("x", theta=np.array([float(p[("LS1", "Theta_0")]),
                                                             float(p[("LS1", "Theta_1")])]))
        demand_g = theta_g * np.array([0.5, 1.0, 2.0])
        np.testing.assert_allclose(rv.cdf(demand_g * G), norm.cdf(np.log(demand_g / theta_g) / beta), atol=1e-9)


def test_the_id_map_says_what_the_curves_are_on():
    ds = fits("pga", component="rotd50")
    ds.attrs["orientation"] = "worst"
    rows = list(csv.DictReader(io.StringIO(ids_csv(ds))))
    assert rows[0] == {"block_id": "STAT-01", "openquake_taxonomy": "STAT-01", "pelicun_component": "RS.STAT_01",
                       "im": "pga", "im_component": "rotd50", "orientation": "worst"}
    assert "worst orientation" in openquake_nrml(ds)
