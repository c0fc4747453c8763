"""The per-scene results as a typed table, and the per-scene variables' names as attributes.

:class:`SceneColumns` is the one table between the simulator and every reader of its per-scene results: one
array per variable of the schema's :data:`~pipeline.schema.SIMULATION_VARS` and
:data:`~pipeline.schema.PROBABILITY_VARS` (the fields are those names, in that order; a test keeps them equal).
The screening fills it from each :class:`~pipeline.rocking.scene.Scene` in one place
(:func:`pipeline.run.screening.scene_values`, the only renames); the scene cache and the netCDF writer take it by
iterating its fields (:meth:`SceneColumns.columns`); ``screen fragility`` and ``screen bench`` read its fields.

:data:`SCENE` names the per-scene variables of ``screening.nc`` for the readers of a dataset:
``ds[SCENE.p_overturn]``. A name that is not a per-scene variable of the schema raises ``AttributeError``
where it is read, and a test checks every ``SCENE.<name>`` in the package.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from .schema import FLOOR_VARS, PROBABILITY_VARS, PULSE_BLOCK_VARS, SIMULATION_VARS


@dataclass
class SceneColumns:
    """The simulator's and the sampling's per-scene variables of some scenes (NaN / -1: not evaluated).

    Each field is an array over the scenes (the blocks of one record, or records x blocks when stacked); its
    meaning, units and flags are the schema's entry of the same name.
    """

    physics: np.ndarray
    response: np.ndarray
    overturn_simulated: np.ndarray
    theta_max: np.ndarray
    n_impacts: np.ndarray
    time_overturn: np.ndarray
    friction_demand: np.ndarray
    friction_exceeded: np.ndarray
    sliding_max: np.ndarray
    free_flight: np.ndarray
    time_free_flight: np.ndarray
    governing_azimuth: np.ndarray
    orientation: np.ndarray
    planes_simulated: np.ndarray
    contact_modes: np.ndarray
    simulation_guard: np.ndarray
    p_overturn: np.ndarray
    p_overturn_low: np.ndarray
    p_overturn_high: np.ndarray
    robustness: np.ndarray
    samples_drawn: np.ndarray
    samples_overturned: np.ndarray
    samples_without_verdict: np.ndarray
    sample_simulations: np.ndarray
    p_overturn_azimuth: np.ndarray
    p_overturn_random_orientation: np.ndarray
    p_overturn_random_orientation_low: np.ndarray
    p_overturn_random_orientation_high: np.ndarray

    @classmethod
    def empty(cls, shape) -> SceneColumns:
        """A table of ``shape`` (an int, or records x blocks) with every value NaN (not evaluated)."""
        return cls(**{f.name: np.full(shape, np.nan) for f in fields(cls)})

    @classmethod
    def stack(cls, tables: list[SceneColumns]) -> SceneColumns:
        """The tables of several records, one row each (records x blocks)."""
        return cls(**{f.name: np.stack([getattr(t, f.name) for t in tables]) for f in fields(cls)})

    def put(self, index, **values) -> None:
        """Set the scenes at ``index`` of the fields named by the keywords (a name that is not a field raises
        ``AttributeError``)."""
        for name, value in values.items():
            column = getattr(self, name)
            column[index] = value

    def columns(self) -> dict[str, np.ndarray]:
        """The fields as ``{schema name: array}``, in the schema's order."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


class _VariableNames:
    """Attribute access to the names of a group of schema variables: ``SCENE.p_overturn`` is ``"p_overturn"``."""

    def __init__(self, names: tuple[str, ...]) -> None:
        self._names = frozenset(names)

    def __getattr__(self, name: str) -> str:
        if name.startswith("_") or name not in self._names:
            raise AttributeError(f"{name!r} is not a per-scene variable of the schema")
        return name


#: The per-scene variables of ``screening.nc`` (records x blocks) that the tasks compute, by name.
SCENE = _VariableNames(PULSE_BLOCK_VARS + SIMULATION_VARS + PROBABILITY_VARS + FLOOR_VARS)
