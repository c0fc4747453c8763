"""The fields every reader fills in ``stats.rockscreen``, so that the loader never asks which format a file is.

rockscreen's own obspy plug-ins (:mod:`.at2`, :mod:`.nfascii`, :mod:`.cosmos`, :mod:`.dmg`) fill them when they
read a file. For the formats obspy reads itself (MiniSEED, SAC, K-NET/KiK-net, ...), :func:`annotate` fills
them after the read: what rockscreen knows of those formats lives here, and only here.
"""

from __future__ import annotations

from obspy.core import AttribDict

#: The key of the common fields in a trace's stats.
COMMON = "rockscreen"
#: SAC ``idep`` codes (the dependent variable's type), as SAC defines them.
SAC_IDEP = {5: "IUNKN (unknown)", 6: "IDISP (nm)", 7: "IVEL (nm/s)", 8: "IACC (nm/s**2)", 50: "IVOLTS"}


def common_fields(*, time_known: bool, recording: str = "", standalone: bool = False,
                  calib_to_ms2: bool = False, units_unstated: str = "", label: str = "") -> AttribDict:
    """The common fields of one trace.

    Parameters
    ----------
    time_known : bool
        The file states the start time (components are then aligned in time, not at their first sample).
    recording : str
        A label from the file's header that the files of one station recording share (PEER AT2: the station
        line); "" when the trace's SEED-like ids group it.
    standalone : bool
        The file is a recording of its own (never grouped with another file).
    calib_to_ms2 : bool
        ``stats.calib`` converts the stored counts to m s-2 (the K-NET scale factor).
    units_unstated : str
        Why the file's units are not known from it, for the error when nothing else states them.
    label : str
        The station and earthquake as the file names them, for people to read ("" when it names neither).
    """
    return AttribDict(time_known=time_known, recording=recording, standalone=standalone,
                      calib_to_ms2=calib_to_ms2, units_unstated=units_unstated, label=label)


def codes_label(network: str, station: str, start=None) -> str:
    """``NET.STA`` and the start date (when known), for files that name their station by its codes."""
    codes = ".".join(x for x in (network, station) if x)
    return f"{codes} {start.date}" if codes and start is not None else codes


def seed_label(stats) -> str:
    """:func:`codes_label` of a trace's stats."""
    return codes_label(stats.network, stats.station, stats.starttime)


def _native_fields(trace) -> AttribDict:
    """The common fields of a trace read by one of obspy's own readers."""
    stats = trace.stats
    fmt = getattr(stats, "_format", "?")
    if fmt == "KNET":                         # obspy puts the Scale Factor (gal per count) times 0.01 in calib
        return common_fields(time_known=True, calib_to_ms2=True, label=seed_label(stats))
    if fmt == "SAC":
        idep = int(stats.sac.get("idep", 5)) if "sac" in stats else 5
        return common_fields(time_known=True, units_unstated=(
            f"SAC header idep={SAC_IDEP.get(idep, idep)} does not reliably give the units (producers write IACC "
            "for data in g or cm/s**2);"), label=seed_label(stats))
    return common_fields(time_known=True, label=seed_label(stats))


def annotate(trace) -> None:
    """Fill the common fields of a trace that has none yet (one read by obspy's own readers)."""
    if COMMON not in trace.stats:
        trace.stats[COMMON] = _native_fields(trace)
