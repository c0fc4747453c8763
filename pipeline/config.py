"""Configuration: TOML files validated against one source of truth, the dataclasses here.

Every default lives in this module. ``configs/screen.toml`` spells the same
defaults out for users (a test keeps the two equal). A TOML file only needs
the keys it changes; unknown sections or keys are an error that lists the
valid ones.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .criteria import FORMS
from .errors import ConfigError
from .records.processing import INTEGRATION_METHODS, STEP_PARAMS
from .records.settings import ProcessingConfig, RecordsConfig
from .rocking.settings import ScannedModel, SimulationConfig
from .shapes.mesh_limits import DEFAULT_LIMITS, MeshLimits
from .uncertainty.settings import UncertaintyConfig

__all__ = ["Config", "ProcessingConfig", "RecordsConfig", "SimulationConfig", "UncertaintyConfig", "config_from_dict",
           "load_config"]

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


@dataclass(frozen=True)
class BlocksConfig:
    """Inventory defaults."""

    #: Friction coefficient used where the inventory leaves ``mu`` blank [-].
    default_mu: float = 0.6
    #: The largest scan read (a ``mesh`` column): faces, and the file's size [MB]; a larger one is refused, named,
    #: before it is read (decimate it, or raise these).
    max_mesh_faces: int = DEFAULT_LIMITS.max_faces
    max_mesh_mb: float = DEFAULT_LIMITS.max_mb

    def mesh_limits(self) -> MeshLimits:
        """The largest scan the inventory reads, as :func:`pipeline.shapes.scan.read_scan` takes it (its sizes held
        to the columns' range, :data:`pipeline.shapes.mesh_limits.SIZE_RANGE_M`)."""
        return DEFAULT_LIMITS._replace(max_faces=self.max_mesh_faces, max_mb=self.max_mesh_mb)


@dataclass(frozen=True)
class PulsesConfig:
    """Velocity-pulse extraction (Shahi & Baker 2014)."""

    #: "shahi_baker_2014" (two components, 5 candidates) or "baker_2007" (one component).
    method: str = "shahi_baker_2014"
    #: Shortest and longest pulse period searched [s].
    tp_min_s: float = 0.25
    tp_max_s: float = 15.0


@dataclass(frozen=True)
class CriteriaConfig:
    """The reference paper's criterion (:mod:`pipeline.criteria`)."""

    #: "exact": uplift at g tan(alpha) and the exact critical velocity of Eq. 4;
    #: "small_angle": the paper's alpha g and alpha g / p.
    form: str = "exact"


#: Fidelity tiers, cheapest first (see :class:`FidelityConfig`).
FIDELITY_TIERS = ("criterion", "full", "reference")
#: What ``screen bench`` measured for the ``criterion`` tier against ``reference`` on the bundled records
#: x configs/blocks.csv (printed when the tier is chosen; a test re-measures it).
CRITERION_MEASURED_MISSES = ("on the bundled records x configs/blocks.csv it missed 162 of the 236 overturnings "
                             "the simulator finds (145 of 219 on pulse-like records, 17 of 17 on the others), "
                             "with 2 false alarms (screen bench; docs/validation.md)")
#: Tiers that existed once, and why they are gone.
RETIRED_TIERS = {"screen": "the 'screen' band tier was retired: it trusted the paper's criterion outside a band "
                           "around its boundary and missed overturnings (38 of 216 on the bundled records). "
                           "Use 'full' (the exact at-rest certificate, then the simulator for every scene that "
                           "moves) or 'criterion' (the paper's criterion alone; not conservative)"}


@dataclass(frozen=True)
class FidelityConfig:
    """How much of the ladder of models a run climbs (``screen --fidelity``).

    ``criterion``: the paper's criterion on the extracted pulse only, nothing simulated; fast
    and *not conservative* (its measured misses are printed when it is chosen).
    ``full`` (default): the cheapest tier with no miss measured against ``reference`` (the same
    model at the default tolerances; ``screen bench``). The exact at-rest certificate (no
    uplift and no slip at any sample, vertical included) skips a scene; every other scene is
    simulated. ``reference``: as ``full`` with the tight ``reference_*`` integration settings, and every
    flight of an impact cascade stepped (no closed-form chatter).
    """

    tier: str = "full"
    #: ``reference`` tier: relative and absolute tolerances, rest ratio and largest step (x 1/p).
    reference_rtol: float = 1e-11
    reference_atol: float = 1e-13
    reference_rest_ratio: float = 1e-9
    reference_max_step_p: float = 0.01


@dataclass(frozen=True)
class InferConfig:
    """``screen infer``: the (a_p, t_p) grid and the orientation handling."""

    #: Pulse durations t_p on the grid, log-spaced over 0.1-10 transition durations of the blocks [-].
    n_durations: int = 40
    #: Pulse accelerations a_p on the grid, log-spaced over 0.5-20 uplift accelerations [-].
    n_accelerations: int = 40
    #: Pulse orientations tried when a block has a rocking plane or a fall azimuth [deg].
    azimuth_step_deg: float = 15.0
    #: A block free to rock in any plane falls within this angle of the pulse axis [deg].
    fall_tolerance_deg: float = 20.0
    #: Samples per period T = 2 t_p of the simulated idealized pulse [-].
    samples_per_period: int = 200
    #: A body observed ``displaced`` holds where it stands with a residual offset on what it stands on of at least
    #: this [m].
    displaced_min_m: float = 0.01


@dataclass(frozen=True)
class EventConfig:
    """``screen event``: inspection levels, the shaking's uncertainty where the ShakeMap has none, its component."""

    #: Smallest P(overturn | event) of the inspection level low [-].
    level_low: float = 0.05
    #: ... of the level medium [-].
    level_medium: float = 0.2
    #: ... of the level high [-].
    level_high: float = 0.5
    #: Standard deviation of ln IM where the ShakeMap gives none (neither STD field nor uncertainty.xml): a typical
    #: total sigma of a ground-motion model for PGA and PGV, 0.6-0.7 (e.g. Abrahamson et al. 2014) [-].
    default_log_sd: float = 0.65
    #: The horizontal component the ShakeMap reports (rotd100, rotd50, geomean, larger): ShakeMap's default is the
    #: larger of the two horizontals ("greater of two"; Worden et al. 2020); a map made otherwise says so in its
    #: info file, and this is then changed to match.
    shakemap_component: str = "larger"
    #: Fragility curves drawn on the event page, highest priority first (every number stays in event.nc) [-].
    page_curves: int = 60
    #: ``--records``: an asset within this distance of a station is also screened on that station's record [km].
    station_radius_km: float = 2.0


@dataclass(frozen=True)
class Config:
    """The whole configuration."""

    records: RecordsConfig = field(default_factory=RecordsConfig)
    processing: ProcessingConfig = field(default_factory=ProcessingConfig)
    blocks: BlocksConfig = field(default_factory=BlocksConfig)
    pulses: PulsesConfig = field(default_factory=PulsesConfig)
    criteria: CriteriaConfig = field(default_factory=CriteriaConfig)
    simulation: SimulationConfig = field(default_factory=SimulationConfig)
    fidelity: FidelityConfig = field(default_factory=FidelityConfig)
    infer: InferConfig = field(default_factory=InferConfig)
    uncertainty: UncertaintyConfig = field(default_factory=UncertaintyConfig)
    event: EventConfig = field(default_factory=EventConfig)

    @property
    def sampling(self) -> bool:
        """True when a run estimates probabilities of overturning (:func:`sampling`)."""
        return sampling(self.uncertainty.samples, self.fidelity.tier)

    def simulation_settings(self) -> SimulationConfig:
        """The integration settings of the fidelity tier (tight ones for ``reference``)."""
        if self.fidelity.tier != "reference":
            return self.simulation
        f = self.fidelity
        return dataclasses.replace(self.simulation, rtol=f.reference_rtol, atol=f.reference_atol,
                                   rest_ratio=f.reference_rest_ratio, max_step_p=f.reference_max_step_p,
                                   closed_form_chatter=False)

    def with_tier(self, tier: str) -> "Config":
        """The same configuration at another fidelity tier.

        Raises
        ------
        ConfigError
            For an unknown tier.
        """
        if tier in RETIRED_TIERS:
            raise ConfigError(f"fidelity {tier!r}: {RETIRED_TIERS[tier]}")
        if tier not in FIDELITY_TIERS:
            raise ConfigError(f"fidelity {tier!r}: valid tiers are {list(FIDELITY_TIERS)}")
        return dataclasses.replace(self, fidelity=dataclasses.replace(self.fidelity, tier=tier))

    def with_uncertainty(self, *, where: str = "command line", **values) -> "Config":
        """The same configuration with ``[uncertainty]`` keys replaced (``screen --samples``, ``--seed``).

        Raises
        ------
        ConfigError
            For a value outside its valid range (named, with the range).
        """
        current = self.uncertainty
        checked = {k: _check_value("uncertainty", k, v, getattr(current, k), where) for k, v in values.items()
                   if v is not None}
        unc = dataclasses.replace(current, **checked)
        _check_uncertainty(unc, where)
        return dataclasses.replace(self, uncertainty=unc)

    def to_dict(self) -> dict:
        """Plain-data form (embedded in outputs, hashed for re-runs)."""
        return json.loads(json.dumps(dataclasses.asdict(self), default=list))

    def digest(self) -> str:
        """SHA-256 of the canonical JSON form."""
        return hashlib.sha256(json.dumps(self.to_dict(), sort_keys=True).encode()).hexdigest()


def sampling(samples: int, tier: str) -> bool:
    """Whether a run estimates probabilities of overturning: samples are asked for (``[uncertainty] samples`` > 0)
    and the fidelity tier simulates (not ``criterion``). One rule for the screening, the margins, ``screen
    fragility`` and ``screen bench``; the report applies it to the results' attributes (:func:`sampling_of`)."""
    return samples > 0 and tier != "criterion"


def tier_of(attrs: dict) -> str:
    """The fidelity tier of the run that wrote a results file, from its attributes (``rockscreen_config``)."""
    return str(json.loads(attrs.get("rockscreen_config", "{}")).get("fidelity", {}).get("tier", "full"))


def sampling_of(attrs: dict) -> bool:
    """:func:`sampling` of the run that wrote a results file, from its attributes (``uncertainty_samples`` and the
    tier in ``rockscreen_config``)."""
    return sampling(int(attrs.get("uncertainty_samples", 0)), tier_of(attrs))


#: Float keys for which 0 is a valid value (it switches an approximation or a refinement off).
ZERO_ALLOWED = {("simulation", "vertical_fraction"), ("simulation", "orientation_refine_deg"),
                *(("uncertainty", k) for k in ("amplitude_cov", "restitution_cov", "friction_cov", "size_cov",
                                               "azimuth_sd_deg", "orientation_step_deg")),
                ("event", "default_log_sd"), ("event", "level_low")}
#: Float keys limited to a range.
RANGES = {("simulation", "orientation_step_deg"): (0.1, 90.0), ("simulation", "orientation_refine_deg"): (0.0, 90.0),
          ("uncertainty", "azimuth_sd_deg"): (0.0, 45.0), ("uncertainty", "confidence"): (0.5, 0.999),
          ("uncertainty", "robust_below"): (0.001, 0.5), ("uncertainty", "robust_above"): (0.5, 0.999),
          ("uncertainty", "p_halfwidth"): (0.001, 1.0), ("uncertainty", "orientation_step_deg"): (0.0, 45.0),
          ("uncertainty", "orientation_average_halfwidth"): (0.001, 0.5),
          **{("event", k): (0.0, 1.0) for k in ("level_low", "level_medium", "level_high")},
          ("event", "default_log_sd"): (0.0, 3.0)}
#: Spreads (coefficients of variation): valid in [0, 1); a cov of 1 or more is not a measurement uncertainty.
COV_KEYS = ("amplitude_cov", "restitution_cov", "friction_cov", "size_cov")
#: Largest number of samples per scene.
MAX_SAMPLES = 100000


def _check_uncertainty(u: UncertaintyConfig, where: str) -> None:
    """Ranges of the ``[uncertainty]`` section that the generic checks cannot express."""
    for key in COV_KEYS:
        v = getattr(u, key)
        if not 0.0 <= v < 1.0:
            raise ConfigError(f"{where}: [uncertainty] {key} = {v!r}: expected a coefficient of variation in "
                              "[0, 1) (0: no uncertainty on it; 0.05 is a 5 % spread)")
    if not 0 <= u.samples <= MAX_SAMPLES:
        raise ConfigError(f"{where}: [uncertainty] samples = {u.samples!r}: expected an integer in "
                          f"[0, {MAX_SAMPLES}] (0: nominal verdicts only)")
    if u.batch < 1:
        raise ConfigError(f"{where}: [uncertainty] batch = {u.batch!r}: expected a positive integer")
    if not 1 <= u.orientation_average_samples <= MAX_SAMPLES:
        raise ConfigError(f"{where}: [uncertainty] orientation_average_samples = {u.orientation_average_samples!r}: "
                          f"expected an integer in [1, {MAX_SAMPLES}]")

#: Keys whose string values are limited to a set.
CHOICES: dict[tuple[str, ...], dict[str, tuple[str, ...]]] = {
    ("pulses",): {"method": ("shahi_baker_2014", "baker_2007")},
    ("criteria",): {"form": FORMS},
    ("fidelity",): {"tier": FIDELITY_TIERS},
    ("event",): {"shakemap_component": ("rotd100", "rotd50", "geomean", "larger")},
    ("records",): {"implausible": ("fail", "warn")},
    ("simulation",): {"scanned_model": tuple(m.value for m in ScannedModel)},
}


def _check_value(section: str, key: str, value: Any, default: Any, where: str) -> Any:
    name = f"{where}: [{section}] {key}"
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise ConfigError(f"{name} = {value!r}: expected true or false")
        return value
    if isinstance(default, int) and not isinstance(default, bool):
        if not isinstance(value, int) or isinstance(value, bool) or value < 0:
            raise ConfigError(f"{name} = {value!r}: expected a non-negative integer")
        return value
    if isinstance(default, float):
        zero_ok = (section, key) in ZERO_ALLOWED
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not (
                value >= 0 if zero_ok else value > 0) or not math.isfinite(value):
            raise ConfigError(f"{name} = {value!r}: expected a {'non-negative' if zero_ok else 'positive'} number")
        if (section, key) in RANGES and not RANGES[(section, key)][0] <= value <= RANGES[(section, key)][1]:
            lo, hi = RANGES[(section, key)]
            raise ConfigError(f"{name} = {value!r}: expected a value in [{lo:g}, {hi:g}]")
        return float(value)
    if isinstance(default, str):
        if not isinstance(value, str):
            raise ConfigError(f"{name} = {value!r}: expected a string")
        return value
    if isinstance(default, dict):
        if not isinstance(value, dict):
            raise ConfigError(f"{name}: expected a table")
        return dict(value)
    if isinstance(default, tuple):
        return _check_steps(name, value)
    raise ConfigError(f"{name}: unsupported value {value!r}")  # pragma: no cover


def _check_steps(name: str, steps: Any) -> tuple:
    if not isinstance(steps, list) or not all(isinstance(s, dict) for s in steps):
        raise ConfigError(f"{name}: expected an array of tables [[...]] with a 'step' key")
    out = []
    for k, s in enumerate(steps, start=1):
        step = s.get("step")
        if step not in STEP_PARAMS:
            raise ConfigError(f"{name}, step {k}: unknown step {step!r}; valid steps: {sorted(STEP_PARAMS)}")
        allowed = STEP_PARAMS[step]
        for p, v in s.items():
            if p == "step":
                continue
            if p not in allowed:
                raise ConfigError(f"{name}, step {k} ({step}): unknown parameter {p!r}; "
                                  f"valid: {sorted(allowed)}")
            typ = allowed[p]
            ok = isinstance(v, (int, float)) and not isinstance(v, bool) if typ is float else (
                isinstance(v, typ) and not (typ is int and isinstance(v, bool)))
            if not ok:
                raise ConfigError(f"{name}, step {k} ({step}): {p} = {v!r} must be {typ.__name__}")
        if step == "integrate" and s.get("method", "trapezoid") not in INTEGRATION_METHODS:
            raise ConfigError(f"{name}, step {k}: integrate method {s['method']!r}; "
                              f"valid: {list(INTEGRATION_METHODS)}")
        out.append(dict(s))
    if not out or out[-1]["step"] != "integrate" or sum(s["step"] == "integrate" for s in out) != 1:
        raise ConfigError(f"{name}: the steps must end with exactly one 'integrate' step "
                          "(velocity is needed for the pulses)")
    return tuple(out)


def config_from_dict(data: dict, *, where: str = "<config>") -> Config:
    """Build a validated :class:`Config` from nested plain data (missing keys keep defaults)."""
    base = Config()
    sections = {f.name: f for f in dataclasses.fields(Config)}
    unknown = set(data) - set(sections)
    if unknown:
        raise ConfigError(f"{where}: unknown section(s) {sorted(unknown)}; valid: {sorted(sections)}")
    kwargs = {}
    for name in sections:
        current = getattr(base, name)
        given = data.get(name, {})
        if not isinstance(given, dict):
            raise ConfigError(f"{where}: [{name}] must be a table")
        keys = {f.name for f in dataclasses.fields(current)}
        bad = set(given) - keys
        if bad:
            raise ConfigError(f"{where}: unknown key(s) {sorted(bad)} in [{name}]; valid: {sorted(keys)}")
        values = {k: _check_value(name, k, v, getattr(current, k), where) for k, v in given.items()}
        choices = CHOICES.get((name,), {})
        for k, v in values.items():
            if name == "fidelity" and k == "tier" and v in RETIRED_TIERS:
                raise ConfigError(f"{where}: [fidelity] tier = {v!r}: {RETIRED_TIERS[v]}")
            if k in choices and v not in choices[k]:
                raise ConfigError(f"{where}: [{name}] {k} = {v!r}; valid: {list(choices[k])}")
        kwargs[name] = dataclasses.replace(current, **values)
    _check_uncertainty(kwargs["uncertainty"], where)
    ev = kwargs["event"]
    if not ev.level_low < ev.level_medium < ev.level_high:
        raise ConfigError(f"{where}: [event] level_low {ev.level_low}, level_medium {ev.level_medium} and "
                          f"level_high {ev.level_high} must increase (each is the smallest probability of its level)")
    return Config(**kwargs)


def load_config(path: str | Path | None = None) -> Config:
    """Load and validate a TOML configuration (None gives the defaults).

    Raises
    ------
    ConfigError
        If the file is missing, not TOML, or holds unknown or invalid keys.
    """
    if path is None:
        return Config()
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(f"{path}: configuration file not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from exc
    return config_from_dict(data, where=str(path))
