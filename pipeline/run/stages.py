"""The main job as named stages: prepare -> screen (scan, plan, execute, assemble) -> margins -> write -> report.

:func:`screen` takes a :class:`ScreenRequest` and returns a :class:`ScreenResult`;
the command line only parses arguments into the request and prints the
result. Each stage is a function of its own, so a new stage (uncertainty,
fragility) is one more call here, not a change to the CLI.
"""

from __future__ import annotations

import hashlib
import json
import logging
import shlex
import sys
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import xarray as xr

from ..blocks import Inventory
from ..config import Config
from ..constants import REFERENCE_PAPER
from ..errors import NoRecordsError, RecordsNotFoundError, RockscreenError, raised_by_interrupt
from ..records.listing import files_sha256, list_directory
from ..records.side_files import read_declared_units, stationxml_paths
from ..records.side_files import read_inventory as read_station_inventory
from ..report.html import build_report
from ..rocking.settings import SimulationConfig
from ..store import (
    STATE_DIR,
    Family,
    OutputLock,
    carry,
    check_output_tree,
    describe,
    output_names,
    publish,
    remove_stale_temporaries,
    removed_unless_published,
    signals_held,
    staging_dir,
    write_atomic,
)
from . import uptodate
from .batch import BatchOutcome, run
from .cache import ensure_writable, scene_cache_dir, writable_target
from .executors import checked_workers, make_executor
from .margins import add_margins

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ScreenRequest:
    """Everything a screening run needs (what ``screen --records DIR --blocks CSV ...`` parses into).

    Attributes
    ----------
    records_dir : Path
        Directory of records.
    blocks_csv : Path
        The inventory file (recorded in the provenance).
    inventory : Inventory
        The blocks read from ``blocks_csv``.
    config : Config
        The effective configuration.
    out_dir : Path
        Output directory (results, report, run state).
    stationxml : Path, optional
        StationXML for records in counts (else ``*.xml`` in ``records_dir``).
    n_workers : int
        Local worker processes (1: serial), or Dask workers with ``scheduler = "local"``.
    scheduler : str, optional
        Dask: ``"local"`` or ``tcp://HOST:PORT``.
    force : bool
        Recompute every record and block.
    command : list of str
        The command line, for the lock and the provenance.
    key : dict, optional
        The inputs' digests (:func:`pipeline.run.uptodate.fingerprint`), taken before the run
        started; a complete run records them in the output's manifest, so that the next run with
        nothing new can skip everything. None: no manifest is written.
    """

    records_dir: Path
    blocks_csv: Path
    inventory: Inventory
    config: Config
    out_dir: Path
    stationxml: Path | None = None
    n_workers: int = 1
    scheduler: str | None = None
    force: bool = False
    command: list[str] = field(default_factory=list)
    key: dict | None = None
    #: the buildings blocks stand in (``--buildings``), by id
    buildings: dict = field(default_factory=dict)


@dataclass
class ScreenResult:
    """What a run produced and the counts of its closing summary."""

    screening_path: Path
    report_path: Path
    assets_path: Path
    #: counts of the screening stage (records, scenes by physics / response / orientation, wall time)
    counts: dict
    #: counts of the margins stage (computed, reused, simulations, unavailable records, wall time)
    margins: dict

    @property
    def records_failed(self) -> int:
        return int(self.counts["records_failed"])


class RunInterrupted(RockscreenError, KeyboardInterrupt):
    """Ctrl-C during a run: what was computed is kept in the scene cache."""

    def __init__(self, kept: int, cache_dir: Path, out_dir: Path, *, forced: bool = False, published: bool = False,
                 previous: str = ""):
        self.kept, self.cache_dir, self.out_dir = kept, cache_dir, out_dir
        again = ("Run the same command without --force to finish from them (with --force every record is "
                 "screened again)" if forced else "Run the same command again to finish")
        if published:
            super().__init__(f"interrupted after this run's results were published: {out_dir} holds them, complete "
                             "(report.html and assets.csv included).")
            return
        held = (f"{out_dir} still shows {previous}, complete" if previous else
                f"{out_dir} holds no earlier results")
        super().__init__(f"interrupted: {kept} record(s) screened in this run are saved in {cache_dir} and will "
                         f"not be screened again by a run without --force; {held}. {again}.")


