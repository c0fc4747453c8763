"""Output sets published as one unit: a real SIGKILL at every file-system step of a publish leaves the previous
complete set or the new one, and the next publish recovers; plain files of an older rockscreen are adopted."""

from __future__ import annotations

import os
import shutil
import signal
from pathlib import Path

import pytest
from small_run import one_record_run

from pipeline.errors import OutputError
from pipeline.store import sets
from pipeline.store.sets import Family

#: the file-system calls a publish makes (each one a step at which the test kills it)
STEPS = ((os, "replace"), (os, "symlink"), (os, "link"), (os, "unlink"), (shutil, "rmtree"), (shutil, "copy2"))

FIVE = ("screening.nc", "pulses.nc", "histories.nc", "report.html", "assets.csv")


def view(out: Path, names=FIVE) -> dict:
    """What a reader of ``out`` sees: each name's text, or None when absent."""
    return {n: (out / n).read_text() if (out / n).is_file() else None for n in names}


def stage_set(out: Path, contents: dict, family=Family.SCREENING) -> Path:
    stage = sets.staging_dir(out, family=family)
    for name, text in contents.items():
        (stage / name).write_text(text)
    return stage


def steps_counted(monkeypatch, on_step) -> None:
    """Route every file-system mutation of a publish through ``on_step`` first (patched on the modules
    themselves: a publish calls them as ``os.replace``, ``shutil.rmtree``, ...)."""
    for module, fn in STEPS:
        real = getattr(module, fn)

        def wrapped(*args, _real=real, **kwargs):
            on_step()
            return _real(*args, **kwargs)

        monkeypatch.setattr(module, fn, wrapped)


def scenario(kind: str, out: Path) -> tuple[dict, dict]:
    """Lay out ``out`` before a publish; returns (the set a reader sees now, the staged set's contents)."""
    out.mkdir()
    if kind == "plain files of an older rockscreen":
        for n in FIVE:
            (out / n).write_text(f"plain {n}")
        new = {n: f"new {n}" for n in FIVE}
    else:
        first = {n: f"old {n}" for n in (FIVE if kind != "a set grows" else FIVE[:2])}
        sets.publish(stage_set(out, first), out, list(first))
        new = {n: f"new {n}" for n in (FIVE if kind != "a set shrinks" else FIVE[:3])}
    return view(out), new


KINDS = ("plain files of an older rockscreen", "a set replaces a set", "a set shrinks", "a set grows")


def count_steps(kind: str, tmp: Path, monkeypatch) -> int:
    out = tmp / "count"
    _, new = scenario(kind, out)
    stage = stage_set(out, new)
    calls = []
    with monkeypatch.context() as m:
        steps_counted(m, lambda: calls.append(1))
        sets.publish(stage, out, list(new))
    return len(calls)


@pytest.mark.parametrize("kind", KINDS)
def test_a_sigkill_at_every_step_of_a_publish_leaves_one_whole_set(kind, tmp_path, monkeypatch):
    n_steps = count_steps(kind, tmp_path, monkeypatch)
    assert n_steps >= 3
    seen = set()
    for k in range(n_steps + 1):
        out = tmp_path / f"k{k}"
        before, new = scenario(kind, out)
        stage = stage_set(out, new)
        pid = os.fork()
        if pid == 0:                                     # the child publishes, and is killed before step k
            try:
                calls = []

                def step(calls=calls, k=k):
                    if len(calls) == k:
                        os.kill(os.getpid(), signal.SIGKILL)
                    calls.append(1)

                steps_counted(monkeypatch, step)
                sets.publish(stage, out, list(new))
            finally:
                os._exit(0)
        _, status = os.waitpid(pid, 0)
        killed = os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL
        assert killed == (k < n_steps), (k, status)
        after = view(out)
        expected_new = {n: new.get(n) for n in FIVE}
        assert after in (before, expected_new), (k, after)
        seen.add("new" if after == expected_new else "old")
        # the next publish recovers: the newest set, no link to nothing, one set directory, no temporaries
        newest = {n: f"newest {n}" for n in FIVE[:4]}
        sets.publish(stage_set(out, newest), out, list(newest))
        assert view(out) == {n: newest.get(n) for n in FIVE}
        assert not [p for p in out.iterdir() if p.is_symlink() and not p.exists()]
        assert len(list((out / ".rockscreen" / "sets").iterdir())) == 1
        assert not list(out.rglob("*.tmp"))
    assert seen == {"old", "new"}            # the kills fell on both sides of the switch


def test_each_family_keeps_its_own_set_in_one_directory(tmp_path):
    out = tmp_path / "out"
    sets.publish(stage_set(out, {"screening.nc": "s1"}), out, ["screening.nc"])
    sets.publish(stage_set(out, {"fragility.nc": "f1"}, Family.FRAGILITY), out, ["fragility.nc"])
    sets.publish(stage_set(out, {"screening.nc": "s2"}), out, ["screening.nc"])
    assert (out / "screening.nc").read_text() == "s2" and (out / "fragility.nc").read_text() == "f1"
    assert sorted(p.name.split(".")[0] for p in (out / ".rockscreen" / "sets").iterdir()) == ["fragility",
                                                                                             "screening"]
    assert "published" in sets.describe(out, Family.SCREENING)
    assert sets.describe(tmp_path / "nothing", Family.SCREENING) == ""


