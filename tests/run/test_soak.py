"""Soak: scheduled ``screen`` runs into one output directory, killed at random (SIGKILL or SIGTERM of the run, or
SIGKILL of one of its workers, as the OOM killer does); after each, the directory shows one complete set equal to
an uninterrupted run's: the new one, or the one it showed before. ``make soak`` (about 5 minutes; not in
``make test`` or ``make test-slow``)."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from benchmark_modules import load_benchmark

from pipeline.store.sets import PLAIN_BEFORE_SETS, Family

pytestmark = pytest.mark.soak

PROJECT = Path(__file__).resolve().parents[2]
#: scheduled runs in the soak
RUNS = int(os.environ.get("ROCKSCREEN_SOAK_RUNS", "50"))
#: the latest instant [s] after the start at which a run is killed (an uninterrupted run takes 3-6 s)
KILL_BY_S = 5.0
OUTPUTS = PLAIN_BEFORE_SETS[Family.SCREENING]


def _compare_dirs():
    return load_benchmark("compare_outputs").compare_dirs


def _children(pid: int) -> list[int]:
    try:
        return [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


def _workers(pid: int) -> list[int]:
    """The run's pool workers: the children of its children (the forkserver's), not the forkserver or the
    resource tracker themselves."""
    return [w for c in _children(pid) for w in _children(c)]


def _screen(args: list[str], *, kill: str | None, at_s: float) -> tuple[int, str, bool]:
    """Run ``screen ARGS``, sending ``kill`` at ``at_s``; the exit code, stderr, and whether the kill reached a
    process still running."""
    proc = subprocess.Popen([sys.executable, "-m", "pipeline", *args], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    delivered = False
    if kill is not None:
        try:
            proc.wait(timeout=at_s)
        except subprocess.TimeoutExpired:
            if kill == "worker":
                workers = _workers(proc.pid)
                if workers:
                    os.kill(random.choice(workers), signal.SIGKILL)
                    delivered = True
            else:
                proc.send_signal(signal.SIGKILL if kill == "SIGKILL" else signal.SIGTERM)
                delivered = True
    _, err = proc.communicate(timeout=600)
    return proc.returncode, err, delivered


def _shows(out: Path, ref: Path | None, compare) -> bool:
    """Whether ``out`` shows the set of the uninterrupted run ``ref`` (no outputs at all when None)."""
    if ref is None:
        return not any((out / n).exists() for n in OUTPUTS)
    if not all((out / n).is_file() for n in OUTPUTS):
        return False
    diffs, n = compare(ref, out)
    return not diffs and n == 4


def test_fifty_scheduled_runs_killed_at_random_leave_one_whole_set(make_records, tmp_path):
    compare = _compare_dirs()
    recs = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN77_SFERN_PUL164.AT2",
                        "peer-at2/RSN1176_KOCAELI_YPT060.AT2", "peer-at2/RSN4040_BAM_BAM-L.AT2")
    inventories = {}
    for name, rows in (("a", "TOMB,1.1,0.2,0.65\nCOL,2.0,0.5,0.7\n"),
                       ("b", "TOMB,1.1,0.2,0.65\nCOL,2.0,0.5,0.7\nSTATUE,1.6,0.35,0.6\n")):
        inventories[name] = tmp_path / f"{name}.csv"
        inventories[name].write_text("id,height_m,width_m,mu\n" + rows)
    out = tmp_path / "out"

    def args(inv: str, where: Path) -> list[str]:
        return ["--records", str(recs), "--blocks", str(inventories[inv]), "--out", str(where), "-n", "2", "-q"]

    refs = {}
    for inv in inventories:
        refs[inv] = tmp_path / f"ref-{inv}"
        code, err, _ = _screen(args(inv, refs[inv]), kill=None, at_s=0)
        assert code == 0, err
    rng = random.Random(20261126)
    shown, tally = None, {}
    for run in range(RUNS):
        inv = rng.choice(sorted(inventories))
        kill = rng.choice(["SIGKILL", "SIGTERM", "worker", None])
        at_s = rng.uniform(0.3, KILL_BY_S)
        force = ["--force"] if rng.random() < 0.5 else []        # every record screened again (no cache)
        t0 = time.perf_counter()
        code, err, delivered = _screen(args(inv, out) + force, kill=kill, at_s=at_s)
        now = "new" if _shows(out, refs[inv], compare) else ("previous" if _shows(out, shown, compare) else "neither")
        what = f"{kill} at {at_s:.1f} s" if delivered else "unkilled"
        tally[(what.split()[0], code, now)] = tally.get((what.split()[0], code, now), 0) + 1
        print(f"run {run:2d}: inventory {inv}{' --force' if force else ''}, {what}, exit {code}, "
              f"{time.perf_counter() - t0:.1f} s: shows the {now} set")
        assert now != "neither", (run, kill, code, err[-2000:])
        if code == 0:
            assert now == "new", (run, kill, err[-2000:])
        else:       # a SIGTERM before the command has started its work, or after it has finished, ends it at once
            assert code in (130, -signal.SIGKILL, -signal.SIGTERM), (run, kill, code, err[-2000:])
            assert code != -signal.SIGTERM or kill == "SIGTERM"
        shown = refs[inv] if now == "new" else shown
        time.sleep(1.2)            # the orphan watchdog's poll: a killed run's workers end within it
    code, err, _ = _screen(args("a", out), kill=None, at_s=0)       # the last, uninterrupted run tidies up
    assert code == 0 and _shows(out, refs["a"], compare), err
    assert len(list((out / ".rockscreen" / "sets").iterdir())) == 1
    assert not [p for p in out.iterdir() if p.is_symlink() and not p.exists()]
    print("tally (kill, exit, set shown): runs", dict(sorted(tally.items())))
