"""``screen bench``: what accuracy costs in time."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .exits import _run_exit
from .options import (
    _add_output_options,
    _add_tolerate,
    _compile_simulator,
    _config_and_inventory,
    _epilog,
    _records_dir,
)
from .progress import _ticking


def bench_parser() -> argparse.ArgumentParser:
    """Parser of ``screen bench``."""
    p = argparse.ArgumentParser(prog="screen bench", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("bench", "records"),
                                description="Run every fidelity tier on the same scenes and measure time per scene "
                                            "and agreement with the reference tier; also the cost of the simulation "
                                            "settings. Writes bench.csv, bench.md and bench.png. On the bundled "
                                            "records x configs/blocks.csv (2 cores) the whole bench takes about 7 "
                                            "minutes, --tiers-only about 20 s. A record that cannot be read is "
                                            "named with its reason and left out; the bench then exits 1 (0 with "
                                            "--tolerate-failures).")
    p.add_argument("--records", required=True, type=Path, help="directory of ground-motion records")
    p.add_argument("--blocks", required=True, type=Path, help="inventory CSV (id,height_m,width_m,...)")
    p.add_argument("--out", type=Path, default=Path("results/bench"),
                   help="output directory (default: results/bench/)")
    p.add_argument("--config", type=Path, help="TOML configuration")
    p.add_argument("--tiers-only", action="store_true",
                   help="skip the sweep of the simulation settings (about 20 s instead of about 7 min on the "
                        "bundled records)")
    _add_tolerate(p)
    _add_output_options(p)
    return p


def cmd_bench(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen bench``: what accuracy costs in time."""
    from ..run.accuracy import markdown, run_bench

    config, inventory = _config_and_inventory(args)
    _compile_simulator(args, inventory, config)
    with _ticking(args.quiet) as say:
        bench = run_bench(_records_dir(args.records), inventory, config, out_dir=args.out,
                          settings_sweep=not args.tiers_only, progress=say)
    print(markdown(bench.rows), end="")
    print(f"wrote {args.out / 'bench.csv'}, {args.out / 'bench.md'} and {args.out / 'bench.png'}", file=sys.stderr)
    for f in bench.failures:
        print(f"record {f.record_id} failed and is not in the bench: {f.reason}", file=sys.stderr)
    return _run_exit(len(bench.failures), args)
