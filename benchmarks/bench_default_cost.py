"""What the probabilistic default costs against nominal verdicts, on an inventory unlike the bundled one.

Builds a records directory of RECORDS two-component records from the bundled ones (the records' own files, no
synthetic motion) and an inventory of BLOCKS random blocks (seeded: heights 0.3-25 m log-uniform, slenderness
3-40 deg, mu 0.3-0.9, a third with a blank azimuth), then times the whole ``screen`` command, with its default
executor, once with ``--samples 0`` and once with the defaults, into fresh outputs (``--force``). Prints the two
wall times and their ratio, and where the sampled planes go: per class of scene and per orientation, against
the minimum the sequential rule needs (25 draws in one plane certify robust_stand or robust_overturn at 90 %).

``--bundled`` times the bundled records x configs/blocks.csv instead; ``--repeat K`` runs each command K times,
alternating, and reports the medians. ``--profile`` then runs each once more in one process (``-n 1``) under
cProfile and prints the cumulative time of each stage (:data:`STAGES`) and its calls. ``--by-class`` runs the default
once more in one process, without a profiler, and prints the time of each scene's draws by the model family that
judged it and its robustness class (:data:`BY_CLASS`: the three functions that draw a scene, timed around their calls).
``--by-path`` runs the default once more in one process and prints the blank-azimuth scenes' search for the worst
orientation by the path it took (whether the nominal overturned, whether candidate planes were piloted or the
governing plane's estimate settled it, the class), with the selection cells it simulated, and the random
orientation's time and planes.

Run: ``python benchmarks/bench_default_cost.py [--records 20] [--blocks 200] [--bundled] [--repeat 1] [--profile]
[--by-class] [--by-path]``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import pstats
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
#: Draws in one plane that certify a robust class when every draw agrees (90 % Wilson): n z^2 / (n + z^2) ...
MIN_ROBUST_DRAWS = 25
#: The stages ``--profile`` prints: (label, the function whose cumulative time is the stage's: its name, or the end of
#: its file's path and its name, ``file.py:name``, where the name alone is ambiguous).
STAGES = (("pulses", "pulses_and_directions"), ("nominal scenes", "simulate_scene"),
          ("planar draws in all", "bodies/planar.py:_probability"),
          ("  draws of a blank azimuth", "orientation_probability"),
          ("    the race over planes", "worst_orientation"),
          ("      its pilot, race and neighbours (selection draws)", "orientations.py:fill"),
          ("      the chosen planes' estimates (independent draws)", "orientations.py:estimate"),
          ("    the orientation at random", "random_orientation"),
          ("  draws of a scene (any orientation)", "scene_probability"),
          ("  compiled: sample_plane_outcomes", "sample_plane_outcomes"),
          ("  compiled: sample_verdicts", "sample_verdicts"),
          ("  draws of a 3D body", "solid_probability"),
          ("  compiled: the 3D contact model's loop", "contact3d.py:_run"),
          ("  compiled: the exact box model", "run_box"), ("  compiled: the exact cylinder model", "wobble"),
          ("margins", "factor_sweep"))
#: The robustness classes' names by code (-1: a scene not evaluated)
CLASSES = {0: "robust_stand", 1: "sensitive", 2: "robust_overturn", -1: "not evaluated"}
#: What ``--by-class`` times: (family, the module that calls it, the function drawing a scene).
BY_CLASS = (("3D solid", "pipeline.bodies.solids", "solid_probability"),
            ("planar, one plane", "pipeline.bodies.planar", "scene_probability"),
            ("planar, blank azimuth", "pipeline.bodies.planar", "orientation_probability"))
#: The one-process run of ``--by-class``: each function of :data:`BY_CLASS` wrapped where its caller looks it up, the
#: seconds of its calls summed by (family, the class it returned), printed at the end.
_BY_CLASS_CODE = """
import collections, importlib, sys, time
from pipeline.cli import main
spent = collections.defaultdict(lambda: [0, 0.0])
def timed(family, f):
    def run(*a, **k):
        t0 = time.perf_counter()
        r = f(*a, **k)
        cls = int(r.robustness if hasattr(r, 'robustness') else r.worst.robustness)
        spent[family, cls][0] += 1
        spent[family, cls][1] += time.perf_counter() - t0
        return r
    return run
for family, module, name in FAMILIES:
    m = importlib.import_module(module)
    setattr(m, name, timed(family, getattr(m, name)))
t0 = time.perf_counter()
main(sys.argv[1:])
print(f'  one process: {time.perf_counter() - t0:.1f} s, of which the draws {sum(v[1] for v in spent.values()):.1f} s')
for (family, cls), (n, sec) in sorted(spent.items()):
    print(f'  {family:24s} {CLASSES.get(cls, cls)!s:16s} {n:5d} scenes {sec:7.2f} s')
