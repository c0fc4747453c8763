"""``screen event``: after an earthquake."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from ..errors import (
    UsageError,
)
from .options import (
    _add_output_options,
    _add_stationxml,
    _compile_simulator,
    _config_and_inventory,
    _epilog,
    _records_dir,
    _workers,
    log,
)
from .progress import _progress


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
    from ..event.assets import Level
    from ..run.event import EventRequest, screen_event

    config, inventory = _config_and_inventory(args)
    if args.shakemap_scale is not None and not args.shakemap_scale > 0:
        raise UsageError(f"--shakemap-scale {args.shakemap_scale}: must be a positive factor")
    if not math.isfinite(args.k_sigma):
        raise UsageError(f"--k-sigma {args.k_sigma}: must be a finite number")
    n = _workers(args)
    if args.records is not None:
        _records_dir(args.records)
        _compile_simulator(args, inventory, config)
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
