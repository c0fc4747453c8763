"""Station coordinates read from the bundled records' own headers (or their StationXML), against the values their
headers print (copied here by hand), and none where a format carries none."""

from __future__ import annotations

import pytest

from pipeline.config import Config
from pipeline.records.listing import find_records
from pipeline.records.loader import station_of
from pipeline.records.side_files import read_inventory

#: record id -> (lat, lon) as the file prints it, and the header it comes from
EXPECTED = {
    "CE23837": (34.063, -117.785, "COSMOS"),                      # "Coords: 34.063  -117.785"
    "CE58667": (37.973, -122.038, "DMG"),                         # "Station No. 58667   37.973N, 122.038W"
    "CICLC": (35.816, -117.598, "DMG"),                           # "Station Id. CLC     35.816N, 117.598W"
    "AOM0170806140843": (40.6363, 139.9284, "K-NET"),             # "Station Lat. 40.6363", "Station Long. 139.9284"
    "20190706031952.CJ.T001230.HN": (34.063694, -118.336334, "SAC"),   # stla, stlo (float32)
    "CI.CCC..HN": (35.52495, -117.36453, "StationXML"),           # CI.CCC.xml <Latitude>, <Longitude>
}


@pytest.fixture(scope="module")
def located(records_dir):
    inventory = read_inventory(records_dir / "mseed")
    return {src.record_id: station_of(src, inventory) for src in find_records(records_dir, config=Config())[0]}


@pytest.mark.parametrize("record_id", sorted(EXPECTED))
def test_the_station_is_where_the_header_says(located, record_id):
    lat, lon, where = EXPECTED[record_id]
    station = located[record_id]
    assert station is not None
    assert station.lat == pytest.approx(lat, abs=1e-5) and station.lon == pytest.approx(lon, abs=1e-5)
    assert where in station.source


@pytest.mark.parametrize("record_id", ["RSN1063_NORTHR_RRS", "rinaldi_fn"])
def test_formats_without_coordinates_give_none(located, record_id):
    assert located[record_id] is None