def package_versions() -> str:
    """Versions of rockscreen and the libraries its results depend on, as JSON."""
    out = {}
    for n in ("rockscreen", *uptodate.LIBRARIES):
        try:
            out[n] = metadata.version(n)
        except metadata.PackageNotFoundError:
            pass
    return json.dumps(out, sort_keys=True)


def compile_simulator(inventory: Inventory, *, settings: SimulationConfig, sampling: bool, announce=None,
                      workers: int = 1) -> float:
    """Compile the simulator in this process before any worker needs it: the kernels of every body model that may
    claim a block of ``inventory`` under the simulator's ``settings``, those of its draws only where the run
    ``sampling`` (:func:`pipeline.bodies.warmup.compile_kernels`; ``announce`` is told when it takes a while: the
    first run of an install), where it compiles with a helper for each of the run's ``workers`` beyond the first
    that has a core of its own; seconds taken."""
    from ..bodies.warmup import compile_kernels
    from .executors import available_cores

    return compile_kernels(announce=announce, shapes=inventory.shapes(), settings=settings, sampling=sampling,
                           helpers=min(workers, available_cores()) - 1)


def buildings_of(path: Path | None, inventory: Inventory) -> dict:
    """The buildings of a ``--buildings`` CSV (none: ``{}``), checked against the inventory's placements (the
    errors list every block)."""
    from ..floors.buildings import place_blocks, read_buildings

    buildings = read_buildings(path) if path is not None else {}
    place_blocks(inventory, buildings)
    return buildings


def rebuild_report(results_path: Path, out_dir: Path | None, *, all_figures: bool = False,
                   command: str = "screen report") -> tuple[Path, Path]:
    """``screen report``: the asset-risk report and ``assets.csv`` from a ``screening.nc`` alone, the figures that
    ``screen`` drew into that output reused (kept by content; a changed figure is drawn again). It holds the
    output's lock while it reads and writes, so that it never pairs the files of a screening under way.

    Raises
    ------
    OutputLockedError
        When a run is writing that output.
    """
    cache = Path(results_path).parent / STATE_DIR / "figures"
    out = Path(out_dir) if out_dir is not None else Path(results_path).parent
    check_output_tree(Path(results_path).parent,              # its figure cache is pruned too
                      output_names=output_names(Path(results_path).parent))
    with OutputLock(out, command=command):
        stage = staging_dir(out, family=Family.SCREENING)
        with removed_unless_published(stage):
            kept = carry(stage, out, [n for n in OUTPUT_SET if n not in REPORT_FILES])
            build_report(results_path, stage, all_figures=all_figures,
                         figure_cache=cache if cache.is_dir() else None, home=out)
            with signals_held():                    # a signal during the switch is taken after it: never half a set
                paths = publish(stage, out, [*kept, *REPORT_FILES], command=command)
        return paths[-2], paths[-1]


def provenance(request: ScreenRequest) -> dict:
    """Global attributes recording how the results were made."""
    return {
        "history": f"{time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())} {Path(sys.argv[0]).name} "
                   f"{shlex.join(request.command)}",
        "rockscreen_config": json.dumps(request.config.to_dict(), sort_keys=True),
        "rockscreen_config_sha256": request.config.digest(),
        "package_versions": package_versions(),
        "inventory_file": str(request.blocks_csv),
        "inventory_sha256": hashlib.sha256(Path(request.blocks_csv).read_bytes()).hexdigest(),
        "records_directory": str(request.records_dir),
        "references": f"{REFERENCE_PAPER}; Housner (1963) BSSA 53(2); Shahi & Baker (2014) BSSA 104(5)",
    }


