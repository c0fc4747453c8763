"""The README's figures from the bundled run are the run's: its classes, and the rows of assets.csv it quotes
(stations overturning, margin, p, the sliding distance), checked against `screen` on the bundled records as
`make demo` runs it, so that they cannot drift from what the command prints."""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pytest

from pipeline.cli import main
from pipeline.store import open_results

README = Path(__file__).resolve().parents[1] / "README.md"


@pytest.fixture(scope="module")
def demo(tmp_path_factory, records_dir, blocks_csv):
    out = tmp_path_factory.mktemp("demo")
    assert main(["--records", str(records_dir), "--blocks", str(blocks_csv), "--out", str(out), "-q",
                 "--tolerate-failures"]) == 0
    with open(out / "assets.csv") as f:
        return open_results(out / "screening.nc"), {r["block"]: r for r in csv.DictReader(f)}


@pytest.mark.slow                   # the bundled default run, about 35 s on 2 cores
def test_the_readmes_classes_are_the_runs(demo):
    ds, _ = demo
    quoted = re.search(r"robust_stand (\d+), sensitive (\d+), robust_overturn (\d+)", README.read_text())
    assert quoted is not None
    ok = ds["status"].values == "ok"
    classes = ds["robustness"].values[ok]
    meanings = dict(zip(ds["robustness"].attrs["flag_meanings"].split(), ds["robustness"].attrs["flag_values"]))
    got = tuple(int(np.sum(classes == meanings[name])) for name in ("robust_stand", "sensitive", "robust_overturn"))
    assert got == tuple(int(x) for x in quoted.groups())


@pytest.mark.slow
def test_the_readmes_rows_of_assets_csv_are_the_runs(demo):
    _, rows = demo
    text = README.read_text()
    quoted = re.findall(r"^\| \d+ \| [A-Z]+-[\w.]+ .*$", text, flags=re.M)
    assert len(quoted) >= 3                                      # the worked example's rows
    for line in quoted:
        cells = [c.strip() for c in line.strip("|").split("|")]
        block = cells[1].split()[0]
        row = rows[block]
        over, screened = re.match(r"(\d+) of (\d+)", cells[3]).groups()
        assert (row["stations_overturning"], row["stations_screened"]) == (over, screened), block
        margin = float(row["overturn_scale_simulated"] or "nan")
        assert cells[4] == ("-" if not np.isfinite(margin) else f"{margin:.2f}"), block
        assert f"{float(row['p_overturn']):.2f}" == cells[2].split(",")[0].strip(), block
        assert row["recommendation"].split(":")[0] == cells[5].split(":")[0], block
        slid = re.search(r"slides ([\d.]+) m", cells[5])
        assert slid is None or slid.group(1) in row["recommendation"], block


@pytest.fixture(scope="module")
def stacks_demo(tmp_path_factory, records_dir):
    out = tmp_path_factory.mktemp("assemblies")
    blocks = Path(__file__).resolve().parents[1] / "examples" / "assemblies" / "blocks.csv"
    assert main(["--records", str(records_dir), "--blocks", str(blocks), "--out", str(out), "-q",
                 "--tolerate-failures"]) == 0
    with open(out / "assets.csv") as f:
        return {r["block"]: r for r in csv.DictReader(f)}


@pytest.mark.slow                   # the bundled default run of the stacks' example, about 25 s on 2 cores
def test_the_readmes_stacks_are_the_runs(stacks_demo):
    """The worked example's sentence on the stacks: records overturning each, and the margins it quotes."""
    text = " ".join(README.read_text().split())
    quoted = re.search(r"statue on its plinth falls under (\d+) of the (\d+) records, alone on the floor under (\d+), "
                       r"yet on its plinth (\d+\.\d+) of (\S+) overturns it, alone (\d+\.\d+) of (\S+); the top drum "
                       r"of a two-drum column falls under (\d+) records and at (\d+\.\d+) of (\S+), the column as one "
                       r"block under (\d+) and at (\d+\.\d+) of (\S+) \(as one block, a stack is judged wrong both "
                       r"ways\); of a three-drum column, the top drum under (\d+) records, the lowest under (\d+)\.",
                       text)
    assert quoted is not None

    def margin(row: dict) -> tuple[str, str]:
        return (f"{float(row['overturn_scale_simulated']):.2f}",
                row["recommendation"].split("overturns under ")[1].split(" scaled")[0])

    statue, alone, drum, column = (stacks_demo[b] for b in ("STAT-05", "STAT-05-ALONE", "DRUM-2", "COLUMN-AS-ONE"))
    got = (statue["records_overturning"], statue["records_screened"], alone["records_overturning"], *margin(statue),
           *margin(alone), drum["records_overturning"], *margin(drum), column["records_overturning"],
           *margin(column), stacks_demo["COL3-3"]["records_overturning"], stacks_demo["COL3-1"]["records_overturning"])
    assert got == quoted.groups()
