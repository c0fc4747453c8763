"""Batch screening: re-runs that redo only what changed, locks, faults, executors (serial, processes, Dask).

Every expected value here comes from an independent run: a fresh serial run
into an empty output is the truth that re-runs, partial re-runs and the
other executors must reproduce exactly.
"""

from __future__ import annotations

import errno
import json
import math
import operator
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from handoff import NO_HANDOFF

from pipeline.blocks import read_inventory
from pipeline.cli import EXIT_LOCKED, EXIT_OK, EXIT_OUTPUT, main
from pipeline.records.listing import find_records
from pipeline.records.side_files import read_declared_units
from pipeline.run.batch import _task, plan
from pipeline.run.executors import DaskExecutor, ProcessExecutor, SerialExecutor, TaskLost
from pipeline.run.screening import Context
from pipeline.store import open_results

#: Provenance that differs between two runs by design.
RUN_SPECIFIC = ("screened_utc",)


def assert_same_results(a: xr.Dataset, b: xr.Dataset) -> None:
    """Identical values, dtypes and variable attributes, except run-specific provenance."""
    a, b = a.drop_vars(RUN_SPECIFIC, errors="ignore"), b.drop_vars(RUN_SPECIFIC, errors="ignore")
    a.attrs, b.attrs = {}, {}
    xr.testing.assert_identical(a, b)


def screen(records, blocks, out, *extra) -> int:
    return main([*NO_HANDOFF, "--samples", "0", "--records", str(records), "--blocks", str(blocks), "--out",
                 str(out), "--tolerate-failures", *map(str, extra)])


@pytest.fixture
def few_records(make_records):
    """Six real records of four formats (a quick batch)."""
    return make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2",
                        "peer-at2/RSN77_SFERN_PUL164.AT2", "peer-at2/RSN6_IMPVALL.I_I-ELC180.AT2",
                        "knet/test.knet", "cosmos/CE23837.V1C", "peer-at2/RSN1086_NORTHR_SYL090.AT2",
                        "peer-at2/RSN1086_NORTHR_SYL360.AT2")


@pytest.fixture
def fresh(tmp_path, blocks_csv):
    """A fresh serial run of a records directory into an empty output: the truth."""

    def _fresh(records, blocks=blocks_csv):
        out = tmp_path / f"fresh-{len(list(tmp_path.iterdir()))}"
        assert screen(records, blocks, out) == EXIT_OK
        return open_results(out / "screening.nc")

    return _fresh


def summary_line(capsys) -> str:
    return next(line for line in capsys.readouterr().err.splitlines() if line.startswith("records:"))


def output_bytes(out: Path) -> dict:
    return {name: (out / name).read_bytes() for name in ("screening.nc", "pulses.nc", "histories.nc", "report.html",
                                                          "assets.csv")}


@pytest.fixture
def one_record(make_records):
    """One short record (the up-to-date check does not depend on how many there are)."""
    return make_records("peer-at2/RSN77_SFERN_PUL164.AT2")


def _new_row(csv_text: str, cells: str) -> str:
    """An inventory row of ``cells``, padded with blank cells to the header of ``csv_text``."""
    width = len(csv_text.splitlines()[0].split(","))
    return cells + "," * (width - len(cells.split(",")))

def test_rerun_with_nothing_new_skips_everything_and_says_so(one_record, blocks_csv, tmp_path, capsys):
    out = tmp_path / "out"
    assert screen(one_record, blocks_csv, out) == EXIT_OK
    before = output_bytes(out)
    capsys.readouterr()
    os.utime(next(one_record.rglob("*.AT2")))                 # touched, same content: still nothing new
    assert screen(one_record, blocks_csv, out) == EXIT_OK
    err = capsys.readouterr().err
    assert "up to date:" in err and "nothing was recomputed or rewritten" in err
    assert "1 screened, 0 reused" in err                     # the summary of the run that made the outputs
    assert output_bytes(out) == before


@pytest.mark.slow                    # 6-8 s, three screenings: make test-slow keeps make test under 5 min
def test_any_change_takes_the_full_path(one_record, blocks_csv, tmp_path, capsys):
    """Each change in turn (a file beside the records, the inventory, --samples, an output edited by hand,
    --force) makes the next run take the full path; the same run again is up to date."""
    out = tmp_path / "out"
    assert screen(one_record, blocks_csv, out) == EXIT_OK
    blocks = tmp_path / "blocks.csv"
    new = _new_row(blocks_csv.read_text(), "NEW-1,added drum,2.0,0.4,0.6,,,site,,box")
    blocks.write_text(blocks_csv.read_text() + new + "\n")
    notes = one_record / "notes.txt"
    changes = [("record", lambda: notes.write_text("a note beside the records\n"), blocks_csv, []),
               ("inventory", lambda: None, blocks, []),
               ("samples", lambda: None, blocks, ["--samples", "1"]),
               ("output", lambda: (out / "assets.csv").write_text("edited by hand\n"), blocks, ["--samples", "1"]),
               ("force", lambda: None, blocks, ["--samples", "1", "--force"])]
    for name, change, inventory, extra in changes:
        change()
        capsys.readouterr()
        assert screen(one_record, inventory, out, *extra) == EXIT_OK
        err = capsys.readouterr().err
        assert "up to date:" not in err and "wrote" in err, name
        assert (out / "assets.csv").read_text() != "edited by hand\n", name
        if name != "force":
            assert screen(one_record, inventory, out, *extra) == EXIT_OK
            assert "up to date:" in capsys.readouterr().err, name


