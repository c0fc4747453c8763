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
from ..errors import InterruptedAfterPublishing, OutputError, UnsafeOutputError
from . import dirfd
from .guard import POINTER_SUFFIX, SETS, TEMPORARY_LINK_SUFFIX, check_output_tree

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
    one atomic switch (see the module's description of the steps). Every step is taken relative to the folders'
    descriptors, never through a link (:mod:`.dirfd`).

    Returns
    -------
    list of Path
        ``out_dir / name`` for each of ``names``.

    Raises
    ------
    OutputError
        When a file is missing from the stage, or a step before the switch fails; the outputs are then the
        previous set, unchanged, and the stage is removed.
    UnsafeOutputError
        Where a folder on the way is a link (planted under the output folder).
    """
    stage, out, names = Path(stage), Path(out_dir), list(names)
    family = stage.name.split(".", 1)[0]
    check_output_tree(out, output_names=[*names, *output_names(out)])
    with dirfd.open_tree(out, SETS, stage) as tree:
        missing = [n for n in names if not dirfd.is_regular(tree.stage, n)]
        if missing:
            raise OutputError(f"{stage}: the staged set lacks {', '.join(missing)}; nothing was published")
        try:
            _record(tree.stage, family, names, command)
            dirfd.fsync_dir(tree.stage)
            _relink_copied_pointer(tree, family)
            _adopt_plain_files(tree, family, names)
            for name in names:
                _ensure_link(tree, family, name)
            dirfd.fsync_dir(tree.out)
            _switch(tree, family, stage.name)
        except OSError as exc:
            dirfd.remove_tree(tree.sets, stage.name)
            _remove_dangling(tree, family)
            raise OutputError(f"{out}: publishing the new results failed ({exc.strerror or exc}"
                              f"{': ' + str(exc.filename) if exc.filename else ''}); the previous results are "
                              "intact. Free disk space or fix the directory's permissions") from exc
        _tidy(tree, family, keep=stage.name, out=out)
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


def _record(set_fd: int, family: str, names: list[str], command: str) -> None:
    """The set's record of itself (:data:`SET_RECORD`) in the set directory ``set_fd``."""
    doc = {"family": family, "names": names, "command": command,
           "published_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    dirfd.write_new(set_fd, SET_RECORD, json.dumps(doc, indent=1).encode("utf-8"))


def _pointer_name(family: str) -> str:
    return f"{family}{POINTER_SUFFIX}"


def _relink_copied_pointer(tree: dirfd.Tree, family: str) -> None:
    """A copy that followed links (``cp -r``, ``shutil.copytree``) made the pointer a directory and the outputs
    plain files: that directory becomes a set directory again, pointed at (the plain files are then adopted)."""
    ptr = _pointer_name(family)
    if dirfd.is_real_dir(tree.state, ptr):
        moved = f"{family}.copied-{os.getpid()}-{secrets.token_hex(3)}"
        os.replace(ptr, moved, src_dir_fd=tree.state, dst_dir_fd=tree.sets)
        _switch(tree, family, moved)


def _current_set(tree: dirfd.Tree, family: str) -> str | None:
    """The name of the set directory the pointer names (``sets/<name>``, a folder there), or None."""
    target = dirfd.read_link(tree.state, _pointer_name(family))
    if target is None or not target.startswith(f"{SETS}/"):
        return None
    name = target[len(SETS) + 1:]
    return name if "/" not in name and name not in ("", ".", "..") and dirfd.is_real_dir(tree.sets, name) else None


def _adopt_plain_files(tree: dirfd.Tree, family: str, names: list[str]) -> None:
    """Step 1: plain files among ``names``, the current set's own names and the family's names of before output
    sets (:data:`PLAIN_BEFORE_SETS`) join the current set (one is made
    for them when there is none, its record naming them all first, so that a publish killed half-way through
    adopting them is finished by the next), each then replaced by its link; what a reader sees is unchanged."""
    current = _current_set(tree, family)
    recorded = _recorded_in(tree, current)
    known = list(dict.fromkeys([*names, *recorded, *PLAIN_BEFORE_SETS.get(Family(family), ())]))
    plain = [n for n in known if dirfd.is_regular(tree.out, n)]
    if not plain:
        return
    if current is None:
        current = f"{family}.adopted-{os.getpid()}-{secrets.token_hex(3)}"
        os.mkdir(current, dir_fd=tree.sets)
        with dirfd.within(current, tree.sets, Path(SETS)) as fd:
            _record(fd, family, plain, "files found in place, written before output sets")
        _switch(tree, family, current)
    with dirfd.within(current, tree.sets, Path(SETS)) as fd:
        for name in plain:
            tmp = f".{name}.adopt.tmp"
            dirfd.remove_quietly(fd, tmp)
            os.link(name, tmp, src_dir_fd=tree.out, dst_dir_fd=fd, follow_symlinks=False)
            os.replace(tmp, name, src_dir_fd=fd, dst_dir_fd=fd)
            dirfd.symlink_over(tree.out, name, link_target(family, name))


def _recorded_in(tree: dirfd.Tree, current: str | None) -> list[str]:
    """The names the set directory ``current`` records of itself (none without one, or without a record)."""
    if current is None:
        return []
    try:
        with dirfd.within(current, tree.sets, Path(SETS)) as fd:
            return _names_of(dirfd.read_json(fd, SET_RECORD))
    except (OSError, ValueError, UnsafeOutputError):
        return []


def _names_of(record) -> list[str]:
    """The names a set's record (:data:`SET_RECORD`, parsed) lists; none where it lists none."""
    names = record.get("names", []) if isinstance(record, dict) else []
    return [str(n) for n in names] if isinstance(names, list) else []


def _recorded_names(ptr: Path) -> list[str]:
    """The names the set at ``ptr`` records of itself (none when it has no record)."""
    try:
        return _names_of(json.loads((ptr / SET_RECORD).read_text()))
    except (OSError, ValueError):
        return []


def _ensure_link(tree: dirfd.Tree, family: str, name: str) -> None:
    """Step 2: ``OUT/<name>`` links into the current set (made when missing or pointing elsewhere)."""
    target = link_target(family, name)
    if dirfd.read_link(tree.out, name) == target:
        return
    if dirfd.is_real_dir(tree.out, name):
        raise IsADirectoryError(21, "an output name is a directory", name)
    dirfd.symlink_over(tree.out, name, target)


def _switch(tree: dirfd.Tree, family: str, set_name: str) -> None:
    """Step 3: point the family's pointer at the set ``set_name`` with one rename, then make the rename durable."""
    dirfd.symlink_over(tree.state, _pointer_name(family), f"{SETS}/{set_name}")
    dirfd.fsync_dir(tree.state)


def _tidy(tree: dirfd.Tree, family: str, *, keep: str, out: Path) -> None:
    """Step 4: remove the links to nothing, every set directory of ``family`` but ``keep``, and the temporary links
    of killed publishes; a failure here
    leaves the new set published (warned; the next publish tries again)."""
    try:
        _remove_dangling(tree, family)
        for name in dirfd.names_in(tree.sets):
            if name.startswith(f"{family}.") and name != keep:
                dirfd.remove_tree(tree.sets, name)
        dirfd.remove_tree(tree.state, OLD_STAGING)
        for fd in (tree.out, tree.state):       # a killed publish's (under the lock, no other is under way)
            for name in dirfd.names_in(fd):
                if name.startswith(".") and name.endswith(TEMPORARY_LINK_SUFFIX):
                    dirfd.remove_quietly(fd, name)
        for name in dirfd.names_in(tree.stage):
            if name.startswith(".") and name.endswith(".adopt.tmp"):
                dirfd.remove_quietly(tree.stage, name)
    except OSError as exc:
        log.warning("%s: the new results are published, but tidying the old ones failed (%s); the next run "
                    "tries again", out, exc)


def _remove_dangling(tree: dirfd.Tree, family: str) -> None:
    """Remove ``OUT``'s links into ``family``'s current set that point at nothing (a name the set does not hold)."""
    prefix = link_target(family, "")
    held = _held_names(tree, family)
    for name in dirfd.names_in(tree.out):
        target = dirfd.read_link(tree.out, name)
        if target is not None and target.startswith(prefix) and target[len(prefix):] not in held:
            dirfd.remove_quietly(tree.out, name)


def _held_names(tree: dirfd.Tree, family: str) -> set[str]:
    """The names in ``family``'s current set directory (none without one)."""
    current = _current_set(tree, family)
    if current is None:
        return set()
    try:
        with dirfd.within(current, tree.sets, Path(SETS)) as fd:
            return set(dirfd.names_in(fd))
    except (OSError, UnsafeOutputError):
        return set()


def _link_or_copy(src: Path, dst: Path) -> None:
    _remove_quietly(dst)
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def _remove_quietly(path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass
