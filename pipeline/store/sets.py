"""Output sets published as one unit: a versioned directory and one atomic switch of a pointer.

A command writes its outputs into a new set directory, ``OUT/.rockscreen/sets/<family>.<id>/`` (made by
:func:`staging_dir`), then :func:`publish` switches the pointer ``OUT/.rockscreen/<family>.current`` (a symbolic
link) to it with one ``rename``. Each output ``OUT/<name>`` is a fixed symbolic link to
``.rockscreen/<family>.current/<name>``, so every name changes at the instant of that one rename: a reader, or a
run killed at any instant (SIGKILL, a power cut after the fsyncs), sees the previous complete set or the new
complete set, never a mix, and never none where a set was.

The steps of :func:`publish`, each of which leaves the set a reader sees unchanged until the switch:

1. an output that is still a plain file (written by a rockscreen before output sets, or put there by hand) is
   hard-linked into the current set and replaced by its link (same content, one rename each);
2. a link is made for each new name (it points into the current set, where the name does not exist yet: the name
   reads as absent, as it was);
3. the switch: one rename of the pointer;
4. the links of names that the new set does not have (they now point at nothing) are removed, and every set
   directory but the current one (the previous set, and sets a killed run staged) is deleted.

A run killed between steps 3 and 4 leaves links to nothing and old directories behind; the next publish removes
them. Call :func:`publish` under the output's lock (:class:`pipeline.store.OutputLock`): step 4 deletes what no
pointer names.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import secrets
import shutil
import signal
import threading
import time
from enum import Enum
from pathlib import Path
from typing import Callable

from ..constants import STATE_DIR
from ..errors import InterruptedAfterPublishing, OutputError
from .guard import POINTER_SUFFIX, SETS, check_output_tree

log = logging.getLogger(__name__)

class Family(Enum):
    """The output sets of the commands; an output directory may hold one set of each."""

    #: ``screen`` (and ``screen report``, which replaces the report and keeps the rest)
    SCREENING = "screening"
    #: ``screen fragility``
    FRAGILITY = "fragility"
    #: ``screen event``
    EVENT = "event"
    #: ``screen bench``
    BENCH = "bench"
    #: ``screen infer``
    INFERENCE = "inference"
    #: ``screen constrain``
    CONSTRAINT = "constraint"


#: The files each command wrote as plain files before output sets: found in place, they are adopted into the
#: family's set (and removed when a new set lacks them), so that no stale one is left beside a new set
PLAIN_BEFORE_SETS = {
    Family.SCREENING: ("screening.nc", "pulses.nc", "histories.nc", "report.html", "assets.csv"),
    Family.FRAGILITY: ("fragility.nc", "fragility.html", "fragility_assets.csv", "fragility_openquake.xml",
                       "fragility_pelicun.csv", "fragility_ids.csv"),
    Family.EVENT: ("event.nc", "inspection.csv", "event.html", "shakecast-facilities.xml"),
    Family.BENCH: ("bench.csv", "bench.md", "bench.png"),
    Family.INFERENCE: ("infer.nc", "infer.png"),
    Family.CONSTRAINT: (),
}

#: What each set directory records of itself (family, names, when it was published, the command)
SET_RECORD = "set.json"
#: The staging directory of rockscreen before output sets (removed when found)
OLD_STAGING = "staging"


#: The signals a command treats as Ctrl-C (:data:`pipeline.cli.exits.INTERRUPT_SIGNALS` and SIGINT): held while an
#: output set is swapped, so that none of them leaves half a set.
HELD_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


@contextlib.contextmanager
def signals_held():
    """Hold Ctrl-C, SIGTERM and SIGHUP while the block runs (the renames of :func:`publish`, milliseconds): one that
    arrives meanwhile is noted, and raised again, to the handler it would have met, when the block ends. In the
    main thread only (Python handles signals there). SIGKILL cannot be held: a run killed mid-swap leaves the set
    its renames reached."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = {sig: signal.signal(sig, lambda signum, frame: received.append(signum)) for sig in HELD_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        for signum in dict.fromkeys(received):
            signal.raise_signal(signum)


def state_dir(out_dir: str | Path) -> Path:
    return Path(out_dir) / STATE_DIR


def pointer(out_dir: str | Path, family: Family | str) -> Path:
    """The pointer ``OUT/.rockscreen/<family>.current`` (a symbolic link to the current set directory)."""
    return state_dir(out_dir) / f"{_name(family)}{POINTER_SUFFIX}"


def staging_dir(out_dir: str | Path, *, family: Family) -> Path:
    """A new, empty set directory for ``out_dir``'s next ``family`` output set (same file system: the switch is
    one rename). Nothing reads it until :func:`publish` switches to it.

    Raises
    ------
    OutputError
        When the directory cannot be made.
    """
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    stage = state_dir(out_dir) / SETS / f"{family.value}.{stamp}-{os.getpid()}-{secrets.token_hex(3)}"
    try:
        stage.mkdir(parents=True)
    except OSError as exc:
        raise OutputError(f"{stage}: cannot stage results here ({exc.strerror or exc}); choose another --out "
                          "directory or fix its permissions") from exc
    return stage