"""


#: The one-process run of ``--by-path``: the worst orientation of each blank-azimuth scene timed by its path (the
#: nominal overturned or stood; the search stopped at the governing plane's estimate or piloted candidate planes; the
#: class it returned), with its selection cells; the random orientation's time and planes apart.
_BY_PATH_CODE = """
import collections, sys, time
import pipeline.uncertainty.orientations as O
from pipeline.cli import main
spent = collections.defaultdict(lambda: [0, 0.0, 0])
worst, average = O.worst_orientation, O.random_orientation
def timed_worst(*a, nominal_overturned, **k):
    t0 = time.perf_counter()
    r = worst(*a, nominal_overturned=nominal_overturned, **k)
    cells = int((r.cells.outcome != O.NOT_SIMULATED).sum())
    key = ('nominal overturned' if nominal_overturned else 'nominal stood',
           'candidates piloted' if cells else 'governing plane only', CLASSES.get(int(r.prob.robustness)))
    spent[key][0] += 1; spent[key][1] += time.perf_counter() - t0; spent[key][2] += cells
    return r
def timed_average(*a, **k):
    t0 = time.perf_counter()
    r = average(*a, **k)
    key = ('random orientation', '', '')
    spent[key][0] += 1; spent[key][1] += time.perf_counter() - t0; spent[key][2] += r[3]
    return r
O.worst_orientation, O.random_orientation = timed_worst, timed_average
t0 = time.perf_counter()
main(sys.argv[1:])
print(f'  one process: {time.perf_counter() - t0:.1f} s')
for key, (n, sec, cells) in sorted(spent.items(), key=lambda kv: -kv[1][1]):
    what = 'planes integrated' if key[0] == 'random orientation' else 'selection cells'
    print(f'  {" / ".join(k for k in key if k):62s} {n:5d} scenes {sec:7.2f} s {1e3 * sec / n:6.1f} ms a scene'
          f' {cells:7d} {what}')
"""


def _records(dest: Path, n: int) -> int:
    from pipeline.config import Config
    from pipeline.records.listing import find_records

    sources, _ = find_records(ROOT / "records", config=Config())
    picked = 0
    # two or three files (two horizontals), units stated in the files themselves (no StationXML, no glob)
    usable = [s for s in sources if len(s.files) >= 2
              and not any(Path(f).suffix.lower() in (".mseed", ".sac") for f in s.files)]
    for src in usable[:n]:
        sub = dest / f"r{picked:03d}"
        sub.mkdir(parents=True)
        for f in src.files:
            shutil.copy(f, sub / Path(f).name)
        picked += 1
    # more than are bundled: AT2 copies, each with its own title line (the samples stay the same; a copy of
    # identical bytes would be the same recording under another name and screened once)
    at2 = [s for s in usable if all(Path(f).suffix.upper() == ".AT2" for f in s.files)]
    copy = 0
    while picked < n and at2:
        src = at2[copy % len(at2)]
        sub = dest / f"r{picked:03d}"
        sub.mkdir(parents=True)
        for f in src.files:
            lines = Path(f).read_text().split("\n")
            lines[0] = f"{lines[0]} (benchmark copy {copy // len(at2) + 1})"
            (sub / Path(f).name).write_text("\n".join(lines))
        picked += 1
        copy += 1
    shutil.copy(ROOT / "records" / "units.toml", dest / "units.toml")
    return picked


def _inventory(path: Path, n: int, seed: int = 7) -> None:
    rng = np.random.default_rng(seed)
    lines = ["id,height_m,width_m,mu,azimuth_deg"]
    for k in range(n):
        h = float(np.exp(rng.uniform(np.log(0.3), np.log(25.0))))
        alpha = np.radians(rng.uniform(3.0, 40.0))
        w = h * np.tan(alpha)                    # full width: tan(alpha) = width / height
        az = "" if k % 3 == 0 else f"{rng.uniform(0, 180):.0f}"
        lines.append(f"B{k:03d},{h:.3f},{w:.3f},{rng.uniform(0.3, 0.9):.2f},{az}")
    path.write_text("\n".join(lines) + "\n")


def _run(records: Path, blocks: Path, out: Path, *options: str) -> float:
    label = f"screen {' '.join(options) or '(the default)'}"
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "pipeline.cli", "--records", str(records), "--blocks", str(blocks),
                    "--out", str(out), "--force", "--tolerate-failures", "-q", *options], check=True)
    wall = time.perf_counter() - t0
    print(f"  {label}: {wall:.1f} s", flush=True)
    return wall


def _profile(records: Path, blocks: Path, out: Path, *options: str) -> None:
    """The command once in one process under cProfile: each stage's cumulative time and calls."""
    prof = out.parent / f"{out.name}.prof"
    t0 = time.perf_counter()
    argv = ["--records", str(records), "--blocks", str(blocks), "--out", str(out), "--force", "--tolerate-failures",
            "-q", "-n", "1", *options]
    # main(argv) returns its code; the console script's own ending (os._exit) would leave no profile written
    code = f"import cProfile, sys; from pipeline.cli import main; cProfile.run('main(sys.argv[1:])', {str(prof)!r})"
    subprocess.run([sys.executable, "-c", code, *argv], check=True)
    print(f"  under cProfile, one process: {time.perf_counter() - t0:.1f} s")
    stats = pstats.Stats(str(prof)).stats                   # {(file, line, function): (cc, calls, tt, ct, callers)}
    for label, function in STAGES:
        where, _, name = function.rpartition(":")
        rows = [v for k, v in stats.items() if k[2] == name and k[0].endswith(where)]
        if rows:
            print(f"  {label:54s} {sum(r[3] for r in rows):7.1f} s in {sum(r[1] for r in rows)} calls")


