"""The shape of the code: physics and readers are libraries that never import the application."""

from __future__ import annotations

import subprocess
import sys

import pytest

#: Application modules no library may load.
APPLICATION = ("pipeline.cli", "pipeline.run", "pipeline.screening", "pipeline.config", "pipeline.report",
               "pipeline.store", "pipeline.schema", "pipeline.margins", "pipeline.accuracy", "pipeline.chart",
               "pipeline.infer")


@pytest.mark.parametrize("library", ["pipeline.rocking.planner", "pipeline.rocking.orientation",
                                     "pipeline.rocking.reference", "pipeline.records.loader", "pipeline.pulses",
                                     "pipeline.criteria", "pipeline.closed_forms", "pipeline.blocks",
                                     "pipeline.rocking.sampled", "pipeline.records.intensity",
                                     "pipeline.uncertainty.scenes", "pipeline.uncertainty.fragility",
                                     "pipeline.uncertainty.hazard", "pipeline.uncertainty.sampling",
                                     "pipeline.rocking.rules", "pipeline.rocking.block", "pipeline.records.duplicates",
                                     "pipeline.records.common", "pipeline.rocking.contact", "pipeline.rocking.handoff",
                                     "pipeline.uncertainty.hazard_files", "pipeline.floors.model",
                                     "pipeline.floors.motion"])
def test_libraries_load_no_application_module(library):
    # a fresh interpreter: what importing the library alone pulls in
    code = (f"import sys, {library}\n"
            f"bad = sorted(m for m in sys.modules if m.startswith({APPLICATION!r}))\n"
            "print(','.join(bad))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "", f"importing {library} loads {out}"


def _loaded(library: str, prefixes: tuple[str, ...]) -> str:
    """The modules starting with ``prefixes`` that importing ``library`` alone loads, in a fresh interpreter."""
    code = (f"import sys, {library}\n"
            f"print(','.join(sorted(m for m in sys.modules if m.startswith({prefixes!r}))))")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()


#: The physics libraries: they read blocks as arrays or typed blocks, never the inventory module (a CSV reader).
PHYSICS = ("pipeline.rocking.planner", "pipeline.rocking.orientation", "pipeline.rocking.rules",
           "pipeline.rocking.sampled", "pipeline.rocking.contact", "pipeline.rocking.handoff",
           "pipeline.rocking.geometry", "pipeline.criteria", "pipeline.closed_forms", "pipeline.pulses",
           "pipeline.records.loader", "pipeline.records.coordinates", "pipeline.uncertainty.scenes",
           "pipeline.uncertainty.orientations", "pipeline.uncertainty.fragility", "pipeline.uncertainty.sampling",
           "pipeline.floors.model", "pipeline.floors.motion", "pipeline.floors.buildings", "pipeline.event.assets",
           "pipeline.event.shakemap", "pipeline.event.shakecast")


@pytest.mark.parametrize("library", PHYSICS)
def test_physics_libraries_do_not_load_the_inventory_module(library):
    assert _loaded(library, ("pipeline.blocks",)) == ""


@pytest.mark.parametrize("library", ["pipeline.floors.model", "pipeline.floors.motion", "pipeline.floors.buildings"])
def test_floors_do_not_load_the_rocking_simulator(library):
    assert _loaded(library, ("pipeline.rocking",)) == ""