def test_up_to_date_run_names_the_failed_records_and_exits_as_the_full_run(make_records, blocks_csv, tmp_path,
                                                                            capsys, caplog):
    records = make_records("peer-at2/RSN77_SFERN_PUL164.AT2",
                           "cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c")
    out = tmp_path / "out"
    args = [*NO_HANDOFF, "--samples", "0", "--records", str(records), "--blocks", str(blocks_csv), "--out", str(out)]
    assert main(args) == 1                                     # one record failed: exit 1
    caplog.clear()
    capsys.readouterr()
    assert main(args) == 1                                     # the same exit, from the manifest
    assert "up to date:" in capsys.readouterr().err
    assert "us1000hyfh" in caplog.text and "vertical component only" in caplog.text
    assert main([*args, "--tolerate-failures", "-q"]) == EXIT_OK
    assert "up to date:" not in capsys.readouterr().err       # -q: warnings and errors only


def test_rerun_reuses_everything_and_changes_nothing(few_records, blocks_csv, tmp_path, capsys):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    first = open_results(out / "screening.nc")
    assert "6 screened, 0 reused" in summary_line(capsys)
    (few_records / "notes.txt").write_text("not a record\n")  # the directory changed: the full path, all reused
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    err = capsys.readouterr().err
    assert "0 screened, 6 reused" in err
    n_blocks = sum(1 for line in blocks_csv.read_text().splitlines()[1:] if line.strip())
    assert f"margins: 0 scanned, {n_blocks} reused" in err   # the margin scans are cached too
    second = open_results(out / "screening.nc")
    assert_same_results(first, second)
    # reused records keep the time they were screened
    assert list(first.screened_utc.values) == list(second.screened_utc.values)


@pytest.mark.slow                    # 4-6 s measured: make test keeps under 5 min from a fresh clone
def test_changed_and_new_records_only_are_screened(few_records, blocks_csv, tmp_path, records_dir, capsys, fresh):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    before = open_results(out / "screening.nc")
    # one record edited in place (a sample changed), one new record arrives
    knet = few_records / "knet" / "test.knet"
    text = knet.read_text().splitlines()
    text[-1] = text[-1].replace(text[-1].split()[0], str(int(text[-1].split()[0]) + 5), 1)
    knet.write_text("\n".join(text) + "\n")
    shutil.copy(records_dir / "peer-at2" / "RSN15_KERN_TAF021.AT2", few_records / "peer-at2")
    capsys.readouterr()
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    assert "2 screened, 5 reused" in summary_line(capsys)
    after = open_results(out / "screening.nc")
    assert after.content_sha256.sel(record="test") != before.content_sha256.sel(record="test")
    assert_same_results(after, fresh(few_records))


@pytest.mark.slow                    # 6-8 s, three screenings: make test-slow keeps make test under 5 min
def test_inventory_edit_rescreens_only_affected_blocks(few_records, blocks_csv, tmp_path, capsys, fresh):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    rows = blocks_csv.read_text().splitlines()
    edited = [rows[0]] + [r.replace(",0.5,90,", ",0.45,90,") if r.startswith("STAT-02") else r
                          for r in rows[2:]] + [_new_row(rows[0], "NEW-1,added column drum,2.0,0.4,0.6,,,site,,box")]
    inv2 = tmp_path / "inventory-edited.csv"
    inv2.write_text("\n".join(edited) + "\n")
    capsys.readouterr()
    assert screen(few_records, inv2, out) == EXIT_OK
    line = summary_line(capsys)
    assert "2 new or changed" in line and "scenes computed: 12" in line   # 2 blocks x 6 records
    assert_same_results(open_results(out / "screening.nc"), fresh(few_records, inv2))


@pytest.mark.slow                    # 4-6 s measured: make test keeps under 5 min from a fresh clone
def test_configuration_change_rescreens_everything(few_records, blocks_csv, tmp_path, capsys):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    cfg = tmp_path / "small-angle.toml"
    cfg.write_text('[criteria]\nform = "small_angle"\n')
    capsys.readouterr()
    assert screen(few_records, blocks_csv, out, "--config", cfg) == EXIT_OK
    assert "6 screened, 0 reused" in summary_line(capsys)
    assert json.loads(open_results(out / "screening.nc").attrs["rockscreen_config"])["criteria"]["form"] == \
        "small_angle"
    # the stale cache entries of the old configuration are pruned after the successful write
    assert len(list((out / ".rockscreen" / "cache").glob("*.npz"))) == 6


@pytest.mark.slow
def test_force_recomputes_all(few_records, blocks_csv, tmp_path, capsys):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    capsys.readouterr()
    assert screen(few_records, blocks_csv, out, "--force") == EXIT_OK
    assert "6 screened, 0 reused" in summary_line(capsys)


def test_vanished_record_keeps_its_results_flagged(few_records, blocks_csv, tmp_path, caplog):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    before = open_results(out / "screening.nc")
    (few_records / "knet" / "test.knet").unlink()
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    after = open_results(out / "screening.nc")
    assert "record test: its files are no longer in" in caplog.text
    assert int(after.source_present.sel(record="test")) == 0
    assert int(after.source_present.sel(record="RSN77_SFERN_PUL164")) == 1
    # identical, screened_utc included (the record was not screened again); global attributes are per run
    kept_before, kept_after = (ds.drop_vars("source_present").sel(record="test") for ds in (before, after))
    kept_before.attrs, kept_after.attrs = {}, {}
    xr.testing.assert_identical(kept_before, kept_after)


