"""Fragility curves in the formats of the risk engines: OpenQuake NRML and pelicun's damage-model CSV.

Both come from ``fragility.nc`` (:func:`pipeline.run.fragility_assembly.assemble_fragility`): one lognormal curve per
block, median theta [SI] and dispersion beta, on an IM (PGA, PGV or Sa at the block's period) under a
stated horizontal component definition.

* **OpenQuake** (NRML 0.5, ``fragilityModel``, continuous ``logncdf``): OpenQuake's ``mean`` and ``stddev``
  are the arithmetic mean and standard deviation of the lognormal IML, not its median and beta:
  mean = theta exp(beta^2 / 2), stddev = mean sqrt(exp(beta^2) - 1). IMLs in g (PGA, SA) or cm/s (PGV),
  OpenQuake's units. The fragility function's id is the block's taxonomy (its id).
* **pelicun** (FEMA P-58 style ``ID,Incomplete,Demand-Type,Demand-Unit,Demand-Offset,Demand-Directional,
  LS1-Family,LS1-Theta_0,LS1-Theta_1``): ``Demand-Directional = 1`` so that pelicun applies no
  non-directional multiplier (it multiplies non-directional demands by 1.2 otherwise); the demand to give
  pelicun is the IM under the component definition the fit used (``fragility.nc`` attribute ``im_component``,
  and ``fragility_ids.csv``). ``Demand-Offset = 0``: ground motion, not a floor. pelicun splits identifiers
  at hyphens, so a block's component ID is ``RS.`` and its id with hyphens made underscores.

``fragility_ids.csv`` maps each block to its OpenQuake taxonomy and pelicun component ID. A block with no fit
(nothing overturns at any level) has no curve; the NRML file lists it in a comment.

References
----------
Pagani, M. et al. (2014). OpenQuake engine: an open hazard (and risk) software for the Global Earthquake
Model. Seismol. Res. Lett. 85(3), 692-702. Zsarnoczay, A. & Deierlein, G. G. (2020). PELICUN - a
computational framework for estimating damage, loss and community resilience. Proc. 17th WCEE.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import NamedTuple
from xml.sax.saxutils import quoteattr

import numpy as np
import xarray as xr

from ..constants import G
from ..uncertainty.fragility import FitStatus
from .atomic import write_text_atomic

#: rockscreen IM -> (OpenQuake IMT, pelicun demand type, factor from SI to the tools' unit, OpenQuake unit,
#: pelicun unit)
TOOL_IMS = {"pga": ("PGA", "Peak Ground Acceleration", 1.0 / G, "g", "g"),
            "pgv": ("PGV", "Peak Ground Velocity", 100.0, "cm/s", "cmps"),
            "sa": ("SA({period:.2f})", "Spectral Acceleration|{period:.2f}", 1.0 / G, "g", "g")}
#: IMLs OpenQuake evaluates a curve on are clipped to [median / CLIP, median x CLIP].
CLIP = 100.0


class LognormalMoments(NamedTuple):
    """The arithmetic mean and standard deviation of a lognormal variable."""

    mean: float
    stddev: float


def lognormal_moments(theta: float, beta: float) -> LognormalMoments:
    """Mean theta exp(beta^2 / 2) and standard deviation mean sqrt(exp(beta^2) - 1) of a lognormal of median
    ``theta`` and dispersion ``beta`` (what OpenQuake's continuous fragility takes)."""
    mean = theta * math.exp(beta * beta / 2.0)
    return LognormalMoments(mean, mean * math.sqrt(math.expm1(beta * beta)))


#: Why a block's curve is left out of the exports, by fit status (the statuses not listed are exported)
LEFT_OUT = {FitStatus.none_overturn: "nothing overturns at any level tested (raise the levels)",
            FitStatus.all_overturn: "everything overturns at every level tested (lower the levels)",
            FitStatus.not_bounded: "the stripes do not bracket 50 %: the median lies beyond the levels tested "
                                   "(widen the levels)",
            FitStatus.extrapolated: "the median lies outside the levels tested (widen the levels)"}


#: Why the curve of a block that cannot rock is left out: no level overturns it, however high
CANNOT_ROCK = ("it cannot rock (it slides or stands: mu <= tan alpha, or alpha >= 54.7 deg), so no level overturns it; "
               "its risk is sliding (see the screening's recommendation)")


#: Why the curve of a block whose stripes hold records without a verdict is left out: its fit counts only the judged
#: records, which may read safer than the unknown ones allow; fragility.nc bounds it
UNJUDGED = ("{n:.3g} scaled record-levels have no verdict (a model stopped where the base slides, twists or lifts "
            "off): the fit of the judged records alone may read safer than they allow; fragility.nc bounds it "
            "(median_unjudged_overturn, median_unjudged_stand)")


def _curves(ds: xr.Dataset):
    """(block, theta [SI], beta, period [s]) of every block whose median lies within the levels tested (fit status
    ok or separated) and whose stripes hold no record without a verdict, and (block, why) of the others, which are
    left out."""
    periods = ds["block_period"].values if "block_period" in ds else np.full(ds.sizes["block"], math.nan)
    status = ds["fit_status"].values if "fit_status" in ds else np.zeros(ds.sizes["block"], dtype=int)
    fitted, unfitted = [], []
    for j, block in enumerate(ds["block"].values.tolist()):
        theta, beta = float(ds["median"].values[j]), float(ds["beta"].values[j])
        why = LEFT_OUT.get(FitStatus(int(status[j])))
        if why is None and "n_unjudged" in ds and float(np.sum(ds["n_unjudged"].values[j])) > 0:
            why = UNJUDGED.format(n=float(np.sum(ds["n_unjudged"].values[j])))
        if "can_rock" in ds and not int(ds["can_rock"].values[j]):
            why = CANNOT_ROCK
        if why is None and not (math.isfinite(theta) and theta > 0 and math.isfinite(beta) and beta > 0):
            why = "no finite fit"
        if why is None:
            fitted.append((str(block), theta, beta, float(periods[j])))
        else:
            unfitted.append((str(block), why))
    return fitted, unfitted


def left_out(ds: xr.Dataset) -> list[str]:
    """One line per block the exports leave out, with why."""
    return [f"{block}: {why}" for block, why in _curves(ds)[1]]


def supports(im: str) -> bool:
    """True when the risk engines take this IM (PGA, PGV, Sa)."""
    return im in TOOL_IMS


def openquake_nrml(ds: xr.Dataset) -> str:
    """The fits of ``fragility.nc`` as an OpenQuake NRML 0.5 continuous fragility model (the module's rules)."""
    im = ds.attrs["im"]
    imt, _, factor, unit, _ = TOOL_IMS[im]
    fitted, unfitted = _curves(ds)
    component = ds.attrs.get("im_component", "")
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             '<nrml xmlns="http://openquake.org/xmlns/nrml/0.5" xmlns:gml="http://www.opengis.net/gml">',
             '  <fragilityModel id="rockscreen" assetCategory="contents" lossCategory="structural">',
             "    <description>" + _text(f"Overturning of free-standing blocks, rockscreen multiple-stripe fits on "
                                         f"{im} ({component}, {unit}); blocks of unknown orientation: "
                                         f"{ds.attrs.get('orientation', 'random')} orientation") + "</description>",
             "    <limitStates>overturned</limitStates>"]
    for block, theta, beta, period in fitted:
        m = lognormal_moments(theta * factor, beta)
        name = imt.format(period=period) if im == "sa" else imt
        lines += [f'    <fragilityFunction format="continuous" id={quoteattr(block)} shape="logncdf">',
                  f'      <imls imt="{name}" minIML="{theta * factor / CLIP:.6E}" maxIML="{theta * factor * CLIP:.6E}" '
                  'noDamageLimit="0"/>',
                  f'      <params ls="overturned" mean="{m.mean:.9E}" stddev="{m.stddev:.9E}"/>',
                  "    </fragilityFunction>"]
    lines += ["  </fragilityModel>", "</nrml>", ""]
    for block, why in reversed(unfitted):
        lines.insert(2, "<!-- " + _text(f"no curve for {block}: {why}").replace("--", "- -") + " -->")
    return "\n".join(lines)


