"""``screen`` itself, the main job: its run and its closing summary."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..config import CRITERION_MEASURED_MISSES
from .exits import EXIT_INTERRUPTED, _run_exit
from .options import _buildings, _compile_simulator, _config_and_inventory, _records_dir, _workers, log
from .progress import _after_stage, _progress, _ticking


def _print_summary(summary: dict, out: Path, *, wrote: bool = True) -> None:
    s = summary
    print(f"records: {s['records_ok']} ok ({s['records_screened']} screened, {s['records_reused']} reused"
          + (f", {s['records_vanished']} kept from the last run: files gone" if s["records_vanished"] else "")
          + f"), {s['records_failed']} failed; blocks: {s['blocks']} ({s['blocks_changed']} new or changed); "
          f"scenes computed: {s['scenes_computed']} at fidelity {s['fidelity']}; {s['executor']}; "
          f"wall time {s['wall_time_s']:.1f} s",
          file=sys.stderr)
    print("scenes by physics: " + ", ".join(f"{k} {v}" for k, v in s["scenes_by_physics"].items())
          + "; by response: " + ", ".join(f"{k} {v}" for k, v in s["scenes_by_response"].items()),
          file=sys.stderr)
    print("scenes by orientation: " + ", ".join(f"{k} {v}" for k, v in s["scenes_by_orientation"].items())
          + f"; rocking planes integrated: {s['planes_integrated']}", file=sys.stderr)
    if s.get("boxes"):
        print(f"other base axis: not checked for {s['boxes']} of {s['blocks']} blocks (boxes without both a depth_m "
              "and an azimuth_deg: judged in the plane of width_m; rocking about the other base axis or a corner is "
              f"not modeled); of the scenes of boxes with both on two horizontals, {s.get('box_scenes_3d', 0)} were "
              f"simulated in 3D (orientation given_3d) and {s.get('box_scenes_certified', 0)} in the plane of the "
              "width, the other axis certified never to lift nor slip (given_certified)", file=sys.stderr)
    if any(s.get("scenes_by_robustness", {}).values()):
        print("under the declared uncertainty ([uncertainty]): " + ", ".join(
            f"{k} {v}" for k, v in s["scenes_by_robustness"].items())
            + f"; sampled planes integrated: {s['sampled_simulations']} (sensitive: the verdict can flip; "
            "p_overturn in screening.nc)", file=sys.stderr)
    if s.get("scenes_unjudged") or s.get("draws_unjudged"):
        print(f"not judged: {s.get('scenes_unjudged', 0)} scene(s) and {s.get('draws_unjudged', 0)} "
              f"of {s.get('draws_total', 0)} samples (in {s.get('scenes_with_unjudged_draws', 0)} scenes) have no "
              "verdict (a model stopped where the base slides, twists or lifts off, the ground fell faster than "
              "gravity, or a cap): unknown, never standing; p intervals span them and such assets read 'at risk "
              "until judged' (samples_without_verdict in screening.nc)", file=sys.stderr)
    if s.get("scenes_unjudged_3d"):
        print(f"  {s['scenes_unjudged_3d']} of them are 3D scenes stopped where the base would slide, twist or lift "
              "off, left so by [simulation] contact3d = false: the default (true) decides them by the 3D contact "
              "model (docs/user-guide.md)", file=sys.stderr)
    general = s.get("general_scenes", {})
    if general.get("total"):
        print(f"contact model: {general['total']} scene(s) left pure rocking or sliding and were decided by the "
              f"general contact model: slide-rock in {general['slide_rock']}, free flight in "
              f"{general['ground_flight'] + general['block_liftoff']} (the ground's g + a_v reached 0 in "
              f"{general['ground_flight']}, the block lifted itself off in {general['block_liftoff']}); physics "
              "general, the modes in contact_modes", file=sys.stderr)
    if s.get("stack_contact"):
        print(f"stacks: {s['stack_contact']} body scene(s) where a joint would slip or the ground fell faster than "
              f"gravity ({s.get('stack_flights', 0)}) were followed by the stacks' slip and flight models (the level "
              "slip, the slide-rock and the contact model; sliding_max, free_flight)", file=sys.stderr)
    guarded = s.get("guarded_scenes", [])
    if guarded:
        print(f"guards: {len(guarded)} scene(s) met a guard of the simulator and are flagged (simulation_guard in "
              "screening.nc; tie_hold: held at rest at a tie, stalled or step_cap: ended with the verdict of the "
              "state reached; model_limit: a 3D model stopped where the base would slide or lift off, or a "
              "scanned body's model met what it does not follow, no verdict): " + "; ".join(guarded[:10])
              + ("; ..." if len(guarded) > 10 else ""),
              file=sys.stderr)
    for line in filter(None, s.get("buildings", "").split("\n")):
        print(f"building {line} (floor motion: Miranda & Taghavi 2005)", file=sys.stderr)
    if s.get("slides_off_base"):
        print(f"sliding: {s['slides_off_base']} scene(s) where the block slides farther than its base_margin_m, off "
              "its base (slides_off_base in screening.nc)", file=sys.stderr)
    flights = s.get("free_flight_scenes", 0)
    if flights:
        print(f"free flight: {flights} scene(s) where the ground's g + a_v reached 0 "
              "before any overturning have no verdict (response free_flight: with simulation.contact_model off, or "
              "a body given by its scan, whose models do not follow a flight)",
              file=sys.stderr)

    if s.get("not_records"):
        names = ", ".join(Path(p).name for p, _ in s["not_records"][:5]) + (", ..." if len(s["not_records"]) > 5
                                                                             else "")
        print(f"not records: {len(s['not_records'])} of {s['files_seen']} files ({names}); the list with reasons "
              "is the global attribute files_not_records of screening.nc", file=sys.stderr)
    if s.get("units_toml"):
        print(f"units: records failed because nothing states their units. Paste these lines into "
              f"{Path(s['records_dir']) / 'units.toml'} (if it has a [files] line already, only the lines after "
              "it), check each unit against the data provider, and run again:\n[files]\n"
              + "\n".join(s["units_toml"]), file=sys.stderr)
    for kept, dup in s.get("duplicates", []):
        print(f"duplicate: {dup} holds the same bytes as {kept}; screened once, as {kept}", file=sys.stderr)
    if wrote:
        print(f"wrote {out}", file=sys.stderr)


def cmd_run(args: argparse.Namespace, argv: list[str]) -> int:
    """The main job: screen records against blocks and write results (incrementally)."""
    from ..run import uptodate
    from ..run.executors import start_workers_early

    config, inventory = _config_and_inventory(args)
    records_dir = _records_dir(args.records)
    key, last = uptodate.check(records_dir=records_dir, blocks_csv=args.blocks, config=config,
                               stationxml=args.inventory, out_dir=args.out, buildings_csv=args.buildings,
                               force=args.force)
    if last is not None:
        return _report_up_to_date(args, last, config)
    start_workers_early(n_workers=_workers(args), scheduler=args.scheduler)   # its imports beside this process's
    starting = "starting (loading the simulator, listing the records) ..."
    with _ticking(args.quiet, starting) as say:      # each stage's name, repeated while it runs
        from ..run import RunInterrupted, ScreenRequest, screen
        from ..run.stages import preflight

        preflight(records_dir, args.out)             # an empty --records or an unwritable --out: said at once
        if config.fidelity.tier != "criterion":
            _compile_simulator(args, inventory, config)

        request = ScreenRequest(records_dir=records_dir, blocks_csv=args.blocks, inventory=inventory,
                                config=config, out_dir=args.out, stationxml=args.inventory,
                                n_workers=_workers(args),
                                scheduler=args.scheduler, force=args.force,
                                command=list(argv), key=key, buildings=_buildings(args, inventory))
        try:
            result = screen(request, progress=_after_stage(_progress(args.quiet), say), say=say)
        except RunInterrupted as exc:
            print(str(exc), file=sys.stderr)
            return EXIT_INTERRUPTED
    if config.fidelity.tier == "criterion":
        log.warning("fidelity 'criterion' is not conservative: %s", CRITERION_MEASURED_MISSES)
    if not args.quiet:
        _print_summary(result.counts, result.screening_path)
        _print_margins(result.margins)
        print(f"wrote {result.report_path} and {result.assets_path}", file=sys.stderr)
    return _run_exit(result.records_failed, args, records_ok=int(result.counts.get("records_ok", 1)))


def _print_margins(m: dict) -> None:
    print(f"margins: {m['computed']} scanned, {m['reused']} reused ({m['simulations']} scaled scenes behind them); "
          f"{m['wall_time_s']:.1f} s"
          + (f"; records no longer readable for margins: {', '.join(m['unavailable'])}" if m["unavailable"] else ""),
          file=sys.stderr)


def _report_up_to_date(args: argparse.Namespace, last: dict, config) -> int:
    """A run with nothing new: say so, repeat the last run's summary, exit as it would have."""
    counts = last["counts"]
    if not args.quiet:
        n_files = counts.get("files_seen", last["key"]["records_files"])   # counted as the run's summary counts
        print(f"up to date: the records ({n_files} files), the inventory, the configuration "
              f"and rockscreen are unchanged since the run that finished {last['finished_utc']}, and its outputs "
              f"in {args.out} are intact (checked by SHA-256); nothing was recomputed or rewritten. "
              "--force recomputes.", file=sys.stderr)
    if config.fidelity.tier == "criterion":
        log.warning("fidelity 'criterion' is not conservative: %s", CRITERION_MEASURED_MISSES)
    for record_id, status in last.get("failures", []):
        log.warning("record %s %s (files unchanged since the run that found it)", record_id, status)
    if not args.quiet:
        print("that run's summary:", file=sys.stderr)
        _print_summary(counts, Path(args.out) / "screening.nc", wrote=False)
        _print_margins(last["margins"])
    return _run_exit(int(counts.get("records_failed", 0)), args, records_ok=int(counts.get("records_ok", 1)))
