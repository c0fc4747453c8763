"""The per-scene budget a user can see: the record and scene a worker is on, and slow scenes named."""

from __future__ import annotations

import logging
import os
import pickle
import time

from pipeline import scene_progress
from pipeline.scene_progress import SceneProgress, running


def test_a_long_record_is_named_with_its_scenes_and_the_scene_running(tmp_path, monkeypatch):
    monkeypatch.setattr(scene_progress, "DETAIL_AFTER_S", 0.0)
    prog = pickle.loads(pickle.dumps(SceneProgress(str(tmp_path))))      # as a worker receives it
    prog.record("RSN1063_NORTHR_RRS", 14)
    prog.scene("TRAF-01")
    prog.scene_done(block_id="TRAF-01", seconds=0.1, detail=lambda: "")
    prog.scene("COL-1")
    time.sleep(3 * scene_progress.FLUSH_S)
    (line,) = running(tmp_path)
    assert line.startswith("RSN1063_NORTHR_RRS: 1/14 scenes, block COL-1 running for ")
    prog.finished()
    assert running(tmp_path) == []


def test_a_record_not_yet_long_is_not_detailed(tmp_path):
    prog = SceneProgress(str(tmp_path))
    prog.record("R", 3)
    prog.scene("B")
    time.sleep(3 * scene_progress.FLUSH_S)
    assert running(tmp_path) == []                 # under DETAIL_AFTER_S


def test_a_scene_far_slower_than_its_neighbours_is_named_in_the_log(monkeypatch, caplog):
    monkeypatch.setattr(scene_progress, "SLOW_SCENE_S", 1.0)
    prog = SceneProgress()
    prog.record("R", 5)
    for b in ("A", "B", "C"):
        prog.scene_done(block_id=b, seconds=0.01, detail=lambda: "")
    with caplog.at_level(logging.WARNING):
        prog.scene_done(block_id="D", seconds=0.5, detail=lambda: "fast enough")
        prog.scene_done(block_id="E", seconds=2.0, detail=lambda: "physics general, contact modes rock, slide_rock")
    (rec,) = [r for r in caplog.records if "slow scene" in r.getMessage()]
    assert "record R, block E took 2.0 s" in rec.getMessage() and "slide_rock" in rec.getMessage()


def test_the_writer_thread_ends_with_the_run_that_owned_its_directory(tmp_path):
    import shutil
    import threading

    d = tmp_path / "scenes"
    d.mkdir()
    before = threading.active_count()
    prog = SceneProgress(str(d))
    prog.record("R", 1)
    assert threading.active_count() == before + 1
    shutil.rmtree(d)
    time.sleep(3 * scene_progress.FLUSH_S)
    assert threading.active_count() == before


def _writers() -> int:
    import threading

    return sum(t.name == scene_progress.WRITER_THREAD for t in threading.enumerate())


def test_a_worker_s_writer_threads_end_with_their_records(tmp_path):
    """Each task a worker takes unpickles its reporter anew; a record's writer ends when the record does, so that a
    worker does not gather one thread per record it screened. A reporter used for the next record (the serial
    executor keeps one) writes again."""
    before = _writers()
    for k in range(5):
        prog = pickle.loads(pickle.dumps(SceneProgress(str(tmp_path))))      # as a worker receives each task
        prog.record(f"R{k}", 1)
        prog.finished()
    time.sleep(3 * scene_progress.FLUSH_S)
    assert _writers() == before
    prog.record("again", 2)
    prog.scene("B")
    time.sleep(3 * scene_progress.FLUSH_S)
    assert _writers() == before + 1
    assert (tmp_path / f"{os.getpid()}.json").exists()
    prog.finished()