def screen(request: ScreenRequest, *, progress=None, say=None) -> ScreenResult:
    """Screen every record against every block, incrementally, and write results and the report.

    Stages: :func:`prepare` (inputs and the output directory), then under the output lock
    :func:`pipeline.run.batch.run` (scan, plan, execute, assemble), :func:`margins_stage`,
    :func:`write_stage` and :func:`report_stage`. ``progress``: the display of the records' and margins' tasks;
    ``say(stage)``: told when the writing starts (the tasks' display is silent there).

    Raises
    ------
    RunInterrupted
        On Ctrl-C; the work done is kept in the scene cache.
    OutputError, OutputLockedError, RockscreenError
        Unwritable output, another run holding the lock, bad input.
    """
    checked_workers(request.n_workers)
    station_inventory, stationxml_sha, declared, found, out_dir = prepare(request)
    started, published = time.time(), False
    try:
        with OutputLock(out_dir, command=shlex.join(request.command)) as lock:
            if lock.stale_owner:
                log.warning("took over the lock of a run that died (pid %s, started %s); %s shows %s",
                            lock.stale_owner.get("pid"), lock.stale_owner.get("started_utc"), out_dir,
                            describe(out_dir, Family.SCREENING) or "no earlier results")
            remove_stale_temporaries(out_dir)
            uptodate.invalidate(out_dir)        # the outputs may change from here on
            with make_executor(n_workers=request.n_workers, scheduler=request.scheduler) as executor:
                log.debug("prepare: %d record(s), %d unreadable, %d not records, %d duplicate(s); executor %s",
                          len(found.sources), len(found.failures), len(found.not_records), len(found.duplicates),
                          executor.name)
                outcome = run(request.records_dir, request.inventory, request.config, out_dir=out_dir,
                              executor=executor, force=request.force, station_inventory=station_inventory,
                              declared_units=declared, stationxml_sha256=stationxml_sha, progress=progress,
                              listing=found, buildings=request.buildings)
                margin_cache = outcome.cache.margins() if outcome.cache is not None else None
                log.debug("screen: %s", {k: v for k, v in outcome.counts.items() if isinstance(v, (int, float))})
                results, histories, margins = margins_stage(outcome, executor, cache=margin_cache,
                                                            progress=progress)
                log.debug("margins: %s", margins)
            # the output set is staged, then published together: a failed write leaves the previous set intact
            if say is not None:
                say("writing screening.nc, pulses.nc, histories.nc and the report ...")
            stage = staging_dir(out_dir, family=Family.SCREENING)
            with removed_unless_published(stage):   # a failed write (a full disk) leaves no staged set behind
                staged = write_stage(outcome, results, histories, stage, provenance(request),
                                     margin_cache=margin_cache)
                log.debug("write: %s", staged)
                counts = outcome.counts
                failed = [(str(r), str(st)) for r, st in zip(results["record"].values, results["status"].values)
                          if st != "ok"]
                del outcome, results, histories     # written: the report reads the files, not these
                report_stage(staged, figure_cache=out_dir / STATE_DIR / "figures", home=out_dir)
                with signals_held():                # a signal during the swap is taken after it: never half a set
                    path, _, _, report, assets = publish(stage, out_dir, OUTPUT_SET,
                                                         command=shlex.join(["screen", *request.command]))
                    published = True
            log.debug("report: %s, %s", report, assets)
            if request.key is not None:
                uptodate.write_manifest(out_dir, request.key, counts=counts, margins=margins, failures=failed)
    except BaseException as exc:
        if not raised_by_interrupt(exc):        # (a Ctrl-C a C extension's import turned into its own error is one)
            raise
        cache_dir = scene_cache_dir(out_dir)
        kept = sum(1 for p in cache_dir.glob("*.npz") if p.stat().st_mtime >= started) if cache_dir.is_dir() else 0
        raise RunInterrupted(kept, cache_dir, out_dir, forced=request.force, published=published,
                             previous=describe(out_dir, Family.SCREENING)) from None
    return ScreenResult(path, report, assets, counts, margins)