def test_a_failed_switch_leaves_the_previous_set_and_removes_the_stage(tmp_path, monkeypatch):
    out = tmp_path / "out"
    sets.publish(stage_set(out, {n: "old" for n in FIVE[:2]}), out, list(FIVE[:2]))
    stage = stage_set(out, {n: "new" for n in FIVE})
    real = os.replace

    def refuse_pointer(src, dst, **kw):
        if str(dst).endswith(sets.POINTER_SUFFIX):
            raise OSError(28, "No space left on device", str(dst))
        return real(src, dst, **kw)

    monkeypatch.setattr(sets.os, "replace", refuse_pointer)
    with pytest.raises(OutputError, match="previous results are intact"):
        sets.publish(stage, out, list(FIVE))
    monkeypatch.undo()
    assert view(out) == {n: ("old" if n in FIVE[:2] else None) for n in FIVE}
    assert not stage.exists()
    assert not [p for p in out.iterdir() if p.is_symlink() and not p.exists()]


def test_a_stage_missing_a_file_publishes_nothing(tmp_path):
    out = tmp_path / "out"
    stage = stage_set(out, {"screening.nc": "x"})
    with pytest.raises(OutputError, match="lacks report.html"):
        sets.publish(stage, out, ["screening.nc", "report.html"])
    assert view(out) == {n: None for n in FIVE}


def test_carry_keeps_the_files_a_partial_set_does_not_replace(tmp_path):
    out = tmp_path / "out"
    sets.publish(stage_set(out, {n: f"old {n}" for n in FIVE}), out, list(FIVE))
    stage = sets.staging_dir(out, family=Family.SCREENING)
    kept = sets.carry(stage, out, FIVE[:3])
    (stage / "report.html").write_text("new report")
    (stage / "assets.csv").write_text("new assets")
    sets.publish(stage, out, [*kept, "report.html", "assets.csv"])
    assert view(out) == {**{n: f"old {n}" for n in FIVE[:3]}, "report.html": "new report",
                         "assets.csv": "new assets"}


def test_an_output_directory_moved_whole_keeps_its_outputs(tmp_path):
    """The links are relative: a directory moved (or copied with its links) still shows its set."""
    out = tmp_path / "out"
    sets.publish(stage_set(out, {"screening.nc": "s"}), out, ["screening.nc"])
    moved = tmp_path / "elsewhere"
    shutil.move(out, moved)
    assert (moved / "screening.nc").read_text() == "s"


# --- each command's publish, killed at every step (slow: a real command per case) ---------------------------

KILLER = Path(__file__).resolve().parents[1] / "support" / "publish_killer.py"


