"""File operations under an output folder relative to directory descriptors, never following a link.

A publish (:func:`.sets.publish`) opens the output folder, its state folder ``.rockscreen``, the folder of sets
and the set being published once, each relative to the one before with ``O_NOFOLLOW`` (:func:`open_tree`), and
makes every later step relative to those descriptors: a rename, a link, a removal, a record written. A link
planted under the output folder while a run holds its lock, between any two of those steps, is then never
followed: a folder replaced by a link after it was opened is not the one the descriptor holds (the steps go on in
the real folder, which the link no longer names), and a name replaced by a link is renamed, removed or read as the
link itself, never as what it points at (``follow_symlinks=False``, ``O_NOFOLLOW``). A folder that is a link when
it is opened is refused, named. The output folder itself may be a link: the user chose that path.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import NamedTuple

from ..constants import STATE_DIR
from ..errors import UnsafeOutputError

#: Opening a folder under the output: a folder, never through a link.
DIR_FLAGS = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW
#: How deep a removed set directory may go (its files, a folder of figures); deeper is not rockscreen's.
MAX_DEPTH = 4


class Tree(NamedTuple):
    """Descriptors of the output folder, its state folder, its folder of sets and the set being published."""

    out: int
    state: int
    sets: int
    stage: int


@contextlib.contextmanager
def open_tree(out: Path, sets_name: str, stage: Path) -> Iterator[Tree]:
    """The :class:`Tree` of ``out`` with the set ``stage`` (which must be ``out``'s
    ``.rockscreen/<sets_name>/<name>``, the folder :func:`.sets.staging_dir` made); closed when the block ends.

    Raises
    ------
    UnsafeOutputError
        Where a folder on the way is a link or not a folder, or ``stage`` is not that folder (a link planted
        since it was made).
    """
    opened: list[int] = []
    try:
        opened.append(os.open(out, os.O_RDONLY | os.O_DIRECTORY))
        for name, where in ((STATE_DIR, out), (sets_name, out / STATE_DIR), (stage.name, out / STATE_DIR / sets_name)):
            opened.append(open_dir(name, opened[-1], where))
        held, named = os.fstat(opened[-1]), os.stat(stage, follow_symlinks=False)
        if (held.st_dev, held.st_ino) != (named.st_dev, named.st_ino):
            raise UnsafeOutputError(f"{stage}: not the set directory under {out / STATE_DIR / sets_name} (a link "
                                    "was planted on its path); nothing was published: remove the link and run again")
        yield Tree(*opened)
    finally:
        for fd in opened:
            os.close(fd)


def open_dir(name: str, dir_fd: int, where: Path) -> int:
    """The folder ``name`` in the folder ``dir_fd`` (``where``, for the message), opened without following a link.

    Raises
    ------
    UnsafeOutputError
        Where ``name`` is a link or not a folder.
    """
    try:
        return os.open(name, DIR_FLAGS, dir_fd=dir_fd)
    except OSError as exc:
        if exc.errno in (errno.ELOOP, errno.ENOTDIR):
            raise UnsafeOutputError(f"{where / name}: a link or a file where rockscreen keeps a folder; nothing under "
                                    "the output folder is followed out of it: remove it and run again") from exc
        raise


@contextlib.contextmanager
def within(name: str, dir_fd: int, where: Path) -> Iterator[int]:
    """The folder ``name`` in ``dir_fd`` opened as :func:`open_dir` opens it, closed when the block ends."""
    fd = open_dir(name, dir_fd, where)
    try:
        yield fd
    finally:
        os.close(fd)


def read_json(dir_fd: int, name: str):
    """The JSON document in the file ``name`` of ``dir_fd``, read without following a link."""
    with os.fdopen(os.open(name, os.O_RDONLY | os.O_NOFOLLOW, dir_fd=dir_fd), encoding="utf-8") as fh:
        return json.load(fh)


def lstat_at(dir_fd: int, name: str) -> os.stat_result | None:
    """``name``'s own status in ``dir_fd`` (a link's, not its target's), or None where it does not exist."""
    try:
        return os.stat(name, dir_fd=dir_fd, follow_symlinks=False)
    except FileNotFoundError:
        return None


def is_regular(dir_fd: int, name: str) -> bool:
    """``name`` in ``dir_fd`` is a regular file (not a link to one)."""
    st = lstat_at(dir_fd, name)
    return st is not None and stat.S_ISREG(st.st_mode)


def is_real_dir(dir_fd: int, name: str) -> bool:
    """``name`` in ``dir_fd`` is a folder (not a link to one)."""
    st = lstat_at(dir_fd, name)
    return st is not None and stat.S_ISDIR(st.st_mode)


def read_link(dir_fd: int, name: str) -> str | None:
    """Where the link ``name`` in ``dir_fd`` points, or None where it is not a link."""
    try:
        return os.readlink(name, dir_fd=dir_fd)
    except OSError:
        return None


def symlink_over(dir_fd: int, name: str, target: str) -> None:
    """Create or replace the link ``name`` -> ``target`` in ``dir_fd`` atomically (a temporary link, then one
    rename, which replaces a planted link as the link it is)."""
    tmp = f".{name}.{os.getpid()}.link.tmp"
    remove_quietly(dir_fd, tmp)
    os.symlink(target, tmp, dir_fd=dir_fd)
    try:
        os.replace(tmp, name, src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
    except OSError:
        remove_quietly(dir_fd, tmp)
        raise


def write_new(dir_fd: int, name: str, data: bytes) -> None:
    """Write ``data`` to ``name`` in ``dir_fd``, made or truncated, never through a link, and make it durable."""
    fd = os.open(name, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o644, dir_fd=dir_fd)
    try:
        os.write(fd, data)
        os.fsync(fd)
    finally:
        os.close(fd)


def remove_quietly(dir_fd: int, name: str) -> None:
    """Remove the file or link ``name`` in ``dir_fd`` where it exists."""
    with contextlib.suppress(OSError):
        os.unlink(name, dir_fd=dir_fd)


def remove_tree(dir_fd: int, name: str, *, depth: int = 0) -> None:
    """Remove the folder ``name`` in ``dir_fd`` and what it holds, never following a link (a link in it is removed
    as a link; a link by ``name`` itself is left: it is not a folder rockscreen made); errors are ignored (the
    next publish tries again)."""
    if depth > MAX_DEPTH:
        return
    try:
        fd = os.open(name, DIR_FLAGS, dir_fd=dir_fd)
    except OSError:
        return
    try:
        for entry in list_entries(fd):
            if entry.is_dir(follow_symlinks=False):
                remove_tree(fd, entry.name, depth=depth + 1)
            else:
                remove_quietly(fd, entry.name)
    finally:
        os.close(fd)
    with contextlib.suppress(OSError):
        os.rmdir(name, dir_fd=dir_fd)


def list_entries(dir_fd: int) -> list[os.DirEntry]:
    """The entries of the folder ``dir_fd`` (read whole, the listing closed)."""
    with os.scandir(dir_fd) as it:
        return list(it)


def names_in(dir_fd: int) -> list[str]:
    """The names in the folder ``dir_fd``."""
    return [entry.name for entry in list_entries(dir_fd)]


def fsync_dir(dir_fd: int) -> None:
    """Make the renames in the folder ``dir_fd`` durable."""
    os.fsync(dir_fd)
