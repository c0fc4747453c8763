"""Hypothesis: garbage and truncations of real files fail alone, with a reason, never a crash."""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from pipeline.blocks import read_inventory
from pipeline.config import Config
from pipeline.records.listing import find_records
from pipeline.records.side_files import read_declared_units
from pipeline.run.screening import Context, failure_result, screen_record

RECORDS = Path(__file__).resolve().parents[2] / "records"
BLOCKS = Path(__file__).resolve().parents[2] / "configs" / "blocks.csv"
GOOD = "peer-at2/RSN77_SFERN_PUL164.AT2"
REAL = ["peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/NGA_no_1063_RRS228.AT2",
        "cosmos/CE23837.V1C", "dmg/CE58667.V2", "dmg/CICLC.v1", "knet/test.knet",
        "fn-ascii/rinaldi_fn.dat", "sac/20190706031952.CJ.T001230.HNE.sac", "mseed/CI.CCC..HNE.mseed"]
SUFFIXES = [".AT2", ".V1C", ".V2", ".v1", ".dat", ".sac", ".mseed", ".NS", ""]


def _screen_dir(root: Path) -> dict[str, str]:
    config = Config()
    sources, failures = find_records(root, config=config)
    ctx = Context(str(root), config, read_inventory(BLOCKS, default_mu=0.6),
                  read_declared_units(root, config))
    results = [failure_result(f) for f in failures] + [screen_record(s, ctx) for s in sources]
    return {r.record_id: r.status for r in results}


def _with_bad_file(name: str, content: bytes) -> dict[str, str]:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "peer-at2").mkdir()
        shutil.copy(RECORDS / GOOD, root / GOOD)
        shutil.copy(RECORDS / "units.toml", root / "units.toml")
        (root / name).write_bytes(content)
        return _screen_dir(root)


def _check(statuses: dict[str, str]) -> None:
    assert statuses["RSN77_SFERN_PUL164"] == "ok"
    for rid, status in statuses.items():
        assert status == "ok" or (status.startswith("failed: ") and len(status) > 20), (rid, status)
        assert "unexpected" not in status, (rid, status)


@pytest.mark.slow
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(content=st.binary(max_size=3000), suffix=st.sampled_from(SUFFIXES))
def test_random_bytes_fail_alone(content, suffix):
    _check(_with_bad_file("junk" + suffix, content))


@pytest.mark.slow
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rel=st.sampled_from(REAL), fraction=st.floats(0.0, 0.999))
@example(rel="knet/test.knet", fraction=0.008489300046130447)   # cut inside the header: a trace with no samples
def test_truncated_real_files_fail_alone(rel, fraction):
    data = (RECORDS / rel).read_bytes()
    cut = data[: int(len(data) * fraction)]
    _check(_with_bad_file("cut_" + Path(rel).name, cut))


@settings(max_examples=30, deadline=None)
@given(position=st.integers(5, 400), token=st.sampled_from(["NaN", "inf", "-inf", "1.0.0", "--"]))
def test_bad_tokens_in_at2(position, token):
    lines = (RECORDS / GOOD).read_text().splitlines()
    row = min(4 + position, len(lines) - 1)
    fields = lines[row].split()
    fields[0] = token
    lines[row] = "  ".join(fields)
    statuses = _with_bad_file("bad_tok.AT2", ("\n".join(lines) + "\n").encode())
    _check(statuses)
    assert statuses["bad_tok"] != "ok"


def test_all_nan_record_is_reported():
    lines = (RECORDS / GOOD).read_text().splitlines()
    lines = lines[:4] + ["   NaN   NaN   NaN   NaN   NaN"] * ((4172 + 4) // 5)
    statuses = _with_bad_file("allnan.AT2", ("\n".join(lines) + "\n").encode())
    assert "NaN" in statuses["allnan"]
