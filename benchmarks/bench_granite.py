"""The nominal verdicts of two scanned granite rocks against their shake-table tests.

For every test of DATA_DIR (the layout of ``../shared/experiments/granite-pbr``: ``tests.csv``, ``motions/``,
``geometry/``) with a table motion: the motion read by rockscreen's table reader and processed by its uncorrected
chain (mean and trend removed, 5 % taper, 0.05 Hz high-pass), each rock's rocking geometry from its scan
(:mod:`pipeline.shapes.scan`: SP1 from ``SP1.obj``, SP2 from ``final_sp2_1.obj``, the closed mesh of the same
shape; settled on a flat base), and the two-sided rocking model (:mod:`pipeline.rocking.asymmetric`), nominal,
no parameter fitted:

* the pivots are where each side's static tipping angle puts them (``b = z_G tan(tipping)``: the threshold of
  quasi-static overturning, which does not depend on a footprint tolerance);
* restitution: the impact rule's own value (angular momentum about the new pivot); friction is not modelled;
* the orientation on the table is not recorded: the declared one is the published simulation's (the scans' x axis
  along the shaking), in both senses (+x and -x: which way the table's positive acceleration pointed is not
  recorded either), and the y axis is measured beside it.

Writes ``OUT_DIR/predictions.csv`` (``test``, ``rock``, ``orientation``, ``overturn_nominal``, ``observed``) and
prints, per rock and orientation, the accuracy and F1 against the observations, with the always-stands baseline.
The data stays where it is (GPL-3 material: the project ships no copy).

Run: ``python benchmarks/bench_granite.py ../shared/experiments/granite-pbr --out results/granite``.
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np
import obspy

from pipeline.constants import G
from pipeline.records.processing import apply_steps
from pipeline.records.settings import ProcessingConfig
from pipeline.rocking.asymmetric import TwoSided, rock_two_sided
from pipeline.shapes.scan import pivots, read_scan

SCANS = {"SP1": "SP1.obj", "SP2": "final_sp2_1.obj"}
#: (label, azimuth of the shaking axis in the scan's settled frame [deg], sense of the table's +x along it)
ORIENTATIONS = (("x", 0.0, 1.0), ("-x", 0.0, -1.0), ("y", 90.0, 1.0), ("-y", 90.0, -1.0))


def body_of(scan_path: Path, azimuth_deg: float, *, footprint_tol_m: float | None = None) -> TwoSided:
    """The two-sided body of a scan in the plane at ``azimuth_deg``: its pivots at the static tipping angles, or
    (``footprint_tol_m``) at the footprint's extreme points within that tolerance of the base."""
    shape = read_scan(scan_path)
    piv = pivots(shape, azimuth_deg, footprint_tol_m=footprint_tol_m or 0.002)
    z = shape.com_height_m
    phi = math.radians(azimuth_deg)
    n = np.array([-math.sin(phi), math.cos(phi), 0.0])
    b_plus, b_minus = ((piv.b_plus_m, piv.b_minus_m) if footprint_tol_m
                       else (z * math.tan(piv.tipping_plus), z * math.tan(piv.tipping_minus)))
    return TwoSided(b_plus, b_minus, z, float(n @ shape.inertia_per_mass_m2 @ n))


def motion(path: Path) -> tuple[np.ndarray, float]:
    """A table motion [m s-2] and its interval [s], processed as rockscreen processes uncorrected records."""
    tr = obspy.read(str(path), format="TABLE")[0]
    tr.data = tr.data.astype(float) * (G if tr.stats.physical_units == "g" else 1.0)
    apply_steps(tr, ProcessingConfig().uncorrected)
    return np.asarray(tr.data, dtype=float), float(tr.stats.delta)


def _scores(pred: list[int], obs: list[int]) -> tuple[float, float]:
    p, o = np.array(pred), np.array(obs)
    tp, fp, fn = int(np.sum((p == 1) & (o == 1))), int(np.sum((p == 1) & (o == 0))), int(np.sum((p == 0) & (o == 1)))
    f1 = 2 * tp / (2 * tp + fp + fn) if tp + fp + fn else 1.0
    return float(np.mean(p == o)), f1


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("data", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--limit", type=int, default=0, help="the first N tests only (0: all)")
    ap.add_argument("--footprint-mm", type=float, default=0.0,
                    help="pivots at the footprint's extremes within this tolerance [mm] (0: at the static tipping "
                         "angles, the default)")
    args = ap.parse_args()
    tests = [r for r in csv.DictReader((args.data / "tests.csv").open()) if r["has_motion"] == "1"]
    if args.limit:
        tests = tests[:args.limit]
    tol = args.footprint_mm / 1000.0 or None
    bodies = {(rock, label): body_of(args.data / "geometry" / scan, az, footprint_tol_m=tol)
              for rock, scan in SCANS.items() for label, az, _sense in ORIENTATIONS}
    for (rock, label), b in bodies.items():
        tip = [math.degrees(math.atan2(x, b.com_height_m)) for x in (b.b_plus_m, b.b_minus_m)]
        print(f"{rock} {label:>2}: tipping {tip[0]:.1f} / {tip[1]:.1f} deg, z_G {1e3 * b.com_height_m:.1f} mm")
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    t0 = time.perf_counter()
    for n, test in enumerate(tests, 1):
        ah, dt = motion(args.data / "motions" / f"{test['test']}.acc.gz")
        for rock in SCANS:
            observed = int(test[f"{rock.lower()}_overturned"])
            for label, _az, sense in ORIENTATIONS:
                out = rock_two_sided(sense * ah, dt, bodies[(rock, label)], rtol=1e-7, atol_alpha=1e-9)
                rows.append({"test": test["test"], "rock": rock, "orientation": label,
                             "overturn_nominal": -1 if out.undecided else int(out.overturned), "observed": observed,
                             "pga_g": f"{np.max(np.abs(ah)) / G:.4f}"})
        if n % 10 == 0:
            print(f"{n}/{len(tests)} tests, {time.perf_counter() - t0:.0f} s", flush=True)
    with (args.out / "predictions.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    for rock in SCANS:
        obs = [r["observed"] for r in rows if r["rock"] == rock and r["orientation"] == "x"]
        print(f"{rock}: {len(obs)} tests, overturned {sum(obs)}; always stands: accuracy {1 - np.mean(obs):.3f}")
        for label, _az, _s in ORIENTATIONS:
            sel = [r for r in rows if r["rock"] == rock and r["orientation"] == label]
            acc, f1 = _scores([max(r["overturn_nominal"], 0) for r in sel], [r["observed"] for r in sel])
            undecided = sum(r["overturn_nominal"] < 0 for r in sel)
            print(f"  {label:>2}: accuracy {acc:.3f}, F1 {f1:.3f}, undecided {undecided}")
        for pair in (("x", "-x"), ("y", "-y")):
            sel = {lab: [r for r in rows if r["rock"] == rock and r["orientation"] == lab] for lab in pair}
            worst = [max(a["overturn_nominal"], b["overturn_nominal"], 0) for a, b in zip(sel[pair[0]], sel[pair[1]])]
            acc, f1 = _scores(worst, [r["observed"] for r in sel[pair[0]]])
            print(f"  either sense of {pair[0]}: accuracy {acc:.3f}, F1 {f1:.3f}")
    print(f"wrote {args.out / 'predictions.csv'}; {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
