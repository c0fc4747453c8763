"""Run a ``screen`` command and kill its output set's publish at every step (a test harness, not a test).

Usage: ``python tests/support/publish_killer.py REPORT.json SCREEN_ARGS...``

When the command publishes, the harness copies the output directory as it is, then for each file-system step
k = 0, 1, ... of the publish (every ``os.replace``, ``os.symlink``, ``os.link``, ``os.unlink``, ``shutil.rmtree``
and ``shutil.copy2`` it makes, those inside ``rmtree`` too) forks a child that runs the real publish and sends
itself SIGKILL just before step k. After each child it records what a reader of the output directory sees, then
publishes the same set again from the state the kill left (the next run's recovery) and records that too, then
puts the directory back as it was. When a child finishes unkilled, every step has been tried; the command then
publishes for real and exits as it would. The record of every kill goes to REPORT.json for the test to judge.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import sys
from pathlib import Path

from pipeline.cli import main
from pipeline.run import stages
from pipeline.store import sets

STEPS = ((os, "replace"), (os, "symlink"), (os, "link"), (os, "unlink"), (shutil, "rmtree"), (shutil, "copy2"))


def view(out: Path, names) -> dict:
    """Each name's SHA-256 as a reader of ``out`` sees it, or None when absent."""
    return {n: hashlib.sha256((out / n).read_bytes()).hexdigest() if (out / n).is_file() else None
            for n in sorted(names)}


def kill_before_step(k: int) -> None:
    """In a child: SIGKILL just before the publish's k-th file-system call."""
    calls = []
    for module, fn in STEPS:
        real = getattr(module, fn)

        def wrapped(*args, _real=real, **kwargs):
            if len(calls) == k:
                os.kill(os.getpid(), signal.SIGKILL)
            calls.append(1)
            return _real(*args, **kwargs)

        setattr(module, fn, wrapped)


def restore(out: Path, pristine: Path) -> None:
    shutil.rmtree(out)
    shutil.copytree(pristine, out, symlinks=True)


def judged_publish(report_path: Path, real_publish):
    def publish(stage, out_dir, names, **kwargs):
        stage, out, names = Path(stage), Path(out_dir), list(names)
        family = sets.Family(stage.name.split(".", 1)[0])
        every = set(names) | set(sets.PLAIN_BEFORE_SETS[family]) | {p.name for p in out.iterdir()
                                                                     if not p.name.startswith(".")}
        old = view(out, every)
        new = {n: (hashlib.sha256((stage / n).read_bytes()).hexdigest() if n in names else None) for n in old}
        pristine = out.parent / f".{out.name}.pristine"
        shutil.copytree(out, pristine, symlinks=True)
        kills, k = [], 0
        while True:
            pid = os.fork()
            if pid == 0:
                try:
                    kill_before_step(k)
                    real_publish(stage, out, names, **kwargs)
                finally:
                    os._exit(0)
            _, status = os.waitpid(pid, 0)
            killed = os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL
            seen = view(out, every)
            again = sets.staging_dir(out, family=family)
            for n in names:
                shutil.copy2(pristine / stage.relative_to(out) / n, again / n)
            real_publish(again, out, names, **kwargs)
            kills.append({"step": k, "killed": killed, "old": seen == old, "new": seen == new,
                          "recovered": view(out, every) == new,
                          "set_dirs": sorted(p.name for p in (out / ".rockscreen" / "sets").iterdir()
                                             if p.name.startswith(family.value + ".")),
                          "dangling": sorted(p.name for p in out.iterdir() if p.is_symlink() and not p.exists()),
                          "temporaries": sorted(str(p.relative_to(out)) for p in out.rglob("*.tmp"))})
            restore(out, pristine)
            if not killed:
                break
            k += 1
        shutil.rmtree(pristine)
        doc = json.loads(report_path.read_text()) if report_path.exists() else []
        report_path.write_text(json.dumps(doc + [{"family": family.value, "names": names, "kills": kills}]))
        return real_publish(stage, out, names, **kwargs)

    return publish


if __name__ == "__main__":
    report = Path(sys.argv[1])
    wrapped = judged_publish(report, sets.publish)
    sets.publish = wrapped                 # publish_staged (fragility, event, ...) calls it from there
    stages.publish = wrapped               # screen and screen report import it by name
    sys.exit(main(sys.argv[2:]))
