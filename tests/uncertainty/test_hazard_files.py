"""Hazard curves as the tools export them (OpenQuake CSV written by OpenQuake itself, USGS JSON, a plain CSV),
zeros and flat stretches, the choice of site and IM, and the horizontal component definitions."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.errors import HazardError
from pipeline.records.intensity import peak_by_component, spectral_acceleration
from pipeline.uncertainty.hazard import Component, HazardCurve, annual_rate, hazard_set
from pipeline.uncertainty.hazard_files import read_hazard

THETA_MS2, BETA = 0.3 * G, 0.4      # a fragility to integrate against


@pytest.fixture(scope="session")
def openquake_csv(data_dir):
    """PGA curves of two sites over 50 years, exported by OpenQuake engine 3.26.2 from the run in
    tests/data/hazard/openquake/job.ini (the command is in that file)."""
    return data_dir / "hazard" / "hazard_curve-mean-PGA_3.csv"


def hand_converted(path, site):
    """The site's row converted by hand: levels from the poe-<g> columns, rates -ln(1 - poe) / 50."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[1]
    row = next(r for r in rows[2:] if r[0] == site)
    levels = np.array([float(c[4:]) for c in header[4:]])
    poe = np.array([float(x) for x in row[4:]])
    keep = poe > 0
    return levels[keep] * G, -np.log(1.0 - poe[keep]) / 50.0


@pytest.mark.parametrize("site", ["MUSEUM", "DEPOT"])
def test_an_openquake_export_gives_the_rate_of_its_hand_converted_curve(openquake_csv, tmp_path, site):
    curve = read_hazard(openquake_csv, im="pga", site=site)
    levels, rates = hand_converted(openquake_csv, site)
    np.testing.assert_allclose(curve.levels, levels, rtol=1e-12)
    np.testing.assert_allclose(curve.rates, rates, rtol=1e-9)      # log(1 - poe) loses digits for a tiny poe
    plain = tmp_path / "plain.csv"
    plain.write_text("pga_g_rotd50,annual_rate\n"
                     + "\n".join(f"{float(a / G)!r},{float(r)!r}" for a, r in zip(levels, rates)))
    expected = annual_rate(read_hazard(plain, im="pga"), THETA_MS2, BETA)
    assert annual_rate(curve, THETA_MS2, BETA) == pytest.approx(expected, rel=1e-9)
    assert curve.component == Component.rotd50 and not curve.component_stated
    assert curve.source_format == "openquake" and site in curve.site


def test_openquake_zeros_end_the_curve_and_are_said(openquake_csv):
    curve = read_hazard(openquake_csv, im="pga", site="DEPOT")
    assert np.all(curve.rates > 0)
    assert any("the curve ends there" in n for n in curve.notes)


def test_openquake_several_sites_need_a_choice_that_is_listed(openquake_csv):
    with pytest.raises(HazardError, match=r"2 sites and none chosen.*MUSEUM, DEPOT"):
        read_hazard(openquake_csv, im="pga")
    with pytest.raises(HazardError, match="no site 'GARDEN'; sites: MUSEUM, DEPOT"):
        read_hazard(openquake_csv, im="pga", site="GARDEN")
    near = read_hazard(openquake_csv, im="pga", lonlat=(12.88, 42.21))
    assert near.site.startswith("DEPOT") and "km from the given point" in near.site


def test_openquake_imt_must_match(openquake_csv):
    with pytest.raises(HazardError, match="holds IMT PGA, not pgv"):
        read_hazard(openquake_csv, im="pgv", site="MUSEUM")


def test_saturated_probabilities_are_dropped(tmp_path):
    path = tmp_path / "hazard_curve-mean-PGA_1.csv"
    path.write_text('#,,,,,"generated_by=\'OpenQuake engine 3.26.2\', kind=\'mean\', investigation_time=50.0, '
                    'imt=\'PGA\'"\nlon,lat,depth,poe-0.0100000,poe-0.1000000,poe-0.2000000,poe-0.4000000\n'
                    "0.0,0.0,0.0,1.000000E+00,6.321205E-01,6.321205E-01,1.0E-02\n")
    curve = read_hazard(path, im="pga")
    np.testing.assert_allclose(curve.levels, np.array([0.1, 0.2, 0.4]) * G)
    assert curve.rates[0] == pytest.approx(0.02, rel=1e-6) and curve.rates[0] == curve.rates[1]
    assert any("saturated" in n for n in curve.notes) and any("flat segment" in n for n in curve.notes)


