"""What ``screen event`` costs: N assets (default 10,000) against the bundled scenario ShakeMap (269 x 229 nodes).

Writes an inventory of N assets at seeded random places inside the grid (block sizes like configs/blocks.csv) and
a fragility.nc for them in the form ``screen fragility`` writes (medians 0.05-1 g log-uniform, beta 0.2-0.6: the
event stage only reads them), then times the whole command a user runs, ``screen event``, as a subprocess (start,
imports, grid, interpolation, probabilities, event.nc, inspection.csv, the page with its map and curves, the
ShakeCast export). Prints the wall time of each of REPEAT runs; the first run into a fresh output, the others
replacing the same version.

Run: ``python benchmarks/bench_event.py [--assets 10000] [--repeat 3]``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
GRID = ROOT / "examples" / "event" / "903_m6p09_se-scenario-grid.xml.gz"
G = 9.80665


def _inputs(root: Path, n: int, seed: int = 11) -> tuple[Path, Path]:
    from pipeline.event.shakemap import read_grid
    from pipeline.schema import FRAGILITY, apply_schema

    grid = read_grid(GRID)
    rng = np.random.default_rng(seed)
    lon = rng.uniform(grid.lon[0], grid.lon[-1], n)
    lat = rng.uniform(grid.lat[0], grid.lat[-1], n)
    h = np.exp(rng.uniform(np.log(0.3), np.log(5.0), n))
    w = h * np.tan(np.radians(rng.uniform(5.0, 35.0, n)))
    ids = [f"A{k:05d}" for k in range(n)]
    rows = ["id,height_m,width_m,mu,lon,lat"] + [f"{ids[k]},{h[k]:.3f},{w[k]:.3f},0.5,{lon[k]:.5f},{lat[k]:.5f}"
                                                 for k in range(n)]
    blocks = root / "blocks.csv"
    blocks.write_text("\n".join(rows) + "\n")
    median = np.exp(rng.uniform(np.log(0.05), np.log(1.0), n)) * G
    ds = xr.Dataset({"median": (("block",), median), "beta": (("block",), rng.uniform(0.2, 0.6, n)),
                     "median_low": (("block",), median * 0.8), "median_high": (("block",), median * 1.25),
                     "fit_status": (("block",), np.zeros(n, dtype=np.int8))},
                    coords={"block": np.array(ids, dtype=object), "im_level": np.geomspace(0.05, 1.0, 6) * G})
    ds.attrs.update({"im": "pga", "im_units": "m s-2", "im_component": "larger"})
    frag = root / "fragility"
    frag.mkdir()
    apply_schema(ds, FRAGILITY).to_netcdf(frag / "fragility.nc")
    return blocks, frag


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--assets", type=int, default=10000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        blocks, frag = _inputs(root, args.assets)
        times = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "pipeline.cli", "event", "--shakemap", str(GRID), "--blocks",
                            str(blocks), "--fragility", str(frag), "--out", str(root / "out"), "-q"], check=True)
            times.append(time.perf_counter() - t0)
        print(f"screen event, {args.assets} assets x the scenario grid (61,601 nodes): "
              f"{', '.join(f'{t:.2f}' for t in times)} s (median {float(np.median(times)):.2f} s)")


if __name__ == "__main__":
    main()
