"""``screen constrain``: the constraint standing fragile rocks put on a site's hazard."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from .exits import EXIT_OK
from .options import _add_hazard_site, _add_output_options, _epilog, _hazard_site
from .progress import _ticking


def constrain_parser() -> argparse.ArgumentParser:
    """Parser of ``screen constrain``."""
    from ..uncertainty.constraint import Combine
    from ..uncertainty.hazard import Component

    p = argparse.ArgumentParser(prog="screen constrain", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("constrain", "locked"),
                                description="Fragile rocks that stood through their exposure ages reweight the "
                                            "branches of a hazard model: per branch each rock's toppling rate, the "
                                            "probability it stood, the posterior weights, and the site's mean and "
                                            "fractile hazard before and after.")
    p.add_argument("--fragility", required=True, type=Path,
                   help="the --out folder of 'screen fragility' on the rocks (its fragility.nc), or a CSV "
                        "rock,im,component,median,unit,beta[,median_low,median_high,beta_low,beta_high]")
    p.add_argument("--ages", required=True, type=Path,
                   help="CSV rock,age_yr,age_sd_yr (a normal age, truncated at 0) or rock,age_yr,weight (a table "
                        "of ages per rock)")
    p.add_argument("--hazard-branches", required=True, type=Path, dest="branches",
                   help="folder of the hazard model's end branches: OpenQuake's export (hazard_curve-rlz-*.csv and "
                        "realizations_<calc>.csv) or curve files and weights.csv (file,weight)")
    p.add_argument("--combine", choices=[c.value for c in Combine], default=Combine.strongest.value,
                   help="how the rocks combine: strongest (the default: the most constraining rock alone, "
                        "conservative where the same earthquakes shake every rock) or independent (the product)")
    p.add_argument("--draws", type=int, default=200, metavar="N",
                   help="draws of each rock's fragility carried into the likelihood (200)")
    _add_hazard_site(p)
    p.add_argument("--hazard-period", type=float, metavar="SECONDS", help="Sa's period where the folder holds several")
    p.add_argument("--hazard-component", choices=[c.value for c in Component],
                   help="the hazard's component definition where its files do not say (OpenQuake's: rotd50)")
    p.add_argument("--hazard-scale", type=float, metavar="FACTOR",
                   help="a stated conversion where the hazard's component differs from the fragility's: levels x "
                        "FACTOR")
    p.add_argument("--go-on", action="store_true",
                   help="reweight even where a rock contradicts every branch (its best branch gives it less than a "
                        "0.001 chance of having stood through its age): each such rock is then a warning; without "
                        "it the run stops and names the rock")
    p.add_argument("--out", type=Path, default=Path("results/constrain"),
                   help="output directory (default: results/constrain/)")
    _add_output_options(p)
    return p


def cmd_constrain(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen constrain``: write the outputs and print the change of the hazard at 1e-4 per year."""
    from ..run.constrain import ConstrainRequest, constrain, summary_lines
    from ..uncertainty.constraint import Combine
    from ..uncertainty.hazard import Component

    site, lonlat = _hazard_site(args)
    request = ConstrainRequest(
        args.fragility, args.ages, args.branches, args.out, combine=Combine(args.combine), draws=args.draws,
        site=site, lonlat=lonlat, period_s=args.hazard_period,
        hazard_component=Component(args.hazard_component) if args.hazard_component else None,
        hazard_scale=args.hazard_scale, go_on=args.go_on, command=("screen", *map(shlex.quote, argv)))
    with _ticking(args.quiet) as say:
        result = constrain(request, say=say)
    ds = result.dataset
    for w in result.warnings:
        print(f"WARNING: {w}", file=sys.stderr)
    rule = (f"the most constraining rock alone ({ds.attrs['constraining_rock']})" if ds.attrs["combine"] ==
            "strongest" else "independent rocks (product)")
    for line in summary_lines(ds):
        print(line, flush=True)
    print(f"{len(ds['rock'])} rock(s) combined as {rule}; {len(ds['branch'])} branches reweighted", file=sys.stderr)
    if not args.quiet:
        print(f"{result.seconds:.1f} s; wrote {', '.join(str(p) for p in result.paths)}", file=sys.stderr)
    return EXIT_OK