def usgs_json(tmp_path, *, maxdir=False, imts=("PGA", "SA1P0")):
    curves = []
    for k, imt in enumerate(imts):
        curves.append({"imt": {"display": imt, "value": imt}, "data": [
            {"component": "Total", "values": {"xs": [0.01, 0.1, 0.3, 1.0, 3.0],
                                             "ys": [2e-2 / (k + 1), 3e-3, 4e-4, 1e-5, 0.0]}},
            {"component": "Fault", "values": {"xs": [0.01, 0.1], "ys": [1.0, 0.5]}}]})
    doc = {"name": "Hazard Curves", "status": "success", "request": {"maxdir": maxdir, "imts": list(imts)},
           "response": {"metadata": {"xlabel": "Ground Motion (g)", "ylabel": "Annual Frequency of Exceedance"},
                        "hazardCurves": curves}}
    path = tmp_path / "usgs.json"
    path.write_text(json.dumps(doc))
    return path


def test_usgs_json_is_read_as_annual_rates_with_its_component(tmp_path):
    curve = read_hazard(usgs_json(tmp_path), im="pga")
    np.testing.assert_allclose(curve.levels, np.array([0.01, 0.1, 0.3, 1.0]) * G)
    np.testing.assert_allclose(curve.rates, [2e-2, 3e-3, 4e-4, 1e-5])
    assert curve.component == Component.rotd50
    assert read_hazard(usgs_json(tmp_path, maxdir=True), im="pga").component == Component.rotd100
    sa = read_hazard(usgs_json(tmp_path), im="sa")
    assert sa.period_s == 1.0 and sa.rates[0] == pytest.approx(1e-2)


def test_usgs_json_with_several_sa_asks_for_the_period(tmp_path):
    path = usgs_json(tmp_path, imts=("SA0P2", "SA1P0"))
    with pytest.raises(HazardError, match=r"2 SA curves \(SA0P2, SA1P0\)"):
        read_hazard(path, im="sa")
    assert read_hazard(path, im="sa", period_s=0.2).period_s == 0.2
    with pytest.raises(HazardError, match="no PGV curve; the file holds SA0P2, SA1P0"):
        read_hazard(path, im="pgv")


def test_a_flat_stretch_adds_nothing_to_the_rate(tmp_path):
    """Equal rates over [0.1, 0.2] g: no motion exceeds 0.1 g without exceeding 0.2 g, so the rate of
    overturning equals that of the curve that starts at 0.2 g."""
    flat, short = tmp_path / "flat.csv", tmp_path / "short.csv"
    flat.write_text("pga_g,annual_rate\n0.1,1e-2\n0.2,1e-2\n0.4,1e-3\n0.8,1e-4\n")
    short.write_text("pga_g,annual_rate\n0.2,1e-2\n0.4,1e-3\n0.8,1e-4\n")
    a, b = read_hazard(flat, im="pga"), read_hazard(short, im="pga")
    assert annual_rate(a, THETA_MS2, BETA) == pytest.approx(annual_rate(b, THETA_MS2, BETA), rel=1e-12)


def test_the_component_must_match_the_fit_or_the_conversion_be_stated(tmp_path):
    rotd50 = HazardCurve("pga", np.array([1.0, 2.0]), np.array([1e-2, 1e-3]), "h.csv", component=Component.rotd50,
                         component_stated=True)
    with pytest.raises(HazardError, match="the hazard is rotd50, the fragility is fitted on rotd100"):
        hazard_set([rotd50], im="pga", fit_component=Component.rotd100)
    converted = hazard_set([rotd50], im="pga", fit_component=Component.rotd100, scale=1.2).curves[0]
    np.testing.assert_allclose(converted.levels, [1.2, 2.4])
    assert converted.component == Component.rotd100 and "1.2" in converted.notes[-1]
    # a curve that states no definition, in a format without a usual one, is an error naming the fix (a 25 %
    # difference in TOMB-01's rate came from taking such a file as RotD100 in silence)
    unstated = HazardCurve("pga", np.array([1.0, 2.0]), np.array([1e-2, 1e-3]), "h.csv")
    with pytest.raises(HazardError, match="h.csv: the hazard curve does not state its horizontal component.*"
                                          "--hazard-component"):
        hazard_set([unstated], im="pga", fit_component=Component.rotd50)
    stated = hazard_set([unstated.with_component(Component.rotd50, stated=True)], im="pga",
                        fit_component=Component.rotd50).curves[0]
    assert stated.component == Component.rotd50


