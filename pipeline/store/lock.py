"""The output lock: one writer per output directory at a time."""

from __future__ import annotations

import fcntl
import json
import os
import socket
import time
from pathlib import Path

from ..errors import OutputLockedError, UnsafeOutputError
from .atomic import STATE_DIR
from .guard import check_output_tree
from .sets import output_names


class OutputLock:
    """An exclusive lock on an output directory, held for the length of a run.

    The lock is an exclusive ``flock`` on the file ``OUT/.rockscreen/lock``, which holds the owner's pid, host, start
    time and command. The kernel releases it when its process ends, however it ends (SIGKILL, the OOM killer), so
    a run that died leaves no lock to take over: the next run takes the lock at once, and says so when the dead
    run's file was left behind. On a local file system two runs cannot both hold it (tested with processes racing
    for a lock left by a dead run); on a network file system that holds as far as its locking service does. A live
    lock raises :class:`OutputLockedError`.
    """

    def __init__(self, out_dir: str | Path, *, command: str = ""):
        self.path = Path(out_dir) / STATE_DIR / "lock"
        self.command = command
        self.stale_owner: dict | None = None
        self._fd: int | None = None

    def _owner(self) -> dict:
        try:
            return json.loads(self.path.read_text())
        except (OSError, ValueError):
            return {}

    def acquire(self) -> "OutputLock":
        out = self.path.parent.parent
        check_output_tree(out, output_names=output_names(out))    # nothing planted is followed out of OUT
        self.path.parent.mkdir(parents=True, exist_ok=True)
        info = {"pid": os.getpid(), "host": socket.gethostname(),
                "started_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "command": self.command}
        for _ in range(MAX_LOCK_ATTEMPTS):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_RDWR | os.O_NOFOLLOW, 0o644)
            except OSError as exc:                    # ELOOP: a link planted since the check
                raise UnsafeOutputError(f"{self.path}: cannot open the lock file without following a link "
                                        f"({exc.strerror or exc}); remove it and run again") from exc
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                owner = self._owner()
                raise OutputLockedError(
                    f"{self.path.parent.parent}: another run is writing this output (pid {owner.get('pid', '?')} "
                    f"on {owner.get('host', '?')}, started {owner.get('started_utc', '?')}: "
                    f"{owner.get('command', '')!s}). Wait for it to finish or use another --out") from None
            if not _same_file(fd, self.path):      # released and removed by its holder while we waited: again
                os.close(fd)
                continue
            previous = os.read(fd, 1 << 16)
            if previous.strip():                      # its run died without releasing it (the kernel did)
                try:
                    self.stale_owner = json.loads(previous)
                except ValueError:
                    self.stale_owner = {}
            os.lseek(fd, 0, os.SEEK_SET)
            os.ftruncate(fd, 0)
            os.write(fd, json.dumps(info).encode())
            self._fd = fd
            return self
        raise OutputLockedError(f"{self.path}: could not take the lock in {MAX_LOCK_ATTEMPTS} attempts (other runs "
                                "keep taking and releasing it); try again")

    def release(self) -> None:
        if self._fd is None:
            return
        self.path.unlink(missing_ok=True)     # removed while held: a run waiting on this file tries the new one
        os.close(self._fd)
        self._fd = None

    def __enter__(self) -> "OutputLock":
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()


#: Attempts at the lock when its holders keep releasing it between our open and our lock.
MAX_LOCK_ATTEMPTS = 50


def _same_file(fd: int, path: Path) -> bool:
    """Whether the open file ``fd`` is still the file at ``path`` (not removed or replaced since it was opened)."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return False
    own = os.fstat(fd)
    return (own.st_dev, own.st_ino) == (st.st_dev, st.st_ino)
