"""A spy on a module's function: the calls made to it through the module, counted."""

from __future__ import annotations

from types import ModuleType


def count_calls(monkeypatch, module: ModuleType, name: str) -> list[int]:
    """A list that gains an item at every call of ``module.name`` (which goes on to run), for the test's length."""
    calls: list[int] = []
    run = getattr(module, name)

    def spy(*args, **kwargs):
        calls.append(1)
        return run(*args, **kwargs)

    monkeypatch.setattr(module, name, spy)
    return calls