def _text(s: str) -> str:
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def pelicun_csv(ds: xr.Dataset) -> str:
    """The fits of ``fragility.nc`` as a pelicun damage-model CSV (the module's rules)."""
    im = ds.attrs["im"]
    _, demand, factor, _, unit = TOOL_IMS[im]
    fitted, _ = _curves(ds)
    rows = ["ID,Incomplete,Demand-Type,Demand-Unit,Demand-Offset,Demand-Directional,LS1-Family,LS1-Theta_0,"
            "LS1-Theta_1"]
    for block, theta, beta, period in fitted:
        kind = demand.format(period=period) if im == "sa" else demand
        rows.append(f"{pelicun_id(block)},0,{kind},{unit},0,1,lognormal,{theta * factor:.9g},{beta:.9g}")
    return "\n".join(rows) + "\n"


def pelicun_id(block: str) -> str:
    """A block's pelicun component ID (pelicun splits IDs at hyphens)."""
    return "RS." + block.replace("-", "_")


def ids_csv(ds: xr.Dataset) -> str:
    """Each block's OpenQuake taxonomy (its fragility function's id, for the exposure model) and pelicun
    component ID, with the IM and component definition the curves are on, and the probability fitted for a
    block of blank azimuth (``random`` orientation or the ``worst``)."""
    fitted, _ = _curves(ds)
    im, component, orientation = ds.attrs["im"], ds.attrs.get("im_component", ""), ds.attrs.get("orientation", "")
    return ("block_id,openquake_taxonomy,pelicun_component,im,im_component,orientation\n"
            + "".join(f"{b},{b},{pelicun_id(b)},{im},{component},{orientation}\n" for b, *_ in fitted))


def write_exports(ds: xr.Dataset, out_dir: Path) -> list[Path]:
    """Write ``fragility_openquake.xml``, ``fragility_pelicun.csv`` and ``fragility_ids.csv`` (nothing for an IM
    the engines do not take); returns the paths written."""
    if not supports(ds.attrs["im"]):
        return []
    out_dir = Path(out_dir)
    return [write_text_atomic(out_dir / "fragility_openquake.xml", openquake_nrml(ds)),
            write_text_atomic(out_dir / "fragility_pelicun.csv", pelicun_csv(ds)),
            write_text_atomic(out_dir / "fragility_ids.csv", ids_csv(ds))]