def carry(stage: str | Path, out_dir: str | Path, names) -> list[str]:
    """Hard-link (or copy, where links are refused) the outputs ``names`` that ``out_dir`` shows now into
    ``stage``, for a set that replaces some outputs and keeps the others; returns the names carried."""
    carried = []
    for name in names:
        src = Path(out_dir) / name
        if not src.is_file():
            continue
        try:
            _link_or_copy(src.resolve(), Path(stage) / name)
        except OSError as exc:
            raise OutputError(f"{src}: cannot carry it into the new output set ({exc.strerror or exc}); free disk "
                              "space or fix the directory's permissions") from exc
        carried.append(name)
    return carried


def publish(stage: str | Path, out_dir: str | Path, names, *, command: str = "") -> list[Path]:
    """Make the set staged in ``stage`` (by :func:`staging_dir`; it holds ``names``) the outputs of ``out_dir``, in
    one atomic switch (see the module's description of the steps).

    Returns
    -------
    list of Path
        ``out_dir / name`` for each of ``names``.

    Raises
    ------
    OutputError
        When a file is missing from the stage, or a step before the switch fails; the outputs are then the
        previous set, unchanged, and the stage is removed.
    """
    stage, out, names = Path(stage), Path(out_dir), list(names)
    family = stage.name.split(".", 1)[0]
    check_output_tree(out, output_names=[*names, *output_names(out)])
    missing = [n for n in names if not (stage / n).is_file()]
    if missing:
        raise OutputError(f"{stage}: the staged set lacks {', '.join(missing)}; nothing was published")
    try:
        _record(stage, family, names, command)
        _fsync_dir(stage)
        _relink_copied_pointer(out, family)
        _adopt_plain_files(out, family, names)
        for name in names:
            _ensure_link(out, family, name)
        _fsync_dir(out)
        _switch(pointer(out, family), Path(SETS) / stage.name)
    except OSError as exc:
        shutil.rmtree(stage, ignore_errors=True)
        _remove_dangling(out, family)
        raise OutputError(f"{out}: publishing the new results failed ({exc.strerror or exc}"
                          f"{': ' + str(exc.filename) if exc.filename else ''}); the previous results are intact. "
                          "Free disk space or fix the directory's permissions") from exc
    _tidy(out, family, keep=stage.name)
    return [out / name for name in names]


def publish_staged(out_dir: str | Path, write: Callable[[Path], list[Path]], *, family: Family,
                   command: str = "") -> list[Path]:
    """Stage a set (``write(stage)`` writes it and returns the files written), then publish it with Ctrl-C,
    SIGTERM and SIGHUP held over the switch (:func:`signals_held`). Call it under the output's lock.

    Raises
    ------
    InterruptedAfterPublishing
        When one of those signals arrived during the switch: the new set is published, whole.
    OutputError
        As :func:`publish`; the previous set is then intact.
    """
    stage = staging_dir(out_dir, family=family)
    try:
        names = [Path(p).name for p in write(stage)]
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    try:
        with signals_held():
            return publish(stage, out_dir, names, command=command)
    except KeyboardInterrupt:
        raise InterruptedAfterPublishing(f"interrupted after the new results were published: {out_dir} holds them, "
                                         f"complete ({', '.join(names)})") from None


@contextlib.contextmanager
def removed_unless_published(stage: str | Path):
    """The staged set ``stage`` is removed when the block ends in an error before its publication (a full disk, an
    interrupt), so failed runs leave no staged sets behind; a published stage is the current set and stays."""
    try:
        yield
    except BaseException:
        stage = Path(stage)
        ptr = pointer(stage.parent.parent.parent, stage.name.split(".", 1)[0])
        if not (ptr.is_symlink() and ptr.resolve() == stage.resolve()):
            shutil.rmtree(stage, ignore_errors=True)
        raise


def describe(out_dir: str | Path, family: Family) -> str:
    """Which set ``out_dir`` shows for ``family``: its publication time and command, or '' when it has none."""
    try:
        rec = json.loads((pointer(out_dir, family) / SET_RECORD).read_text())
    except (OSError, ValueError):
        return ""
    return f"the set published {rec.get('published_utc', '?')} by '{rec.get('command', '?')}'"


def output_names(out_dir: str | Path) -> list[str]:
    """Every name of ``out_dir`` an output set may hold: each family's outputs, and the names each current set
    records of itself."""
    names = [n for family in Family for n in PLAIN_BEFORE_SETS[family]]
    for family in Family:
        names += _recorded_names(pointer(out_dir, family))
    return list(dict.fromkeys(names))


def link_target(family: Family | str, name: str) -> str:
    """What ``OUT/<name>`` links to (relative: an output directory moved or copied with its links keeps working)."""
    return f"{STATE_DIR}/{_name(family)}{POINTER_SUFFIX}/{name}"


def _name(family: Family | str) -> str:
    return family.value if isinstance(family, Family) else family


def _record(stage: Path, family: str, names: list[str], command: str) -> None:
    doc = {"family": family, "names": names, "command": command,
           "published_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    path = stage / SET_RECORD
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(doc, fh, indent=1)
        fh.flush()
        os.fsync(fh.fileno())


def _relink_copied_pointer(out: Path, family: str) -> None:
    """A copy that followed links (``cp -r``, ``shutil.copytree``) made the pointer a directory and the outputs
    plain files: that directory becomes a set directory again, pointed at (the plain files are then adopted)."""
    ptr = pointer(out, family)
    if ptr.is_dir() and not ptr.is_symlink():
        moved = state_dir(out) / SETS / f"{family}.copied-{os.getpid()}-{secrets.token_hex(3)}"
        moved.parent.mkdir(parents=True, exist_ok=True)
        os.replace(ptr, moved)
        _switch(ptr, Path(SETS) / moved.name)


def _adopt_plain_files(out: Path, family: str, names: list[str]) -> None:
    """Step 1: plain files among ``names``, the current set's own names and the family's names of before output
    sets (:data:`PLAIN_BEFORE_SETS`) join the current set (one is made
    for them when there is none, its record naming them all first, so that a publish killed half-way through
    adopting them is finished by the next), each then replaced by its link; what a reader sees is unchanged."""
    ptr = pointer(out, family)
    known = list(dict.fromkeys([*names, *_recorded_names(ptr), *PLAIN_BEFORE_SETS.get(Family(family), ())]))
    plain = [n for n in known if (out / n).is_file() and not (out / n).is_symlink()]
    if not plain:
        return
    if not ptr.is_dir():
        adopted = state_dir(out) / SETS / f"{family}.adopted-{os.getpid()}-{secrets.token_hex(3)}"
        adopted.mkdir(parents=True)
        _record(adopted, family, plain, "files found in place, written before output sets")
        _switch(ptr, Path(SETS) / adopted.name)
    current = ptr.resolve()
    for name in plain:
        tmp = current / f".{name}.adopt.tmp"
        _remove_quietly(tmp)
        os.link(out / name, tmp)
        os.replace(tmp, current / name)
        _symlink_over(out / name, link_target(family, name))


def _recorded_names(ptr: Path) -> list[str]:
    """The names the set at ``ptr`` records of itself (none when it has no record)."""
    try:
        return list(json.loads((ptr / SET_RECORD).read_text()).get("names", []))
    except (OSError, ValueError, AttributeError):
        return []


def _ensure_link(out: Path, family: str, name: str) -> None:
    """Step 2: ``OUT/<name>`` links into the current set (made when missing or pointing elsewhere)."""
    path, target = out / name, link_target(family, name)
    if path.is_symlink() and os.readlink(path) == target:
        return
    if path.is_dir() and not path.is_symlink():
        raise IsADirectoryError(21, "an output name is a directory", str(path))
    _symlink_over(path, target)


def _switch(ptr: Path, target: Path) -> None:
    """Step 3: point ``ptr`` at ``target`` with one rename, then make the rename durable."""
    _symlink_over(ptr, str(target))
    _fsync_dir(ptr.parent)


def _symlink_over(path: Path, target: str) -> None:
    """Create or replace the symbolic link ``path`` -> ``target`` atomically (a temporary link, then rename)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.link.tmp")
    _remove_quietly(tmp)
    os.symlink(target, tmp)
    try:
        os.replace(tmp, path)
    except OSError:
        _remove_quietly(tmp)
        raise


def _tidy(out: Path, family: str, *, keep: str) -> None:
    """Step 4: remove the links to nothing, every set directory of ``family`` but ``keep``, and the temporary links
    of killed publishes; a failure here
    leaves the new set published (warned; the next publish tries again)."""
    try:
        _remove_dangling(out, family)
        for old in (state_dir(out) / SETS).glob(f"{family}.*"):
            if old.name != keep:
                shutil.rmtree(old, ignore_errors=True)
        shutil.rmtree(state_dir(out) / OLD_STAGING, ignore_errors=True)
        for where, pattern in ((out, ".*.link.tmp"), (state_dir(out), ".*.link.tmp"),
                               (state_dir(out) / SETS / keep, ".*.adopt.tmp")):
            for tmp in where.glob(pattern):          # a killed publish's (under the lock, no other is under way)
                _remove_quietly(tmp)
    except OSError as exc:
        log.warning("%s: the new results are published, but tidying the old ones failed (%s); the next run "
                    "tries again", out, exc)


def _remove_dangling(out: Path, family: str) -> None:
    """Remove ``OUT``'s links into ``family``'s current set that point at nothing."""
    prefix = link_target(family, "")
    for entry in os.scandir(out):
        if entry.is_symlink() and os.readlink(entry.path).startswith(prefix) and not os.path.exists(entry.path):
            _remove_quietly(entry.path)


def _link_or_copy(src: Path, dst: Path) -> None:
    _remove_quietly(dst)
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def _fsync_dir(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _remove_quietly(path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass
