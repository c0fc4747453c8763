"""Command line: ``screen`` and its subcommands.

``screen --records DIR --blocks inventory.csv [--out DIR]`` screens every
record against every block and writes ``OUT/screening.nc`` and
``OUT/pulses.nc``. Running it again into the same ``--out`` computes only
what is new or changed (:mod:`pipeline.run`), and nothing at all when the inputs, the
configuration, the code and the outputs are as the last run left them
(:mod:`pipeline.run.uptodate`); ``-n N`` uses N local
processes and ``--scheduler`` a Dask cluster (:mod:`pipeline.run.executors`).
This module only parses arguments, calls the run layer or the libraries, and prints.

Exit codes: 0 success; 1 at least one record failed (its reason is in
``status`` and the log; ``--tolerate-failures`` makes this 0); 2 bad usage,
configuration or inventory (nothing is written); 3 the output cannot be
written (earlier results intact); 75 another run holds the output;
130 interrupted (what was computed is kept in the scene cache).
"""

from __future__ import annotations

import argparse
import contextlib
import difflib
import logging
import math
import os
import shlex
import signal
import sys
import threading
import time
from pathlib import Path

from . import __version__
from .config import CRITERION_MEASURED_MISSES, FIDELITY_TIERS
from .errors import (
    InterruptedAfterPublishing,
    InventoryError,
    OutputError,
    OutputLockedError,
    RecordsNotFoundError,
    RockscreenError,
    UsageError,
)
from .ticker import POLL_FRACTION, Ticker

log = logging.getLogger("pipeline")

EXIT_OK, EXIT_RECORD_FAILURES, EXIT_USAGE, EXIT_OUTPUT = 0, 1, 2, 3
EXIT_LOCKED = 75          # sysexits EX_TEMPFAIL: another run holds the output; try again later
EXIT_INTERRUPTED = 130


#: What each command's exit codes mean, for its --help
EXIT_CODES = {
    "run": "0 ok; 1 some records failed (each reported; --tolerate-failures makes it 0, except when no record was "
           "screened); 2 bad usage, configuration, inventory or no record found; 3 the output cannot be written "
           "(earlier results intact); 75 another run holds the output; 130 interrupted (the work done is kept)",
    "records": "0 ok; 1 some records failed (--tolerate-failures: 0); 2 bad usage, configuration or inventory; "
               "3 the output cannot be written; 75 another run holds the output; 130 interrupted",
    "plain": "0 ok; 2 bad usage, configuration, inventory or input file; 3 the output cannot be written; "
             "130 interrupted",
    "locked": "0 ok; 2 bad usage, configuration, inventory or input file; 3 the output cannot be written; 75 another "
              "run holds the output; 130 interrupted",
}
#: An example of each command, run from the project's folder on its bundled data
EXAMPLES = {
    "run": "screen --records records --blocks configs/blocks.csv --out results --tolerate-failures",
    "chart": "screen chart --block COL-1 --blocks configs/blocks.csv --results results/screening.nc",
    "report": "screen report results",
    "bench": "screen bench --records records --blocks configs/blocks.csv --out results/bench",
    "infer": "screen infer --blocks configs/colonnade-blocks.csv --observed configs/colonnade-observed.csv",
    "fragility": "screen fragility --records records --blocks configs/blocks.csv --im pga --levels auto "
                 "--tolerate-failures",
    "fragility_event": "screen fragility --records records --blocks examples/event/blocks.csv --im pgv "
                       "--im-component larger --levels auto --out results/event-fragility --tolerate-failures",
    "event": "screen event --shakemap examples/event/903_m6p09_se-scenario-grid.xml.gz --blocks "
             "examples/event/blocks.csv --fragility results/event-fragility",
}


def _epilog(command: str, codes: str) -> str:
    """The end of a command's --help: an example (two for ``event``: the fragility it reads first) and its exit
    codes."""
    first = f"  {EXAMPLES['fragility_event']}\n" if command == "event" else ""
    return f"example:\n{first}  {EXAMPLES[command]}\n\nexit codes: {EXIT_CODES[codes]}"


def _add_stationxml(p: argparse.ArgumentParser, what: str) -> None:
    """--stationxml (``--inventory`` is its old name, kept: the block inventory is --blocks)."""
    p.add_argument("--stationxml", "--inventory", dest="inventory", type=Path, metavar="STATIONXML",
                   help=f"StationXML {what} (--inventory is this option's old name; the blocks' inventory is "
                        "--blocks)")


def _add_inputs(p: argparse.ArgumentParser, *, out: Path, out_help: str) -> None:
    """--records, --blocks, --out, --config, --stationxml (screen, screen fragility)."""
    p.add_argument("--records", required=True, type=Path, help="directory of ground-motion records")
    p.add_argument("--blocks", required=True, type=Path, help="inventory CSV (id,height_m,width_m,...)")
    p.add_argument("--out", type=Path, default=out, help=out_help)
    p.add_argument("--config", type=Path, help="TOML configuration (default: built-in, as configs/screen.toml)")
    _add_stationxml(p, "for records in counts (else *.xml in --records)")
    p.add_argument("--buildings", type=Path,
                   help="buildings CSV id,period_s,damping,stiffness_ratio,height_m[,n_stories]: blocks whose "
                        "'building' column names one are screened on their floor's motion (the continuous "
                        "shear-flexural model of Miranda & Taghavi 2005)")


