"""The run layer: orchestration of the libraries into the jobs a user runs.

:func:`screen` (:mod:`.stages`) is the main job; :mod:`.batch` the screening stage
(scan, plan, execute, assemble), :mod:`.cache` the scene and margin caches,
:mod:`.executors` serial, process and Dask execution behind one interface,
:mod:`.uptodate` the check that lets a run with nothing new skip everything.

The names below are imported on first use (PEP 562), so that :mod:`.uptodate` can be
imported without the science stack.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .stages import RunInterrupted, ScreenRequest, ScreenResult, screen

__all__ = ["RunInterrupted", "ScreenRequest", "ScreenResult", "screen"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        return getattr(importlib.import_module(".stages", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