def _in_one_process(code: str, records: Path, blocks: Path, out: Path) -> None:
    """The default once in one process, run by ``code`` (:data:`_BY_CLASS_CODE`, :data:`_BY_PATH_CODE`: it wraps the
    functions it times, then calls the command), :data:`CLASSES` and :data:`BY_CLASS` defined for it."""
    argv = ["--records", str(records), "--blocks", str(blocks), "--out", str(out), "--force", "--tolerate-failures",
            "-q", "-n", "1"]
    prelude = f"FAMILIES = {BY_CLASS!r}\nCLASSES = {CLASSES!r}\n"
    subprocess.run([sys.executable, "-c", prelude + code, *argv], check=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=20)
    ap.add_argument("--blocks", type=int, default=200)
    ap.add_argument("--bundled", action="store_true", help="the bundled records x configs/blocks.csv")
    ap.add_argument("--repeat", type=int, default=1, help="runs of each command (alternating); medians reported")
    ap.add_argument("--profile", action="store_true", help="then each command once under cProfile, by stage")
    ap.add_argument("--by-class", action="store_true", help="then the default once in one process: its draws' time "
                    "by model family and robustness class")
    ap.add_argument("--by-path", action="store_true", help="then the default once in one process: the blank-azimuth "
                    "scenes' worst orientation by the path its search took, and the random orientation")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        if args.bundled:
            records, blocks = ROOT / "records", ROOT / "configs" / "blocks.csv"
            n_rec = 0
        else:
            records, blocks = root / "records", root / "blocks.csv"
            n_rec = _records(records, args.records)
            _inventory(blocks, args.blocks)
        times: dict[str, list[float]] = {"nominal": [], "default": []}
        for _ in range(max(1, args.repeat)):
            times["nominal"].append(_run(records, blocks, root / "nominal", "--samples", "0"))
            times["default"].append(_run(records, blocks, root / "default"))
        nominal, default = (float(np.median(times[k])) for k in ("nominal", "default"))
        ds = xr.open_dataset(root / "default" / "screening.nc")
        if args.bundled:
            n_rec, args.blocks = ds.sizes["record"], ds.sizes["block"]
        sims, rob, orient = ds["sample_simulations"].values, ds["robustness"].values, ds["orientation"].values
        moving = ds["physics"].values > 0
        print(f"{n_rec} records x {args.blocks} blocks: --samples 0 {nominal:.1f} s, default {default:.1f} s: "
              f"{default / nominal:.2f}x (wall, median of {len(times['nominal'])}: "
              f"{', '.join(f'{a:.1f}/{b:.1f}' for a, b in zip(times['default'], times['nominal']))} s)", flush=True)
        if args.profile:
            for name, options in (("nominal", ("--samples", "0")), ("default", ())):
                print(f"{name}, by stage:")
                _profile(records, blocks, root / f"{name}-profiled", *options)
        if args.by_class:
            print("the default's draws in one process, by family and class:")
            _in_one_process(_BY_CLASS_CODE, records, blocks, root / "by-class")
        if args.by_path:
            print("the blank-azimuth scenes' draws in one process, by the worst orientation's path:")
            _in_one_process(_BY_PATH_CODE, records, blocks, root / "by-path")
    print(f"moving scenes {int(moving.sum())} of {moving.size}; sampled planes {int(sims[sims > 0].sum())}, "
          f"{sims[moving].clip(0).mean():.1f} per moving scene against {MIN_ROBUST_DRAWS} for a robust class in one "
          "plane")
    for code, name in CLASSES.items():
        if code < 0:
            continue
        sel = (rob == code) & (sims > 0)
        print(f"  {name}: {int(sel.sum())} scenes, {int(sims[sel].sum())} planes, "
              f"{sims[sel].mean() if sel.any() else 0:.1f} per scene")
    for code, name in {0: "given azimuth", 1: "scanned", 2: "scanned (relative azimuths)", 3: "one horizontal"}.items():
        sel = (orient == code) & (sims > 0)
        print(f"  {name}: {int(sel.sum())} scenes, {int(sims[sel].sum())} planes")


if __name__ == "__main__":
    main()
