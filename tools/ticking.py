"""Run a command and say, every 2 s it is silent, that it is still running: ``python tools/ticking.py LABEL --
COMMAND ...``.

The command's own output passes through as it comes; while it prints nothing (pip installing the packages it has
collected, numba compiling), a line ``  ... LABEL: 12 s`` follows every :data:`LINE_S` seconds. The exit code is
the command's. Standard library only: make runs it before anything is installed.
"""

from __future__ import annotations

import subprocess
import sys
import threading
import time

#: Longest silence [s]
LINE_S = 2.0
#: How often the silence is looked at [s]
POLL_S = 0.5


def main(argv: list[str]) -> int:
    if "--" not in argv or argv.index("--") != 1 or len(argv) < 3:
        print("usage: python tools/ticking.py LABEL -- COMMAND [ARG ...]", file=sys.stderr)
        return 2
    label, command = argv[0], argv[2:]
    t0 = time.monotonic()
    last = {"t": t0}
    lock = threading.Lock()
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)

    def tick() -> None:
        while proc.poll() is None:
            time.sleep(POLL_S)
            with lock:
                if time.monotonic() - last["t"] >= LINE_S - POLL_S:
                    print(f"  ... {label}: {time.monotonic() - t0:.0f} s", flush=True)
                    last["t"] = time.monotonic()

    threading.Thread(target=tick, daemon=True).start()
    assert proc.stdout is not None
    for line in iter(proc.stdout.readline, b""):
        with lock:
            sys.stdout.buffer.write(line)
            sys.stdout.flush()
            last["t"] = time.monotonic()
    return proc.wait()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
