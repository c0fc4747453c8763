"""The entry point: the subcommands, the main parser and the errors mapped to exit codes."""

from __future__ import annotations

import argparse
import difflib
import errno
import logging
import sys

from .. import __version__
from ..errors import (
    InterruptedAfterPublishing,
    InventoryError,
    OutputError,
    OutputLockedError,
    RockscreenError,
    raised_by_interrupt,
)
from .bench import bench_parser, cmd_bench
from .chart import chart_parser, cmd_chart
from .constrain import cmd_constrain, constrain_parser
from .event import cmd_event, event_parser
from .exits import EXIT_INTERRUPTED, EXIT_LOCKED, EXIT_OUTPUT, EXIT_USAGE, _signals_interrupt, finish_console
from .fragility import cmd_fragility, fragility_parser
from .infer import cmd_infer, infer_parser
from .options import _add_run_arguments, _epilog, log
from .report import cmd_report, report_parser
from .screen import cmd_run

SUBCOMMANDS = {"chart": (chart_parser, cmd_chart), "report": (report_parser, cmd_report),
               "bench": (bench_parser, cmd_bench), "infer": (infer_parser, cmd_infer),
               "fragility": (fragility_parser, cmd_fragility), "event": (event_parser, cmd_event),
               "constrain": (constrain_parser, cmd_constrain)}


SUBCOMMAND_HELP = {
    "chart": "stability chart of one block (the paper's Figs. 2a and 4), records as points, --simulate",
    "report": "rebuild report.html and assets.csv from a screening.nc",
    "bench": "what accuracy costs: every fidelity tier and setting against the reference, measured",
    "infer": "archaeoseismology: the pulses consistent with which blocks toppled, which stood and which stacked "
             "bodies stood displaced",
    "fragility": "fragility curves by multiple-stripe analysis, the IMs that predict overturning, hazard",
    "event": "after an earthquake: P(overturn) per asset from the ShakeMap, an inspection list and map",
    "constrain": "fragile rocks that stood reweight a hazard model's branches: the site's hazard before and after",
}


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``screen`` (the main job; subcommands are dispatched before it)."""
    p = argparse.ArgumentParser(
        prog="screen",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Screen strong-motion records for the overturning of free-standing rigid blocks.\n\n"
                    "screen --records DIR --blocks CSV [--out DIR] ...   the main job (options below)\n\n"
                    "subcommands (screen SUBCOMMAND --help for each):\n"
                    + "\n".join(f"  {name:<9} {SUBCOMMAND_HELP[name]}" for name in SUBCOMMANDS),
        epilog=_epilog("run", "run"),
    )
    p.add_argument("--version", action="version", version=f"rockscreen {__version__}")
    _add_run_arguments(p)
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``screen`` console script."""
    console = argv is None                  # the process is the command: its last instants answer signals too
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and not argv[0].startswith("-") and argv[0] not in SUBCOMMANDS:
        meant = difflib.get_close_matches(argv[0], list(SUBCOMMANDS), n=1, cutoff=0.6)
        print(f"error: {argv[0]!r} is not a subcommand"
              + (f"; did you mean 'screen {meant[0]}'?" if meant else "")
              + f" Subcommands: {', '.join(SUBCOMMANDS)}; the main job is 'screen --records DIR --blocks CSV' "
              "(screen --help).", file=sys.stderr)
        return EXIT_USAGE
    if argv and argv[0] in SUBCOMMANDS:
        parser_factory, handler = SUBCOMMANDS[argv[0]]
        args = parser_factory().parse_args(argv[1:])
        command = handler
    else:
        args = build_parser().parse_args(argv)
        command = cmd_run
    # third parties (matplotlib, numba, distributed, ...) speak at WARNING; -v opens rockscreen's own debug lines
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s: %(message)s", stream=sys.stderr)
    log.setLevel(logging.DEBUG if getattr(args, "verbose", False) else logging.WARNING)
    received: list[int] = []
    code = _run(command, args, argv, console=console, received=received)
    if console:
        finish_console(code, received)
    return code


def _run(command, args, argv: list[str], *, console: bool, received: list[int]) -> int:
    """Run ``command`` with the signals of :func:`_signals_interrupt` (those noted into ``received``), each error
    turned into its message and exit code."""
    try:
        with _signals_interrupt(to_the_end=console, received=received):
            if sys.stderr.isatty() and not getattr(args, "quiet", False):
                from tqdm.contrib.logging import logging_redirect_tqdm

                with logging_redirect_tqdm():                    # warnings above the progress bar, never inside it
                    code = command(args, argv)
            else:
                code = command(args, argv)
        if received and code != EXIT_INTERRUPTED:   # swallowed (raised in a finalizer), not reported by the command
            print("interrupted as the command ended: what it wrote above is complete", file=sys.stderr)
            return EXIT_INTERRUPTED
        return code
    except InventoryError as exc:
        print(f"error: {exc}\nnothing was screened or written.", file=sys.stderr)
        return EXIT_USAGE
    except InterruptedAfterPublishing as exc:
        print(str(exc), file=sys.stderr)
        return EXIT_INTERRUPTED
    except OutputLockedError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_LOCKED
    except OutputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_OUTPUT
    except RockscreenError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:      # a path the command cannot create, read or write (outside the checked inputs)
        where = exc.filename if exc.filename is not None else "a file"
        if exc.errno == errno.ENOSPC:
            print(f"error: the disk is full ({exc.strerror}) writing {where}; earlier results are intact. Free disk "
                  "space or choose another --out", file=sys.stderr)
            return EXIT_OUTPUT
        print(f"error: cannot use {where}: {exc.strerror or exc}. Check that the path is right, its parent "
              "directory exists, and you may write there; earlier results are intact.", file=sys.stderr)
        return EXIT_OUTPUT
    except KeyboardInterrupt:
        return _interrupted()
    except Exception as exc:
        if received and raised_by_interrupt(exc):       # an interrupt a C extension's import turned into its error
            return _interrupted()
        raise


def _interrupted() -> int:
    """Say what an interrupted command leaves; :data:`EXIT_INTERRUPTED`."""
    print("interrupted: every output this run reported writing above is complete, and nothing else of it was "
          "written; earlier results are intact.",
          file=sys.stderr)
    return EXIT_INTERRUPTED

