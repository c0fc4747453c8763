"""Batch screening at scale: 100 real records x 1000 blocks at the default fidelity.

The records directory holds the 35 bundled real records once, then copies of
the bundled PEER AT2 records in sub-directories until there are 100 records
(each copy is its own record to the pipeline: its own id and cache entry; each copy's title line is
changed, since files of identical bytes are one recording under two names and are screened once).
The 1000 blocks are drawn once with a fixed seed over the range of the
sample inventory: full height 0.3-4 m, slenderness alpha 0.08-0.6 rad,
friction 0.3-0.8, half with a blank azimuth (checked along the pulse).

Each configuration runs the real ``screen`` command (screening, margins,
report) in a fresh process into an empty output, and the script prints what
it measured:

* wall time, scenes computed per second and peak memory (the largest process and
  the sum over the process tree, sampled every 0.05 s) for serial, ``-n 2``
  processes and a Dask LocalCluster of 2 workers;
* a re-run into the same output (everything reused from the scene cache);
* the criterion tier alone: ``criteria.evaluate`` on the 100 x 1000 pulse
  arrays of the results, scenes per second;
* peak memory against the number of records (25, 50, 100; serial).

Run: python benchmarks/bench_batch.py [--records N] [--blocks N] [--skip-dask] [--skip-memory]
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

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def make_records(dest: Path, n_records: int) -> int:
    """The bundled records, then AT2 copies in sub-directories until ``n_records``; returns the count."""
    from pipeline.config import Config
    from pipeline.records.listing import find_records

    shutil.copytree(ROOT / "records", dest)
    cfg = Config()
    base = len(find_records(dest, config=cfg)[0])
    at2 = len(find_records(ROOT / "records" / "peer-at2", config=cfg)[0])
    k = 0
    while base + k * at2 < n_records:
        k += 1
        shutil.copytree(ROOT / "records" / "peer-at2", dest / f"copy-{k}")
        # a copy of identical bytes is the same recording under another name and is screened once: give each
        # copy its own title line (first header line; the samples stay the same) so that it counts as a record
        for f in (dest / f"copy-{k}").glob("*.AT2"):
            lines = f.read_text().split("\n")
            lines[0] = f"{lines[0]} (benchmark copy {k})"
            f.write_text("\n".join(lines))
    sources = find_records(dest, config=cfg)[0]
    # trim so that exactly n_records are scanned: the last copy's records first, then (for fewer records
    # than are bundled) bundled records by id, keeping the vertical-only file that fails on purpose
    extra = len(sources) - n_records
    if extra > 0:
        def order(s):
            copy = next((int(p.split("-")[1]) for p in Path(s.files[0]).relative_to(dest).parts
                         if p.startswith("copy-")), 0)
            return (-copy, "1000hyfh" in s.record_id, s.record_id)
        for s in sorted(sources, key=order)[:extra]:
            for f in s.files:
                Path(f).unlink()
    n = len(find_records(dest, config=cfg)[0])
    if n != n_records:
        raise SystemExit(f"made {n} records, expected {n_records}")
    return n


def make_blocks(path: Path, n_blocks: int, seed: int = 20261122) -> None:
    rng = np.random.default_rng(seed)
    height = rng.uniform(0.3, 4.0, n_blocks)
    alpha = rng.uniform(0.08, 0.6, n_blocks)
    width = height * np.tan(alpha)
    mu = rng.uniform(0.3, 0.8, n_blocks)
    az = np.where(rng.random(n_blocks) < 0.5, np.nan, rng.uniform(0, 180, n_blocks))
    lines = ["id,height_m,width_m,mu,azimuth_deg"]
    for j in range(n_blocks):
        lines.append(f"B{j:05d},{height[j]:.4f},{width[j]:.4f},{mu[j]:.3f},"
                     + ("" if np.isnan(az[j]) else f"{az[j]:.1f}"))
    path.write_text("\n".join(lines) + "\n")


#: Polls of the watched command between two readings of its proportional set size (PSS reads each process's page
#: map, far dearer than its RSS)
PSS_EVERY = 10


def _watch(proc) -> tuple[float, int, int, int]:
    """Poll ``proc`` every 50 ms until it ends: the CPU time of its process tree [s] (each process's as last seen:
    the workers are not all reaped by the command itself), its peak RSS, largest process and tree total [B], and the
    peak of the tree's total PSS [B], read every :data:`PSS_EVERY` polls (the memory the tree holds: each shared
    page counted once, split between the processes that map it; RSS counts it in each, so the RSS total overstates
    the tree; 0 where the system does not give PSS)."""
    import psutil

    ps = psutil.Process(proc.pid)
    cpu_of: dict[int, float] = {}
    peak_one = peak_sum = peak_pss = 0
    polls = 0
    while proc.poll() is None:
        rss, pss = [], []
        try:
            for p in [ps, *ps.children(recursive=True)]:
                rss.append(p.memory_info().rss)
                if polls % PSS_EVERY == 0:
                    pss.append(getattr(p.memory_full_info(), "pss", 0))
                times = p.cpu_times()
                cpu_of[p.pid] = times.user + times.system
        except psutil.Error:
            pass
        if rss:
            peak_one, peak_sum = max(peak_one, max(rss)), max(peak_sum, sum(rss))
        peak_pss = max(peak_pss, sum(pss))
        polls += 1
        time.sleep(0.05)
    return sum(cpu_of.values()), peak_one, peak_sum, peak_pss


def timed_run(args: list[str]) -> dict:
    """Run ``screen`` in a fresh process; wall time, CPU time of the whole process tree (user and system) and peak
    RSS (largest process, tree total) and PSS (tree total)."""
    cmd = [sys.executable, "-m", "pipeline", *args, "--tolerate-failures"]   # not -q: the summary is parsed
    # stderr to a file, not a pipe: a pipe nobody reads while the run is polled fills up (64 KiB of progress
    # lines) and blocks the command, which then never ends
    with tempfile.TemporaryFile(mode="w+") as log:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stderr=log, text=True)
        cpu, peak_one, peak_sum, peak_pss = _watch(proc)
        wall = time.perf_counter() - t0
        log.seek(0)
        err = log.read()
    if proc.returncode not in (0, 1):
        raise SystemExit(f"screen failed ({proc.returncode}):\n{err}")
    summary = "\n    ".join(line for line in err.splitlines() if line.startswith(("records:", "margins:")))
    return {"wall_s": wall, "cpu_s": cpu, "peak_one_mb": peak_one / 2**20, "peak_sum_mb": peak_sum / 2**20,
            "peak_pss_mb": peak_pss / 2**20, "summary": summary}


def criterion_rate(results: Path, repeat: int = 20) -> tuple[int, float]:
    """Scenes per second of the paper's criterion alone on the run's pulse arrays."""
    from pipeline import criteria
    from pipeline.store import open_results

    ds = open_results(results)
    geo = dict(R_m=ds.corner_distance.values, alpha=ds.slenderness.values, p=ds.frequency_parameter.values,
               mu=ds.mu.values, g_ms2=9.80665, form="exact")
    args = [ds[n].values for n in ("block_pulse_ap", "block_pulse_tp", "block_pulse_beta", "block_pulse_dv")]
    criteria.evaluate(*args, **geo)
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        criteria.evaluate(*args, **geo)
        best = min(best, time.perf_counter() - t0)
    return args[0].size, args[0].size / best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=100)
    ap.add_argument("--blocks", type=int, default=1000)
    ap.add_argument("--skip-dask", action="store_true")
    ap.add_argument("--skip-memory", action="store_true")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-batch-") as tmp:
        tmp = Path(tmp)
        n_rec = make_records(tmp / "records", args.records)
        blocks = tmp / "blocks.csv"
        make_blocks(blocks, args.blocks)
        scenes = n_rec * args.blocks
        print(f"{n_rec} records x {args.blocks} blocks = {scenes} scenes (scenes/s counts the scenes computed: "
              "a record that fails has none)")
        # compile the kernel's numba cache once, outside the timings
        timed_run(["--records", str(ROOT / "records" / "sac"), "--blocks", str(blocks), "--out", str(tmp / "warm")])
        configs = [("serial", []), ("processes -n 2", ["-n", "2"])]
        if not args.skip_dask:
            configs.append(("dask local, 2 workers", ["--scheduler", "local", "-n", "2"]))
        print(f"{'executor':24s} {'wall s':>8s} {'scenes/s':>9s} {'peak RSS MB (largest / total)':>30s}")
        last_out = None
        for name, extra in configs:
            out = tmp / f"out-{len(extra)}-{name.split()[0]}"
            r = timed_run(["--records", str(tmp / "records"), "--blocks", str(blocks), "--out", str(out), *extra])
            computed = int(r["summary"].split("scenes computed: ")[1].split()[0])      # screened scenes
            print(f"{name:24s} {r['wall_s']:8.1f} {computed / r['wall_s']:9.0f} "
                  f"{r['peak_one_mb']:14.0f} / {r['peak_sum_mb']:.0f}")
            print(f"    {r['summary']}")
            last_out = out
        r = timed_run(["--records", str(tmp / "records"), "--blocks", str(blocks), "--out", str(last_out)])
        print(f"{'re-run, all reused':24s} {r['wall_s']:8.1f} {'':9s} {r['peak_one_mb']:14.0f} / "
              f"{r['peak_sum_mb']:.0f}\n    {r['summary']}")
        n, rate = criterion_rate(last_out / "screening.nc")
        print(f"criterion tier alone (criteria.evaluate on {n} scenes, best of 20): {rate:.3g} scenes/s")
        if not args.skip_memory:
            print("peak RSS against the number of records (serial, largest process):")
            for n_sub in (25, 50, 100):
                sub = tmp / f"records-{n_sub}"
                make_records(sub, n_sub)
                r = timed_run(["--records", str(sub), "--blocks", str(blocks), "--out", str(tmp / f"m{n_sub}")])
                print(f"    {n_sub:4d} records: {r['peak_one_mb']:6.0f} MB, wall {r['wall_s']:.1f} s")
                shutil.rmtree(sub)


if __name__ == "__main__":
    main()
