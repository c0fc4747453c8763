"""A link planted under the output folder *between* two steps of a publish, while the run holds the lock (past the
guard's check), is never followed: before each file-system step k of a publish, in turn, a folder on the way
(``.rockscreen``, its ``sets``, the current set), the pointer or an output name is swapped for a link into a folder
outside the output that mirrors it, and the publish goes on (or stops, refusing). Every file outside the output
stays byte-identical, and the victim's folders gain nothing."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from planted_links import FIVE, fingerprint, published

from pipeline.errors import OutputError, UnsafeOutputError
from pipeline.store import sets
from pipeline.store.sets import Family

#: The file-system calls a publish makes (each a step a link can be planted before).
STEPS = ("replace", "symlink", "link", "unlink", "mkdir", "rmdir", "open")


def _swap(path: Path, target: Path) -> None:
    """``path`` (a folder or a link) moved aside and replaced by a link to ``target``."""
    path.rename(path.with_name(path.name + ".moved"))
    path.symlink_to(target)


def _current(out: Path) -> Path:
    return out / ".rockscreen" / "sets" / os.readlink(out / ".rockscreen" / "screening.current").split("/", 1)[1]


#: where the link is planted -> how (the output, the victim: a copy of the output's state folder outside it)
PLANTS = {
    "the state folder": lambda out, v: _swap(out / ".rockscreen", v / "state"),
    "the sets folder": lambda out, v: _swap(out / ".rockscreen" / "sets", v / "state" / "sets"),
    "the current set": lambda out, v: _swap(_current(out), v / "state" / "sets" / _current(out).name),
    "the pointer": lambda out, v: (os.unlink(out / ".rockscreen" / "screening.current"),
                                   (out / ".rockscreen" / "screening.current").symlink_to(v / "state" / "sets")),
    "an output name": lambda out, v: (os.unlink(out / "report.html"), (out / "report.html").symlink_to(
        v / "report.html")),
}


def _victim(root: Path, out: Path) -> Path:
    """A folder outside the output holding a copy of its state folder and outputs: what a path followed through a
    planted link would change."""
    v = root / "victim"
    shutil.copytree(out / ".rockscreen", v / "state", symlinks=True)
    for name in FIVE:
        (v / name).write_text(f"the victim's {name}")
    return v


def _names(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


def _publish_planting(monkeypatch, out: Path, victim: Path, plant, at: int) -> int:
    """Publish a new set, planting before the ``at``-th file-system step; the steps the publish took."""
    stage = sets.staging_dir(out, family=Family.SCREENING)
    for name in FIVE:
        (stage / name).write_text(f"new {name}")
    steps: list[int] = []
    planted: list[int] = []
    for fn in STEPS:
        real = getattr(os, fn)

        def wrapped(*args, _real=real, **kwargs):
            if len(steps) == at and not planted:
                planted.append(1)                # the plant's own calls are not steps
                plant(out, victim)
            if planted or len(steps) < at:
                steps.append(1)
            return _real(*args, **kwargs)

        monkeypatch.setattr(os, fn, wrapped)
    try:
        sets.publish(stage, out, list(FIVE))
    except (UnsafeOutputError, OutputError, OSError):
        pass                                  # refusing is fine; following is not
    finally:
        monkeypatch.undo()
    return len(steps)


@pytest.mark.parametrize("where", sorted(PLANTS))
def test_a_link_planted_between_any_two_steps_of_a_publish_is_never_followed(where, tmp_path, monkeypatch):
    at, taken = 0, None
    while taken is None or at <= taken:
        root = tmp_path / f"{at}"
        root.mkdir()
        out = published(root / "out")
        victim = _victim(root, out)
        before, names = fingerprint(victim), _names(victim)
        taken = _publish_planting(monkeypatch, out, victim, PLANTS[where], at)
        assert fingerprint(victim) == before, (where, at)
        assert _names(victim) == names, (where, at, _names(victim) ^ names)
        at += 1
    assert taken > 10                                  # the publish's steps were all tried