def prepare(request: ScreenRequest) -> tuple:
    """Stage 1: the StationXML inventory and its digest, the declared units, the scan of the records
    directory, then a writable output directory (nothing is created when there is nothing to screen).

    Raises
    ------
    NoRecordsError
        When the directory holds no file that is, or looks like, a strong-motion record.
    """
    if not Path(request.records_dir).is_dir():
        raise RecordsNotFoundError(f"{request.records_dir}: records directory not found; give an existing "
                                   "directory to --records")
    found = list_directory(request.records_dir, config=request.config)
    if not found.sources and not found.failures:
        listed = "; ".join(f"{Path(p).name}: {r}" for p, r in found.not_records[:5])
        raise NoRecordsError(
            f"{request.records_dir}: no strong-motion record found ({found.files_seen} file(s) looked at"
            + (f"; {listed}" + ("; ..." if len(found.not_records) > 5 else "") if listed else "")
            + "). Put AT2, COSMOS, CSMIP/DMG, K-NET, SAC, MiniSEED or other obspy-readable records there, "
              "or point --records at the directory that holds them")
    station_inventory = read_station_inventory(request.records_dir, request.stationxml)
    stationxml_sha = files_sha256(stationxml_paths(request.records_dir, request.stationxml))
    declared = read_declared_units(request.records_dir, request.config)
    return station_inventory, stationxml_sha, declared, found, ensure_writable(request.out_dir,
                                                                             replaces=OUTPUT_SET)


def preflight(records_dir: Path, out_dir: Path) -> None:
    """What can be checked in a moment, before the simulator is compiled or loaded: the records directory holds a
    file, and the output directory can be written (the inputs stage checks both again, in full).

    Raises
    ------
    NoRecordsError
        The records directory holds no file at all.
    OutputError
        The output directory cannot be written.
    """
    if not any(p.is_file() for p in Path(records_dir).rglob("*")):
        raise NoRecordsError(f"{records_dir}: no strong-motion record found: the records directory is empty; put "
                             "the records there, or point --records at the directory that holds them")
    writable_target(out_dir)


def margins_stage(outcome: BatchOutcome, executor, *, cache=None, progress=None
                  ) -> tuple[xr.Dataset, xr.Dataset, dict]:
    """Stage 3: governing records, margins and histories, on the run's executor (``cache``: a
    :class:`~pipeline.run.cache.MarginCache` of earlier scans; ``progress``: as for the screening)."""
    t0 = time.perf_counter()
    results, histories, summary = add_margins(outcome.results, outcome.sources, outcome.context, executor,
                                              cache=cache, progress=progress)
    return results, histories, dict(summary, wall_time_s=time.perf_counter() - t0)


def write_stage(outcome: BatchOutcome, results: xr.Dataset, histories: xr.Dataset, out_dir: Path,
                attrs: dict, *, margin_cache=None) -> Path:
    """Stage 4: ``pulses.nc``, ``histories.nc``, then ``screening.nc`` last, each atomically; prune the caches."""
    results.attrs.update(attrs)
    histories.attrs["rockscreen_run_key"] = outcome.pulses.attrs["rockscreen_run_key"] = \
        results.attrs["rockscreen_run_key"]
    outcome.pulses.write(out_dir / "pulses.nc")                # record by record: one record's series in memory
    write_atomic(histories, out_dir / "histories.nc")
    path = write_atomic(results, out_dir / "screening.nc")      # the main file last
    if outcome.cache is not None:
        outcome.cache.prune()
    if margin_cache is not None:
        margin_cache.prune()
    return path


def report_stage(screening_path: Path, *, figure_cache: Path | None = None, home: Path | None = None
                 ) -> tuple[Path, Path]:
    """Stage 5: ``report.html`` and ``assets.csv`` from the results files alone, beside them; figures unchanged
    since the last run are taken from ``figure_cache``; ``home``: the directory the page will be read in (what
    else it links to is looked for there)."""
    return build_report(screening_path, figure_cache=figure_cache, home=home)


#: The files a screening writes, replaced together (:func:`pipeline.store.publish`), the main file first
OUTPUT_SET = uptodate.OUTPUTS
#: The files of the set that ``screen report`` replaces (it keeps the others)
REPORT_FILES = ("report.html", "assets.csv")
