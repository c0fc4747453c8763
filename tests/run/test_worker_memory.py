"""A pool worker's memory: the pages its task freed handed back to the system (``executors.trimmed``), and the
workers ended once the run's last tasks are done (``release``).

The truth is the kernel's: its count of the process's resident pages (``/proc/self/statm``; memory freed inside the
heap, below a block still in use, stays resident until it is trimmed) and its table of processes.
"""

from __future__ import annotations

import gc
import os
import sys

import numpy as np
import pytest

from pipeline.run.executors import ProcessExecutor, SerialExecutor, _malloc_trim, process_alive, trim_heap, trimmed

#: Arrays of 64 KiB come from the heap (below glibc's mmap threshold of 128 KiB) [bytes].
CHUNK_BYTES = 64 * 1024
#: The freed heap the test makes resident [bytes].
FREED_BYTES = 64 * 1024 * 1024

glibc = pytest.mark.skipif(not sys.platform.startswith("linux") or _malloc_trim() is None,
                           reason="malloc_trim is glibc's (Linux)")


def _resident_bytes() -> int:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@glibc
def test_trimming_releases_heap_freed_below_a_block_in_use():
    chunks = [np.ones(CHUNK_BYTES // 8) for _ in range(FREED_BYTES // CHUNK_BYTES)]
    pinned = np.ones(CHUNK_BYTES // 8)            # allocated last: the heap's top stays in use
    del chunks
    before = _resident_bytes()
    assert trim_heap()
    after = _resident_bytes()
    assert before - after > FREED_BYTES // 2, (before, after)
    assert pinned.sum() == CHUNK_BYTES // 8


def _task(item, shared):
    if item == "fail":
        raise ValueError(shared)
    return item, shared


def test_a_trimmed_task_returns_its_result_and_raises_its_error():
    assert trimmed(_task, 3, "ctx") == (3, "ctx")
    with pytest.raises(ValueError, match="ctx"):
        trimmed(_task, "fail", "ctx")


def _pid(item, shared):
    return os.getpid()


def test_released_workers_end_and_a_later_map_starts_new_ones():
    with ProcessExecutor(2) as ex:
        first = {pid for _, pid in ex.map_unordered(_pid, range(4), None)}
        ex.release()
        assert first and not any(process_alive(pid) for pid in first)
        second = {pid for _, pid in ex.map_unordered(_pid, range(4), None)}
        assert second and not second & first
    with SerialExecutor() as ex:
        ex.release()
        assert [pid for _, pid in ex.map_unordered(_pid, range(2), None)] == [os.getpid()] * 2


def _private_dirty_bytes() -> int:
    with open("/proc/self/smaps_rollup") as fh:
        return next(int(line.split()[1]) * 1024 for line in fh if line.startswith("Private_Dirty:"))


def _collect(item, shared):
    before = _private_dirty_bytes()
    gc.collect()
    return gc.get_freeze_count(), _private_dirty_bytes() - before


@pytest.mark.skipif(not os.path.exists("/proc/self/smaps_rollup"), reason="reads Linux's /proc/self/smaps_rollup")
def test_a_workers_full_collection_leaves_the_pages_it_shares_with_the_server_shared():
    """Without the freeze, the collection wrote to the forkserver's imported objects and copied about 40 MB of
    shared pages into the worker."""
    with ProcessExecutor(1) as ex:
        [(_, (frozen, copied))] = list(ex.map_unordered(_collect, [0], None))
    assert frozen > 0
    assert copied < 8 * 1024 * 1024, copied
