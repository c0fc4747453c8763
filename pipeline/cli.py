"""Command line: ``screen`` and its subcommands.

``screen --records DIR --blocks inventory.csv [--out DIR]`` screens every
record against every block and writes ``OUT/screening.nc``.

Exit codes: 0 success; 1 at least one record failed (its reason is in
``status`` and the log; ``--tolerate-failures`` makes this 0); 2 bad usage,
configuration or inventory (nothing is written).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import logging
import shlex
import sys
from importlib import metadata
from pathlib import Path

from . import __version__
from .errors import InventoryError, OutputError, RockscreenError

log = logging.getLogger("pipeline")

EXIT_OK, EXIT_RECORD_FAILURES, EXIT_USAGE = 0, 1, 2


def _package_versions() -> str:
    names = ("rockscreen", "obspy", "numpy", "scipy", "PyWavelets", "xarray", "netCDF4", "numba")
    out = {}
    for n in names:
        try:
            out[n] = metadata.version(n)
        except metadata.PackageNotFoundError:
            pass
    return json.dumps(out, sort_keys=True)


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _add_run_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--records", required=True, type=Path, help="directory of ground-motion records")
    p.add_argument("--blocks", required=True, type=Path, help="inventory CSV (id,height_m,width_m,...)")
    p.add_argument("--out", type=Path, default=Path("results"), help="output directory (default: results/)")
    p.add_argument("--config", type=Path, help="TOML configuration (default: built-in, as configs/screen.toml)")
    p.add_argument("--inventory", type=Path, help="StationXML for records in counts (else *.xml in --records)")
    p.add_argument("--tolerate-failures", action="store_true",
                   help="exit 0 even when some records failed (their reasons stay in status)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar, warnings only")
    p.add_argument("-v", "--verbose", action="store_true", help="debug logging")


def _progress(quiet: bool):
    if quiet:
        return None
    from tqdm import tqdm

    return lambda it: tqdm(it, desc="records", unit="rec", file=sys.stderr, disable=None, leave=False)


def cmd_run(args: argparse.Namespace, argv: list[str]) -> int:
    """The main job: screen records against blocks and write results."""
    from .blocks import read_inventory
    from .config import load_config
    from .records.loader import read_declared_units, read_inventory as read_station_inventory
    from .screening import run
    from .store import write_atomic

    config = load_config(args.config)
    inventory = read_inventory(args.blocks, default_mu=config.blocks.default_mu)
    if not args.records.is_dir():
        raise RockscreenError(f"{args.records}: records directory not found")
    station_inventory = read_station_inventory(args.records, args.inventory)
    declared = read_declared_units(args.records, config)
    ds, summary = run(args.records, inventory, config, station_inventory=station_inventory,
                      declared_units=declared, progress=_progress(args.quiet))
    ds.attrs.update({
        "history": f"{Path(sys.argv[0]).name} {shlex.join(argv)}",
        "rockscreen_config": json.dumps(config.to_dict(), sort_keys=True),
        "rockscreen_config_sha256": config.digest(),
        "package_versions": _package_versions(),
        "inventory_file": str(args.blocks),
        "inventory_sha256": _sha256(args.blocks),
        "references": "Housner (1963) BSSA 53(2); Shahi & Baker (2014) BSSA 104(5); "
                      "reference paper: energy-based critical pulse model for rocking blocks",
    })
    out = write_atomic(ds, args.out / "screening.nc")
    write_atomic(summary["pulse_series"], args.out / "pulses.nc")
    print(f"records: {summary['records_ok']} ok, {summary['records_failed']} failed; "
          f"blocks: {summary['blocks']}; wall time {summary['wall_time_s']:.1f} s", file=sys.stderr)
    print("scenes by physics: " + ", ".join(f"{k} {v}" for k, v in summary["scenes_by_physics"].items())
          + "; by response: " + ", ".join(f"{k} {v}" for k, v in summary["scenes_by_response"].items()),
          file=sys.stderr)
    print(f"wrote {out}", file=sys.stderr)
    if summary["records_failed"] and not args.tolerate_failures:
        return EXIT_RECORD_FAILURES
    return EXIT_OK


def chart_parser() -> argparse.ArgumentParser:
    """Parser of ``screen chart``."""
    from .closed_forms import PULSE_BETA

    p = argparse.ArgumentParser(
        prog="screen chart",
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
    p.add_argument("--inventory", type=Path, help="StationXML for --records in counts")
    p.add_argument("--config", type=Path, help="TOML configuration")
    p.add_argument("--simulate", action="store_true",
                   help="add critical_acceleration_simulated: upward amplitude scan with the rocking simulator")
    p.add_argument("--cycles", type=int, default=25, help="cycles of the harmonic pulse for --simulate (25)")
    p.add_argument("--out", type=Path, default=Path("chart.nc"), help="chart data, netCDF (default chart.nc)")
    p.add_argument("--figure", type=Path, help="figure, .png/.svg/.pdf (default: --out with .png)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.add_argument("-v", "--verbose", action="store_true", help="debug logging")
    return p


def cmd_chart(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen chart``: write the chart's netCDF and figure."""
    import xarray as xr

    from .blocks import Inventory, read_inventory
    from .chart import points_from_results, stability_chart
    from .config import load_config
    from .report.stability_plot import plot_stability_chart
    from .store import write_atomic

    config = load_config(args.config)
    if args.block is not None:
        if args.blocks is None or args.height is not None or args.width is not None:
            raise RockscreenError("screen chart: give either --block ID with --blocks CSV, or --height and --width")
        block = read_inventory(args.blocks, default_mu=config.blocks.default_mu).select(args.block)
        if args.mu is not None:
            block = Inventory.single(height_m=float(block.height_m[0]), width_m=float(block.width_m[0]),
                                     mu=args.mu, block_id=args.block, azimuth_deg=float(block.azimuth_deg[0]))
    elif args.height is not None and args.width is not None:
        block = Inventory.single(height_m=args.height, width_m=args.width,
                                 mu=config.blocks.default_mu if args.mu is None else args.mu)
    else:
        raise RockscreenError("screen chart: give the block as --height H --width W [--mu MU], "
                              "or as --block ID --blocks inventory.csv")
    chart = stability_chart(float(block.height_m[0]), float(block.width_m[0]), mu=float(block.mu[0]),
                            pulse=args.pulse, periods_s=args.periods, g_ms2=config.records.g_ms2,
                            form=config.criteria.form)
    if args.simulate:
        from .chart import simulated_critical_acceleration

        if args.cycles < 1:
            raise RockscreenError(f"--cycles {args.cycles}: must be a positive integer")
        chart = simulated_critical_acceleration(chart, cycles=args.cycles, settings=config.simulation)
    block_id = args.block
    if args.records is not None:
        from .records.loader import read_declared_units, read_inventory as read_station_inventory
        from .screening import run

        if not args.records.is_dir():
            raise RockscreenError(f"{args.records}: records directory not found")
        results, _ = run(args.records, block, config,
                         station_inventory=read_station_inventory(args.records, args.inventory),
                         declared_units=read_declared_units(args.records, config), progress=_progress(args.quiet))
        block_id = block.ids[0]
    elif args.results is not None:
        from .store import open_results

        results = open_results(args.results)
    else:
        results = None
    if results is not None:
        chart = xr.merge([chart, points_from_results(chart, results, block_id=block_id)],
                         combine_attrs="override")
    chart.attrs["history"] = f"screen {shlex.join(argv)}"
    out = write_atomic(chart, args.out)
    figure = plot_stability_chart(chart, args.figure or args.out.with_suffix(".png"))
    print(f"transition period {chart.attrs['transition_period']:.3f} s (Eq. 9); wrote {out} and {figure}",
          file=sys.stderr)
    return EXIT_OK


SUBCOMMANDS = {"chart": (chart_parser, cmd_chart)}


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``screen`` (the main job; subcommands are dispatched before it)."""
    p = argparse.ArgumentParser(
        prog="screen",
        description="Screen strong-motion records for the overturning of free-standing rigid blocks.",
        epilog="Exit codes: 0 ok; 1 some records failed (see status); 2 bad usage, config or inventory.",
    )
    p.add_argument("--version", action="version", version=f"rockscreen {__version__}")
    _add_run_arguments(p)
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``screen`` console script."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in SUBCOMMANDS:
        parser_factory, handler = SUBCOMMANDS[argv[0]]
        args = parser_factory().parse_args(argv[1:])
        command = handler
    else:
        args = build_parser().parse_args(argv)
        command = cmd_run
    level = logging.DEBUG if getattr(args, "verbose", False) else logging.WARNING
    logging.basicConfig(level=level, format="%(levelname)s: %(message)s", stream=sys.stderr)
    try:
        return command(args, argv)
    except InventoryError as exc:
        print(f"error: {exc}\nnothing was screened or written.", file=sys.stderr)
        return EXIT_USAGE
    except OutputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except RockscreenError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("interrupted: no results were written for this run; earlier results are intact.",
              file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
