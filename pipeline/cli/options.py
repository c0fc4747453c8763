"""The options the subcommands share, their help's examples and exit codes, and the inputs they read."""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

from ..config import FIDELITY_TIERS
from ..errors import (
    RecordsNotFoundError,
    UsageError,
)
from .exits import EXIT_CODES

log = logging.getLogger("pipeline")


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
    "fragility_constrain": "screen fragility --records records --blocks examples/constrain/rocks.csv --im pga "
                           "--im-component rotd50 --levels auto --out results/pbr-fragility --tolerate-failures",
    "constrain": "screen constrain --fragility results/pbr-fragility --ages examples/constrain/ages.csv "
                 "--hazard-branches examples/constrain/openquake --out results/constrain",
}


def _epilog(command: str, codes: str) -> str:
    """The end of a command's --help: an example (two for ``event`` and ``constrain``: the fragility each reads
    first) and its exit codes."""
    first = f"  {EXAMPLES['fragility_' + command]}\n" if f"fragility_{command}" in EXAMPLES else ""
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


def _add_hazard_site(p: argparse.ArgumentParser) -> None:
    """--hazard-site and --hazard-lonlat: the site of OpenQuake files of several (screen fragility, screen
    constrain); read back by :func:`_hazard_site`."""
    p.add_argument("--hazard-site", metavar="SITE_ID",
                   help="OpenQuake file of several sites: the custom_site_id to use")
    p.add_argument("--hazard-lonlat", metavar="LON,LAT",
                   help="OpenQuake file of several sites: LON,LAT; the nearest site is used")


def _hazard_site(args: argparse.Namespace) -> tuple[str | None, tuple[float, float] | None]:
    """--hazard-site and --hazard-lonlat parsed (and --hazard-scale checked positive where given).

    Raises
    ------
    UsageError
        For a LON,LAT that is not two numbers, or a factor that is not positive.
    """
    scale = getattr(args, "hazard_scale", None)
    if scale is not None and not scale > 0:
        raise UsageError(f"--hazard-scale {scale}: must be a positive factor")
    if not args.hazard_lonlat:
        return args.hazard_site, None
    try:
        lon, lat = (float(x) for x in args.hazard_lonlat.split(","))
    except ValueError:
        raise UsageError(f"--hazard-lonlat {args.hazard_lonlat!r}: expected LON,LAT in degrees, e.g. "
                         "12.5,41.9") from None
    return args.hazard_site, (lon, lat)


def _add_tolerate(p: argparse.ArgumentParser) -> None:
    p.add_argument("--tolerate-failures", action="store_true",
                   help="exit 0 even when some records failed (each is still reported, with its reason)")


#: Environment variable giving the default of ``-n`` (scheduled runs sharing a machine set it).
WORKERS_ENV = "ROCKSCREEN_NUM_PROCESSES"           # named in the help; the policy is run.executors.default_workers


def _workers(args: argparse.Namespace) -> int:
    """``-n``, or its default (:func:`pipeline.run.executors.default_workers`), checked."""
    from ..run.executors import workers

    return workers(args.num_processes)


def _config_and_inventory(args: argparse.Namespace):
    """The configuration (``--config``, and ``--fidelity`` where the command has it) and the ``--blocks`` inventory."""
    from ..blocks import read_inventory
    from ..config import load_config

    config = load_config(args.config)
    if getattr(args, "fidelity", None) is not None:
        config = config.with_tier(args.fidelity)
    if getattr(args, "samples", None) is not None or getattr(args, "seed", None) is not None:
        config = config.with_uncertainty(samples=args.samples, seed=args.seed, where="command line")
    return config, read_inventory(args.blocks, default_mu=config.blocks.default_mu,
                                  mesh_limits=config.blocks.mesh_limits())


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


def _buildings(args: argparse.Namespace, inventory) -> dict:
    """The buildings of ``--buildings``, checked against the inventory's placements (errors list every block)."""
    from ..run.stages import buildings_of

    return buildings_of(getattr(args, "buildings", None), inventory)


def _say(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _compile_simulator(args: argparse.Namespace, inventory, config) -> None:
    """Compile the simulator in this process before the workers start (announced when it takes a while: the
    first run of an install), with as many processes as the run's workers on the cores it may use: the kernels of
    the models that may judge a block of the inventory under the configuration's simulator settings, and their
    draws' where it samples."""
    from ..run.executors import workers
    from ..run.stages import compile_simulator

    compile_simulator(inventory, settings=config.simulation_settings(), sampling=config.sampling,
                      announce=None if getattr(args, "quiet", False) else _say,
                      workers=workers(getattr(args, "num_processes", None)))