def test_each_block_takes_the_sa_curve_of_the_nearest_period():
    curves = [HazardCurve("sa", np.array([1.0, 2.0]), np.array([1e-2, 1e-3]), f"sa{T}.csv", period_s=T,
                          component=Component.rotd100, component_stated=True) for T in (0.2, 1.0, 3.0)]
    hz = hazard_set(curves, im="sa", fit_component=Component.rotd100)
    for period, expected in ((0.25, 0.2), (0.9, 1.0), (1.7, 1.0), (1.75, 3.0), (10.0, 3.0)):   # sqrt(3) between
        curve, ratio = hz.for_block(period)
        assert curve.period_s == expected and ratio == pytest.approx(expected / period)
    with pytest.raises(HazardError, match="without its period"):
        hazard_set([HazardCurve("sa", np.array([1.0, 2.0]), np.array([1e-2, 1e-3]), "x.csv")], im="sa",
                   fit_component=Component.rotd100)


def polarized(angle_deg, amplitude=1.0, n=4001):
    t = np.linspace(0.0, 20.0, n)
    s = amplitude * np.sin(2 * np.pi * 0.7 * t) * np.exp(-0.1 * t)
    a = math.radians(angle_deg)
    return np.vstack([s * math.cos(a), s * math.sin(a)]), t[1] - t[0]


@pytest.mark.parametrize("angle", [0.0, 30.0, 72.0])
def test_component_definitions_of_a_polarized_motion(angle):
    """A motion along one direction: RotD100 is its peak A, RotD50 A cos 45 deg (the median of A |cos| over the
    directions), the larger component A max(|cos|, |sin|), the geometric mean A sqrt(|cos sin|)."""
    h, dt = polarized(angle)
    A = float(np.max(np.hypot(h[0], h[1])))
    c, s = abs(math.cos(math.radians(angle))), abs(math.sin(math.radians(angle)))
    assert peak_by_component(h, "rotd100") == pytest.approx(A, rel=1e-12)
    assert peak_by_component(h, "rotd50") == pytest.approx(A / math.sqrt(2), rel=2e-4)
    assert peak_by_component(h, "larger") == pytest.approx(A * max(c, s), rel=1e-12)
    assert peak_by_component(h, "geomean") == pytest.approx(A * math.sqrt(c * s), rel=1e-12)
    # a linear oscillator keeps the polarization: Sa's definitions scale the same way
    sa100 = spectral_acceleration(h, dt, 0.5)
    assert spectral_acceleration(h, dt, 0.5, component="rotd50") == pytest.approx(sa100 / math.sqrt(2), rel=2e-4)


def test_a_circular_motion_has_the_same_peak_in_every_direction():
    t = np.linspace(0.0, 10.0, 20001)
    h = np.vstack([np.cos(2 * np.pi * t), np.sin(2 * np.pi * t)])
    assert peak_by_component(h, "rotd50") == pytest.approx(peak_by_component(h, "rotd100"), rel=1e-4)


def test_a_block_far_from_the_nearest_sa_period_is_warned_of():
    import xarray as xr

    from pipeline.run.fragility_assembly import stripe_warnings
    ds = xr.Dataset({"scale_factor": (("record", "im_level", "block"), np.ones((1, 2, 2))),
                     "n_records": (("block", "im_level"), np.ones((2, 2), dtype=int)),
                     "block_period": (("block",), np.array([1.0, 2.0])),
                     "hazard_period": (("block",), np.array([1.0, 1.0])),
                     "hazard_period_ratio": (("block",), np.array([1.0, 0.5]))},
                    coords={"block": ["NEAR", "FAR"], "record": ["r"], "im_level": [1.0, 2.0]},
                    attrs={"im": "sa", "im_units": "m s-2"})
    warnings = stripe_warnings(ds)
    assert len(warnings) == 1 and warnings[0].startswith("block FAR: its Sa period is 2 s") and "0.50" in warnings[0]