def test_file_vanishing_after_the_scan_fails_that_record_alone(few_records, blocks_csv, config):
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    sources, _ = find_records(few_records, config=config)
    gone = next(s for s in sources if s.record_id == "test")
    Path(gone.files[0]).unlink()
    p = plan(sources, inventory, cache=None)
    assert [r.record_id for r in p.failures] == ["test"]
    assert "vanished" in p.failures[0].status and "test.knet" in p.failures[0].status
    assert len(p.tasks) == len(sources) - 1
    ctx = Context(str(few_records), config, inventory, read_declared_units(few_records, config))
    res = _task((gone, None, None), ctx)
    assert res.status.startswith("failed") and "vanished" in res.status


# -- locks, unwritable output, full disk --------------------------------------------------------------

def _write_lock(out: Path, pid: int) -> Path:
    lock = out / ".rockscreen" / "lock"
    lock.parent.mkdir(parents=True)
    lock.write_text(json.dumps({"pid": pid, "host": socket.gethostname(), "started_utc": "2026-11-22T00:00:00Z",
                                "command": "screen --records elsewhere"}))
    return lock


def test_live_lock_refuses_a_second_writer(few_records, blocks_csv, tmp_path, capsys):
    from pipeline.store import OutputLock

    out = tmp_path / "out"
    with OutputLock(out, command="screen --records elsewhere"):       # held by this live process
        assert screen(few_records, blocks_csv, out) == EXIT_LOCKED
    err = capsys.readouterr().err
    assert "another run is writing this output" in err and f"pid {os.getpid()}" in err
    assert not (out / "screening.nc").exists()


def test_screen_report_waits_for_no_one_and_refuses_an_output_being_written(few_records, blocks_csv, tmp_path,
                                                                              capsys):
    """``screen report`` takes the output's lock: run during a screening it refuses (75) instead of pairing a new
    screening.nc with an old assets.csv."""
    from pipeline.store import OutputLock

    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    before = (out / "assets.csv").read_bytes()
    with OutputLock(out, command="screen --records elsewhere"):
        assert main(["report", str(out / "screening.nc")]) == EXIT_LOCKED
    assert "another run is writing this output" in capsys.readouterr().err
    assert (out / "assets.csv").read_bytes() == before
    assert main(["report", str(out / "screening.nc")]) == EXIT_OK and not (out / ".rockscreen" / "lock").exists()


def _race_for_the_lock(out: Path, start, results) -> None:
    from pipeline.errors import OutputLockedError
    from pipeline.store import OutputLock

    start.wait()
    try:
        with OutputLock(out):
            held = time.monotonic()
            time.sleep(0.3)
            results.put(("held", held, time.monotonic()))
    except OutputLockedError:
        results.put(("refused", math.nan, math.nan))


@pytest.mark.parametrize("trial", range(12))
def test_runs_racing_for_a_dead_runs_lock_never_both_hold_it(tmp_path, trial):
    """Four processes start at once on an output whose lock file a dead run left behind: one takes it over, and no
    two ever hold it at the same time (two took it over together in 12 of 300 trials before)."""
    import multiprocessing

    dead = subprocess.Popen(["true"])
    dead.wait()
    out = tmp_path / "out"
    _write_lock(out, dead.pid)
    ctx = multiprocessing.get_context("fork")
    start, results = ctx.Event(), ctx.Queue()
    procs = [ctx.Process(target=_race_for_the_lock, args=(out, start, results)) for _ in range(4)]
    for p in procs:
        p.start()
    start.set()
    for p in procs:
        p.join(timeout=30)
    events = [results.get(timeout=5) for _ in range(4)]
    held = sorted((t0, t1) for kind, t0, t1 in events if kind == "held")
    assert held, events
    assert all(later[0] >= earlier[1] for earlier, later in zip(held, held[1:])), held      # never two at once
    assert not (out / ".rockscreen" / "lock").exists()


def test_lock_of_a_dead_run_is_taken_over(few_records, blocks_csv, tmp_path, caplog):
    dead = subprocess.Popen(["true"])
    dead.wait()
    out = tmp_path / "out"
    lock = _write_lock(out, dead.pid)
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    assert "took over the lock of a run that died" in caplog.text
    assert not lock.exists()                           # released at the end


