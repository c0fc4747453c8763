"""The run layer: orchestration of the libraries into the jobs a user runs.

:func:`screen` (:mod:`.screen`) is the main job; :mod:`.batch` the screening stage
(scan, plan, execute, assemble), :mod:`.cache` the scene and margin caches,
:mod:`.executors` serial, process and Dask execution behind one interface.
"""

from .screen import RunInterrupted, ScreenRequest, ScreenResult, screen

__all__ = ["RunInterrupted", "ScreenRequest", "ScreenResult", "screen"]
