"""Fidelity tiers and ``screen bench``: each tier does what it says, the bench counts what a run records."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from pipeline.bench import run_bench
from pipeline.blocks import read_inventory
from pipeline.cli import main
from pipeline.config import FIDELITY_TIERS, Config
from pipeline.errors import ConfigError
from pipeline.store import open_results

RECORDS = ("peer-at2/RSN77_SFERN_PUL164.AT2", "peer-at2/RSN6_IMPVALL.I_I-ELC180.AT2", "knet/test.knet",
           "peer-at2/RSN1086_NORTHR_SYL090.AT2", "peer-at2/RSN1086_NORTHR_SYL360.AT2",
           "peer-at2/RSN15_KERN_TAF021.AT2")


@pytest.fixture(scope="module")
def records(tmp_path_factory, records_dir):
    import shutil

    root = tmp_path_factory.mktemp("recs")
    for rel in RECORDS:
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(records_dir / rel, root / rel)
    shutil.copy(records_dir / "units.toml", root)
    return root


@pytest.fixture(scope="module")
def by_tier(records, blocks_csv, tmp_path_factory):
    """One screening per tier of the same records."""
    out = {}
    for tier in FIDELITY_TIERS:
        d = tmp_path_factory.mktemp(tier)
        assert main(["--records", str(records), "--blocks", str(blocks_csv), "--out", str(d), "-q",
                     "--fidelity", tier]) == 0
        out[tier] = open_results(d / "screening.nc")
    return out


def test_criterion_tier_simulates_nothing(by_tier):
    ds = by_tier["criterion"]
    assert (ds.physics.values == -1).all() and (ds.margin_simulations.values == -1).all()
    np.testing.assert_array_equal(ds.overturn.values, ds.overturn_criterion.values)
    assert set(np.unique(ds.verdict_source.values)) <= {-1, 0}
    assert np.isnan(ds.overturn_scale_simulated.values).all()


def test_screen_tier_simulates_exactly_the_ambiguity_band(by_tier):
    ds = by_tier["screen"]
    band = Config().fidelity.band
    scale = ds.criterion_scale.values
    with np.errstate(invalid="ignore", divide="ignore"):
        expected = ~((scale < 1 / band) | (scale > band))
    np.testing.assert_array_equal(ds.physics.values >= 0, expected)
    simulated = ds.verdict_source.values == 1
    np.testing.assert_array_equal(ds.overturn.values[simulated], ds.overturn_simulated.values[simulated])
    np.testing.assert_array_equal(ds.overturn.values[~simulated], ds.overturn_criterion.values[~simulated])
    # where it simulates, it is the full tier's simulation
    full = by_tier["full"]
    np.testing.assert_array_equal(ds.theta_max.values[simulated], full.theta_max.values[simulated])


def test_full_and_reference_tiers_simulate_every_scene(by_tier):
    for tier in ("full", "reference"):
        assert (by_tier[tier].physics.values >= 0).all()
    # the reference tier really integrates with other settings: some theta_max differ, slightly
    diff = np.abs(by_tier["full"].theta_max.values - by_tier["reference"].theta_max.values)
    rocking = by_tier["reference"].theta_max.values > 0
    assert 0 < np.nanmax(diff[rocking]) < 0.05


def test_bench_counts_equal_those_of_a_reference_run(records, blocks_csv, config, by_tier, tmp_path):
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    rows = run_bench(records, inventory, config, out_dir=tmp_path, settings_sweep=False)
    tiers = {r["value"]: r for r in rows if r["section"] == "tier"}
    assert list(tiers) == list(FIDELITY_TIERS)
    ref = by_tier["reference"]
    judged = ref.overturn_simulated.values >= 0
    ref_yes = ref.overturn_simulated.values == 1
    pulse = np.broadcast_to((ref.is_pulse.values == 1)[:, None], ref_yes.shape)
    for tier, ds in by_tier.items():
        yes = ds.overturn.values == 1
        miss, alarm = ref_yes & ~yes, judged & ~ref_yes & yes
        row = tiers[tier]
        assert (row["misses"], row["false_alarms"]) == (int(miss.sum()), int(alarm.sum())), tier
        assert (row["misses_pulse"], row["misses_non_pulse"]) == (int((miss & pulse).sum()),
                                                                  int((miss & ~pulse).sum())), tier
        assert row["scenes_simulated"] == int((ds.physics.values >= 0).sum()), tier
    assert tiers["reference"]["misses"] == tiers["reference"]["false_alarms"] == 0
    with open(tmp_path / "bench.csv", newline="") as fh:
        assert len(list(csv.DictReader(fh))) == len(rows)
    md = (tmp_path / "bench.md").read_text().splitlines()
    assert len(md) == 2 + len(rows)
    assert (tmp_path / "bench.png").read_bytes()[:4] == b"\x89PNG"


def test_bench_settings_sweep_marks_defaults(records, blocks_csv, config, tmp_path):
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu).take(range(4))
    rows = run_bench(records, inventory, config, out_dir=tmp_path)
    settings = {(r["section"], r["setting"].split()[0]) for r in rows}
    assert {("simulation", "rtol"), ("simulation", "rest_ratio"), ("simulation", "max_step_p"),
            ("margin", "margin_step")} <= settings
    defaults = [r for r in rows if "(default)" in r["setting"]]
    assert sorted(r["setting"].split()[0] for r in defaults) == ["margin_step", "max_step_p", "rest_ratio", "rtol"]
    finest = [r for r in rows if r["section"] == "margin" and r["value"] == min(
        x["value"] for x in rows if x["section"] == "margin")]
    assert finest[0]["theta_error_max"] == 0.0                 # the finest step against itself


def test_tier_names_are_checked(blocks_csv, records, capsys):
    assert Config().with_tier("reference").simulation_settings().rtol == Config().fidelity.reference_rtol
    assert Config().simulation_settings() == Config().simulation
    with pytest.raises(ConfigError, match="valid tiers"):
        Config().with_tier("fast")
    with pytest.raises(SystemExit):
        main(["--records", str(records), "--blocks", str(blocks_csv), "--fidelity", "fast"])
    assert "invalid choice: 'fast'" in capsys.readouterr().err