def _add_execution(p: argparse.ArgumentParser) -> None:
    """-n, --scheduler, --fidelity and the [uncertainty] overrides --samples, --seed."""
    ex = p.add_argument_group("execution")
    ex.add_argument("-n", "--num-processes", type=int, default=None, metavar="N",
                    help="worker processes on this machine (default: the cores available to this process, or "
                         f"${WORKERS_ENV}; 1: serial in this process). Tests check -n 2 and Dask against serial: "
                         "identical results")
    ex.add_argument("--scheduler", metavar="ADDRESS",
                    help="Dask: 'local' for a LocalCluster of N workers, or a scheduler address tcp://HOST:PORT "
                         "(the records directory must be readable by the workers at the same path)")
    ex.add_argument("--fidelity", choices=FIDELITY_TIERS,
                    help="criterion (the paper's criterion alone: fast, NOT conservative) | full (default: "
                         "the exact at-rest certificate, then the simulator for every scene that moves) | "
                         "reference (full at tight tolerances); 'screen bench' measures the cost and error of each")
    un = p.add_argument_group("uncertainty (config [uncertainty]; docs/user-guide.md, 'Judges every verdict "
                              "under declared uncertainty')")
    un.add_argument("--samples", type=int, metavar="N",
                    help="largest number of samples per scene for p_overturn (default 40; 0: nominal verdicts "
                         "only, no probability)")
    un.add_argument("--seed", type=int, metavar="S", help="seed of the common random numbers (default 20261123)")


def _add_run_arguments(p: argparse.ArgumentParser) -> None:
    _add_inputs(p, out=Path("results"), out_help="output directory (default: results/)")
    _add_execution(p)
    p.add_argument("--force", action="store_true",
                   help="recompute every record and block (default: only what is new or changed; when nothing "
                        "is, the run is skipped after checking the digests of inputs, code and outputs)")
    _add_tolerate(p)
    _add_output_options(p)


def _add_tolerate(p: argparse.ArgumentParser) -> None:
    p.add_argument("--tolerate-failures", action="store_true",
                   help="exit 0 even when some records failed (each is still reported, with its reason)")


#: Environment variable giving the default of ``-n`` (scheduled runs sharing a machine set it).
WORKERS_ENV = "ROCKSCREEN_NUM_PROCESSES"           # named in the help; the policy is run.executors.default_workers


def _workers(args: argparse.Namespace) -> int:
    """``-n``, or its default (:func:`pipeline.run.executors.default_workers`), checked."""
    from .run.executors import workers

    return workers(args.num_processes)


def _config_and_inventory(args: argparse.Namespace):
    """The configuration (``--config``, and ``--fidelity`` where the command has it) and the ``--blocks`` inventory."""
    from .blocks import read_inventory
    from .config import load_config

    config = load_config(args.config)
    if getattr(args, "fidelity", None) is not None:
        config = config.with_tier(args.fidelity)
    if getattr(args, "samples", None) is not None or getattr(args, "seed", None) is not None:
        config = config.with_uncertainty(samples=args.samples, seed=args.seed, where="command line")
    return config, read_inventory(args.blocks, default_mu=config.blocks.default_mu)


def _records_dir(path: Path) -> Path:
    """``--records``, checked to be a directory."""
    if not path.is_dir():
        raise RecordsNotFoundError(f"{path}: records directory not found; give an existing directory to --records")
    return path


def _add_output_options(p: argparse.ArgumentParser) -> None:
    """-q and -v, the same on every subcommand."""
    p.add_argument("-q", "--quiet", action="store_true",
                   help="print only warnings and errors (no progress, no summary)")
    p.add_argument("-v", "--verbose", action="store_true", help="rockscreen's own debug messages")


#: Longest silence of a command while it works [s]: a progress line, a stage's name or the bar's refresh comes at
#: least this often (stderr not a terminal: scheduled runs, logs; or the stages of screen bench), by a
#: :class:`~pipeline.ticker.Ticker`
PROGRESS_LINE_S = 2.0


def _progress(quiet: bool):
    """How finished tasks are shown: nothing with ``-q``; a tqdm bar on a terminal of known width; otherwise a
    progress line at every tenth of the work, and whenever :data:`PROGRESS_LINE_S` seconds pass without one."""
    if quiet:
        return None
    if sys.stderr.isatty() and _terminal_columns() > 0:
        return _progress_bar
    return _progress_lines


def _terminal_columns() -> int:
    """The width of the terminal on stderr; 0 where it has none (a pseudo-terminal whose size was never set, as
    some job runners open, in which a tqdm bar draws nothing)."""
    try:
        return os.get_terminal_size(sys.stderr.fileno()).columns
    except (OSError, ValueError):
        return 0


def _progress_bar(items, total=None, running=None, label: str = "records screened"):
    """Yield ``items`` under a tqdm bar whose postfix names the records running long and their scenes (``label``:
    what a finished item is; its first word is the bar's name)."""
    from tqdm import tqdm

    bar = tqdm(items, total=total, desc=label.split()[0], unit="rec", file=sys.stderr, leave=False)

    def refresh(_elapsed_s: float) -> None:
        bar.set_postfix_str("; ".join(running()) if running is not None else "", refresh=True)

    try:
        with Ticker(refresh, every_s=PROGRESS_LINE_S * (1.0 - POLL_FRACTION)):
            yield from bar
    finally:
        bar.close()


