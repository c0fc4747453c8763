"""``screen fragility``: multiple-stripe analysis, lognormal fragility fits, IM ranking, hazard integral.

Data flow (one task per record, on the same executors as ``screen``)::

    scan -> per record: load, pulse, IMs, then for each level the record scaled (all components
    by one factor) so that its IM equals the level, every block judged as ``screen`` judges it
    (certificate, simulator, orientation scan; p_overturn with [uncertainty] samples)
    -> fragility cache entry per record (a re-run or a resumed run computes only what is missing)
    -> stripes -> fits, bootstrap, IM efficiency and sufficiency -> hazard -> fragility.nc, report

This module runs that flow; its stages have their own homes: the stripes and their cache
(:mod:`.fragility_stripes`), the levels of ``--levels auto`` (:mod:`.fragility_levels`), the fits and the dataset
(:mod:`.fragility_assembly`) and the hazard's rates (:mod:`.fragility_hazard`).
"""
from __future__ import annotations

import dataclasses
import json
import logging
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from ..blocks import Inventory
from ..config import Config
from ..errors import UsageError
from ..records.intensity import COMPONENT_IMS
from ..records.listing import list_directory
from ..uncertainty.hazard import Component, HazardSet
from .fragility_assembly import ORIENTATIONS, assemble_fragility, fits_probabilities, stripe_warnings
from .fragility_levels import auto_stripes
from .fragility_stripes import run_stripes

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class FragilityRequest:
    """Everything ``screen fragility`` was asked for."""

    records_dir: Path
    blocks_csv: Path
    inventory: Inventory
    config: Config
    im: str
    #: the IM levels [SI]; None: ``--levels auto`` (:func:`auto_stripes`)
    levels: np.ndarray | None
    out_dir: Path
    hazard: HazardSet | None = None
    #: the horizontal component definition of PGA, PGV and Sa the fit uses
    component: Component = Component.rotd100
    #: the unit ``--levels`` was given in (label, factor to SI): the outputs' medians are in it
    level_unit: tuple[str, float] | None = None
    #: the buildings blocks stand in (``--buildings``), by id
    buildings: dict = dataclasses.field(default_factory=dict)
    n_workers: int = 1
    scheduler: str | None = None
    bootstrap: int = 200
    command: tuple = ()
    #: StationXML for records in counts (``--stationxml``; else ``*.xml`` in the records directory)
    stationxml: Path | None = None
    #: the probability fitted for a block of blank azimuth (:data:`ORIENTATIONS`)
    orientation: str = "random"


def _say_why_all_is_new(out_dir: Path, request: FragilityRequest) -> None:
    """Warn when the last fragility run into ``out_dir`` fitted the same IM under another component definition:
    the records are scaled to the levels under the new one, so no scaled scene of the last run can be reused."""
    path = out_dir / "fragility.nc"
    if not path.is_file():
        return
    try:
        with xr.open_dataset(path, engine="netcdf4") as last:
            im, component = str(last.attrs.get("im", "")), str(last.attrs.get("im_component", ""))
    except (OSError, ValueError):
        return
    if im == request.im and component and request.im in COMPONENT_IMS and component != request.component.value:
        log.warning("the last run fitted %s as %s, this one as %s (the hazard's definition, or --im-component): "
                    "the records are scaled to the levels under %s, so every scaled scene is simulated again (to "
                    "reuse the last run's, fit on %s: --im-component %s, with --hazard-scale converting the hazard)",
                    im, component, request.component.value, request.component.value, component, component)


def fragility(request: FragilityRequest, *, progress=None, say=None) -> dict:
    """Run the stripes (resumable), fit, integrate the hazard, write fragility.nc, fragility.html and
    fragility_assets.csv.

    Returns
    -------
    dict
        Counts, paths and warnings for the closing summary.
    """
    from ..records.listing import files_sha256
    from ..records.side_files import read_inventory, stationxml_paths
    from ..report.fragility_html import build_fragility_report
    from ..store import Family, OutputLock, publish_staged, write_atomic
    from ..store.exports import left_out, write_exports
    from ..store.sets import PLAIN_BEFORE_SETS
    from .cache import ensure_writable
    from .executors import make_executor

    out_dir = ensure_writable(request.out_dir, replaces=PLAIN_BEFORE_SETS[Family.FRAGILITY])
    station = read_inventory(request.records_dir, request.stationxml)
    levels = request.levels
    _say_why_all_is_new(out_dir, request)
    found = list_directory(request.records_dir, config=request.config)      # once, for every round of auto
    with OutputLock(out_dir, command=" ".join(request.command)):
        with make_executor(n_workers=request.n_workers, scheduler=request.scheduler) as executor:
            def run(lv: np.ndarray, prune: bool = True):
                return run_stripes(request.records_dir, request.inventory, request.config, im=request.im, levels=lv,
                                   executor=executor, out_dir=out_dir, progress=progress, station_inventory=station,
                                   stationxml_sha256=files_sha256(stationxml_paths(request.records_dir,
                                                                                   request.stationxml)),
                                   component=request.component, buildings=request.buildings, prune=prune,
                                   listing=found)

            if levels is None:                         # --levels auto
                levels, results, failures, counts = auto_stripes(
                    lambda lv: run(lv, prune=False), request.inventory, request.config, request.im, say=say,
                    outcome=ORIENTATIONS[request.orientation][0] if fits_probabilities(request.config) else "verdict")
            else:
                results, failures, counts = run(levels)
        if not results:
            raise UsageError(f"{request.records_dir}: no record could be scaled and judged; failures: "
                             + "; ".join(f"{f.record_id}: {f.reason}" for f in failures[:5]))
        ds = assemble_fragility(results, request.inventory, request.config, im=request.im, levels=levels,
                                hazard=request.hazard, bootstrap=request.bootstrap,
                                orientation=request.orientation, component=request.component,
                                level_unit=request.level_unit, progress=progress)
        if say is not None:
            say("writing fragility.nc, fragility.html (its figures) and the exports ...")
        ds.attrs.update({"history": f"{time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())} "
                                    f"{' '.join(request.command)}",
                         "rockscreen_config": json.dumps(request.config.to_dict(), sort_keys=True),
                         "inventory_file": str(request.blocks_csv),
                         "records_failed": "\n".join(f"{f.record_id}: {f.reason}" for f in failures),
                         "hazard_curve": request.hazard.path if request.hazard is not None else "",
                         "hazard_title": request.hazard.title if request.hazard is not None else "",
                         "hazard_synthetic": int(request.hazard.synthetic) if request.hazard is not None else 0})
        nc, html, csv_path, *exports = publish_staged(       # the set is published whole, or not at all
            out_dir, lambda stage: [write_atomic(ds, stage / "fragility.nc"),
                                    *build_fragility_report(ds, stage, hazard=request.hazard),
                                    *write_exports(ds, stage)],
            family=Family.FRAGILITY, command=" ".join(request.command))
    return {**counts, "scenes": int(ds.sizes["record"] * ds.sizes["im_level"] * ds.sizes["block"]),
            "failures": failures, "paths": (nc, html, csv_path, *exports),
            "warnings": stripe_warnings(ds) + [f"exports leave out {x}" for x in (left_out(ds) if exports else [])]}
