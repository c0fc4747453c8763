"""Where the paper's criterion is wrong on idealized pulses: false-alarm and miss margins.

Compares the criterion's threshold for each pulse (largest lobe = a half-sine
of duration pi / w_p, with uplift: max(1, w_p / (2 p)) in units of alpha g,
linear model) with the minimum overturning amplitudes of an independent
event-driven solver (tests/data/rocking-pulse-minimum-overturning-computed.csv; alpha = 0.25,
e = 0.9, linear rows) and with the Makris & Roussos (2000) closed form.
A ratio below 1 is a false alarm margin (the rule flags pulses that are
safe), above 1 a miss.

Run: python benchmarks/criterion_vs_reference.py
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import csv
from pathlib import Path

from pipeline.closed_forms import PULSE_BETA, impulse_limit, makris_roussos_halfsine

CSV = Path(__file__).resolve().parents[1] / "tests" / "data" / "rocking-pulse-minimum-overturning-computed.csv"


def main() -> None:
    with open(CSV) as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    table: dict[float, dict[str, str]] = {}
    for r in rows:
        if r["formulation"] != "linear":
            continue
        k = float(r["omega_p_over_p"])
        rule = float(impulse_limit(k, PULSE_BETA["half-sine"]))
        cell = "none <= 20" if not r["ap_min_over_g_alpha"] else f"{rule / float(r['ap_min_over_g_alpha']):.2f}"
        table.setdefault(k, {})[r["pulse"]] = cell
        table[k]["closed form"] = f"{rule / float(makris_roussos_halfsine(k)):.2f}"
    print("| w_p/p | half-sine | one-sine | one-cosine | half-sine, M&R eq. 27 |")
    print("|---|---|---|---|---|")
    for k in sorted(table):
        t = table[k]
        print(f"| {k:g} | {t['halfsine']} | {t['onesine']} | {t['onecos']} | {t['closed form']} |")
    print("\nrule threshold / true minimum: < 1 false alarm, > 1 miss")


if __name__ == "__main__":
    main()
