"""Which record each worker is on, and which of its scenes: the per-scene budget a user can see.

A task (one record and its blocks) tells its :class:`SceneProgress` when each scene starts and ends. The state is
kept in memory and written, at most every :data:`FLUSH_S` seconds and only while it changes, by a small thread
of the worker to one file per process in a directory the run owns, so that a scene that never returns is still
named; the parent's progress line reads the directory (:func:`running`). The thread runs while its record does
(each task a worker takes is given its reporter anew), and ends with it or with the run that owned the directory.
A scene far slower than the record's others is named in the log when it ends (:meth:`SceneProgress.scene_done`).

Workers on other machines (a remote Dask scheduler) cannot write there; their records show as running without
scene detail.
"""

from __future__ import annotations

import json
import logging
import os
import statistics
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

log = logging.getLogger(__name__)

#: Seconds between writes of a worker's state (while it changes)
FLUSH_S = 0.5
#: The name of the thread that writes them
WRITER_THREAD = "rockscreen-scene-progress"
#: A record running at least this long gets its scene detail on the progress line [s]
DETAIL_AFTER_S = 3.0
#: A scene is named in the log when it takes at least this long (a long record with sampling takes 5-7 s in an
#: ordinary run of the bundled records: below this, a warning would be noise) [s] ...
SLOW_SCENE_S = 30.0
#: ... and this many times the median of the record's other scenes (when it has at least 3) [-]
SLOW_FACTOR = 20.0


@dataclass
class SceneProgress:
    """A task's progress reporter (picklable: only the directory travels to the workers).

    Parameters
    ----------
    directory : str
        Where each worker process writes its state (``<pid>.json``); empty: report nothing, only the log of
        slow scenes.
    """

    directory: str = ""
    _state: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    _times: list = field(default_factory=list, init=False, repr=False, compare=False)
    _lock: threading.Lock | None = field(default=None, init=False, repr=False, compare=False)
    _changed: bool = field(default=False, init=False, repr=False, compare=False)
    #: set when the record is done: its writer thread ends
    _stop: threading.Event | None = field(default=None, init=False, repr=False, compare=False)

    def __getstate__(self):
        return {"directory": self.directory}

    def __setstate__(self, state):
        self.directory = state["directory"]
        self._state, self._times, self._lock, self._changed, self._stop = {}, [], None, False, None

    def record(self, record_id: str, n_scenes: int) -> None:
        """A record's screening starts, with ``n_scenes`` scenes (blocks) to simulate."""
        self._times = []
        self._set(record=record_id, scenes=n_scenes, done=0, block="", started=time.time(), scene_started=0.0)

    def scene(self, block_id: str) -> None:
        """A scene (the record and ``block_id``, in every plane it needs, with its samples) starts."""
        self._set(block=block_id, scene_started=time.time())

    def scene_done(self, *, block_id: str, seconds: float, detail) -> None:
        """A scene ended after ``seconds``; named in the log, with ``detail()`` (what the scene was doing, made only
        then), when far slower than the record's others."""
        others = self._times
        if seconds >= SLOW_SCENE_S and (len(others) < 3 or seconds >= SLOW_FACTOR * statistics.median(others)):
            median = f"{statistics.median(others):.2f} s" if others else "none yet"
            log.warning("slow scene: record %s, block %s took %.1f s (median of the record's other scenes: %s); %s",
                        self._state.get("record", "?"), block_id, seconds, median, detail())
        self._times.append(seconds)
        self._set(done=self._state.get("done", 0) + 1, block="")

    def finished(self) -> None:
        """The record is done: its state is removed at once, and its writer thread ends."""
        self._set(record="")
        if self._stop is not None:
            self._stop.set()
        if self.directory:
            try:
                os.remove(Path(self.directory) / f"{os.getpid()}.json")
            except OSError:
                pass

    def _set(self, **values) -> None:
        if not self.directory:
            self._state.update(values)
            return
        if self._lock is None:
            self._lock = threading.Lock()
        if self._stop is None or self._stop.is_set():       # a record starts: its writer
            self._stop = threading.Event()
            threading.Thread(target=self._flush_loop, args=(self._stop,), name=WRITER_THREAD, daemon=True).start()
        with self._lock:
            self._state.update(values)
            self._changed = True

    def _flush_loop(self, stop: threading.Event) -> None:
        path = Path(self.directory) / f"{os.getpid()}.json"
        while not stop.wait(FLUSH_S):
            if not path.parent.is_dir():     # the run that owned the directory has ended: so does this thread
                return
            assert self._lock is not None
            with self._lock:
                if not self._changed:
                    continue
                state, self._changed = dict(self._state), False
            try:
                tmp = path.with_suffix(".tmp")
                tmp.write_text(json.dumps(state))
                os.replace(tmp, path)
            except OSError:             # the run's directory is gone (the run ended) or not on this machine
                return


def running(directory: str | Path) -> list[str]:
    """One phrase per record that has run at least :data:`DETAIL_AFTER_S`: its scenes done and the scene
    running, e.g. ``"RSN1063_NORTHR_RRS: 5/14 scenes, block TRAF-01 running for 12 s"``."""
    now = time.time()
    out = []
    for path in sorted(Path(directory).glob("*.json")):
        try:
            s = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        if not s.get("record") or now - s.get("started", now) < DETAIL_AFTER_S:
            continue
        phrase = f"{s['record']}: {s.get('done', 0)}/{s.get('scenes', '?')} scenes"
        if s.get("block"):
            phrase += f", block {s['block']} running for {now - s.get('scene_started', now):.0f} s"
        out.append(phrase)
    return out