def test_unwritable_output_is_reported_before_any_work(few_records, blocks_csv, tmp_path, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory")
    assert screen(few_records, blocks_csv, blocker / "out") == EXIT_OUTPUT
    err = capsys.readouterr().err
    assert "output directory is not writable" in err and "Nothing was screened" in err


@pytest.mark.slow                    # 4-6 s measured: make test keeps under 5 min from a fresh clone
def test_disk_full_keeps_previous_results_and_the_work_done(few_records, blocks_csv, tmp_path, capsys,
                                                            monkeypatch):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    previous = (out / "screening.nc").read_bytes()
    cfg = tmp_path / "c.toml"
    cfg.write_text('[criteria]\nform = "small_angle"\n')

    def disk_full(self, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    with monkeypatch.context() as m:
        m.setattr(xr.Dataset, "to_netcdf", disk_full)
        assert screen(few_records, blocks_csv, out, "--config", cfg) == EXIT_OUTPUT
    err = capsys.readouterr().err
    assert "No space left on device" in err and "previous results, if any, are intact" in err
    assert (out / "screening.nc").read_bytes() == previous
    assert not list(out.glob(".*.tmp"))
    # space freed: the next run writes the work already done without screening anything again
    assert screen(few_records, blocks_csv, out, "--config", cfg) == EXIT_OK
    assert "0 screened, 6 reused" in summary_line(capsys)


@pytest.mark.slow                    # 6-8 s, three screenings: make test-slow keeps make test under 5 min
def test_cache_that_cannot_be_written_does_not_stop_the_run(few_records, blocks_csv, tmp_path, monkeypatch,
                                                            caplog, fresh):
    def disk_full(*a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", disk_full)
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    assert "cannot save the scene cache (No space left on device)" in caplog.text
    monkeypatch.undo()
    assert_same_results(open_results(out / "screening.nc"), fresh(few_records))


# -- killed and interrupted runs (a real process, a real signal) --------------------------------------

#: Records of the kill tests: enough, and long enough, that a run is caught mid-way.
KILL_RECORDS = ("RSN1492_CHICHI", "RSN1503_CHICHI", "RSN1505_CHICHI", "RSN1529_CHICHI", "RSN1605_DUZCE",
                "RSN1176_KOCAELI", "RSN1044_NORTHR", "RSN1084_NORTHR")


@pytest.mark.slow
@pytest.mark.parametrize("sig, code", [(signal.SIGKILL, -signal.SIGKILL), (signal.SIGINT, 130), (signal.SIGTERM, 130),
                                       (signal.SIGHUP, 130)])
def test_killed_or_interrupted_run_loses_nothing(records_dir, blocks_csv, tmp_path, config, sig, code):
    out = tmp_path / "out"
    recs = tmp_path / "recs"
    recs.mkdir()
    for f in (records_dir / "peer-at2").iterdir():          # 8 long two- and three-component recordings
        if f.name.startswith(KILL_RECORDS):
            shutil.copy(f, recs / f.name)
    shutil.copy(records_dir / "units.toml", recs)
    n_records = len(find_records(recs, config=config)[0])
    assert screen(recs, blocks_csv, out) == EXIT_OK
    previous = (out / "screening.nc").read_bytes()
    cfg = tmp_path / "c.toml"
    cfg.write_text('[criteria]\nform = "small_angle"\n')       # a new run key: every record is screened again
    cache = out / ".rockscreen" / "cache"
    old_entries = set(cache.glob("*.npz"))
    cmd = [sys.executable, "-m", "pipeline", "--samples", "0", "--records", str(recs), "--blocks", str(blocks_csv),
           "--out", str(out), "--config", str(cfg), "--tolerate-failures"]
    # Ctrl-C reaches a command started from a terminal; a child inherits an *ignored* SIGINT from its parent
    # (a background job, possibly a test worker: one CI run saw the command finish untouched), so the
    # child's disposition is set explicitly
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120
    while len(set(cache.glob("*.npz")) - old_entries) < 2 and time.monotonic() < deadline:
        time.sleep(0.02)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == code, err
    if code == 130:                             # Ctrl-C, and what schedulers send to stop a job (SIGTERM, SIGHUP)
        assert "interrupted:" in err and "will not be screened again" in err
        assert not (out / ".rockscreen" / "lock").exists()
    done = len(set(cache.glob("*.npz")) - old_entries)
    assert 2 <= done < n_records, "the run must be stopped mid-way"
    assert (out / "screening.nc").read_bytes() == previous     # the previous complete result, untouched
    rerun = subprocess.run(cmd, stderr=subprocess.PIPE, text=True, timeout=300)
    assert rerun.returncode == 0, rerun.stderr
    assert f"{n_records - done} screened, {done} reused" in rerun.stderr
    assert json.loads(open_results(out / "screening.nc").attrs["rockscreen_config"])["criteria"]["form"] == \
        "small_angle"


@pytest.mark.slow
@pytest.mark.parametrize("after_s", [0.5, 1.0, 1.5, 2.0, 2.5, 3.0])
def test_ctrl_c_to_the_whole_group_while_the_workers_start(records_dir, blocks_csv, tmp_path, after_s):
    """Ctrl-C from a terminal reaches every process of the command's group: the run's own process, and the pool's
    forkserver and resource tracker while they start and import (the first seconds of a run). The run stops as
    interrupted (130) and no process prints a traceback (the forkserver, interrupted in its imports, printed a
    KeyboardInterrupt's, and a Ctrl-C that Python swallowed in a finalizer let the run finish with 0)."""
    cmd = [sys.executable, "-m", "pipeline", "--samples", "0", "-n", "2", "--records", str(records_dir), "--blocks",
           str(blocks_csv), "--out", str(tmp_path / "out"), "--tolerate-failures", "-q"]
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(after_s)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    # stopped where it was, or (a Ctrl-C Python swallowed in a finalizer, sent again too late to stop it) at its end
    assert ("interrupted:" in err or "interrupted as the command ended:" in err) and "Traceback" not in err, err


# -- executors -----------------------------------------------------------------------------------------

@pytest.fixture
def tasks(few_records, blocks_csv, config):
    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    sources, _ = find_records(few_records, config=config)
    ctx = Context(str(few_records), config, inventory, read_declared_units(few_records, config))
    return [(s, None, None) for s in sources], ctx


def _by_record(pairs) -> dict:
    return {item[0].record_id: res for item, res in pairs}


def assert_same_record_results(a: dict, b: dict) -> None:
    assert sorted(a) == sorted(b)
    for rid in a:
        ra, rb = a[rid], b[rid]
        assert ra.status == rb.status and ra.block_ids == rb.block_ids
        for name in ra.blocks:
            np.testing.assert_array_equal(ra.blocks[name], rb.blocks[name])
        np.testing.assert_equal({k: v for k, v in ra.values.items() if k not in RUN_SPECIFIC},
                                {k: v for k, v in rb.values.items() if k not in RUN_SPECIFIC})


@pytest.mark.slow
def test_process_pool_survives_a_killed_worker(tasks):
    items, ctx = tasks
    with SerialExecutor() as ex:
        serial = _by_record(ex.map_unordered(_task, items, ctx))
    got = []
    with ProcessExecutor(2) as ex:
        for k, pair in enumerate(ex.map_unordered(_task, items, ctx)):
            got.append(pair)
            if k == 0:
                victim = next(iter(ex._pool._processes))
                os.kill(victim, signal.SIGKILL)
    assert_same_record_results(serial, _by_record(got))


def test_a_task_that_always_kills_its_worker_fails_alone():
    """Its neighbours in flight die with the pool too; re-run alone, they succeed and it is isolated."""
    items = [abs] * 6 + [signal.raise_signal] + [abs] * 6      # operator.call(item, SIGKILL)
    with ProcessExecutor(2) as ex:
        out = list(ex.map_unordered(operator.call, items, signal.SIGKILL))
    lost = [item for item, r in out if isinstance(r, TaskLost)]
    assert lost == [signal.raise_signal]
    assert sorted(r for _, r in out if not isinstance(r, TaskLost)) == [int(signal.SIGKILL)] * 12


def test_process_workers_hold_what_dasks_nanny_gives_its_workers():
    """Each worker of the process pool runs with the variables Dask's Nanny sets for its workers at Dask's values
    (one BLAS/OpenMP thread, glibc's trim threshold) and the pool's own (one numba thread, the mmap threshold a trim
    threshold leaves fixed), unless the user set them: then with the user's."""
    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    from pipeline.run.executors import WORKER_ENVIRONMENT

    nanny = {k: str(v) for k, v in dask.config.get("distributed.nanny.pre-spawn-environ").items()}
    assert {k: WORKER_ENVIRONMENT[k] for k in nanny} == nanny
    assert WORKER_ENVIRONMENT["MALLOC_MMAP_THRESHOLD_"] == str(32 * 1024 * 1024)     # glibc's largest adjusted value
    users = {n: os.environ[n] for n in WORKER_ENVIRONMENT if n in os.environ}
    names = tuple(WORKER_ENVIRONMENT) * 3
    with ProcessExecutor(2) as ex:
        seen = list(ex.map_unordered(os.getenv, names, None))
    assert len(seen) == len(names)
    for name, value in seen:
        assert value == users.get(name, WORKER_ENVIRONMENT[name]), name


@pytest.fixture
def dask_cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=":0") as cluster:
        yield cluster


@pytest.mark.slow
def test_dask_scheduler_results_identical_to_serial(few_records, blocks_csv, tmp_path, dask_cluster, fresh,
                                                    capsys):
    out = tmp_path / "out"
    address = dask_cluster.scheduler_address
    assert address.startswith("tcp://127.0.0.1:")
    assert screen(few_records, blocks_csv, out, "--scheduler", address) == EXIT_OK
    assert "dask (2 workers)" in summary_line(capsys)
    assert_same_results(open_results(out / "screening.nc"), fresh(few_records))


@pytest.mark.slow                    # a process pool against serial (7-8 s): make test-slow
def test_processes_results_identical_to_serial(few_records, blocks_csv, tmp_path, fresh):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out, "-n", 2) == EXIT_OK
    assert_same_results(open_results(out / "screening.nc"), fresh(few_records))


@pytest.mark.slow                    # a process pool against serial (7-8 s): make test-slow
def test_default_uses_the_available_cores_with_results_identical_to_serial(make_records, blocks_csv, tmp_path,
                                                                         fresh, capsys, monkeypatch):
    from pipeline.run.executors import default_workers

    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "knet/test.knet")
    serial = fresh(root)                                     # -n 1 (the test default)
    capsys.readouterr()
    monkeypatch.delenv("ROCKSCREEN_NUM_PROCESSES")
    cores = len(os.sched_getaffinity(0))
    assert default_workers() == cores
    out = tmp_path / "default"
    assert screen(root, blocks_csv, out) == EXIT_OK
    executor = "serial (1 worker)" if cores == 1 else f"processes ({cores} workers)"
    assert executor in summary_line(capsys)
    assert_same_results(open_results(out / "screening.nc"), serial)
    monkeypatch.setenv("ROCKSCREEN_NUM_PROCESSES", "zero")
    assert screen(root, blocks_csv, tmp_path / "bad") == 2


