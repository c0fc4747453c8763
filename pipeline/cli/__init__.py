"""Command line: ``screen`` and its subcommands.

``screen --records DIR --blocks inventory.csv [--out DIR]`` screens every
record against every block and writes ``OUT/screening.nc`` and
``OUT/pulses.nc``. Running it again into the same ``--out`` computes only
what is new or changed (:mod:`pipeline.run`), and nothing at all when the inputs, the
configuration, the code and the outputs are as the last run left them
(:mod:`pipeline.run.uptodate`); ``-n N`` uses N local
processes and ``--scheduler`` a Dask cluster (:mod:`pipeline.run.executors`).
This package only parses arguments, calls the run layer or the libraries, and prints: one module per
subcommand (:mod:`.screen`, :mod:`.chart`, :mod:`.report`, :mod:`.bench`, :mod:`.fragility`, :mod:`.infer`,
:mod:`.event`), the shared options (:mod:`.options`), what a command prints while it works (:mod:`.progress`), exit
codes and signals (:mod:`.exits`), and the entry point (:mod:`.main`).

Exit codes: 0 success; 1 at least one record failed (its reason is in
``status`` and the log; ``--tolerate-failures`` makes this 0); 2 bad usage,
configuration or inventory (nothing is written); 3 the output cannot be
written (earlier results intact); 75 another run holds the output;
130 interrupted (what was computed is kept in the scene cache).
"""

from .exits import EXIT_CODES, EXIT_INTERRUPTED, EXIT_LOCKED, EXIT_OK, EXIT_OUTPUT, EXIT_RECORD_FAILURES, EXIT_USAGE
from .main import SUBCOMMANDS, build_parser, main
from .options import EXAMPLES
from .progress import _progress, _progress_bar, _progress_lines

__all__ = ["EXAMPLES", "EXIT_CODES", "EXIT_INTERRUPTED", "EXIT_LOCKED", "EXIT_OK", "EXIT_OUTPUT",
           "EXIT_RECORD_FAILURES", "EXIT_USAGE", "SUBCOMMANDS", "_progress", "_progress_bar", "_progress_lines",
           "build_parser", "main"]
