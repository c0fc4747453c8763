"""Whole process: ``screen`` against a straightforward port of the published classifier, in one run.

The records are 50 two-component PEER AT2 records: the bundled pairs, then copies of them
in sub-directories (each copy's title line is changed, since files of identical bytes
are one recording under two names and are screened once).

* ``screen``: the command a user runs, in a fresh process (imports, scan, reading,
  processing, pulse extraction and classification, the criterion tier for one block,
  writing, report), with the parity configuration (``configs/shahi_baker_2014.toml``),
  into an empty output directory, with the default executor; then the same command
  again into the same output (a re-run with nothing new: the up-to-date check answers);
  then once more after a file that is not a record was added to the records directory
  (the full path, every record reused from the scene cache).
* ``screen`` with its defaults (the command a user runs without options: the full tier, sampled
  verdicts, the sample inventory ``configs/blocks.csv``), into an empty output;
* the port: a fresh process that reads each pair's AT2 files with a plain parser,
  integrates them to velocity and runs the straightforward port of the MATLAB classifier
  (``bench_pulses.naive_classify``: the transform at every scale of both components,
  rebuilt each time, as the published code does), nothing else.

Both are timed by wall clock around the whole process; the script prints the times and
the ratios it measured. Run: python benchmarks/bench_whole.py [--records 50]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PORT = r"""
import sys, time
from pathlib import Path
import numpy as np
sys.path.insert(0, sys.argv[1])
from bench_pulses import naive_classify

def read_at2(path):
    lines = Path(path).read_text().splitlines()
    head = lines[3].replace(",", " ").split()
    npts = int(head[head.index("NPTS=") + 1]) if "NPTS=" in head else int(head[0])
    dt = float(head[head.index("DT=") + 1]) if "DT=" in head else float(head[1])
    acc = np.array(" ".join(lines[4:]).split(), dtype=float)[:npts]
    return acc, dt

n = 0
for pair in Path(sys.argv[2]).read_text().splitlines():
    (a1, dt), (a2, _) = (read_at2(f) for f in pair.split("\t"))
    m = min(a1.size, a2.size)
    v = np.vstack([np.cumsum(a1[:m]) * dt * 981.0, np.cumsum(a2[:m]) * dt * 981.0])
    naive_classify(v, dt)
    n += 1
print(n)
"""


def two_component_groups() -> list[list[Path]]:
    """The bundled AT2 records with two horizontals: their two horizontal files."""
    from pipeline.config import Config
    from pipeline.records.listing import find_records

    groups = []
    for src in find_records(ROOT / "records" / "peer-at2", config=Config())[0]:
        hor = [Path(f) for f in src.files if not Path(f).stem.upper().endswith(("-UP", "-V", "UP"))]
        if len(hor) == 2:
            groups.append(sorted(hor))
    return groups


def make_records(dest: Path, n_records: int) -> list[tuple[Path, Path]]:
    """``n_records`` two-component records under ``dest``: the pairs, then retitled copies."""
    groups = two_component_groups()
    pairs: list[tuple[Path, Path]] = []
    k = 0
    while len(pairs) < n_records:
        sub = dest / f"copy-{k}"
        sub.mkdir(parents=True)
        for g in groups[: n_records - len(pairs)]:
            out = []
            for f in g:
                lines = f.read_text().split("\n")
                if k:
                    lines[0] = f"{lines[0]} (benchmark copy {k})"
                (sub / f.name).write_text("\n".join(lines))
                out.append(sub / f.name)
            pairs.append((out[0], out[1]))
        k += 1
    return pairs


def wall(cmd: list[str]) -> float:
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if proc.returncode not in (0, 1):
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stderr}")
    return dt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=50)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-whole-") as tmp:
        tmp = Path(tmp)
        pairs = make_records(tmp / "records", args.records)
        listing = tmp / "pairs.txt"
        listing.write_text("\n".join(f"{a}\t{b}" for a, b in pairs))
        blocks = tmp / "one-block.csv"
        blocks.write_text("id,height_m,width_m,mu\nCOL-1,2.0,0.5,0.7\n")
        screen = [sys.executable, "-m", "pipeline", "--records", str(tmp / "records"), "--blocks", str(blocks),
                  "--config", str(ROOT / "configs" / "shahi_baker_2014.toml"), "--fidelity", "criterion",
                  "-q", "--tolerate-failures"]
        # numba's and Python's caches warm once, as on a machine that has run rockscreen before
        wall([*screen, "--out", str(tmp / "warm")])
        port = tmp / "port.py"
        port.write_text(PORT)
        t_port = wall([sys.executable, str(port), str(ROOT / "benchmarks"), str(listing)])
        t_screen = wall([*screen, "--out", str(tmp / "out")])
        t_rerun = wall([*screen, "--out", str(tmp / "out")])
        (tmp / "records" / "notes.txt").write_text("not a record: the directory changed, no record did\n")
        t_reuse = wall([*screen, "--out", str(tmp / "out")])
        default = [sys.executable, "-m", "pipeline", "--records", str(tmp / "records"), "--blocks",
                   str(ROOT / "configs" / "blocks.csv"), "-q", "--tolerate-failures"]
        t_default = wall([*default, "--out", str(tmp / "default")])
        t_nominal = wall([*default, "--samples", "0", "--out", str(tmp / "nominal")])
        shutil.rmtree(tmp / "warm")
    print(f"{len(pairs)} two-component records (parity configuration, criterion tier, one block)")
    print(f"straightforward port of the classifier (read, integrate, classify): {t_port:6.1f} s")
    print(f"screen, whole process (first run into an empty output):             {t_screen:6.1f} s")
    print(f"screen again, nothing new (up-to-date check):                       {t_rerun:6.1f} s")
    print(f"screen again, a non-record file added (full path, all reused):      {t_reuse:6.1f} s")
    print(f"port / screen: {t_port / t_screen:.1f}x   re-run / first run: {100 * t_rerun / t_screen:.0f} % "
          f"(full path with everything reused: {100 * t_reuse / t_screen:.0f} %)")
    print(f"screen with its defaults (full tier, sampled, configs/blocks.csv):  {t_default:6.1f} s   "
          f"port / default: {t_port / t_default:.1f}x")
    print(f"screen --samples 0 (full tier, nominal, configs/blocks.csv):        {t_nominal:6.1f} s   "
          f"default / nominal: {t_default / t_nominal:.1f}x")


if __name__ == "__main__":
    main()