@pytest.mark.slow
def test_dask_worker_killed_mid_run_still_gives_complete_results(tasks):
    items, ctx = tasks
    with SerialExecutor() as ex:
        serial = _by_record(ex.map_unordered(_task, items, ctx))
    got = []
    killed = None
    with DaskExecutor("local", n_workers=2) as ex:
        for pair in ex.map_unordered(_task, items, ctx):
            got.append(pair)
            if killed is None:
                busy = [w for w, keys in ex.client.processing().items() if keys]
                if busy:
                    pid = ex.client.run(os.getpid, workers=[busy[0]])[busy[0]]
                    os.kill(pid, signal.SIGKILL)
                    killed = pid
    assert killed is not None, "no worker was busy to kill"
    assert_same_record_results(serial, _by_record(got))


def _worker_environment(names: tuple) -> dict:
    return {n: os.environ.get(n) for n in names}


def _worker_settings(keys: tuple) -> dict:
    import dask

    return {k: dask.config.get(k) for k in keys}


@pytest.mark.slow
def test_dask_local_cluster_workers_run_with_its_quiet_housekeeping():
    """The LocalCluster's workers (not only the process that starts them) hold LOCAL_CLUSTER_CONFIG: the nannies
    hand it on (a worker at Dask's defaults profiles itself every 10 ms), and with it the process workers'
    environment, a variable the user set at the user's value."""
    from pipeline.run.executors import LOCAL_CLUSTER_CONFIG, WORKER_ENVIRONMENT

    with DaskExecutor("local", n_workers=1) as ex:
        seen = ex.client.run(_worker_settings, tuple(LOCAL_CLUSTER_CONFIG))
        environment = ex.client.run(_worker_environment, tuple(WORKER_ENVIRONMENT))
    users = {n: os.environ[n] for n in WORKER_ENVIRONMENT if n in os.environ}
    assert len(seen) == 1
    assert next(iter(seen.values())) == LOCAL_CLUSTER_CONFIG
    assert next(iter(environment.values())) == {n: users.get(n, v) for n, v in WORKER_ENVIRONMENT.items()}


