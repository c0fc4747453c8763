"""Nothing under an output directory is followed out of it.

Whoever can write into a shared results folder could plant a symbolic link where rockscreen deletes, writes, locks or
links (``OUT/.rockscreen/cache`` pointing at another folder, ``OUT/.rockscreen/lock`` at another file), and the next
scheduled run would act there with its runner's rights. :func:`check_output_tree` walks every path rockscreen
touches under ``OUT`` without following a link (``os.lstat``, ``os.scandir``) and refuses, naming the path, anything
that is not what rockscreen makes there:

- ``OUT/.rockscreen`` and its folders (``sets``, ``cache``, ``figures``, ``margins``, ``fragility``, ...): real
  directories; the files in them, and in each set directory, regular files or folders of the same kind, never links;
- ``OUT/.rockscreen/lock``: a regular file (it is also opened with ``O_NOFOLLOW``: :class:`.lock.OutputLock`);
- ``OUT/.rockscreen/<family>.current``: a link ``sets/<one name>`` to a real set directory (or a real directory: a
  copy that followed the links, which a publish turns back into a set);
- ``OUT/<name>``, for each name an output set may hold: absent, a regular file (a copy's, or an older rockscreen's),
  or the link ``.rockscreen/<family>.current/<name>`` rockscreen makes; in a folder without ``.rockscreen`` (one
  rockscreen never wrote into) regular files by the names the command writes, without a netCDF result among them,
  are the user's, and refused rather than replaced (``replaces``, as the commands prepare their output).

It runs when the output's lock is taken (every command that writes ``OUT`` takes it) and again before each publish
and each clean-up, so a planted link is refused (:class:`~pipeline.errors.UnsafeOutputError`, exit 3) before anything
is changed. A process that plants a link *between* the check and a use, while rockscreen runs with the lock held, is
met by the ``O_NOFOLLOW`` of the lock and, in a publish, by every step's being taken relative to the folders'
descriptors opened without following a link (:mod:`.dirfd`; tested by planting before each step). What that does
not cover: the files a command writes into its staged set before the publish, and the caches, are written by path.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from ..constants import STATE_DIR
from ..errors import UnsafeOutputError

#: The suffix of a family's pointer in the state directory, ``<family>.current`` (:mod:`.sets` uses these)
POINTER_SUFFIX = ".current"
#: The folder of set directories, in the state directory
SETS = "sets"
#: A temporary link of a publish killed before its rename (``.<name>.<pid>.link.tmp``), removed by the next publish
TEMPORARY_LINK_SUFFIX = ".link.tmp"
#: How deep the state directory's folders go (sets/<set>/<file>); deeper is not rockscreen's
MAX_DEPTH = 3


def check_output_tree(out_dir: str | Path, *, output_names, replaces=()) -> None:
    """Refuse an output directory where something rockscreen touches is not what it makes there (see the module).

    Parameters
    ----------
    out_dir : str or Path
        The output directory (it may itself be a link: the user chose that path). Nothing is checked when it does
        not exist yet.
    output_names : iterable of str
        The names of ``OUT`` a set may hold (:func:`.sets.output_names`: each family's outputs and the names each
        current set records); a link by one of these names must be rockscreen's own.
    replaces : iterable of str
        The names the command will write: in a folder rockscreen never wrote into, a regular file by one of them
        (with no results netCDF beside it) is the user's, and refused.

    Raises
    ------
    UnsafeOutputError
        Naming the path, what it is and what rockscreen expects there; nothing has been changed.
    """
    out = Path(out_dir)
    if not out.exists():
        return
    if not out.is_dir():
        raise UnsafeOutputError(f"{out}: the output directory is a file; choose another --out")
    state = out / STATE_DIR
    kind = _kind(state)
    if kind == "link":
        _refuse(state, "a symbolic link", "the real directory rockscreen keeps its state in")
    if kind not in ("absent", "directory"):
        _refuse(state, f"a {kind}", "the directory rockscreen keeps its state in (move that file away)")
    if kind == "directory":
        _check_state(state)
    _check_outputs(out, set(output_names))
    if kind == "absent":
        _refuse_foreign_files(out, set(replaces))


def _check_state(state: Path) -> None:
    for entry in os.scandir(state):
        path = Path(entry.path)
        if entry.name == "lock":
            if _kind(path) != "file":
                _refuse(path, f"a {_kind(path)}", "the lock file rockscreen makes (a regular file)")
        elif entry.name.endswith(POINTER_SUFFIX):
            _check_pointer(state, path)
        elif entry.is_symlink():
            if not entry.name.endswith(TEMPORARY_LINK_SUFFIX):          # a killed publish's: unlinked, never followed
                _refuse(path, "a symbolic link", "a real file or directory of rockscreen's")
        elif entry.is_dir(follow_symlinks=False):
            _check_folder(path, depth=1)


def _check_folder(folder: Path, *, depth: int) -> None:
    """A folder of the state directory: regular files and real folders, no link, at most MAX_DEPTH deep."""
    for entry in os.scandir(folder):
        path = Path(entry.path)
        if entry.is_symlink():
            _refuse(path, "a symbolic link", "a regular file of rockscreen's")
        if entry.is_dir(follow_symlinks=False):
            if depth >= MAX_DEPTH:
                _refuse(path, "a directory", "a regular file (rockscreen's folders go no deeper)")
            _check_folder(path, depth=depth + 1)


def _check_pointer(state: Path, pointer: Path) -> None:
    """``<family>.current``: a link ``sets/<name>`` to a real set directory, or a real directory (a copy)."""
    kind = _kind(pointer)
    if kind == "directory":
        _check_folder(pointer, depth=2)
        return
    if kind != "link":
        _refuse(pointer, f"a {kind}", "a link to one of rockscreen's set directories")
    target = os.readlink(pointer)
    parts = Path(target).parts
    if len(parts) != 2 or parts[0] != SETS or parts[1] in ("..", ".") or os.path.isabs(target):
        _refuse(pointer, f"a link to {target}", f"a link to {SETS}/<set> inside {state}")
    if _kind(state / target) not in ("directory", "absent"):          # absent: a killed run's; the publish mends it
        _refuse(state / target, f"a {_kind(state / target)}", "a real set directory")


def _check_outputs(out: Path, names: set[str]) -> None:
    prefix = f"{STATE_DIR}/"
    for entry in os.scandir(out):
        if not entry.is_symlink():
            continue
        target = os.readlink(entry.path)
        ours = (target.startswith(prefix) and Path(target).parts[1:2] and
                Path(target).parts[1].endswith(POINTER_SUFFIX) and Path(target).parts[2:] == (entry.name,))
        if entry.name in names and not ours:
            _refuse(Path(entry.path), f"a link to {target}",
                    f"rockscreen's own link {prefix}<family>{POINTER_SUFFIX}/{entry.name} (or a regular file)")


def _refuse_foreign_files(out: Path, names: set[str]) -> None:
    """A folder rockscreen never wrote into (no state directory) holding files by its output names and none of its
    netCDF results: they are the user's, and a run would replace them; refused, named. Beside a results file
    (``screening.nc``, ...) they are a copy of rockscreen's outputs that followed the links, and are taken as such."""
    found = sorted(n for n in names if _kind(out / n) == "file")
    if any(n.endswith(".nc") for n in found):          # a copy of rockscreen's outputs (scp -r, cp -rL OUT/*)
        return
    if found:
        raise UnsafeOutputError(
            f"{out}: holds {', '.join(found)}, which rockscreen did not write there (the folder has no "
            f"{STATE_DIR}); a run would replace {'them' if len(found) > 1 else 'it'}. Move "
            f"{'them' if len(found) > 1 else 'it'} away or choose another --out; nothing was changed")


def _kind(path: Path) -> str:
    """What ``path`` is, its links not followed: absent, link, directory, file or other."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return "absent"
    if stat.S_ISLNK(mode):
        return "link"
    if stat.S_ISDIR(mode):
        return "directory"
    if stat.S_ISREG(mode):
        return "file"
    return "special file"


def _refuse(path: Path, found: str, expected: str) -> None:
    raise UnsafeOutputError(
        f"{path}: found {found} where rockscreen expects {expected}; rockscreen follows no link out of its "
        "output directory and changed nothing. Remove it (or choose another --out) and run again")
