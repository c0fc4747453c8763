"""The simulator is compiled once before the workers start (with helper processes on a first run), and a compilation
that takes a while is announced."""

from __future__ import annotations

import pytest

from pipeline.bodies import warmup


def test_a_long_compilation_is_announced_and_a_quick_one_is_silent(monkeypatch):
    said: list[str] = []
    warmup.compile_kernels(announce=said.append)         # compiled (or loaded) here; quick once cached
    quick = list(said)
    monkeypatch.setattr(warmup, "ANNOUNCE_AFTER_S", 0.0)  # anything now counts as long
    said.clear()
    elapsed = warmup.compile_kernels(announce=said.append)
    assert elapsed >= 0.0
    # the first call compiled or loaded every kernel: this one loads them all, and says so, never "compiling"
    assert said[0].startswith("loading the simulator") and said[-1].startswith("loaded the simulator in")
    # a fresh install compiles here: announced, with lines while it goes on; else nothing is said
    assert not quick or (quick[0].startswith(("compiling", "loading")) and quick[-1].startswith(("compiled",
                                                                                                "loaded")))


def test_the_counter_sees_a_compilation_and_not_a_call_of_compiled_code():
    """What decides "compiling" or "loading": numba's compile events, counted."""
    import numpy as np

    from pipeline.compiled import HAVE_NUMBA

    if not HAVE_NUMBA:
        return
    import numba

    counter = warmup.CompileCounter()
    with counter.listening():
        f = numba.njit(lambda x: x + 1.0)
        f(np.float64(1.0))                                # compiled here
    compiled = counter.n
    with counter.listening():
        f(np.float64(2.0))                                # the same signature: no compilation
    assert compiled >= 1 and counter.n == compiled


def test_every_warm_up_is_called_once_and_a_model_without_kernels_adds_none(monkeypatch):
    """Each shared warm-up first (the longest compilations), then each model's own in order, each exactly once; a
    model whose kernels are all shared (no warm-up of its own, as the scanned body in 3D) adds no call."""
    from types import SimpleNamespace

    from pipeline.compiled import HAVE_NUMBA

    if not HAVE_NUMBA:
        return
    made: list[str] = []

    def call(name):
        return lambda: made.append(name)

    shared = call("shared")
    def model(own, shared_calls=()):
        return SimpleNamespace(warmups=own, shared_warmups=shared_calls, draws_warmups=(), warmups_for=None)

    models = [model((), (shared,)), model((call("a"),)), model((call("b"), call("b2")), (shared,)),
              model((call("c"),))]
    monkeypatch.setattr(warmup.registry, "models_for", lambda shapes, settings: models)
    warmup.compile_kernels()
    assert made == ["shared", "a", "b", "b2", "c"]


def test_a_run_without_draws_does_not_compile_the_draws_kernels(monkeypatch):
    """The planar draws' sampled kernels (about half of a fresh install's compilation: 25 of 45 s for a box on
    2 cores) are called by the warm-up of a run that samples, and not by one with ``--samples 0``, which never
    calls them (its scenes are the planar scene models')."""
    from pipeline.bodies import planar
    from pipeline.compiled import HAVE_NUMBA
    from pipeline.rocking.block import BlockShape

    if not HAVE_NUMBA:
        return
    called: list[str] = []

    def recorder(name):
        return lambda *args: called.append(name)

    monkeypatch.setattr(planar, "kernels", lambda: (recorder("sample_verdicts"), recorder("sample_plane_outcomes")))
    box = [BlockShape(height_m=3.0, width_m=1.5, mu=0.5)]
    warmup.compile_kernels(shapes=box, sampling=False)
    assert called == []
    warmup.compile_kernels(shapes=box, sampling=True)
    assert set(called) == {"sample_verdicts", "sample_plane_outcomes"}


def test_helpers_take_the_calls_each_once_and_the_caller_ends_holding_every_one(tmp_path):
    """Calls of 0.3 s, one helper started at once: each call is taken by exactly one process, the helper takes some
    (it is free while the caller makes one), and the caller then makes every call it did not make itself (each
    loading what a helper compiled), so that it ends holding all of them."""
    import os

    from shared_calls import calls, helper, made_by

    from pipeline.bodies.compile_share import SharedCalls

    log, n = tmp_path / "made.txt", 12
    shared = SharedCalls(calls(log, n, 0.3), helpers=1, target=helper, args=(log, n, 0.3))
    assert shared.start_helpers() == 1 and shared.start_helpers() == 0          # once
    shared.run_here()
    made = made_by(log)
    here = [i for i, p in made if p == os.getpid()]
    there = [i for i, p in made if p != os.getpid()]
    assert there and len(set(there)) == len(there) and len(there) < n      # the helper took some, each once
    taken_here, loaded_here = here[:len(here) - len(there)], here[len(here) - len(there):]
    assert not set(taken_here) & set(there)                                # no call taken by both
    assert loaded_here == sorted(there)                                    # then made here: held here
    assert sorted(here) == list(range(n))
    assert shared.made_here == set(range(n))


def test_a_helper_that_took_no_call_is_ended_and_none_starts_after_the_end(tmp_path):
    """Calls quicker than a helper starts (a warm cache): the caller takes them all, ends the helper, which never
    made one, and starts none after the end."""
    import os
    import signal

    from shared_calls import calls, helper, made_by

    from pipeline.bodies.compile_share import SharedCalls

    log = tmp_path / "made.txt"
    shared = SharedCalls(calls(log, 3, 0.0), helpers=1, target=helper, args=(log, 3, 0.0))
    shared.start_helpers()
    shared.run_here()
    (process,) = shared.processes
    assert process.exitcode == -signal.SIGTERM                  # ended while it started, not waited for
    assert made_by(log) == [(i, os.getpid()) for i in range(3)]   # every call made here, once
    assert shared.start_helpers() == 0