def test_same_name_in_two_directories_stays_two_records(make_records, blocks_csv, tmp_path, capsys):
    # same file name and samples, different bytes (another title line): two records with two ids and cache entries
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2")
    (root / "copy").mkdir()
    lines = (root / "peer-at2" / "RSN77_SFERN_PUL164.AT2").read_text().split("\n")
    (root / "copy" / "RSN77_SFERN_PUL164.AT2").write_text("\n".join([lines[0] + " (copy)"] + lines[1:]))
    out = tmp_path / "out"
    for expected in ("2 screened, 0 reused", "0 screened, 2 reused"):
        if "0 screened" in expected:
            (root / "notes.txt").write_text("not a record\n")    # the directory changed: the full path
        assert screen(root, blocks_csv, out) == EXIT_OK
        assert expected in summary_line(capsys)
        ds = open_results(out / "screening.nc")
        assert sorted(ds.record.values) == ["RSN77_SFERN_PUL164", "RSN77_SFERN_PUL164#2"]
        a, b = (ds.isel(record=k).drop_vars(["record", "files", "screened_utc", "content_sha256"])
                for k in (0, 1))
        xr.testing.assert_identical(a, b)


def test_one_recording_under_two_names_is_screened_once(make_records, blocks_csv, tmp_path, capsys):
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2")
    shutil.copy(root / "peer-at2" / "RSN77_SFERN_PUL164.AT2", root / "PACOIMA_UPPER_LEFT_164.txt")
    out = tmp_path / "out"
    assert screen(root, blocks_csv, out) == EXIT_OK
    err = capsys.readouterr().err
    assert "1 screened" in err and "duplicate" in err and "PACOIMA_UPPER_LEFT_164" in err
    ds = open_results(out / "screening.nc")
    assert list(ds.record.values) == ["PACOIMA_UPPER_LEFT_164"] or list(ds.record.values) == ["RSN77_SFERN_PUL164"]
    assert "PACOIMA_UPPER_LEFT_164" in ds.attrs["duplicate_records"] and "RSN77" in ds.attrs["duplicate_records"]


def test_record_corrupted_since_the_last_run_fails_and_is_not_kept_as_vanished(few_records, blocks_csv,
                                                                                 tmp_path, caplog):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    (few_records / "knet" / "test.knet").write_bytes(b"\x00garbage\x00" * 10)
    assert main([*NO_HANDOFF, "--samples", "0",
                 "--records", str(few_records), "--blocks", str(blocks_csv), "--out", str(out), "-q"]) == 1
    ds = open_results(out / "screening.nc")
    assert list(ds.record.values).count("test") == 1
    status = ds.status.sel(record="test").item()
    assert status.startswith("failed") and "test.knet" in status
    assert "no longer in" not in caplog.text


@pytest.mark.slow                    # 20 s measured (two screenings and a fresh one): make test keeps under 5 min
def test_damaged_cache_entry_is_screened_again(few_records, blocks_csv, tmp_path, capsys, caplog, fresh):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    entry = sorted((out / ".rockscreen" / "cache").glob("*.npz"))[0]
    entry.write_bytes(b"PK\x03\x04 truncated")
    (few_records / "notes.txt").write_text("not a record\n")  # the directory changed: the full path
    capsys.readouterr()
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    assert "1 screened, 5 reused" in summary_line(capsys)
    assert "unreadable scene cache entry" in caplog.text
    assert_same_results(open_results(out / "screening.nc"), fresh(few_records))


@pytest.mark.slow                    # 4-6 s measured: make test keeps under 5 min from a fresh clone
def test_a_cached_record_whose_new_blocks_fail_is_a_failure_with_no_pulse_row(make_records, blocks_csv, tmp_path,
                                                                                 monkeypatch):
    """A record already in the cache (its pulse series shed from memory) that fails when screened for a new
    block: the run completes, the record is failed, and pulses.nc has no row for it."""
    from pipeline.run import batch
    from pipeline.run.screening import RecordResult

    few_records = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "knet/test.knet")
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    inv2 = tmp_path / "inventory-plus.csv"
    new = _new_row(blocks_csv.read_text(), "NEW-1,added drum,2.0,0.4,0.6,,,site,,box")
    inv2.write_text(blocks_csv.read_text() + new + "\n")
    real = batch._task

    def crash_one(item, ctx):
        source = item[0]
        if source.record_id == "test":
            return RecordResult(source.record_id, "failed: unexpected RuntimeError: boom", {"files": "test.knet"})
        return real(item, ctx)

    monkeypatch.setattr(batch, "_task", crash_one)
    assert screen(few_records, inv2, out) == EXIT_OK
    ds = open_results(out / "screening.nc")
    assert str(ds.status.sel(record="test").values).startswith("failed: unexpected RuntimeError")
    pulses = open_results(out / "pulses.nc")
    assert pulses.record_id.values.tolist() == ["RSN77_SFERN_PUL164"]


