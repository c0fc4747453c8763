"""``screen fragility``: fragility curves by multiple-stripe analysis."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import (
    UsageError,
)
from .exits import _run_exit
from .options import (
    _add_execution,
    _add_hazard_site,
    _add_inputs,
    _add_output_options,
    _add_tolerate,
    _buildings,
    _compile_simulator,
    _config_and_inventory,
    _epilog,
    _hazard_site,
    _records_dir,
    _workers,
    log,
)
from .progress import _after_stage, _progress, _ticking


def fragility_parser() -> argparse.ArgumentParser:
    """Parser of ``screen fragility``."""
    from ..records.intensity import IMS, SCALABLE
    from ..uncertainty.hazard import Component

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
    _add_hazard_site(p)
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
    starting = "starting (reading the inventory, loading the simulator, listing the records) ..."
    with _ticking(args.quiet, starting) as say:      # each stage's name, repeated while it runs
        from ..levels import levels_unit, parse_levels
        from ..records.intensity import display_unit
        from ..run.executors import start_workers_early
        from ..run.fragility import FragilityRequest, fragility

        config, inventory = _config_and_inventory(args)
        buildings = _buildings(args, inventory)
        auto = args.levels.strip().lower() == "auto"
        levels = None if auto else parse_levels(args.levels, args.im)
        if args.bootstrap < 0:
            raise UsageError(f"--bootstrap {args.bootstrap}: must be >= 0")
        hazard, component = _hazard_and_component(args)
        n = _workers(args)
        start_workers_early(n_workers=n, scheduler=args.scheduler)     # its imports beside this process's
        if config.fidelity.tier != "criterion":
            _compile_simulator(args, inventory, config)
        request = FragilityRequest(_records_dir(args.records), args.blocks, inventory, config, args.im, levels,
                                   args.out, hazard=hazard, component=component,
                                   level_unit=display_unit(args.im) if auto else levels_unit(args.levels, args.im),
                                   buildings=buildings, n_workers=n, scheduler=args.scheduler, bootstrap=args.bootstrap,
                                   command=("screen", *argv), stationxml=args.inventory, orientation=args.orientation)
        out = fragility(request, progress=_after_stage(_progress(args.quiet), say), say=say)
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
    fit uses (:func:`pipeline.run.fragility_hazard.hazard_and_component`)."""
    from ..run.fragility_hazard import hazard_and_component

    site, lonlat = _hazard_site(args)
    return hazard_and_component(args.hazard or [], im=args.im, site=site, lonlat=lonlat,
                                stated=args.hazard_component, im_component=args.im_component, scale=args.hazard_scale)
