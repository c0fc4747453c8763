"""The motion each block stands on: the ground record, or a floor's motion computed from it once per floor.

:func:`floor_record` is a :class:`~pipeline.records.record.Record` whose horizontals (and their velocities) are
those of a floor (:func:`.motion.floor_response`), its vertical the ground's; :class:`FloorMotions` groups the
blocks of an inventory by the floor they stand on (:func:`.buildings.floor_groups`) and gives each group its
record, computed on first use and shared by the group's blocks.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..records.record import Record
from .buildings import Placement, floor_groups
from .motion import Building, floor_filter, floor_response


def floor_record(rec: Record, building: Building, height_m: float) -> Record:
    """The motion on the floor at ``height_m`` [m] of ``building``: both horizontals (and their velocities)
    through the building's modes; the vertical unchanged."""
    flt = floor_filter(building, height_m)
    acc, vel = floor_response(rec.horizontal_ms2, rec.dt_s, flt, rec.velocity_ms)
    return dataclasses.replace(rec, horizontal_ms2=acc, velocity_ms=vel, notes=[
        *rec.notes, f"floor at {height_m:g} m of building {building.building_id} ({flt.periods_s.size} modes, "
                    f"{flt.mass_share:.1%} of the mass)"])


class FloorMotions:
    """The record each block of an inventory stands on, under one ground record.

    Parameters
    ----------
    rec : Record
        The ground record.
    placements : list of Placement
        Where each block stands (:func:`.buildings.place_blocks`).

    Attributes
    ----------
    groups : dict
        Floor key (building id, height [m]), or ``()`` for the ground and ground floors -> block indices.
    """

    def __init__(self, rec: Record, placements: list[Placement]):
        self.groups = floor_groups(placements)
        self._buildings = {p.building.building_id: p.building for p in placements if p.building is not None}
        self._records: dict[tuple, Record] = {(): rec}
        self._key_of = {int(j): key for key, idx in self.groups.items() for j in idx}

    @property
    def upper_floors(self) -> dict[tuple, np.ndarray]:
        """The groups of the blocks standing above the ground (their motion is not the ground's)."""
        return {key: idx for key, idx in self.groups.items() if key}

    def record(self, key: tuple) -> Record:
        """The motion of floor ``key`` (the ground record for ``()``), computed once."""
        if key not in self._records:
            self._records[key] = floor_record(self._records[()], self._buildings[key[0]], key[1])
        return self._records[key]

    def of_block(self, j: int) -> Record:
        """The motion block ``j`` stands on."""
        return self.record(self._key_of[int(j)])
