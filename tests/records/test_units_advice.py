"""Units advice that works when pasted: the lines a failed run prints go into units.toml as they are."""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest

from pipeline.errors import UnitsError
from pipeline.records.listing import find_records
from pipeline.records.loader import load_record
from pipeline.records.side_files import read_declared_units
from pipeline.records.units import common_glob, plausible_units, suggest_declarations

G = 9.80665


@pytest.mark.parametrize("names, glob", [
    (["a.HNE.sac", "a.HNN.sac", "a.HNZ.sac"], "a.HN?.sac"),
    (["lucerne_fn.dat", "rinaldi_fn.dat", "sylmar_fn.dat"], "*_fn.dat"),
    (["only.dat"], "only.dat"),
])
def test_common_glob(names, glob):
    assert common_glob(names) == glob


def test_glob_is_not_used_when_it_would_catch_another_file():
    failing = {"x/a1.dat": "g", "x/a2.dat": "g"}
    assert suggest_declarations(failing, ["x/a1.dat", "x/a2.dat"]) == ['"x/a?.dat" = "g"']
    # a third file that states its own units would be caught by the glob: the files are listed one by one
    assert suggest_declarations(failing, ["x/a1.dat", "x/a2.dat", "x/a3.dat"]) == ['"x/a1.dat" = "g"',
                                                                                   '"x/a2.dat" = "g"']


@pytest.mark.parametrize("peak, first", [(0.021, "g"), (890.0, "cm/s**2"), (2.0e5, None)])
def test_plausible_units_reads_the_peak(peak, first):
    data = np.array([0.0, peak, -peak / 2, 0.0]) + 7.0        # an offset, as raw files carry
    found = plausible_units(data, g_ms2=G)
    assert (found[0][0] if found else None) == first


def test_declaration_outside_the_files_table_is_an_error(tmp_path, config):
    (tmp_path / "units.toml").write_text('"lucerne_fn.dat" = "cm/s**2"\n')
    with pytest.raises(UnitsError, match=r"outside the \[files\] table.*\n\[files\]"):
        read_declared_units(tmp_path, config)


def test_a_record_names_every_file_that_needs_a_declaration(make_records, config):
    root = make_records(*(f"sac/20190706031952.CJ.T001230.HN{c}.sac" for c in "ENZ"), units_toml=False)
    with pytest.raises(UnitsError) as info:
        load_record(find_records(root, config=config)[0][0], root=root, config=config)
    text = str(info.value)
    assert "HNN.sac" in text and "HNZ.sac" in text
    assert '[files]\n"sac/20190706031952.CJ.T001230.HN?.sac" = "g"' in text


@pytest.mark.slow
def test_pasted_advice_makes_every_record_load(tmp_path, records_dir, blocks_csv, config):
    """The bundled records are byte copies of ../shared/records with a units.toml added: without it, the run
    prints lines; pasted as they are into units.toml, no record fails. The real units (SOURCES.md) are g for the
    CSN SAC files and cm/s**2 for the near-fault ASCII files."""
    root = tmp_path / "recs"
    shutil.copytree(records_dir, root, ignore=shutil.ignore_patterns("units.toml"))

    def run(out: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "pipeline", "--records", str(root), "--blocks", str(blocks_csv),
                               "--out", str(tmp_path / out), "--fidelity", "criterion", "--samples", "0", "-n", "1",
                               "--tolerate-failures"], capture_output=True, text=True, check=True)

    first = run("a").stderr
    summary = first[first.index("\nunits: records failed"):]         # the run's summary, after the warnings
    printed = summary[summary.index("\n[files]\n") + 1:].split("\n")
    lines = ["[files]"] + [ln for ln in printed[1:] if ln.startswith('"')]
    assert len(lines) == 3, first
    (root / "units.toml").write_text("\n".join(lines) + "\n")
    second = run("b").stderr
    failed = [ln for ln in second.splitlines() if " failed: " in ln]
    assert failed == [], second
    assert read_declared_units(root, config) == {"fn-ascii/*_fn.dat": "cm/s**2",
                                                 "sac/20190706031952.CJ.T001230.HN?.sac": "g"}
