"""The simulator is compiled once in the calling process, and a compilation that takes a while is announced."""

from __future__ import annotations

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


def test_the_shares_make_every_warm_up_once_and_a_model_without_kernels_takes_no_share(monkeypatch):
    """Two processes' shares: each model's own warm-up and each shared one exactly once between them; a model whose
    kernels are all shared (warmup None, as the scanned body in 3D) adds no call, so the calls alternate as if it
    were not there."""
    from types import SimpleNamespace

    from pipeline.compiled import HAVE_NUMBA

    if not HAVE_NUMBA:
        return
    made: list[str] = []

    def call(name):
        return lambda: made.append(name)

    shared = call("shared")
    models = [SimpleNamespace(warmup=None, shared_warmups=(shared,), draws_warmups=()),
              SimpleNamespace(warmup=call("a"), shared_warmups=(), draws_warmups=()),
              SimpleNamespace(warmup=call("b"), shared_warmups=(shared,), draws_warmups=()),
              SimpleNamespace(warmup=call("c"), shared_warmups=(), draws_warmups=())]
    monkeypatch.setattr(warmup.registry, "models_for", lambda shapes, settings: models)
    warmup.compile_kernels(share=(0, 2))
    first = list(made)
    warmup.compile_kernels(share=(1, 2))
    assert first == ["a", "c"] and made[len(first):] == ["b", "shared"]


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
