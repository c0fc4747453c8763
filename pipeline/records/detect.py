"""Which waveform format a file holds, by its content, cheaply.

``obspy.read`` without a format asks every installed plug-in in turn, looking
each one up among the installed entry points for every file; on a directory of
records that look-up costs more than reading. Here the plug-ins' ``isFormat``
functions are loaded once per process into a table (rockscreen's own formats
first, then obspy's preferred order) and each file is offered to them by its
content, whatever its name. The reader of the detected format is then called
by name.

The ``PICKLE`` plug-in is left out: its test unpickles the file, which would run
code from an untrusted records directory.
"""

from __future__ import annotations

from functools import lru_cache
from importlib.metadata import entry_points
from pathlib import Path
from typing import Callable

#: rockscreen's plug-ins, tried first (their tests read a few text lines).
OWN_FORMATS = ("PEER_AT2", "COSMOS", "CSMIP_DMG", "NF_ASCII", "KNET", "TABLE")
#: Never offered a file: detection would execute the file's content.
UNSAFE_FORMATS = frozenset({"PICKLE"})
#: File-name suffixes of strong-motion records: such a file that no reader recognises is a failed record;
#: any other unrecognised file is reported as "not a record".
RECORD_SUFFIXES = frozenset({".at2", ".v1", ".v2", ".v1c", ".v2c", ".v3", ".dmg", ".sac", ".mseed", ".miniseed",
                             ".ms", ".knet", ".ew", ".ns", ".ud", ".ew1", ".ns1", ".ud1", ".ew2", ".ns2",
                             ".ud2", ".acc", ".dat", ".smc", ".evt", ".seed"})


@lru_cache(maxsize=1)
def format_table() -> tuple[tuple[str, Callable[[str], bool]], ...]:
    """(name, isFormat) of every installed obspy waveform plug-in, in detection order (cached per process)."""
    try:
        from obspy.core.util.base import WAVEFORM_PREFERRED_ORDER as preferred
    except ImportError:  # pragma: no cover - older obspy
        preferred = []
    installed = entry_points()                 # one pass over the installed distributions, then selections
    names = [ep.name for ep in installed.select(group="obspy.plugin.waveform")]
    order = [n for n in OWN_FORMATS if n in names] + [n for n in preferred if n in names]
    order += [n for n in names if n not in order]
    table = []
    for name in order:
        if name in UNSAFE_FORMATS:
            continue
        found = list(installed.select(group=f"obspy.plugin.waveform.{name}", name="isFormat"))
        if not found:
            continue
        try:
            table.append((name, found[0].load()))
        except Exception:  # a broken plug-in must not stop detection of the others
            continue
    return tuple(table)


def detect_format(path: str | Path) -> str | None:
    """The obspy format name of the record in ``path``, by content; None when no reader recognises it."""
    name = str(path)
    for fmt, is_format in format_table():
        try:
            if is_format(name):
                return fmt
        except Exception:  # a plug-in's test choking on foreign content means "not mine"
            continue
    return None


def looks_like_a_record(path: str | Path) -> bool:
    """True when the file's name says it is a strong-motion record (see :data:`RECORD_SUFFIXES`)."""
    return Path(path).suffix.lower() in RECORD_SUFFIXES
