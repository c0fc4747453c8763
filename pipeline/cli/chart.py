"""``screen chart``: one block's stability chart."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from ..errors import (
    UsageError,
)
from .exits import EXIT_OK
from .options import _add_output_options, _add_stationxml, _epilog, _records_dir
from .progress import _progress


def chart_parser() -> argparse.ArgumentParser:
    """Parser of ``screen chart``."""
    from ..closed_forms import PULSE_BETA

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
    from ..blocks import Inventory, read_inventory
    from ..config import load_config
    from ..run.chart import ChartRequest, write_chart

    config = load_config(args.config)
    if args.block is not None:
        if args.blocks is None or args.height is not None or args.width is not None:
            raise UsageError("screen chart: give either --block ID with --blocks CSV, or --height and --width")
        block = read_inventory(args.blocks, default_mu=config.blocks.default_mu, warn_for=args.block,
                               mesh_limits=config.blocks.mesh_limits()).select(args.block)
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