def _progress_lines(items, total=None, running=None, label: str = "records screened"):
    """Yield ``items``, printing progress lines (from a watcher thread while a task takes long); ``running()``
    names the records that have run long and the scene each is on; ``label``: what a finished item is."""
    t0 = time.monotonic()
    state = {"done": 0}
    lock = threading.Lock()

    def line(_elapsed_s: float = 0.0) -> None:
        with lock:
            busy = running() if running is not None else []
            print(f"progress: {state['done']}/{total} {label}, {time.monotonic() - t0:.0f} s"
                  + (f"; running long: {'; '.join(busy)}" if busy else ""), file=sys.stderr, flush=True)
            ticker.said()

    ticker = Ticker(line, every_s=PROGRESS_LINE_S)
    if not total:
        yield from items
        return
    step = max(1, total // 10)
    line()                                       # at once: the run has started and how much it has to do
    with ticker:
        for k, item in enumerate(items, 1):
            yield item
            state["done"] = k
            if k % step == 0 or k == total:
                line()


def _print_summary(summary: dict, out: Path, *, wrote: bool = True) -> None:
    s = summary
    print(f"records: {s['records_ok']} ok ({s['records_screened']} screened, {s['records_reused']} reused"
          + (f", {s['records_vanished']} kept from the last run: files gone" if s["records_vanished"] else "")
          + f"), {s['records_failed']} failed; blocks: {s['blocks']} ({s['blocks_changed']} new or changed); "
          f"scenes computed: {s['scenes_computed']} at fidelity {s['fidelity']}; {s['executor']}; "
          f"wall time {s['wall_time_s']:.1f} s",
          file=sys.stderr)
    print("scenes by physics: " + ", ".join(f"{k} {v}" for k, v in s["scenes_by_physics"].items())
          + "; by response: " + ", ".join(f"{k} {v}" for k, v in s["scenes_by_response"].items()),
          file=sys.stderr)
    print("scenes by orientation: " + ", ".join(f"{k} {v}" for k, v in s["scenes_by_orientation"].items())
          + f"; rocking planes integrated: {s['planes_integrated']}", file=sys.stderr)
    if s.get("boxes"):
        print(f"other base axis: not checked for {s['boxes']} of {s['blocks']} blocks (boxes without both a depth_m "
              "and an azimuth_deg: judged in the plane of width_m; rocking about the other base axis or a corner is "
              f"not modeled); of the scenes of boxes with both on two horizontals, {s.get('box_scenes_3d', 0)} were "
              f"simulated in 3D (orientation given_3d) and {s.get('box_scenes_certified', 0)} in the plane of the "
              "width, the other axis certified never to lift nor slip (given_certified)", file=sys.stderr)
    if any(s.get("scenes_by_robustness", {}).values()):
        print("under the declared uncertainty ([uncertainty]): " + ", ".join(
            f"{k} {v}" for k, v in s["scenes_by_robustness"].items())
            + f"; sampled planes integrated: {s['sampled_simulations']} (sensitive: the verdict can flip; "
            "p_overturn in screening.nc)", file=sys.stderr)
    if s.get("scenes_unjudged") or s.get("draws_unjudged"):
        print(f"not judged: {s.get('scenes_unjudged', 0)} scene(s) and {s.get('draws_unjudged', 0)} "
              f"of {s.get('draws_total', 0)} samples (in {s.get('scenes_with_unjudged_draws', 0)} scenes) have no "
              "verdict (a model stopped where the base slides, twists or lifts off, the ground fell faster than "
              "gravity, or a cap): unknown, never standing; p intervals span them and such assets read 'at risk "
              "until judged' (samples_without_verdict in screening.nc)", file=sys.stderr)
    general = s.get("general_scenes", {})
    if general.get("total"):
        print(f"contact model: {general['total']} scene(s) left pure rocking or sliding and were decided by the "
              f"general contact model: slide-rock in {general['slide_rock']}, free flight in "
              f"{general['ground_flight'] + general['block_liftoff']} (the ground's g + a_v reached 0 in "
              f"{general['ground_flight']}, the block lifted itself off in {general['block_liftoff']}); physics "
              "general, the modes in contact_modes", file=sys.stderr)
    guarded = s.get("guarded_scenes", [])
    if guarded:
        print(f"guards: {len(guarded)} scene(s) met a guard of the simulator and are flagged (simulation_guard in "
              "screening.nc; tie_hold: held at rest at a tie, stalled or step_cap: ended with the verdict of the "
              "state reached; model_limit: a 3D model stopped where the base would slide or lift off, or a "
              "scanned body's model met what it does not follow, no verdict): " + "; ".join(guarded[:10])
              + ("; ..." if len(guarded) > 10 else ""),
              file=sys.stderr)
    for line in filter(None, s.get("buildings", "").split("\n")):
        print(f"building {line} (floor motion: Miranda & Taghavi 2005)", file=sys.stderr)
    if s.get("slides_off_base"):
        print(f"sliding: {s['slides_off_base']} scene(s) where the block slides farther than its base_margin_m, off "
              "its base (slides_off_base in screening.nc)", file=sys.stderr)
    flights = s.get("free_flight_scenes", 0)
    if flights:
        print(f"free flight: {flights} scene(s) where the ground's g + a_v reached 0 "
              "before any overturning have no verdict (response free_flight: with simulation.contact_model off, or "
              "a body given by its scan, whose two-sided model does not follow a flight)",
              file=sys.stderr)

    if s.get("not_records"):
        names = ", ".join(Path(p).name for p, _ in s["not_records"][:5]) + (", ..." if len(s["not_records"]) > 5
                                                                             else "")
        print(f"not records: {len(s['not_records'])} of {s['files_seen']} files ({names}); the list with reasons "
              "is the global attribute files_not_records of screening.nc", file=sys.stderr)
    if s.get("units_toml"):
        print(f"units: records failed because nothing states their units. Paste these lines into "
              f"{Path(s['records_dir']) / 'units.toml'} (if it has a [files] line already, only the lines after "
              "it), check each unit against the data provider, and run again:\n[files]\n"
              + "\n".join(s["units_toml"]), file=sys.stderr)
    for kept, dup in s.get("duplicates", []):
        print(f"duplicate: {dup} holds the same bytes as {kept}; screened once, as {kept}", file=sys.stderr)
    if wrote:
        print(f"wrote {out}", file=sys.stderr)


def _buildings(args: argparse.Namespace, inventory) -> dict:
    """The buildings of ``--buildings``, checked against the inventory's placements (errors list every block)."""
    from .run.stages import buildings_of

    return buildings_of(getattr(args, "buildings", None), inventory)


def cmd_run(args: argparse.Namespace, argv: list[str]) -> int:
    """The main job: screen records against blocks and write results (incrementally)."""
    from .run import uptodate

    config, inventory = _config_and_inventory(args)
    records_dir = _records_dir(args.records)
    key, last = uptodate.check(records_dir=records_dir, blocks_csv=args.blocks, config=config,
                               stationxml=args.inventory, out_dir=args.out, buildings_csv=args.buildings,
                               force=args.force)
    if last is not None:
        return _report_up_to_date(args, last, config)

    from .run import RunInterrupted, ScreenRequest, screen
    from .run.stages import preflight

    preflight(records_dir, args.out)             # an empty --records or an unwritable --out: said at once
    if config.fidelity.tier != "criterion":
        _compile_simulator(args, inventory)

    request = ScreenRequest(records_dir=records_dir, blocks_csv=args.blocks, inventory=inventory,
                            config=config, out_dir=args.out, stationxml=args.inventory,
                            n_workers=_workers(args),
                            scheduler=args.scheduler, force=args.force,
                            command=list(argv), key=key, buildings=_buildings(args, inventory))
    try:
        result = screen(request, progress=_progress(args.quiet))
    except RunInterrupted as exc:
        print(str(exc), file=sys.stderr)
        return EXIT_INTERRUPTED
    if config.fidelity.tier == "criterion":
        log.warning("fidelity 'criterion' is not conservative: %s", CRITERION_MEASURED_MISSES)
    if not args.quiet:
        _print_summary(result.counts, result.screening_path)
        _print_margins(result.margins)
        print(f"wrote {result.report_path} and {result.assets_path}", file=sys.stderr)
    return _run_exit(result.records_failed, args, records_ok=int(result.counts.get("records_ok", 1)))


def _say(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _compile_simulator(args: argparse.Namespace, inventory) -> None:
    """Compile the simulator in this process before the workers start (announced when it takes a while: the
    first run of an install); the 3D models' kernels too where the inventory has a cylinder, or a box with a depth
    and an azimuth, and the two-sided one where it has a body given by its scan."""
    from .run.stages import compile_simulator

    compile_simulator(announce=None if getattr(args, "quiet", False) else _say,
                      cylinders=bool(inventory.cylinders().any()), boxes=bool(inventory.boxes_in_3d().any()),
                      scanned=bool(inventory.scanned().any()))


def _run_exit(records_failed: int, args: argparse.Namespace, *, records_ok: int = 1) -> int:
    """1 when records failed (unless --tolerate-failures), else 0: the same for a run and an up-to-date one. A run
    that screened no record exits 1 whatever the flags: nothing it wrote says an asset is safe."""
    if records_failed and not records_ok:
        log.error("no record was screened (%d failed): every asset is 'not screened'; fix the failures above and run "
                  "again (this exits 1 even with --tolerate-failures)", records_failed)
        return EXIT_RECORD_FAILURES
    return EXIT_RECORD_FAILURES if records_failed and not args.tolerate_failures else EXIT_OK


def _print_margins(m: dict) -> None:
    print(f"margins: {m['computed']} scanned, {m['reused']} reused ({m['simulations']} scaled scenes behind them); "
          f"{m['wall_time_s']:.1f} s"
          + (f"; records no longer readable for margins: {', '.join(m['unavailable'])}" if m["unavailable"] else ""),
          file=sys.stderr)


def _report_up_to_date(args: argparse.Namespace, last: dict, config) -> int:
    """A run with nothing new: say so, repeat the last run's summary, exit as it would have."""
    counts = last["counts"]
    if not args.quiet:
        n_files = counts.get("files_seen", last["key"]["records_files"])   # counted as the run's summary counts
        print(f"up to date: the records ({n_files} files), the inventory, the configuration "
              f"and rockscreen are unchanged since the run that finished {last['finished_utc']}, and its outputs "
              f"in {args.out} are intact (checked by SHA-256); nothing was recomputed or rewritten. "
              "--force recomputes.", file=sys.stderr)
    if config.fidelity.tier == "criterion":
        log.warning("fidelity 'criterion' is not conservative: %s", CRITERION_MEASURED_MISSES)
    for record_id, status in last.get("failures", []):
        log.warning("record %s %s (files unchanged since the run that found it)", record_id, status)
    if not args.quiet:
        print("that run's summary:", file=sys.stderr)
        _print_summary(counts, Path(args.out) / "screening.nc", wrote=False)
        _print_margins(last["margins"])
    return _run_exit(int(counts.get("records_failed", 0)), args, records_ok=int(counts.get("records_ok", 1)))


def chart_parser() -> argparse.ArgumentParser:
    """Parser of ``screen chart``."""
    from .closed_forms import PULSE_BETA

    p = argparse.ArgumentParser(
        prog="screen chart", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=_epilog("chart", "plain"),
        description="Stability chart of one block for one pulse shape (the reference paper's Figs. 2a and 4), "
                    "optionally with every record's pulse as a point.",
    )
    g = p.add_argument_group("block (sizes, or an id in an inventory)")
    g.add_argument("--height", type=float, help="full block height [m]")
    g.add_argument("--width", type=float, help="full base width in the rocking plane [m]")
    g.add_argument("--mu", type=float, help="friction coefficient (default: blocks.default_mu)")
    g.add_argument("--block", help="block id in --blocks")
    g.add_argument("--blocks", type=Path, help="inventory CSV holding --block")
    p.add_argument("--pulse", default="half-sine", choices=sorted(PULSE_BETA), help="pulse shape")
    p.add_argument("--periods", type=float, nargs="+", metavar="T",
                   help="pulse periods T = 2 t_p [s] (default: 0.1 to 10 transition periods)")
    pts = p.add_mutually_exclusive_group()
    pts.add_argument("--records", type=Path, help="directory of records to extract pulses from and plot")
    pts.add_argument("--results", type=Path, help="screening.nc whose pulses to plot")
    _add_stationxml(p, "for --records in counts")
    p.add_argument("--config", type=Path, help="TOML configuration")
    p.add_argument("--simulate", action="store_true",
                   help="add critical_acceleration_simulated: upward amplitude scan with the rocking simulator")
    p.add_argument("--cycles", type=int, default=25, help="cycles of the harmonic pulse for --simulate (25)")
    p.add_argument("--out", type=Path, default=None,
                   help="chart data, netCDF (default results/chart/chart-<block id, or HxW>.nc; a chart already "
                        "there is replaced, and the run says so)")
    p.add_argument("--figure", type=Path, help="figure, .png/.svg/.pdf (default: --out with .png)")
    _add_output_options(p)
    return p


def cmd_chart(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen chart``: write the chart's netCDF and figure."""
    from .blocks import Inventory, read_inventory
    from .config import load_config
    from .run.chart import ChartRequest, write_chart

    config = load_config(args.config)
    if args.block is not None:
        if args.blocks is None or args.height is not None or args.width is not None:
            raise UsageError("screen chart: give either --block ID with --blocks CSV, or --height and --width")
        block = read_inventory(args.blocks, default_mu=config.blocks.default_mu, warn_for=args.block).select(args.block)
        if args.mu is not None:
            block = Inventory.single(height_m=float(block.height_m[0]), width_m=float(block.width_m[0]),
                                     mu=args.mu, block_id=args.block, azimuth_deg=float(block.azimuth_deg[0]))
    elif args.height is not None and args.width is not None:
        block = Inventory.single(height_m=args.height, width_m=args.width,
                                 mu=config.blocks.default_mu if args.mu is None else args.mu)
    else:
        raise UsageError("screen chart: give the block as --height H --width W [--mu MU], "
                              "or as --block ID --blocks inventory.csv")
    if args.out is None:
        name = args.block if args.block is not None else f"{args.height:g}x{args.width:g}"
        args.out = Path("results") / "chart" / f"chart-{name}.nc"
    if args.out.exists() and not args.quiet:
        print(f"replacing {args.out} (the chart of an earlier run; give --out for another file)", file=sys.stderr)
    if not args.quiet:
        print(f"stability chart of {args.block or f'{args.height:g} x {args.width:g} m'}"
              + (": the criterion, the closed forms" + (", the simulated amplitude scan" if args.simulate else "")
                 + (" and the records' pulses" if args.records or args.results else "")) + " ...", file=sys.stderr)
    out, figure, transition_s = write_chart(ChartRequest(
        config=config, block=block, block_id=args.block, pulse=args.pulse, periods_s=args.periods, out=args.out,
        simulate=args.simulate, cycles=args.cycles,
        records_dir=_records_dir(args.records) if args.records is not None else None, stationxml=args.inventory,
        results=args.results, figure=args.figure, history=f"screen {shlex.join(argv)}"),
        progress=_progress(args.quiet))
    print(f"transition period {transition_s:.3f} s (Eq. 9); wrote {out} and {figure}", file=sys.stderr)
    return EXIT_OK


def report_parser() -> argparse.ArgumentParser:
    """Parser of ``screen report``."""
    p = argparse.ArgumentParser(prog="screen report", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("report", "plain"),
                                description="Regenerate report.html and assets.csv from a results file "
                                            "(pulses.nc and histories.nc are read from the same directory).")
    p.add_argument("results", type=Path, help="screening.nc written by screen")
    p.add_argument("--out", type=Path, help="output directory (default: the results file's directory)")
    p.add_argument("--all-figures", action="store_true",
                   help="draw the velocity figure of every record (default: pulse-like records only)")
    _add_output_options(p)
    return p


def cmd_report(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen report``: the asset-risk report from results alone."""
    from .run.stages import rebuild_report

    if args.results.is_dir():                   # the output folder of a run: its screening.nc
        args.results = args.results / "screening.nc"
    html, assets = rebuild_report(args.results, args.out, all_figures=args.all_figures,
                                  command=shlex.join(["screen", *argv]))
    print(f"wrote {html} and {assets}", file=sys.stderr)
    return EXIT_OK


def bench_parser() -> argparse.ArgumentParser:
    """Parser of ``screen bench``."""
    p = argparse.ArgumentParser(prog="screen bench", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("bench", "records"),
                                description="Run every fidelity tier on the same scenes and measure time per scene "
                                            "and agreement with the reference tier; also the cost of the simulation "
                                            "settings. Writes bench.csv, bench.md and bench.png.")
    p.add_argument("--records", required=True, type=Path, help="directory of ground-motion records")
    p.add_argument("--blocks", required=True, type=Path, help="inventory CSV (id,height_m,width_m,...)")
    p.add_argument("--out", type=Path, default=Path("results/bench"),
                   help="output directory (default: results/bench/)")
    p.add_argument("--config", type=Path, help="TOML configuration")
    p.add_argument("--tiers-only", action="store_true", help="skip the sweep of the simulation settings")
    _add_output_options(p)
    return p


@contextlib.contextmanager
def _ticking(quiet: bool):
    """A stage announcer (None with ``-q``) that, while a stage runs, repeats its name with the time spent on it
    every :data:`PROGRESS_LINE_S` seconds: nothing is silent for longer."""
    if quiet:
        yield None
        return
    stage, started = {"text": ""}, {"t": time.monotonic()}

    def announce(text: str) -> None:
        stage["text"], started["t"] = text, time.monotonic()
        ticker.said()
        _say(text)

    def tick(_elapsed_s: float) -> None:
        if stage["text"]:
            _say(f"  ... {stage['text'].split(' (')[0]}: {time.monotonic() - started['t']:.0f} s")

    ticker = Ticker(tick, every_s=PROGRESS_LINE_S)
    with ticker:
        yield announce


def cmd_bench(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen bench``: what accuracy costs in time."""
    from .run.accuracy import markdown, run_bench

    config, inventory = _config_and_inventory(args)
    _compile_simulator(args, inventory)
    with _ticking(args.quiet) as say:
        rows = run_bench(_records_dir(args.records), inventory, config, out_dir=args.out,
                         settings_sweep=not args.tiers_only, progress=say)
    print(markdown(rows), end="")
    print(f"wrote {args.out / 'bench.csv'}, {args.out / 'bench.md'} and {args.out / 'bench.png'}", file=sys.stderr)
    return EXIT_OK


def fragility_parser() -> argparse.ArgumentParser:
    """Parser of ``screen fragility``."""
    from .records.intensity import IMS, SCALABLE
    from .uncertainty.hazard import Component

    p = argparse.ArgumentParser(prog="screen fragility", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("fragility", "records"),
                                description="Multiple-stripe analysis: every record scaled to each IM level, every "
                                            "block judged; lognormal fragility fits, the IMs that predict "
                                            "overturning, and with --hazard the annual rate of overturning.")
    _add_inputs(p, out=Path("results/fragility"), out_help="output directory (default results/fragility/; a run "
                "into it again resumes and reuses what was computed)")
    p.add_argument("--im", required=True, choices=SCALABLE,
                   help="IM the records are scaled to: " + ", ".join(f"{k} [{IMS[k][0]}]" for k in SCALABLE))
    p.add_argument("--levels", required=True,
                   help="'auto': a ladder from the blocks' own capacities (uplift acceleration, or critical velocity "
                        "for pgv), doubled level by level and extended until every block that can rock has "
                        "stripes below 10 %% and above 90 %% overturning; or increasing IM levels, comma-separated, "
                        "in the IM's SI unit; a unit suffix (g, gal, cms2, "
                        "ms2 for accelerations; cms, ms for velocities) on any level applies to all and must be "
                        "the same on every level that has one: 0.1,0.2,0.3g is 0.1 g, 0.2 g, 0.3 g")
    p.add_argument("--hazard", type=Path, action="append",
                   help="hazard curve as exported: OpenQuake hazard_curve-*.csv, the USGS hazard service's JSON, or "
                        "a CSV <im>_<unit>[_<component>],annual_rate; repeat for Sa at several periods (each "
                        "block uses the nearest) (docs/user-guide.md)")
    p.add_argument("--hazard-site", metavar="SITE_ID",
                   help="OpenQuake file of several sites: the custom_site_id to use")
    p.add_argument("--hazard-lonlat", metavar="LON,LAT",
                   help="OpenQuake file of several sites: LON,LAT; the nearest site is used")
    p.add_argument("--hazard-component", choices=[c.value for c in Component],
                   help="the horizontal component definition of the hazard curve, where the file does not say "
                        "(OpenQuake curves are taken as rotd50 unless stated)")
    p.add_argument("--im-component", choices=[c.value for c in Component],
                   help="the component definition the fragility is fitted on (default: the hazard's, else rotd100, "
                        "the peak of the horizontal vector)")
    p.add_argument("--hazard-scale", type=float, metavar="FACTOR",
                   help="a stated conversion when --im-component differs from the hazard's: hazard levels x FACTOR")
    p.add_argument("--bootstrap", type=int, default=200, metavar="N", help="bootstrap draws for the intervals (200)")
    p.add_argument("--orientation", choices=("random", "worst"), default="random",
                   help="for a block of blank azimuth, fit the probability of a block of unknown orientation "
                        "(random, the default: its risk) or in the orientation found worst on the scan's grid "
                        "(worst)")
    _add_execution(p)
    _add_tolerate(p)
    _add_output_options(p)
    return p


def cmd_fragility(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen fragility``: stripes, fits, IM ranking, hazard; writes fragility.nc, fragility.html and
    fragility_assets.csv."""
    from .levels import levels_unit, parse_levels
    from .records.intensity import display_unit
    from .run.fragility import FragilityRequest, fragility

    config, inventory = _config_and_inventory(args)
    buildings = _buildings(args, inventory)
    auto = args.levels.strip().lower() == "auto"
    levels = None if auto else parse_levels(args.levels, args.im)
    if args.bootstrap < 0:
        raise UsageError(f"--bootstrap {args.bootstrap}: must be >= 0")
    hazard, component = _hazard_and_component(args)
    n = _workers(args)
    if config.fidelity.tier != "criterion":
        _compile_simulator(args, inventory)
    request = FragilityRequest(_records_dir(args.records), args.blocks, inventory, config, args.im, levels, args.out,
                               hazard=hazard, component=component,
                               level_unit=display_unit(args.im) if auto else levels_unit(args.levels, args.im),
                               buildings=buildings, n_workers=n, scheduler=args.scheduler, bootstrap=args.bootstrap,
                               command=("screen", *argv), stationxml=args.inventory, orientation=args.orientation)
    out = fragility(request, progress=_progress(args.quiet), say=None if args.quiet else _say)
    for w in out["warnings"]:
        log.warning("%s", w)
    for f in out["failures"]:
        log.warning("record %s failed: %s", f.record_id, f.reason)
    if not args.quiet:
        print(f"fragility: {out['records_computed']} record(s) computed, {out['records_reused']} reused, "
              f"{out['records_failed']} failed; {out['scenes']} scaled scenes; {out['wall_time_s']:.1f} s\n"
              f"wrote {', '.join(str(p) for p in out['paths'])}", file=sys.stderr)
    return _run_exit(len(out["failures"]), args)


def _hazard_and_component(args: argparse.Namespace):
    """``--hazard`` and its options, parsed: the hazard curves (bound to the fit) and the component definition the
    fit uses (:func:`pipeline.run.fragility.hazard_and_component`)."""
    from .run.fragility import hazard_and_component

    lonlat = None
    if args.hazard_lonlat:
        try:
            lon, lat = (float(x) for x in args.hazard_lonlat.split(","))
        except ValueError:
            raise UsageError(f"--hazard-lonlat {args.hazard_lonlat!r}: expected LON,LAT in degrees, e.g. "
                             "12.5,41.9") from None
        lonlat = (lon, lat)
    if args.hazard_scale is not None and not (args.hazard_scale > 0):
        raise UsageError(f"--hazard-scale {args.hazard_scale}: must be a positive factor")
    return hazard_and_component(args.hazard or [], im=args.im, site=args.hazard_site, lonlat=lonlat,
                                stated=args.hazard_component, im_component=args.im_component, scale=args.hazard_scale)


def infer_parser() -> argparse.ArgumentParser:
    """Parser of ``screen infer``."""
    from .run.infer import INFER_SHAPES

    p = argparse.ArgumentParser(prog="screen infer", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("infer", "plain"),
                                description="Archaeoseismology: the pulses (a_p, t_p, orientation) consistent with "
                                            "which blocks toppled and which stood, by the paper's criterion and by "
                                            "simulation; conflicting observations are reported.")
    p.add_argument("--blocks", required=True, type=Path, help="inventory CSV of the observed blocks")
    p.add_argument("--observed", required=True, type=Path,
                   help="CSV id,outcome[,fall_azimuth_deg] with outcome toppled or standing")
    p.add_argument("--pulse", default="half-sine", choices=INFER_SHAPES, help="assumed pulse shape")
    p.add_argument("--out", type=Path, default=Path("results/infer"),
                   help="output directory (default: results/infer/)")
    p.add_argument("--config", type=Path, help="TOML configuration ([infer] grid)")
    _add_output_options(p)
    return p


def cmd_infer(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen infer``: write infer.nc and infer.png, print the bounds and any conflict."""
    from .run.infer import summarize, write_inference

    config, inventory = _config_and_inventory(args)
    ds, out, figure = write_inference(args.observed, inventory, shape=args.pulse, config=config, out_dir=args.out,
                                      history=f"screen {shlex.join(argv)}", progress=_progress(args.quiet))
    g = config.records.g_ms2
    for method, info in summarize(ds).items():
        if info["consistent"]:
            tp = info["tp_range_s"]
            print(f"{method}: every observation holds for t_p {tp[0]:.3g}-{tp[1]:.3g} s, "
                  f"a_p {info['ap_range_ms2'][0] / g:.3g}-{info['ap_range_ms2'][1] / g:.3g} g, "
                  f"pulse velocity beta a_p t_p {info['pgv_range_ms'][0]:.3g}-{info['pgv_range_ms'][1]:.3g} m/s, "
                  f"axis {', '.join(f'{a:g}' for a in info['azimuths_deg'])} deg ({info['grid_points']} grid points)")
        else:
            print(f"{method}: the observations cannot all hold under one pulse of this shape. Conflicting pairs: "
                  f"{'; '.join(' vs '.join(p) for p in info['pairs']) or 'none alone (three or more together)'}"
                  + (f"; impossible alone: {', '.join(info['impossible'])}" if info["impossible"] else "")
                  + f". Largest consistent subset ({len(info['largest_subset'])} of "
                  f"{len(info['largest_subset']) + len(info['left_out'])}) leaves out: {', '.join(info['left_out'])}")
    print(f"simulation: {ds.attrs['simulation_runs']} runs in {ds.attrs['simulation_time_s']:.1f} s; "
          f"wrote {out} and {figure}", file=sys.stderr)
    return EXIT_OK


def event_parser() -> argparse.ArgumentParser:
    """Parser of ``screen event``."""
    p = argparse.ArgumentParser(prog="screen event", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("event", "locked"),
                                description="After an earthquake: every asset's probability of overturning from the "
                                            "event's ShakeMap and the fragilities of 'screen fragility', ranked into "
                                            "an inspection list (event.nc, inspection.csv, event.html, "
                                            "shakecast-facilities.xml).")
    p.add_argument("--shakemap", type=Path, required=True,
                   help="the event's ShakeMap grid.xml (ShakeMap 3.5 or 4; .xml.gz read as is)")
    p.add_argument("--uncertainty", type=Path, default=None,
                   help="its uncertainty.xml, for the STD fields grid.xml lacks (default: the grid's own, else "
                        "[event] default_log_sd, said in the output)")
    p.add_argument("--blocks", type=Path, required=True,
                   help="inventory CSV; the assets' locations from its lon and lat columns [decimal degrees]")
    p.add_argument("--sites", type=Path, default=None,
                   help="CSV site,lon,lat: the location of the assets whose row has no lon and lat, by their site")
    p.add_argument("--fragility", type=Path, required=True,
                   help="the --out directory of a 'screen fragility' run on the same inventory (its fragility.nc)")
    p.add_argument("--out", type=Path, default=Path("results/event"),
                   help="output directory (default results/event/); a newer ShakeMap version of the same event "
                        "replaces its results, an older one is refused")
    p.add_argument("--k-sigma", type=float, default=0.0, metavar="K",
                   help="take the shaking at its median x exp(K sigma) (default 0: the median)")
    p.add_argument("--shakemap-scale", type=float, default=None, metavar="F",
                   help="a stated conversion when the ShakeMap's component ([event] shakemap_component) differs "
                        "from the fragility's: ShakeMap values x F")
    p.add_argument("--records", type=Path, default=None,
                   help="the event's station records: an asset within [event] station_radius_km of a station (its "
                        "coordinates from the files or the StationXML) is also screened on that record, into "
                        "OUT/records/; the larger probability governs")
    _add_stationxml(p, "for --records in counts or without coordinates (default: *.xml in --records)")
    p.add_argument("-n", "--num-processes", type=int, default=None, metavar="N",
                   help="worker processes that screen --records (default: the cores)")
    p.add_argument("--config", type=Path, default=None, help="TOML configuration ([event]: levels, default sigma)")
    _add_output_options(p)
    return p


def cmd_event(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen event``: the inspection list of one ShakeMap."""
    from .event.assets import Level
    from .run.event import EventRequest, screen_event

    config, inventory = _config_and_inventory(args)
    if args.shakemap_scale is not None and not args.shakemap_scale > 0:
        raise UsageError(f"--shakemap-scale {args.shakemap_scale}: must be a positive factor")
    if not math.isfinite(args.k_sigma):
        raise UsageError(f"--k-sigma {args.k_sigma}: must be a finite number")
    n = _workers(args)
    if args.records is not None:
        _records_dir(args.records)
        _compile_simulator(args, inventory)
    out = screen_event(EventRequest(args.shakemap, inventory, args.fragility, args.out, config,
                                    uncertainty=args.uncertainty, sites=args.sites, k_sigma=args.k_sigma,
                                    shakemap_scale=args.shakemap_scale, records=args.records,
                                    stationxml=args.inventory, n_workers=n,
                                    command=("screen", "event", *argv[1:])), progress=_progress(args.quiet))
    for w in out.warnings:
        log.warning("%s", w)
    if not args.quiet:
        ds = out.dataset
        counts = ", ".join(f"{int((ds['level'].values == lv).sum())} {lv.name}"
                           for lv in sorted(Level, key=lambda m: -m.value))
        print(f"event {ds.attrs['event_id']} ShakeMap v{ds.attrs['shakemap_version']}: {ds.sizes['block']} assets "
              f"({counts}); {out.seconds:.1f} s", file=sys.stderr)
        if out.replaced_version:
            print(f"replaced version {out.replaced_version}: {len(out.changed)} asset(s) changed level"
                  + "".join(f"\n  {b}: {was} -> {now}" for b, was, now in out.changed[:20]), file=sys.stderr)
        print(f"wrote {', '.join(str(p) for p in out.paths)}", file=sys.stderr)
    return 0


SUBCOMMANDS = {"chart": (chart_parser, cmd_chart), "report": (report_parser, cmd_report),
               "bench": (bench_parser, cmd_bench), "infer": (infer_parser, cmd_infer),
               "fragility": (fragility_parser, cmd_fragility), "event": (event_parser, cmd_event)}
SUBCOMMAND_HELP = {
    "chart": "stability chart of one block (the paper's Figs. 2a and 4), records as points, --simulate",
    "report": "rebuild report.html and assets.csv from a screening.nc",
    "bench": "what accuracy costs: every fidelity tier and setting against the reference, measured",
    "infer": "archaeoseismology: the pulses consistent with which blocks toppled and which stood",
    "fragility": "fragility curves by multiple-stripe analysis, the IMs that predict overturning, hazard",
    "event": "after an earthquake: P(overturn) per asset from the ShakeMap, an inspection list and map",
}


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``screen`` (the main job; subcommands are dispatched before it)."""
    p = argparse.ArgumentParser(
        prog="screen",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Screen strong-motion records for the overturning of free-standing rigid blocks.\n\n"
                    "screen --records DIR --blocks CSV [--out DIR] ...   the main job (options below)\n\n"
                    "subcommands (screen SUBCOMMAND --help for each):\n"
                    + "\n".join(f"  {name:<9} {SUBCOMMAND_HELP[name]}" for name in SUBCOMMANDS),
        epilog=_epilog("run", "run"),
    )
    p.add_argument("--version", action="version", version=f"rockscreen {__version__}")
    _add_run_arguments(p)
    return p


#: Signals a command treats as Ctrl-C (what systemd, Kubernetes and Slurm send to stop a job, and a closed terminal):
#: the work done is kept, the output's lock released, and the exit code is 130.
INTERRUPT_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


def _raise_interrupt(signum, frame) -> None:
    raise KeyboardInterrupt(f"signal {signal.Signals(signum).name}")


@contextlib.contextmanager
def _signals_interrupt():
    """While a command runs (in the main thread), :data:`INTERRUPT_SIGNALS` raise ``KeyboardInterrupt`` as Ctrl-C
    does; the previous handlers are restored after."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, _raise_interrupt) for s in INTERRUPT_SIGNALS}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``screen`` console script."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and not argv[0].startswith("-") and argv[0] not in SUBCOMMANDS:
        meant = difflib.get_close_matches(argv[0], list(SUBCOMMANDS), n=1, cutoff=0.6)
        print(f"error: {argv[0]!r} is not a subcommand"
              + (f"; did you mean 'screen {meant[0]}'?" if meant else "")
              + f" Subcommands: {', '.join(SUBCOMMANDS)}; the main job is 'screen --records DIR --blocks CSV' "
              "(screen --help).", file=sys.stderr)
        return EXIT_USAGE
    if argv and argv[0] in SUBCOMMANDS:
        parser_factory, handler = SUBCOMMANDS[argv[0]]
        args = parser_factory().parse_args(argv[1:])
        command = handler
    else:
        args = build_parser().parse_args(argv)
        command = cmd_run
    # third parties (matplotlib, numba, distributed, ...) speak at WARNING; -v opens rockscreen's own debug lines
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s: %(message)s", stream=sys.stderr)
    log.setLevel(logging.DEBUG if getattr(args, "verbose", False) else logging.WARNING)
    try:
        with _signals_interrupt():
            if sys.stderr.isatty() and not getattr(args, "quiet", False):
                from tqdm.contrib.logging import logging_redirect_tqdm

                with logging_redirect_tqdm():                    # warnings above the progress bar, never inside it
                    return command(args, argv)
            return command(args, argv)
    except InventoryError as exc:
        print(f"error: {exc}\nnothing was screened or written.", file=sys.stderr)
        return EXIT_USAGE
    except InterruptedAfterPublishing as exc:
        print(str(exc), file=sys.stderr)
        return EXIT_INTERRUPTED
    except OutputLockedError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_LOCKED
    except OutputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_OUTPUT
    except RockscreenError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:      # a path the command cannot create, read or write (outside the checked inputs)
        where = exc.filename if exc.filename is not None else "a file"
        print(f"error: cannot use {where}: {exc.strerror or exc}. Check that the path is right, its parent "
              "directory exists, and you may write there; earlier results are intact.", file=sys.stderr)
        return EXIT_OUTPUT
    except KeyboardInterrupt:
        print("interrupted: no results were written for this run; earlier results are intact.",
              file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
