"""``screen infer``: archaeoseismology."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from .exits import EXIT_OK
from .options import _add_output_options, _config_and_inventory, _epilog
from .progress import _progress


def infer_parser() -> argparse.ArgumentParser:
    """Parser of ``screen infer``."""
    from ..run.infer import INFER_SHAPES, OUTCOME_WORDS

    p = argparse.ArgumentParser(prog="screen infer", formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=_epilog("infer", "plain"),
                                description="Archaeoseismology: the pulses (a_p, t_p, orientation) consistent with "
                                            "which blocks toppled, which stood and which stacked bodies stood "
                                            "displaced, by the paper's criterion and by simulation; conflicting "
                                            "observations are reported.")
    p.add_argument("--blocks", required=True, type=Path, help="inventory CSV of the observed blocks")
    p.add_argument("--observed", required=True, type=Path,
                   help=f"CSV id,outcome[,fall_azimuth_deg] with outcome {OUTCOME_WORDS} (displaced: a body of "
                        "a stack)")
    p.add_argument("--pulse", default="half-sine", choices=INFER_SHAPES, help="assumed pulse shape")
    p.add_argument("--out", type=Path, default=Path("results/infer"),
                   help="output directory (default: results/infer/)")
    p.add_argument("--config", type=Path, help="TOML configuration ([infer] grid)")
    _add_output_options(p)
    return p


def cmd_infer(args: argparse.Namespace, argv: list[str]) -> int:
    """``screen infer``: write infer.nc and infer.png, print the bounds and any conflict."""
    from ..run.infer import summarize, write_inference

    config, inventory = _config_and_inventory(args)
    ds, out, figure = write_inference(args.observed, inventory, shape=args.pulse, config=config, out_dir=args.out,
                                      history=f"screen {shlex.join(argv)}", progress=_progress(args.quiet))
    g = config.records.g_ms2
    skipped = [b for b in str(ds.attrs.get("criterion_not_applied", "")).split(", ") if b]
    if skipped:
        print(f"criterion: not applied to the bodies of stacks ({', '.join(skipped)}): it judges a block alone on "
              "the ground; the simulation judges them with their stacks")
    for method, info in summarize(ds).items():
        if method == "criterion" and len(skipped) == ds.sizes["observation"]:
            continue                                    # nothing the criterion judges
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
