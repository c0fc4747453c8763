"""Stability charts: the paper's safe-unsafe boundary of one block for one pulse shape.

:func:`stability_chart` gives, over a grid of pulse periods T = 2 t_p, the
criterion's critical acceleration (Eq. 7 with the configured form of Eqs. 1
and 4), the paper's small-angle boundary, the energy hyperbola, the uplift and
sliding lines and, where one is published, the closed-form threshold of the
idealized pulse (Makris & Roussos 2000 for the half-sine, Housner 1963 for the
step). :func:`chart_points` places recorded pulses on it.

Records have their own fullness factor beta. On the dimensional chart a
record is drawn at the period a pulse of the chart's shape would need to carry
the same velocity increment with the same peak, T beta / beta_shape (the
reference paper's Fig. 6 normalization), so a point lies above the energy
curve exactly when its energy ratio is >= 1. On the normalized chart (the
paper's Fig. 4) the axes are a_p / a_uplift and t_p / t_transition(beta),
where every block and every pulse shape share the boundary max(1 / x, 1).

References
----------
Reference paper, Eqs. (1)-(9), Figs. 2a, 4 and 6.
Makris & Roussos (2000) eq. 27; Housner (1963) eq. 9.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from .. import criteria
from ..blocks import Inventory
from ..closed_forms import housner_rectangle_amplitude, makris_roussos_halfsine, pulse_beta
from ..config import Config
from ..constants import REFERENCE_PAPER, G
from ..errors import ParameterError, ResultsError, UsageError
from ..rocking.geometry import check_friction, geometry
from ..scene_table import SCENE
from ..schema import CHART, apply_schema

#: Default period grid, as multiples of the paper's transition period.
DEFAULT_PERIOD_RANGE = (0.1, 10.0)
DEFAULT_PERIOD_COUNT = 241


def default_periods(transition_period_s: float) -> np.ndarray:
    """Log-spaced periods [s] around a transition period [s]."""
    t_bar = transition_period_s
    lo, hi = DEFAULT_PERIOD_RANGE
    return np.geomspace(lo * t_bar, hi * t_bar, DEFAULT_PERIOD_COUNT)


def closed_form_acceleration(periods_s, *, pulse: str, p: float, alpha: float, g_ms2: float = G) -> np.ndarray:
    """Closed-form minimum overturning amplitude of one idealized pulse [m s-2] (linear model).

    Half-sine of period T (duration T/2, w_p = 2 pi / T): Makris & Roussos
    (2000) eq. 27. Step of duration T/2: Housner (1963) eq. 9. NaN for shapes
    without a published closed form.
    """
    T = np.asarray(periods_s, dtype=float)
    if pulse == "half-sine":
        ratio = makris_roussos_halfsine(2.0 * np.pi / (T * p))
    elif pulse == "step":
        ratio = housner_rectangle_amplitude(p * T / 2.0)
    else:
        return np.full(T.shape, np.nan)
    return ratio * alpha * g_ms2


def stability_chart(height_m: float, width_m: float, *, mu: float, pulse: str = "half-sine",
                    periods_s=None, g_ms2: float = G, form: str = "exact") -> xr.Dataset:
    """The stability chart of one block for one pulse shape, as a Dataset.

    Parameters
    ----------
    height_m, width_m : float
        Full block height and base width [m], > 0.
    mu : float
        Friction coefficient [-], > 0.
    pulse : str
        Pulse shape (:data:`pipeline.closed_forms.PULSE_BETA`).
    periods_s : array_like, optional
        Pulse periods T = 2 t_p [s], > 0 (default: around the transition period).
    g_ms2 : float
        Gravity [m s-2].
    form : {"exact", "small_angle"}
        Forms of the paper's Eqs. 1 and 4 for ``critical_acceleration``.

    Returns
    -------
    xarray.Dataset
        Coordinate ``period`` [s]; ``critical_acceleration`` [m s-2] and the
        curves it is made of; global attribute ``transition_period`` [s]
        (Eq. 9, 2 / (p beta), pi / p for a half-sine).
    """
    geom = geometry(height_m, width_m, g_ms2=g_ms2)
    mu = float(check_friction(mu))
    beta = pulse_beta(pulse)
    R, alpha, p = float(geom.R), float(geom.alpha), float(geom.p)
    t_bar = float(criteria.transition_period(p, beta))
    T = default_periods(t_bar) if periods_s is None else np.asarray(periods_s, dtype=float).ravel()
    if T.size == 0 or np.any(~(T > 0)) or not np.all(np.isfinite(T)):
        raise ParameterError(f"periods = {T.tolist()[:5]}: pulse periods must be finite and > 0 s")
    T = np.sort(T)
    tp = T / 2.0
    a_up = float(criteria.uplift_acceleration(alpha, g_ms2=g_ms2, form=form))
    v_crit = float(criteria.critical_velocity(R, alpha, g_ms2=g_ms2, form=form))
    crit = criteria.critical_acceleration(tp, R, alpha, beta, g_ms2=g_ms2, form=form)
    crit_small = criteria.critical_acceleration(tp, R, alpha, beta, g_ms2=g_ms2, form="small_angle")
    t_bar_form = 2.0 * float(criteria.transition_duration(R, alpha, beta, g_ms2=g_ms2, form=form))
    ds = xr.Dataset(
        {
            "critical_acceleration": ("period", crit),
            "critical_acceleration_small_angle": ("period", crit_small),
            "energy_acceleration": ("period", v_crit / (beta * tp)),
            "closed_form_acceleration": ("period", closed_form_acceleration(
                T, pulse=pulse, p=p, alpha=alpha, g_ms2=g_ms2)),
            "normalized_period": ("period", T / t_bar_form),
            "critical_acceleration_normalized": ("period", crit / a_up),
            "uplift_acceleration": ((), a_up),
            "sliding_acceleration": ((), mu * g_ms2),
            "critical_velocity": ((), v_crit),
        },
        coords={"period": ("period", T)},
    )
    apply_schema(ds, CHART)
    ds["critical_acceleration"].attrs["comment"] = (f"Eq. 7 with the {form} forms of Eqs. 1 and 4; valid below "
                                                    "sliding_acceleration")
    ds.attrs.update({
        "Conventions": "CF-1.11",
        "title": f"stability chart: {height_m:g} m x {width_m:g} m block, {pulse} pulse",
        "pulse": pulse, "beta": beta, "form": form,
        "height": height_m, "width": width_m, "mu": mu, "g": g_ms2,
        "half_height": float(geom.h), "half_width": float(geom.b), "corner_distance": R,
        "slenderness": alpha, "frequency_parameter": p, "restitution_housner": float(geom.e_housner),
        "rocking_applicable": int(criteria.rocking_applicable(alpha)),
        "transition_period": t_bar,
        "transition_period_comment": "Eq. 9: 2 / (p beta), pi / p for a half-sine [s]",
        "transition_period_form": t_bar_form,
        "transition_period_form_comment": f"intersection of the {form} Eq. 5 curve with the Eq. 1 line [s]",
        "references": f"{REFERENCE_PAPER}, Eqs. 1-9; Makris & Roussos (2000) eq. 27; Housner (1963) eq. 9",
    })
    return ds


def chart_points(chart: xr.Dataset, *, record_ids, ap_ms2, tp_s, beta, dv_ms, is_pulse=None,
                 overturn_simulated=None) -> xr.Dataset:
    """Recorded pulses as points on a chart (dimension ``record``).

    The criterion's verdicts are recomputed for the chart's block and form; ``overturn_simulated`` (1, 0,
    or -1 for no verdict, per record) is the nonlinear simulation's verdict for the same block on the whole
    record, carried as given (-1 when not given). Records without a pulse are dropped.
    """
    a = np.abs(np.asarray(ap_ms2, dtype=float))
    keep = np.isfinite(a) & np.isfinite(np.asarray(tp_s, dtype=float))
    ids = np.asarray(record_ids, dtype=object)[keep]
    a, tp = a[keep], np.asarray(tp_s, dtype=float)[keep]
    b, dv = np.asarray(beta, dtype=float)[keep], np.abs(np.asarray(dv_ms, dtype=float))[keep]
    pulse_like = (np.full(a.shape, -1) if is_pulse is None else np.asarray(is_pulse)[keep]).astype("i1")
    simulated = (np.full(a.shape, -1) if overturn_simulated is None
                 else np.asarray(overturn_simulated)[keep]).astype("i1")
    at = chart.attrs
    geom = geometry(at["height"], at["width"], g_ms2=at["g"])
    scene = criteria.evaluate(a, tp, b, dv, R_m=geom.R, alpha=geom.alpha, p=geom.p, mu=at["mu"],
                              g_ms2=at["g"], form=at["form"])
    ds = xr.Dataset(
        {
            "record_ap": ("record", a),
            "record_tp": ("record", tp),
            "record_beta": ("record", b),
            "record_dv": ("record", dv),
            "record_period": ("record", 2.0 * tp * b / at["beta"]),
            "record_energy_ratio": ("record", scene["energy_ratio"]),
            "record_normalized_acceleration": ("record", scene["normalized_acceleration"]),
            "record_normalized_duration": ("record", scene["normalized_duration"]),
            "record_overturn_criterion": ("record", scene["overturn_criterion"]),
            "record_is_pulse": ("record", pulse_like),
            "record_overturn_simulated": ("record", simulated),
        },
        coords={"record": ("record", ids)},
    )
    return apply_schema(ds, CHART)


def points_from_results(chart: xr.Dataset, results: xr.Dataset, *, block_id: str | None) -> xr.Dataset:
    """Points of every record of a ``screening.nc`` on ``chart``.

    With ``block_id`` present in the results, the pulse along that block's
    direction is used; otherwise the record's strongest pulse axis.
    """
    ok = results["status"].values == "ok"
    simulated = None
    if block_id is not None and "block" in results.dims and block_id in list(results["block"].values):
        sel = results.sel(block=block_id)
        names = (SCENE.block_pulse_ap, SCENE.block_pulse_tp, SCENE.block_pulse_beta, SCENE.block_pulse_dv)
        verdict = "overturn" if "overturn" in sel else SCENE.overturn_simulated
        simulated = sel[verdict].values[ok] if verdict in sel else None
    else:
        sel = results
        names = ("pulse_ap", "pulse_tp", "pulse_beta", "pulse_dv")
    missing = [n for n in names if n not in sel]
    if missing:
        raise ResultsError(f"results file has no {missing}: it was written before pulses were extracted; "
                              "re-run screen on the records")
    cols = [sel[n].values[ok] for n in names]
    is_pulse = sel["is_pulse"].values[ok] if "is_pulse" in sel else None
    return chart_points(chart, record_ids=results["record"].values[ok], ap_ms2=cols[0], tp_s=cols[1],
                        beta=cols[2], dv_ms=cols[3], is_pulse=is_pulse, overturn_simulated=simulated)


def simulated_critical_acceleration(chart: xr.Dataset, *, cycles: int = 25, settings=None,
                                    samples_per_period: int = 200) -> xr.Dataset:
    """Add ``critical_acceleration_simulated`` [m s-2]: the first overturning amplitude of the pulse.

    For each period the pulse (``harmonic``: ``cycles`` sine cycles; other
    shapes: one pulse) is simulated with the nonlinear rigid rocking model,
    the amplitude scanned upward from the uplift acceleration in steps of
    ``settings.scan_step`` times it until the first overturning, never by
    bisection (overturning is not monotonic in amplitude). NaN where nothing
    overturns below the sliding line mu g (or ``settings.scan_max_factor``
    times the uplift acceleration).
    """
    from ..config import SimulationConfig
    from ..rocking.references.excitation import pulse
    from ..rocking.simulate import rock

    settings = settings or SimulationConfig()
    at = chart.attrs
    geom = geometry(at["height"], at["width"], g_ms2=at["g"])
    alpha, p, R, e = float(geom.alpha), float(geom.p), float(geom.R), float(geom.e_housner)
    shape = at["pulse"]
    a_up = float(criteria.uplift_acceleration(alpha, g_ms2=at["g"]))
    top = min(at["mu"] * at["g"], settings.scan_max_factor * a_up)
    out = np.full(chart.sizes["period"], np.nan)
    n_runs = 0
    for i, T in enumerate(chart["period"].values):
        k = 1
        while a_up * (1 + k * settings.scan_step) <= top:
            amp = a_up * (1 + k * settings.scan_step)
            acc, dt = pulse(shape, amplitude_ms2=amp, period_s=float(T), cycles=cycles,
                            samples_per_period=samples_per_period)
            n_runs += 1
            if rock(acc, dt, p=p, alpha=alpha, e=e, R_m=R, g_ms2=at["g"], settings=settings).overturned:
                out[i] = amp
                break
            k += 1
    chart = chart.copy()
    chart["critical_acceleration_simulated"] = ("period", out)
    apply_schema(chart, CHART)
    chart["critical_acceleration_simulated"].attrs["comment"] = (
        f"{shape}, {cycles if shape == 'harmonic' else 1} cycle(s); upward scan from the uplift acceleration in "
        f"steps of {settings.scan_step:g} of it, no bisection; NaN: none below {top:.4g} m s-2")
    chart.attrs["simulation_runs"] = n_runs
    return chart


@dataclass(frozen=True)
class ChartRequest:
    """What ``screen chart`` draws: one block's chart for one pulse shape, and the pulses put on it.

    ``records_dir`` screens those records against the block first (their pulses as points); ``results`` takes the
    points from a ``screening.nc`` instead, those of ``block_id`` (None: every scene's); ``figure`` defaults to
    ``out`` with ``.png``.
    """

    config: Config
    block: Inventory
    block_id: str | None
    pulse: str
    periods_s: list | None
    out: Path
    simulate: bool = False
    cycles: int = 25
    records_dir: Path | None = None
    stationxml: Path | None = None
    results: Path | None = None
    figure: Path | None = None
    history: str = ""


def write_chart(request: ChartRequest, *, progress=None) -> tuple[Path, Path, float]:
    """Build, write and draw a stability chart (:func:`stability_chart`, with the simulated boundary when asked
    and the records' pulses as points); the netCDF, the figure and the block's transition period [s]."""
    from ..records.side_files import read_declared_units
    from ..records.side_files import read_inventory as read_station_inventory
    from ..report.stability_plot import plot_stability_chart
    from ..store import open_results, write_atomic
    from .batch import run

    config, block = request.config, request.block
    place = block.stack_of(0)
    if place is not None:
        raise UsageError(f"{block.ids[0]}: a body of the stack {' < '.join(reversed(place.ids))}; a stability chart "
                         "(the criterion's and the closed forms' boundaries) is of a block alone on the ground; its "
                         "verdicts with its stack are in screening.nc and the report")
    chart = stability_chart(float(block.height_m[0]), float(block.width_m[0]), mu=float(block.mu[0]),
                            pulse=request.pulse, periods_s=request.periods_s, g_ms2=config.records.g_ms2,
                            form=config.criteria.form)
    if request.simulate:
        if request.cycles < 1:
            raise UsageError(f"--cycles {request.cycles}: must be a positive integer")
        chart = simulated_critical_acceleration(chart, cycles=request.cycles, settings=config.simulation)
    results, block_id = None, request.block_id
    if request.records_dir is not None:
        block_id = str(block.ids[0])
        results = run(request.records_dir, block, config,
                      station_inventory=read_station_inventory(request.records_dir, request.stationxml),
                      declared_units=read_declared_units(request.records_dir, config), progress=progress).results
    elif request.results is not None:
        results = open_results(request.results)
    if results is not None:
        chart = xr.merge([chart, points_from_results(chart, results, block_id=block_id)], combine_attrs="override")
    chart.attrs["history"] = request.history
    out = write_atomic(chart, request.out)
    figure = plot_stability_chart(chart, request.figure or request.out.with_suffix(".png"))
    return out, figure, float(chart.attrs["transition_period"])
