"""Fidelity tiers and ``screen bench``: each tier does what it says, the bench counts what a run records."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from pipeline.blocks import read_inventory
from pipeline.cli import main
from pipeline.config import FIDELITY_TIERS, Config
from pipeline.errors import ConfigError
from pipeline.run.accuracy import run_bench
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


#: The three screenings of the bundled records that these tests share take about 21 s (once per test worker,
#: with five boxes judged in 3D): the tests join make test-slow (the Makefile's rule: each over 15 s)
BY_TIER_IS_SLOW = pytest.mark.slow


@pytest.fixture(scope="module")
def by_tier(records, blocks_csv, tmp_path_factory):
    """One screening per tier of the same records."""
    out = {}
    for tier in FIDELITY_TIERS:
        d = tmp_path_factory.mktemp(tier)
        assert main(["--samples", "0", "--records", str(records), "--blocks", str(blocks_csv), "--out", str(d), "-q",
                     "--fidelity", tier]) == 0
        out[tier] = open_results(d / "screening.nc")
    return out


@BY_TIER_IS_SLOW
def test_criterion_tier_simulates_nothing(by_tier):
    ds = by_tier["criterion"]
    assert (ds.physics.values == -1).all() and (ds.margin_simulations.values == -1).all()
    np.testing.assert_array_equal(ds.overturn.values, ds.overturn_criterion.values)
    assert set(np.unique(ds.verdict_source.values)) <= {-1, 0}
    assert np.isnan(ds.overturn_scale_simulated.values).all()


@BY_TIER_IS_SLOW
def test_full_tier_integrates_nothing_only_where_the_scene_provably_rests(by_tier, records, config):
    # independent check of the at-rest certificate: the block's demand max |a| / (g + a_v) over every
    # sample, in every plane (the horizontal vector's magnitude bounds all planes), stays at or below
    # min(tan(alpha), mu); recomputed here from the loaded records with numpy
    from pipeline.records.loader import iter_records

    ds = by_tier["full"]
    recs = {r.record_id: r for r in iter_records(records, config=config)}
    tan_a, mu = np.tan(ds.slenderness.values), ds.mu.values
    for i, rid in enumerate(ds.record.values):
        if rid not in recs:
            continue
        rec = recs[rid]
        gv = config.records.g_ms2 + (rec.vertical_ms2 if rec.vertical_ms2 is not None else 0.0)
        vec = np.hypot(*rec.horizontal_ms2) if rec.horizontal_ms2.shape[0] == 2 else np.abs(rec.horizontal_ms2[0])
        for j in range(ds.sizes["block"]):
            if ds.physics.values[i, j] != 0:
                continue
            if ds.orientation.values[i, j] == 0:          # a given plane: its own projection
                az = np.radians(ds.governing_azimuth.values[i, j] - rec.azimuths_deg[0])
                demand = np.abs(np.cos(az) * rec.horizontal_ms2[0] + np.sin(az) * rec.horizontal_ms2[1]) / gv
            else:
                demand = vec / gv
            assert np.all(gv > 0) and demand.max() <= min(tan_a[j], mu[j]) + 1e-12, (rid, ds.block.values[j])
    assert (ds.physics.values == 0).any() and (ds.physics.values > 0).any()


def test_retired_screen_tier_is_refused_with_the_reason(tmp_path):
    with pytest.raises(ConfigError, match="retired.*missed overturnings.*'full'"):
        Config().with_tier("screen")
    bad = tmp_path / "old.toml"
    bad.write_text('[fidelity]\ntier = "screen"\n')
    from pipeline.config import load_config
    with pytest.raises(ConfigError, match="old.toml.*retired"):
        load_config(bad)


@BY_TIER_IS_SLOW
def test_full_and_reference_tiers_simulate_every_scene(by_tier):
    for tier in ("full", "reference"):
        assert (by_tier[tier].physics.values >= 0).all()
    # the reference tier really integrates with other settings: some theta_max differ, slightly (over the scenes
    # with a verdict in both: a scene without one has the peak up to where its model stopped, a step's end)
    diff = np.abs(by_tier["full"].theta_max.values - by_tier["reference"].theta_max.values)
    judged = (by_tier["full"].overturn_simulated.values >= 0) & (by_tier["reference"].overturn_simulated.values >= 0)
    rocking = (by_tier["reference"].theta_max.values > 0) & judged
    assert 0 < np.nanmax(diff[rocking]) < 0.05


@BY_TIER_IS_SLOW
def test_bench_counts_equal_those_of_a_reference_run(records, blocks_csv, config, by_tier, tmp_path):
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    said: list[str] = []
    rows = run_bench(records, inventory, config, out_dir=tmp_path, settings_sweep=False, progress=said.append).rows
    assert [": ".join(x.split(": ")[:2]) for x in said] == [f"bench: section {k} of {len(said)}"
                                                             for k in range(1, len(said) + 1)]
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
    assert tiers["full"]["misses"] == 0                       # the default tier is conservative here
    with open(tmp_path / "bench.csv", newline="") as fh:
        assert len(list(csv.DictReader(fh))) == len(rows)
    md = (tmp_path / "bench.md").read_text().splitlines()
    assert len(md) == 2 + len(rows)
    assert (tmp_path / "bench.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.slow
def test_bench_settings_sweep_marks_defaults(records, blocks_csv, config, tmp_path):
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu).take(range(4))
    said: list[str] = []
    rows = run_bench(records, inventory, config, out_dir=tmp_path, progress=said.append).rows
    # every section is announced with its number, and the count announced is the count run
    total = int(said[0].split(" of ")[1].split(":")[0])
    assert [int(x.split("section ")[1].split(" of ")[0]) for x in said] == list(range(1, total + 1))
    settings = {(r["section"], r["setting"].split()[0]) for r in rows}
    assert {("simulation", "rtol"), ("simulation", "rest_ratio"), ("simulation", "max_step_p"),
            ("margin", "margin_step")} <= settings
    defaults = [r for r in rows if "(default)" in r["setting"]]
    assert sorted(r["setting"].split()[0] for r in defaults) == [
        "closed_form_chatter", "contact_model", "margin_step", "max_step_p", "orientation_step_deg", "rest_ratio",
        "rtol"]
    # a scan of step s brackets a crossing within a factor (1 + s): where overturning is monotonic near the
    # margin, the default step's margin is within about 2 s of the finest one's; most margins are
    default = [r for r in rows if r["section"] == "margin" and "(default)" in r["setting"]][0]
    assert default["theta_error_median"] <= 2 * config.simulation.margin_step
    # the orientation scan and the vertical approximation are measured against the reference
    assert {("orientation", "orientation_step_deg"), ("orientation", "pulse"),
            ("vertical", "vertical_fraction")} <= settings
    scan = [r for r in rows if r["setting"] == "orientation_step_deg (default)"][0]
    axis = [r for r in rows if r["setting"].startswith("pulse axis only")][0]
    assert scan["misses"] == 0 and scan["planes_simulated"] >= axis["planes_simulated"]


def test_tier_names_are_checked(blocks_csv, records, capsys):
    assert Config().with_tier("reference").simulation_settings().rtol == Config().fidelity.reference_rtol
    assert Config().simulation_settings() == Config().simulation
    with pytest.raises(ConfigError, match="valid tiers"):
        Config().with_tier("fast")
    with pytest.raises(SystemExit):
        main(["--samples", "0", "--records", str(records), "--blocks", str(blocks_csv), "--fidelity", "fast"])
    assert "invalid choice: 'fast'" in capsys.readouterr().err


@pytest.mark.slow
def test_criterion_miss_rate_printed_for_the_criterion_tier_is_measured(records_dir, blocks_csv, config, tmp_path,
                                                                        capsys, caplog):
    # the figures quoted to users of --fidelity criterion, re-measured with screen bench on the bundled records
    import re

    from pipeline.config import CRITERION_MEASURED_MISSES

    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    rows = run_bench(records_dir, inventory, config, out_dir=tmp_path, settings_sweep=False).rows
    tier = {r["value"]: r for r in rows if r["section"] == "tier"}
    crit, ref = tier["criterion"], tier["reference"]
    quoted = [int(x) for x in re.findall(r"\d+", CRITERION_MEASURED_MISSES.split("configs/blocks.csv")[1])]
    missed, total, missed_pulse, _, missed_other, _, alarms = quoted[:7]
    assert (crit["misses"], crit["misses_pulse"], crit["misses_non_pulse"], crit["false_alarms"]) == (
        missed, missed_pulse, missed_other, alarms)
    assert tier["full"]["misses"] == 0 and ref["misses"] == 0
    assert main(["--samples", "0", "--records", str(records_dir), "--blocks", str(blocks_csv),
                 "--out", str(tmp_path / "o"), "-q", "--fidelity", "criterion", "--tolerate-failures"]) == 0
    assert "not conservative: " + CRITERION_MEASURED_MISSES in capsys.readouterr().err + caplog.text


# make test keeps under 5 min from a fresh clone; CI runs it in make test-slow
@pytest.mark.slow
def test_bench_names_a_record_that_fails_and_exits_1_unless_told_to_tolerate(records_dir, tmp_path, capsys):
    """A record that cannot be read is left out of the bench with its name and reason; the bench exits 1, and 0
    with --tolerate-failures (as its help says)."""
    import shutil

    rec = tmp_path / "recs"
    rec.mkdir()
    shutil.copy(records_dir / "peer-at2" / "RSN77_SFERN_PUL164.AT2", rec)
    (rec / "broken.AT2").write_text("PEER NGA STRONG MOTION DATABASE RECORD\nnot a record at all\n")
    (tmp_path / "b.csv").write_text("id,height_m,width_m,mu\nC,1.0,0.2,0.6\n")
    args = ["bench", "--records", str(rec), "--blocks", str(tmp_path / "b.csv"), "--tiers-only", "-q"]
    assert main([*args, "--out", str(tmp_path / "o1")]) == 1
    err = capsys.readouterr().err
    assert "record broken failed and is not in the bench" in err
    assert main([*args, "--out", str(tmp_path / "o2"), "--tolerate-failures"]) == 0
    rows = list(csv.DictReader(open(tmp_path / "o2" / "bench.csv")))
    assert rows and rows[0]["scenes"] == "1"                # the good record's one scene was benchmarked
