"""What the exact models' kernels cost on the bundled records, the models that step through ``numerics.rk.rk_step``.

On each bundled record with two horizontal components, scaled 1, 2 and 3 times, for four slender sections: the planar
model (:func:`pipeline.rocking.simulate.rock`, each horizontal with the vertical), the 3D box
(:func:`~pipeline.rocking.solids.box3d.simulate_box`, mu 0.8) and the 3D cylinder
(:func:`~pipeline.rocking.solids.cylinder3d.simulate_cylinder`, mu 0.8). Prints each model's best of ``--passes``
timed passes (after one pass that loads the compiled kernels) and how many of its runs overturned.

Usage::

    python benchmarks/step_cost.py [--passes 9] [--models planar box cylinder]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import math
import time
from pathlib import Path

from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.simulate import rock
from pipeline.rocking.solids.box3d import Box, housner_e_box, simulate_box
from pipeline.rocking.solids.cylinder3d import Cylinder, housner_e, simulate_cylinder

ROOT = Path(__file__).resolve().parents[1]
G = 9.80665
#: (width or diameter [m], height [m])
SECTIONS = ((0.3, 1.8), (0.4, 1.6), (0.5, 1.5), (0.25, 1.2))
SCALES = (1.0, 2.0, 3.0)
MU = 0.8


def _planar(records) -> int:
    overturned = 0
    for rec in records:
        for comp in rec.horizontal_ms2:
            for w, h in SECTIONS:
                big_r, alpha = math.hypot(w / 2, h / 2), math.atan2(w, h)
                for s in SCALES:
                    overturned += rock(comp * s, rec.dt_s, p=math.sqrt(0.75 * G / big_r), alpha=alpha,
                                       e=housner_e_box(w / 2, h / 2), R_m=big_r, av_ms2=rec.vertical_ms2).overturned
    return overturned


def _solids(records, run) -> int:
    """``run(h1, h2, av, dt_s, width_m, height_m)`` on both horizontals of every record, section and scale; how many
    of its outcomes overturned."""
    overturned = 0
    for rec in records:
        h1, h2 = rec.horizontal_ms2
        for w, h in SECTIONS:
            for s in SCALES:
                overturned += run(h1 * s, h2 * s, rec.vertical_ms2, rec.dt_s, w, h).overturned
    return overturned


def _box(records) -> int:
    return _solids(records, lambda h1, h2, av, dt, w, h: simulate_box(h1, h2, av, dt, Box(w / 2, w / 2, h / 2, mu=MU)))


def _cylinder(records) -> int:
    return _solids(records, lambda h1, h2, av, dt, w, h: simulate_cylinder(
        h1, h2, av, dt, Cylinder(w / 2, h / 2, MU, housner_e(w / 2, h / 2))))


MODELS = {"planar": _planar, "box": _box, "cylinder": _cylinder}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--passes", type=int, default=9)
    ap.add_argument("--models", nargs="+", choices=sorted(MODELS), default=list(MODELS))
    args = ap.parse_args()
    records = [r for r in iter_records(ROOT / "records", config=Config()) if not r.single_component]
    for name in args.models:
        run = MODELS[name]
        run(records)                                        # loads the compiled kernels
        times, overturned = [], 0
        for _ in range(args.passes):
            t0 = time.perf_counter()
            overturned = run(records)
            times.append(time.perf_counter() - t0)
        print(f"{name:9s} best of {args.passes}: {min(times):.3f} s ({overturned} runs overturned)", flush=True)


if __name__ == "__main__":
    main()
