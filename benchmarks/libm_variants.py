"""What turns with the last bit of the math library: the same run under two of glibc's variants of sin, cos, exp
and atan2.

glibc picks its elementary functions by what the CPU offers (on x86-64, variants that use FMA where the CPU has
it); those variants are not correctly rounded and differ in the last bit for some arguments (about 0.06 % of them
here). The compiled kernels call them, so the same code on two machines can integrate trajectories that differ by
rounding, and a scene near its boundary can turn. ``GLIBC_TUNABLES=glibc.cpu.hwcaps=-FMA`` makes this machine pick
the variants of a CPU without FMA, so both can be run on one machine.

``screen`` mode runs the ``screen`` command twice, fresh outputs, once as the machine picks and once with that
tunable, and prints, for every variable of ``screening.nc``, how many values differ at all and by more than
1e-6 relative, and every scene whose verdict, robustness class or ``p_overturn`` differs. ``granite`` mode does
the same for ``benchmarks/bench_granite.py --model contact3d``'s predictions in two output folders (run it twice,
the second time with the tunable).

``functions`` mode prints how many of the four functions' values differ between the two variants over 200,001
arguments each.

Run: ``python benchmarks/libm_variants.py screen [--records records] [--blocks configs/blocks.csv]``,
``python benchmarks/libm_variants.py granite OUT_HOST OUT_NO_FMA`` or ``python benchmarks/libm_variants.py
functions``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
#: The tunable that makes glibc pick its variants for a CPU without FMA (glibc 2.33 and later).
NO_FMA = "glibc.cpu.hwcaps=-FMA"
#: A difference this small, relative, is rounding [-].
REL_TOL = 1e-6
#: The variables whose every difference is listed scene by scene.
DECISIONS = ("overturn_simulated", "overturn", "robustness", "p_overturn", "samples_overturned")


#: The arguments ``functions`` mode evaluates each function at.
ARGUMENTS = "np.linspace(0.1, 100.0, 200001)"
#: What a child process prints for ``functions`` mode: each function's values at :data:`ARGUMENTS`, as hex floats.
_VALUES = (f"import math, numpy as np; x = {ARGUMENTS}; "
           "print(' '.join(float(f(v)).hex() for f in (math.sin, math.cos, math.exp) for v in x)); "
           "print(' '.join(math.atan2(v, 1.3).hex() for v in x))")


def _env(tunables: str | None) -> dict[str, str]:
    """This process's environment, with ``GLIBC_TUNABLES`` set to ``tunables`` where given."""
    return dict(os.environ, **({"GLIBC_TUNABLES": tunables} if tunables else {}))


def functions() -> None:
    """Print how many of sin, cos, exp and atan2's values at :data:`ARGUMENTS` differ between the two variants."""
    got = [subprocess.run([sys.executable, "-c", _VALUES], env=_env(tunables), check=True, capture_output=True,
                          text=True).stdout.split() for tunables in (None, NO_FMA)]
    a, b = (np.array([float.fromhex(v) for v in g]) for g in got)
    n = a.size // 4
    for k, name in enumerate(("sin", "cos", "exp", "atan2")):
        x, y = a[k * n:(k + 1) * n], b[k * n:(k + 1) * n]
        d = x != y
        ulps = np.abs(x[d] - y[d]) / np.spacing(np.maximum(np.abs(x[d]), np.abs(y[d])))
        print(f"{name}: {int(d.sum())} of {n} values differ ({100.0 * d.mean():.3f} %), by at most "
              f"{ulps.max() if d.any() else 0.0:g} unit in the last place")


def _screen(out: Path, records: str, blocks: str, tunables: str | None) -> None:
    subprocess.run([sys.executable, "-m", "pipeline", "--records", records, "--blocks", blocks, "--out", str(out),
                    "--tolerate-failures"], env=_env(tunables), cwd=ROOT, check=True)       # its own progress shows


