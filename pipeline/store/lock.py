"""The output lock: one writer per output directory at a time."""

from __future__ import annotations

import json
import os
import socket
import time
from pathlib import Path

from ..errors import OutputLockedError
from .atomic import STATE_DIR


class OutputLock:
    """An exclusive lock on an output directory, held for the length of a run.

    The lock is the file ``OUT/.rockscreen/lock``, created with ``O_EXCL``
    and holding the owner's pid, host, start time and command. A lock left by
    a run that died on this host (its pid no longer exists) is taken over
    with a warning; a live one raises :class:`OutputLockedError`.
    """

    def __init__(self, out_dir: str | Path, *, command: str = ""):
        self.path = Path(out_dir) / STATE_DIR / "lock"
        self.command = command
        self.stale_owner: dict | None = None

    def _owner(self) -> dict:
        try:
            return json.loads(self.path.read_text())
        except (OSError, ValueError):
            return {}

    def acquire(self) -> "OutputLock":
        self.path.parent.mkdir(parents=True, exist_ok=True)
        info = {"pid": os.getpid(), "host": socket.gethostname(),
                "started_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "command": self.command}
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                owner = self._owner()
                if owner.get("host") == info["host"] and not _pid_alive(int(owner.get("pid", -1))):
                    self.stale_owner = owner
                    self.path.unlink(missing_ok=True)   # the run that held it is dead: take over
                    continue
                raise OutputLockedError(
                    f"{self.path.parent.parent}: another run is writing this output (pid {owner.get('pid', '?')} "
                    f"on {owner.get('host', '?')}, started {owner.get('started_utc', '?')}: "
                    f"{owner.get('command', '')!s}). Wait for it to finish or use another --out; if that run "
                    f"is dead on another machine, delete {self.path}") from None
            with os.fdopen(fd, "w") as fh:
                json.dump(info, fh)
            return self
        raise OutputLockedError(f"{self.path}: could not take the lock; delete it if no run is active")

    def release(self) -> None:
        if self._owner().get("pid") == os.getpid():
            self.path.unlink(missing_ok=True)

    def __enter__(self) -> "OutputLock":
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()


def _pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