def killed_at_every_step(args: list[str], tmp_path: Path) -> list[dict]:
    """Run ``screen ARGS`` under :mod:`publish_killer`; every publish it made, with what each kill left."""
    import json
    import subprocess
    import sys

    report = tmp_path / f"kills-{len(list(tmp_path.glob('kills-*')))}.json"
    proc = subprocess.run([sys.executable, str(KILLER), str(report), *args], capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    publishes = json.loads(report.read_text())
    assert publishes, "the command published nothing"
    for pub in publishes:
        kills = pub["kills"]
        assert len(kills) >= 4 and not kills[-1]["killed"] and all(k["killed"] for k in kills[:-1])
        for k in kills:
            assert k["old"] or k["new"], k                          # one whole set, never a mix or none
            assert k["recovered"] and len(k["set_dirs"]) == 1, k      # the next publish finishes the job
            assert not k["dangling"] and not k["temporaries"], k
        assert kills[0]["old"] and kills[-1]["new"]
        assert any(k["old"] for k in kills[1:]) and any(k["new"] and k["killed"] for k in kills), \
            "the kills fell on both sides of the switch"
    return publishes


def _plain_files_of_an_older_rockscreen(out: Path) -> None:
    """What a rockscreen before output sets left: plain files, no sets."""
    for p in out.iterdir():
        if p.is_symlink():
            data = p.read_bytes()
            p.unlink()
            p.write_bytes(data)
    for p in (out / ".rockscreen").iterdir():
        if p.is_symlink() and p.name.endswith(".current"):
            p.unlink()
        elif p.name == "sets":
            shutil.rmtree(p)


@pytest.mark.slow
def test_screen_and_screen_report_killed_at_every_step_of_their_publish(make_records, tmp_path):
    from pipeline.cli import main

    recs = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN77_SFERN_PUL164.AT2")
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    a.write_text("id,height_m,width_m,mu\nTOMB,1.1,0.2,0.65\nCOL,2.0,0.5,0.7\n")
    b.write_text("id,height_m,width_m,mu\nTOMB,1.1,0.2,0.65\nCOL,2.0,0.5,0.7\nSTATUE,1.6,0.35,0.6\n")
    out = tmp_path / "out"
    base = ["--samples", "0", "--records", str(recs), "--out", str(out), "-q"]
    assert main([*base, "--blocks", str(a)]) == 0
    killed_at_every_step([*base, "--blocks", str(b)], tmp_path)                  # a set over a set
    _plain_files_of_an_older_rockscreen(out)
    killed_at_every_step([*base, "--blocks", str(a), "--force"], tmp_path)       # a set over plain files
    killed_at_every_step(["report", str(out / "screening.nc"), "--all-figures"], tmp_path)  # a new report, rest kept


@pytest.mark.slow
def test_screen_fragility_killed_at_every_step_of_its_publish(make_records, tmp_path):
    from pipeline.cli import main

    recs = make_records("peer-at2/RSN1176_KOCAELI_YPT060.AT2", "peer-at2/RSN4040_BAM_BAM-L.AT2")
    blocks = tmp_path / "b.csv"
    blocks.write_text("id,height_m,width_m,mu\nTOMB,1.1,0.2,0.65\nCOL,2.0,0.5,0.7\n")
    args = ["fragility", "--records", str(recs), "--blocks", str(blocks), "--im", "pga", "--samples", "0",
            "--bootstrap", "10", "--out", str(tmp_path / "out"), "-q"]
    assert main([*args, "--levels", "0.1g,0.3g,0.6g"]) == 0
    killed_at_every_step([*args, "--levels", "0.1g,0.3g,0.6g,1.0g"], tmp_path)


@pytest.mark.slow
def test_screen_event_killed_at_every_step_of_its_publish(data_dir, tmp_path):
    from test_event import ACTUAL, _fragility, _inventory, _node_rows

    from pipeline.cli import main

    grid = data_dir / "shakemaps" / ACTUAL
    rows = _node_rows(grid)
    inv = _inventory(tmp_path / "b.csv", [("A", 1.0, 0.2, 0.6, "", "s", rows[37][0], rows[37][1]),
                                          ("B", 2.0, 0.5, 0.7, "", "s", rows[80][0], rows[80][1])])
    frag = _fragility(tmp_path / "frag", ["A", "B"], median_g=[0.3, 0.5], beta=[0.4, 0.5])
    args = ["event", "--shakemap", str(grid), "--blocks", str(inv), "--fragility", str(frag),
            "--out", str(tmp_path / "out"), "-q"]
    assert main(args) == 0
    _fragility(tmp_path / "frag", ["A", "B"], median_g=[0.2, 0.9], beta=[0.4, 0.5])     # new fits: a new set
    killed_at_every_step(args, tmp_path)


def test_an_output_directory_copied_through_its_links_publishes_again(tmp_path):
    """``cp -r`` and ``shutil.copytree`` follow the links: the copy has plain files and a pointer that is a
    directory; the next publish there makes it a set again (and the original is untouched)."""
    out = tmp_path / "out"
    sets.publish(stage_set(out, {n: f"old {n}" for n in FIVE}), out, list(FIVE))
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    assert (copy / ".rockscreen" / "screening.current").is_dir()
    assert not (copy / ".rockscreen" / "screening.current").is_symlink()
    sets.publish(stage_set(copy, {n: f"new {n}" for n in FIVE[:4]}), copy, list(FIVE[:4]))
    assert view(copy) == {**{n: f"new {n}" for n in FIVE[:4]}, "assets.csv": None}
    assert (copy / ".rockscreen" / "screening.current").is_symlink()
    assert len(list((copy / ".rockscreen" / "sets").iterdir())) == 1
    assert view(out) == {n: f"old {n}" for n in FIVE}


def test_a_full_disk_mid_write_exits_3_named_and_leaves_no_staged_set(make_records, tmp_path, monkeypatch, capsys):
    """netCDF4 reports a write that found the disk full as ``RuntimeError: NetCDF: HDF error``: the run exits 3
    naming the file and the free space, the previous set is what a reader sees, and no staged set is left behind
    (failed runs on a full disk used to pile them up)."""
    import xarray as xr

    from pipeline.cli import main

    run, out = one_record_run(make_records, tmp_path)
    before = {n: (out / n).read_bytes() for n in FIVE}

    def full(self, *args, **kwargs):
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full)
    capsys.readouterr()
    assert main([*run, "--force"]) == 3
    err = capsys.readouterr().err
    assert ".nc: writing failed (NetCDF: HDF error;" in err and "bytes free on that disk" in err, err
    assert "Free disk space" in err
    assert {n: (out / n).read_bytes() for n in FIVE} == before
    assert len(list((out / ".rockscreen" / "sets").iterdir())) == 1