def test_a_content_failure_is_reported_again_without_screening(make_records, blocks_csv, tmp_path, caplog,
                                                               monkeypatch):
    """A record that fails on its content (vertical only) fails again from the cache, with its reason, and no
    task runs."""
    from pipeline.run import batch

    records = make_records("peer-at2/RSN77_SFERN_PUL164.AT2",
                           "cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c")
    out = tmp_path / "out"
    assert screen(records, blocks_csv, out) == EXIT_OK
    first = open_results(out / "screening.nc")
    caplog.clear()
    calls = []
    real = batch._task
    monkeypatch.setattr(batch, "_task", lambda item, ctx: calls.append(item) or real(item, ctx))
    (records / "notes.txt").write_text("not a record\n")      # the directory changed: the full path
    assert screen(records, blocks_csv, out) == EXIT_OK
    assert calls == []                                          # nothing was screened again
    assert "vertical component only" in caplog.text
    assert "files unchanged since the run that found it" in caplog.text
    assert_same_results(first, open_results(out / "screening.nc"))


def test_results_held_by_a_run_share_the_inventorys_block_keys(blocks_csv, config):
    """Results arriving from workers or the scene cache bring their own copies of the block ids and digests
    (about 180 KB per record at 1000 blocks); the run replaces them by the inventory's own, equal strings."""
    from pipeline.run.batch import _SharedKeys
    from pipeline.run.screening import RecordResult

    inventory = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    share = _SharedKeys(inventory)
    ids, digests = list(inventory.ids), list(inventory.digests())

    def copied(keys):                                  # equal strings, other objects (as after unpickling)
        return tuple("".join(list(k)) for k in keys)

    whole = share(RecordResult("A", "ok", block_ids=copied(ids), block_digests=copied(digests)))
    assert whole.block_ids is share.ids and whole.block_digests is share.digests
    assert list(whole.block_ids) == ids and list(whole.block_digests) == digests
    part = share(RecordResult("B", "ok", block_ids=copied(ids[1:3]) + ("gone",),
                              block_digests=copied(digests[1:3]) + ("x" * 64,)))
    assert part.block_ids == (ids[1], ids[2], "gone") and part.block_digests[:2] == (digests[1], digests[2])
    assert all(a is b for a, b in zip(part.block_ids[:2], share.ids[1:3]))
    assert all(a is b for a, b in zip(part.block_digests[:2], share.digests[1:3]))


def test_the_plan_reads_only_the_keys_of_the_previous_results(one_record, blocks_csv, tmp_path):
    """The previous screening.nc is read for its record status, content and block digests only, not its
    records x blocks arrays."""
    from pipeline.run.batch import PLAN_VARIABLES

    assert main([*NO_HANDOFF, "--samples", "0", "--records", str(one_record), "--blocks", str(blocks_csv),
                 "--out", str(tmp_path), "-q"]) == EXIT_OK
    small = open_results(tmp_path / "screening.nc", variables=PLAN_VARIABLES + ("not_there",))
    whole = open_results(tmp_path / "screening.nc")
    assert set(small.data_vars) == set(PLAN_VARIABLES) and "theta_max" in whole
    for name in PLAN_VARIABLES:
        xr.testing.assert_identical(small[name], whole[name])


# make test keeps under 5 min from a fresh clone; CI runs it in make test-slow
@pytest.mark.slow
def test_a_units_toml_line_recomputes_only_the_records_it_names(make_records, blocks_csv, tmp_path, capsys):
    import re

    records = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", "fn-ascii/rinaldi_fn.dat")
    out = tmp_path / "out"
    args = [*NO_HANDOFF, "--samples", "0", "--records", str(records), "--blocks", str(blocks_csv), "--out", str(out)]
    assert main(args) == 0
    capsys.readouterr()
    units = records / "units.toml"
    units.write_text(units.read_text() + '"nothing/*.dat" = "g"\n')        # names no file: nothing recomputed
    assert main(args) == 0
    m = re.search(r"records: (\d+) ok \((\d+) screened, (\d+) reused", capsys.readouterr().err)
    assert m and (m.group(2), m.group(3)) == ("0", "2")
    units.write_text(units.read_text().replace('"fn-ascii/*_fn.dat" = "cm/s**2"', '"fn-ascii/*_fn.dat" = "mm/s**2"'))
    assert main(args) == 0
    m = re.search(r"records: (\d+) ok \((\d+) screened, (\d+) reused", capsys.readouterr().err)
    assert m and (m.group(2), m.group(3)) == ("1", "1")                    # the file it names, alone


# -- transient failures: a lost worker ------------------------------------------------------------------

def _losing(monkeypatch, victim: str) -> None:
    """The next runs lose the worker of ``victim`` every time (as the OOM killer would)."""
    from pipeline.run import batch
    from pipeline.run.screening import failed_result

    real = batch._task

    def task(item, ctx):
        if item[0].record_id == victim:
            return failed_result(item[0], TaskLost("the worker process died 3 times running this task alone"))
        return real(item, ctx)

    monkeypatch.setattr(batch, "_task", task)


