"""The simulator is compiled once in the calling process, and a compilation that takes a while is announced."""

from __future__ import annotations

from pipeline.rocking import warmup


def test_a_long_compilation_is_announced_and_a_quick_one_is_silent(monkeypatch):
    said: list[str] = []
    warmup.compile_kernels(announce=said.append)         # compiled (or loaded) here; quick once cached
    quick = list(said)
    monkeypatch.setattr(warmup, "ANNOUNCE_AFTER_S", 0.0)  # anything now counts as long
    said.clear()
    elapsed = warmup.compile_kernels(announce=said.append)
    assert elapsed >= 0.0
    assert said[0].startswith("compiling the simulator") and said[-1].startswith("compiled the simulator in")
    # a fresh install compiles here: announced, with lines while it goes on; else nothing is said
    assert not quick or (quick[0].startswith("compiling") and quick[-1].startswith("compiled"))
