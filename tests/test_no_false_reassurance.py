"""A run that screened nothing never reassures: every asset is "not screened" with the reason (never "no
action"), the run exits 1 whatever the flags, and the report opens with what failed and the fix (the units.toml
lines as a code block)."""

from __future__ import annotations

import csv
import html
import shutil

import pytest

INVENTORY = "id,height_m,width_m,mu\nCOL,2.0,0.4,0.7\nCRATE,0.5,1.0,0.4\n"


@pytest.fixture(scope="module")
def all_failed(records_dir, tmp_path_factory):
    from pipeline.cli import main

    tmp = tmp_path_factory.mktemp("all-failed")
    root = tmp / "records"
    root.mkdir()
    for path in (records_dir / "fn-ascii").glob("*.dat"):     # their units are stated only in records/units.toml
        shutil.copy(path, root / path.name)
    inv = tmp / "blocks.csv"
    inv.write_text(INVENTORY)
    out = tmp / "out"
    code = main(["--records", str(root), "--blocks", str(inv), "--out", str(out), "-q", "--tolerate-failures"])
    return code, out, root


def test_a_run_that_screened_nothing_exits_1_even_when_failures_are_tolerated(all_failed):
    code, _out, _root = all_failed
    assert code == 1


def test_every_asset_is_not_screened_never_no_action(all_failed):
    _code, out, _root = all_failed
    rows = list(csv.DictReader((out / "assets.csv").open()))
    assert [r["block"] for r in rows] == ["COL", "CRATE"] or [r["block"] for r in rows] == ["CRATE", "COL"]
    for r in rows:
        assert r["recommendation"].startswith("not screened: no record was screened (3 failed")
    assert "no action:" not in (out / "report.html").read_text()


def test_the_report_opens_with_the_failures_and_the_units_lines_to_paste(all_failed):
    _code, out, root = all_failed
    page = html.unescape((out / "report.html").read_text())
    failures, banner = page.index('id="failures"'), page.index('id="what-records-represent"')
    assert failures < banner
    block = page[failures:banner]
    assert "No record was screened" in block
    assert f"<code>{root / 'units.toml'}</code>" in block
    assert "<pre><code>[files]\n" in block and '"*_fn.dat" = "cm/s**2"' in block


def test_screen_report_takes_the_run_folder_and_keeps_not_screened(all_failed):
    from pipeline.cli import main

    _code, out, _root = all_failed
    (out / "report.html").unlink()
    assert main(["report", str(out), "-q"]) == 0
    assert "not screened: no record was screened" in (out / "report.html").read_text()


def test_a_misspelt_subcommand_gets_the_intended_one(capsys):
    from pipeline.cli import main

    assert main(["fragilty"]) == 2
    assert "did you mean 'screen fragility'?" in capsys.readouterr().err