@pytest.mark.slow
def test_the_wait_for_a_helper_leaves_the_announcements_free(tmp_path):
    """While the caller waits for a helper still making a call (a long compilation), the ticker's thread asks
    :meth:`start_helpers` on every line it says: that answers at once (the wait holds no lock it needs), so the
    lines go on during the wait. The helper takes the first call (3 s) before the caller starts; the caller makes
    the second (0.1 s), then waits."""
    import os
    import threading
    import time

    from shared_calls import calls, helper, made_by

    from pipeline.bodies.compile_share import SharedCalls

    log, pauses = tmp_path / "made.txt", (3.0, 0.1)
    shared = SharedCalls(calls(log, 2, pauses), helpers=1, target=helper, args=(log, 2, pauses))
    assert shared.start_helpers() == 1
    t_start = time.perf_counter()
    while not (log.exists() and any(p != os.getpid() for _, p in made_by(log))):
        assert time.perf_counter() - t_start < 30.0, "the helper took no call"
        time.sleep(0.05)
    waiting = threading.Thread(target=shared.run_here)
    waiting.start()
    time.sleep(0.6)                       # the caller has made its 0.1 s call and waits for the helper's 3 s one
    t0 = time.perf_counter()
    assert shared.start_helpers() == 0
    answered_s = time.perf_counter() - t0
    waiting.join()
    assert answered_s < 0.5 and shared.made_here == {0, 1}
    assert made_by(log)[0][1] != os.getpid()          # the first call was the helper's


def test_screen_compiles_with_a_helper_for_each_worker_beyond_the_first_on_the_cores_it_has(kocaeli, tmp_path,
                                                                                              monkeypatch):
    """``-n 1`` compiles in its one process; ``-n 2`` with one helper where two cores are there (none on one)."""
    import os

    from pipeline.cli import main

    seen: list[int] = []
    monkeypatch.setattr(warmup, "compile_kernels", lambda **kw: seen.append(kw["helpers"]) or 0.0)
    blocks = tmp_path / "b.csv"
    blocks.write_text("id,height_m,width_m,mu\nA,1.0,0.25,0.7\n")
    for n in (1, 2):
        assert main(["--records", str(kocaeli), "--blocks", str(blocks), "--out", str(tmp_path / f"out{n}"),
                     "--samples", "0", "-n", str(n), "-q"]) == 0
    assert seen == [0, min(2, len(os.sched_getaffinity(0))) - 1]


@pytest.mark.parametrize("how, expected", [("script with the guard", True), ("script without it", False),
                                           ("python -c", True), ("package's __main__", True),
                                           ("module without the guard, -m", False)])
def test_helpers_start_only_where_the_program_would_not_run_again_in_them(tmp_path, how, expected):
    """A spawned helper imports the caller's main module (unless it is a package's ``__main__``), so a program
    without ``if __name__ == "__main__":`` would run again in it: there no helper starts and the caller compiles
    alone."""
    import subprocess
    import sys

    code = "from pipeline.bodies.compile_share import spawn_safe\nprint(spawn_safe())\n"
    guarded = "if __name__ == '__main__':\n" + "".join(f"    {line}\n" for line in code.splitlines())
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "__init__.py").write_text("")
    (tmp_path / "pkg" / "__main__.py").write_text(code)
    (tmp_path / "plain.py").write_text(code)
    (tmp_path / "prog.py").write_text(guarded)
    argv = {"script with the guard": [str(tmp_path / "prog.py")], "script without it": [str(tmp_path / "plain.py")],
            "python -c": ["-c", code], "package's __main__": ["-m", "pkg"],
            "module without the guard, -m": ["-m", "plain"]}[how]
    out = subprocess.run([sys.executable, *argv], cwd=tmp_path, capture_output=True, text=True, check=True).stdout
    assert out.strip() == str(expected)


def test_a_run_without_draws_warms_up_the_planar_scene_models_its_blocks_may_reach():
    """Without draws, a block that cannot rock (mu = tan alpha) calls no rocking model's warm-up and a block that
    rocks no sliding one, each model's warm-up a call of its own; with draws (which vary alpha and mu), every model."""
    from pipeline.bodies.planar import scene_warmups
    from pipeline.rocking import models
    from pipeline.rocking.block import BlockShape

    rocking = models.by_physics(models.Physics.rocking_vertical).warmup      # pure rocking's kernel
    sliding = models.by_physics(models.Physics.sliding).warmup
    general = models.by_physics(models.Physics.general).warmup
    tie, slender = BlockShape(height_m=3.0, width_m=1.5, mu=0.5), BlockShape(height_m=3.0, width_m=1.0, mu=0.5)
    assert rocking not in scene_warmups([tie], False) and {sliding, general} <= set(scene_warmups([tie], False))
    assert sliding not in scene_warmups([slender], False) and {rocking, general} <= set(scene_warmups([slender], False))
    everything = tuple(m.warmup for m in models.MODELS)
    assert scene_warmups([tie], True) == everything and scene_warmups(None, False) == everything
    assert set(scene_warmups([tie, slender], False)) == set(everything)
