"""The hazard side of ``screen fragility``: the hazard curves bound to the fit's IM and component, and each block's
annual rate of overturning and its 50-year probability from its fitted curve (Sa at the block's own period).
"""

from __future__ import annotations

import math

import numpy as np

from ..blocks import Inventory
from ..config import Config
from ..uncertainty.fragility import FitStatus
from ..uncertainty.hazard import Component, HazardSet, annual_rate, annual_rate_upper, probability_in
from .fragility_levels import can_rock_blocks


def hazard_and_component(paths: list, *, im: str, site: str | None, lonlat: tuple[float, float] | None,
                         stated: str | None, im_component: str | None, scale: float | None
                         ) -> tuple[HazardSet | None, Component]:
    """The hazard curves of ``paths`` (``--hazard``), bound to the fit, and the component definition the fit uses:
    the one asked for (``im_component``), else the first curve's (read from the file, or ``stated`` for it), else
    RotD100.

    Raises
    ------
    RockscreenError
        For a hazard file that cannot be read as a curve of ``im`` (named, with the fix).
    """
    from ..uncertainty.hazard import hazard_set
    from ..uncertainty.hazard_files import read_hazard

    declared = Component(stated) if stated else None
    curves = [read_hazard(path, im=im, site=site, lonlat=lonlat, component=declared) for path in paths]
    fit = Component(im_component) if im_component else (
        curves[0].component if curves and curves[0].component is not None else Component.rotd100)
    hazard = hazard_set(curves, im=im, fit_component=fit, scale=scale) if curves else None
    return hazard, fit


#: A block integrated against an Sa curve whose period differs from its own by more than this factor is warned of.
PERIOD_GAP_WARN = 1.25


def hazard_variables(hazard: HazardSet, fit, inventory: Inventory, config: Config, levels: np.ndarray, *,
                      im: str) -> dict:
    """The annual rates of overturning and the 50-year probabilities (and their upper bounds) from the hazard
    curve of each block's IM (Sa at its own period, with the period taken and its ratio)."""
    periods = 2.0 * math.pi / inventory.geometry(g_ms2=config.records.g_ms2).p
    chosen = [hazard.for_block(float(T) if im == "sa" else math.nan) for T in periods]
    rate, upper = rates_of_overturning(chosen, fit, inventory, config, levels)
    data = {"annual_rate_overturn": (("block",), rate),
            "p_overturn_50yr": (("block",), np.array([probability_in(r, 50.0) for r in rate])),
            "annual_rate_overturn_upper": (("block",), upper),
            "p_overturn_50yr_upper": (("block",), np.array([probability_in(r, 50.0) for r in upper]))}
    if im == "sa":
        data["hazard_period"] = (("block",), np.array([c.period_s for c, _ in chosen]))
        data["hazard_period_ratio"] = (("block",), np.array([r for _, r in chosen]))
    return data


def can_rock(inventory: Inventory, config: Config) -> np.ndarray:
    """Whether each block can rock (:func:`~.fragility_levels.can_rock_blocks`)."""
    return can_rock_blocks(inventory, g_ms2=config.records.g_ms2)


def rates_of_overturning(chosen: list, fit, inventory: Inventory, config: Config, levels: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """Each block's annual rate of overturning, and its upper bound for levels never tested (overturning certain
    above the top level). A block that can rock but overturned at no level has no rate (NaN: raise the levels),
    only the bound, the hazard's rate of exceeding the top level; one that cannot rock (it slides) has 0."""
    top = float(np.max(levels))
    rate, upper = np.full(len(chosen), np.nan), np.full(len(chosen), np.nan)
    rock = can_rock(inventory, config)
    for j, (curve, _) in enumerate(chosen):
        theta, beta = float(fit.theta[j]), float(fit.beta[j])
        if fit.status[j] == FitStatus.none_overturn and not rock[j]:
            rate[j] = upper[j] = 0.0
            continue
        rate[j] = math.nan if fit.status[j] == FitStatus.none_overturn else annual_rate(curve, theta, beta)
        upper[j] = annual_rate_upper(curve, theta, beta, top)
    return rate, upper