def _differs(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where two arrays differ at all, and beyond :data:`REL_TOL` (NaN equal to NaN; non-floats exactly)."""
    if x.dtype.kind != "f":
        d = x != y
        return d, d
    same = (x == y) | (np.isnan(x) & np.isnan(y))
    with np.errstate(invalid="ignore"):
        close = np.abs(x - y) <= REL_TOL * np.maximum(np.abs(x), np.abs(y))
    return ~same, ~same & ~close


def compare_screening(a: xr.Dataset, b: xr.Dataset) -> None:
    """Print what differs between two ``screening.nc`` (see the module)."""
    for name in a.data_vars:
        if name not in b or a[name].dtype.kind not in "fiub":
            continue
        x, y = a[name].values, b[name].values
        if x.shape != y.shape:
            print(f"{name}: shapes differ")
            continue
        anyd, big = _differs(x, y)
        if anyd.any():
            print(f"{name:38s} {int(anyd.sum()):5d} of {x.size} differ, {int(big.sum())} beyond {REL_TOL:g}")
        if name in DECISIONS:
            for idx in zip(*np.nonzero(big)):
                where = ", ".join(f"{d}={a[d].values[i]}" for d, i in zip(a[name].dims, idx))
                print(f"    {name} at {where}: {x[idx]} against {y[idx]}")


def compare_granite(host: Path, other: Path) -> None:
    """Print what differs between two ``bench_granite.py --model contact3d`` outputs (see the module)."""
    a, b = (pd.read_csv(p / "predictions.csv") for p in (host, other))
    m = a.merge(b, on=["test", "rock"], suffixes=("", "_other"))
    turned = m.overturn_nominal != m.overturn_nominal_other
    moved = m.p_overturn != m.p_overturn_other
    yaw = m.yaws_run != m.yaws_run_other
    dp = (m.p_overturn - m.p_overturn_other).abs()[moved]
    print(f"{len(m)} scenes: nominal verdict differs in {int(turned.sum())}, the yaws run before a verdict in "
          f"{int(yaw.sum())}, p_overturn in {int(moved.sum())}"
          + (f" (|difference| median {dp.median():.3f}, 90th percentile {dp.quantile(0.9):.3f}, largest "
             f"{dp.max():.3f})" if moved.any() else ""))
    cols = ["test", "rock", "observed", "overturn_nominal", "overturn_nominal_other", "yaws_run", "yaws_run_other",
            "p_overturn", "p_overturn_other"]
    if moved.any() or turned.any():
        print(m[moved | turned][cols].to_string(index=False))
    for p in (host, other):
        s = pd.read_csv(p / "summary.csv")
        s = s[s.predictor.str.startswith("rockscreen 3D")]
        print(p, "  ".join(f"{r.rock}: accuracy {r.accuracy:.3f}, Brier {r.brier:.3f}" for r in s.itertuples()))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    sc = sub.add_parser("screen", help="run screen twice and compare")
    sc.add_argument("--records", default="records")
    sc.add_argument("--blocks", default="configs/blocks.csv")
    gr = sub.add_parser("granite", help="compare two bench_granite.py --model contact3d outputs")
    gr.add_argument("host", type=Path)
    gr.add_argument("other", type=Path)
    sub.add_parser("functions", help="the functions' values under both variants")
    args = ap.parse_args()
    if args.mode == "functions":
        functions()
        return
    if args.mode == "granite":
        compare_granite(args.host, args.other)
        return
    with tempfile.TemporaryDirectory(prefix="libm-variants-") as tmp:
        outs = [Path(tmp) / "host", Path(tmp) / "no-fma"]
        for out, tunables in zip(outs, (None, NO_FMA)):
            print(f"screen into {out.name}" + (f" with GLIBC_TUNABLES={tunables}" if tunables else ""), flush=True)
            _screen(out, args.records, args.blocks, tunables)
        with xr.open_dataset(outs[0] / "screening.nc") as a, xr.open_dataset(outs[1] / "screening.nc") as b:
            compare_screening(a, b)


if __name__ == "__main__":
    main()
