"""Links planted under an output directory, as an attacker with write access to a shared results folder would plant
them, and the first touches of a command (the lock, a publish, the preparation): shared by the guard's tests."""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

from pipeline.run.cache import ensure_writable
from pipeline.store import OutputLock, sets
from pipeline.store.sets import Family

FIVE = ("screening.nc", "pulses.nc", "histories.nc", "report.html", "assets.csv")


def published(out: Path) -> Path:
    """An output as a run leaves it: a published set, the caches, a lock file of a run that died."""
    out.mkdir()
    stage = sets.staging_dir(out, family=Family.SCREENING)
    for name in FIVE:
        (stage / name).write_text(f"results {name}")
    sets.publish(stage, out, list(FIVE))
    state = out / ".rockscreen"
    for folder in ("cache", "figures", "margins"):
        (state / folder).mkdir()
        (state / folder / "entry.npz").write_bytes(b"cached")
    (state / "lock").write_text("{}")
    return out


def victim(root: Path) -> Path:
    """A folder outside the output that a planted link points at: its files must survive every command."""
    v = root / "victim"
    (v / "sub").mkdir(parents=True)
    (v / "keep.txt").write_text("keep")
    (v / "report.html").write_text("mine")
    (v / "sub" / "x.txt").write_text("x")
    return v


def fingerprint(folder: Path) -> dict:
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _replace_with_link(path: Path, target: Path) -> None:
    if path.is_symlink() or path.is_file():
        path.unlink()
    elif path.is_dir():
        shutil.rmtree(path)
    path.symlink_to(target)


def _current_set(out: Path) -> Path:
    return (out / ".rockscreen" / "screening.current").resolve()


#: where a link can be planted -> how (the output, the victim folder)
PLANTS = {
    "state directory": lambda out, v: _replace_with_link(out / ".rockscreen", v),
    "cache": lambda out, v: _replace_with_link(out / ".rockscreen" / "cache", v),
    "figures": lambda out, v: _replace_with_link(out / ".rockscreen" / "figures", v),
    "margins": lambda out, v: _replace_with_link(out / ".rockscreen" / "margins", v),
    "sets": lambda out, v: _replace_with_link(out / ".rockscreen" / "sets", v),
    "lock": lambda out, v: _replace_with_link(out / ".rockscreen" / "lock", v / "keep.txt"),
    "pointer": lambda out, v: _replace_with_link(out / ".rockscreen" / "screening.current", v),
    "pointer out by ..": lambda out, v: _replace_with_link(out / ".rockscreen" / "screening.current",
                                                           Path("sets") / ".." / ".." / ".." / "victim"),
    "a set directory": lambda out, v: _replace_with_link(_current_set(out), v),
    "a file in the set": lambda out, v: _replace_with_link(_current_set(out) / "report.html", v / "report.html"),
    "a cache entry": lambda out, v: _replace_with_link(out / ".rockscreen" / "cache" / "entry.npz", v / "keep.txt"),
    "an output name": lambda out, v: _replace_with_link(out / "report.html", v / "report.html"),
    "a file as the state directory": lambda out, v: (shutil.rmtree(out / ".rockscreen"),
                                                     (out / ".rockscreen").write_text("not a directory")),
}

#: what touches the output -> the call (each takes the lock, publishes, or prepares the output)
ACTIONS = {
    "lock": lambda out: OutputLock(out, command="test").acquire().release(),
    "publish": lambda out: sets.publish(_staged(out), out, ["report.html"]),
    "prepare": lambda out: ensure_writable(out),
}


def _staged(out: Path) -> Path:
    stage = out.parent / "elsewhere-stage"              # staged outside: the staging dir itself may be refused
    stage.mkdir(exist_ok=True)
    (stage / "report.html").write_text("new")
    return stage