def test_a_lost_worker_never_replaces_a_good_result_of_the_same_inputs(few_records, blocks_csv, tmp_path,
                                                                       monkeypatch, caplog):
    out = tmp_path / "out"
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    before = open_results(out / "screening.nc")
    victim = "RSN77_SFERN_PUL164"
    _losing(monkeypatch, victim)
    assert screen(few_records, blocks_csv, out, "--force") == EXIT_OK        # nothing is lost: nothing failed
    assert f"record {victim} failed: the worker process died" in caplog.text
    assert "the result computed earlier for the same files and configuration is kept" in caplog.text
    after = open_results(out / "screening.nc")
    assert after["status"].sel(record=victim).item() == "ok"
    assert_same_results(after, before)


@pytest.mark.slow
def test_a_run_with_a_lost_worker_is_never_up_to_date(few_records, blocks_csv, tmp_path, monkeypatch, capsys):
    """The first run loses a record's worker (no earlier result to keep): it fails, exit 1; the next run is not
    'up to date' on that failure, it screens the record again."""
    out = tmp_path / "out"
    victim = "RSN77_SFERN_PUL164"
    with monkeypatch.context() as m:
        _losing(m, victim)
        assert main([*NO_HANDOFF, "--samples", "0", "--records", str(few_records), "--blocks", str(blocks_csv), "--out",
                     str(out)]) == 1
    capsys.readouterr()
    assert screen(few_records, blocks_csv, out) == EXIT_OK
    err = capsys.readouterr().err
    assert "up to date" not in err and "1 screened" in err
    assert open_results(out / "screening.nc")["status"].sel(record=victim).item() == "ok"


def _descendants(pid: int) -> set[int]:
    """Every process below ``pid`` (read from /proc)."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_bytes().rsplit(b")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    found, todo = set(), [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            if child not in found:
                found.add(child)
                todo.append(child)
    return found


@pytest.mark.slow
def test_a_run_killed_with_sigkill_leaves_no_process_behind(records_dir, blocks_csv, tmp_path):
    """SIGKILL of the main process (the OOM killer, kill -9): its workers end within seconds, and with them the
    pool's forkserver and resource tracker, so nothing holds the caller's pipes (they were alive 11 minutes
    later, and the caller's wait hung)."""
    from pipeline.run.executors import process_alive

    recs = tmp_path / "recs"
    recs.mkdir()
    for f in (records_dir / "peer-at2").iterdir():
        if f.name.startswith(KILL_RECORDS):
            shutil.copy(f, recs / f.name)
    shutil.copy(records_dir / "units.toml", recs)
    proc = subprocess.Popen([sys.executable, "-m", "pipeline", "--records", str(recs), "--blocks", str(blocks_csv),
                             "--out", str(tmp_path / "out"), "-n", "2", "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    below: set[int] = set()
    while len(below) < 4 and time.monotonic() < deadline:           # tracker, forkserver and two workers
        time.sleep(0.2)
        below = _descendants(proc.pid)
    assert len(below) >= 4, "the pool did not start"
    proc.kill()
    proc.communicate(timeout=30)              # returns once no process holds the pipes: every one has ended
    deadline = time.monotonic() + 15
    while any(process_alive(p) for p in below) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not [p for p in below if process_alive(p)]


# make test keeps under 5 min from a fresh clone; CI runs it in make test-slow
@pytest.mark.slow
def test_margins_split_into_tasks_of_a_few_blocks_give_the_same_margins(few_records, blocks_csv, tmp_path,
                                                                       monkeypatch):
    """The margins of a record's blocks are scanned in tasks of at most MARGIN_TASK_BLOCKS blocks (so that a large
    inventory under few records uses every worker): one block per task gives the same results as the default."""
    from pipeline.run import margins

    whole = tmp_path / "whole"
    assert screen(few_records, blocks_csv, whole) == EXIT_OK
    monkeypatch.setattr(margins, "MARGIN_TASK_BLOCKS", 1)
    split = tmp_path / "split"
    assert screen(few_records, blocks_csv, split) == EXIT_OK
    a, b = open_results(whole / "screening.nc"), open_results(split / "screening.nc")
    governed = [str(r) for r in a["governing_record"].values if str(r)]
    assert max(governed.count(r) for r in governed) >= 2        # a record's blocks were split into tasks
    assert_same_results(a, b)
    assert (whole / "histories.nc").read_bytes() != b"" and \
        open_results(whole / "histories.nc").equals(open_results(split / "histories.nc"))


# each signal's run (5-7 s) in make test-slow, with the other signals' runs: make test keeps under 5 min
@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP])
def test_a_signal_after_the_report_is_written_exits_130(make_records, tmp_path, sig):
    """What a scheduler sends may arrive after the command's last line, while the interpreter winds down (here an
    exit function that takes a second, as a cluster's clean-up may): the process still ends with 130, as documented
    (it ended with 143 or 129, the signal's own death)."""
    recs = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2")
    blocks = tmp_path / "b.csv"
    blocks.write_text("id,height_m,width_m,mu\nTOMB,1.1,0.2,0.65\n")
    console = "import atexit, time; atexit.register(time.sleep, 1.0); from pipeline.cli import main; main()"
    cmd = [sys.executable, "-c", console, "--samples", "0", "--records", str(recs), "--blocks", str(blocks),
           "--out", str(tmp_path / "out")]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert proc.stdout is not None
    for line in proc.stdout:
        if "report.html" in line:                       # the last line: the outputs are complete
            proc.send_signal(sig)
            break
    proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert (tmp_path / "out" / "report.html").is_file()
