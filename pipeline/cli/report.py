"""``screen report``: the report rebuilt from a results file."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from .exits import EXIT_OK
from .options import _add_output_options, _epilog
from .progress import _ticking


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
    if args.results.is_dir():                   # the output folder of a run: its screening.nc
        args.results = args.results / "screening.nc"
    with _ticking(args.quiet, f"writing the report from {args.results} ..."):     # said at once, and repeated
        from ..run.stages import rebuild_report

        html, assets = rebuild_report(args.results, args.out, all_figures=args.all_figures,
                                      command=shlex.join(["screen", *argv]))
    print(f"wrote {html} and {assets}", file=sys.stderr)
    return EXIT_OK
