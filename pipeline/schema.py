"""Every output variable, declared once: dimensions, units, long name, flag meanings.

:data:`SCHEMA` gives each variable of ``screening.nc`` its dimensions, UDUNITS
units (``m s-2``, never ``g``, which UDUNITS reads as gram) and ``long_name``;
categorical variables carry ``flag_values`` / ``flag_meanings`` generated from
the enumerations of the libraries that define the categories
(:class:`pipeline.rocking.planner.Physics`, ...). :func:`apply_schema` attaches
them; :func:`check` lists where a dataset departs from them (the tests walk
every written file with it).
"""

from __future__ import annotations

import re
from enum import IntEnum

import numpy as np
import xarray as xr

from .criteria import Onset
from .event.assets import Basis, Level
from .rocking.block import ShapeKind
from .rocking.orientation import Orientation
from .rocking.planner import ContactMode, FreeFlight, Guard, Physics, Response
from .uncertainty.fragility import FitStatus
from .uncertainty.robust import Robustness

FLAG3 = np.array([-1, 0, 1], dtype="i1")
#: Yes / no values that can be missing (-1), and yes / no values that cannot.
TRISTATE = {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true"}
TRUE_FALSE = {"flag_values": np.array([0, 1], dtype="i1"), "flag_meanings": "false true"}
#: The pulse class of a record (Shahi & Baker 2014).
PULSE_CLASS = {"flag_values": FLAG3, "flag_meanings": "unavailable non_pulse pulse_like"}


class VerdictSource(IntEnum):
    """The model behind a run's verdict."""

    criterion = 0
    simulation = 1


def flags(enum: type[IntEnum], *, missing: str | None = "not_evaluated") -> dict:
    """``flag_values`` / ``flag_meanings`` of an enumeration, with -1 = ``missing`` first (None: no -1)."""
    members = sorted(enum, key=lambda m: m.value)
    values = ([-1] if missing else []) + [m.value for m in members]
    names = ([missing] if missing else []) + [m.name for m in members]
    return {"flag_values": np.array(values, dtype="i1"), "flag_meanings": " ".join(names)}


# The variable groups of screening.nc as the screening of a record fills them, and the dtypes of its counts.

#: Per (record, block) variables computed in the tasks (the criterion is computed in :func:`assemble`).
PULSE_BLOCK_VARS = ("block_pulse_azimuth", "block_pulse_ap", "block_pulse_tp", "block_pulse_beta",
                    "block_pulse_dv", "block_record_ap")

#: Integer variables that are counts rather than flags (-1: not evaluated).
INTEGER_DTYPES = {"n_impacts": "i4", "planes_simulated": "i4", "npts": "i4", "n_horizontal": "i1",
                  "margin_simulations": "i4", "pulse_candidate": "i1", "samples_drawn": "i4",
                  "samples_overturned": "i4", "samples_without_verdict": "i4", "sample_simulations": "i4",
                  "contact_modes": "i1", "simulation_guard": "i1"}

#: Per (record, block) variables of the simulator.
SIMULATION_VARS = ("physics", "response", "overturn_simulated", "theta_max", "n_impacts", "time_overturn",
                   "friction_demand", "friction_exceeded", "sliding_max", "free_flight", "time_free_flight",
                   "governing_azimuth", "orientation", "planes_simulated", "contact_modes", "simulation_guard")

#: Per (record, block) variables of the floor a block stands on (NaN on the ground).
FLOOR_VARS = ("floor_pga", "floor_pgv")
#: Record-level pulse values kept with each floor's pulse series (``pulses.nc``, group ``floors``).
FLOOR_PULSE_VALUES = ("is_pulse", "pulse_indicator", "pulse_period", "pulse_azimuth")

#: Per (record, block) variables of the uncertainty sampling (NaN / -1 where not sampled).
PROBABILITY_VARS = ("p_overturn", "p_overturn_low", "p_overturn_high", "robustness", "samples_drawn",
                    "samples_overturned", "samples_without_verdict", "sample_simulations", "p_overturn_azimuth",
                    "p_overturn_random_orientation", "p_overturn_random_orientation_low",
                    "p_overturn_random_orientation_high")


#: name -> (dims, units or None, long_name, extra attributes)
SCHEMA: dict[str, tuple[tuple[str, ...], str | None, str, dict]] = {
    # coordinates
    "record": (("record",), None, "record identifier (station and event, or file stem)", {}),
    "block": (("block",), None, "block (asset) identifier from the inventory", {}),
    "component": (("component",), None, "component slot: h1 first horizontal, h2 90 deg clockwise of it, "
                  "v vertical", {}),
    # per record
    "status": (("record",), None, "screening status: 'ok' or the reason the record failed", {}),
    "files": (("record",), None, "source files of the record, ';'-separated", {}),
    "record_label": (("record",), None, "station and earthquake as the record's files name them", {}),
    "formats": (("record",), None, "obspy format names of the source files", {}),
    "notes": (("record",), None, "notes on the record (trimming, orientation, flags)", {}),
    "processing_history": (("record",), None, "ordered processing history of the record, newline-separated", {}),
    "content_sha256": (("record",), None, "SHA-256 of the source files' names and content", {}),
    "screened_utc": (("record",), None, "UTC time the record was screened (ISO 8601); older than the run "
                     "when its results were reused", {}),
    "source_present": (("record",), None, "the record's files were in the records directory at this run",
                       {**TRUE_FALSE,
                        "comment": "false: the files vanished; the results of the last run that saw them "
                                   "are kept"}),
    "dt": (("record",), "s", "sampling interval", {}),
    "npts": (("record",), "1", "number of samples after alignment (-1: not read)", {}),
    "duration": (("record",), "s", "record duration", {}),
    "n_horizontal": (("record",), "1", "number of horizontal components (-1: not read)", {}),
    "has_vertical": (("record",), None, "record has a vertical component",
                     TRISTATE),
    "azimuth_known": (("record",), None, "absolute azimuth of the horizontals is known",
                      TRISTATE),
    "processing_level": (("record",), None, "delivery level: corrected or uncorrected", {}),
    "pga": (("record",), "m s-2", "peak ground acceleration, peak of the horizontal vector (RotD100)", {}),
    "pgv": (("record",), "m s-1", "peak ground velocity, peak of the horizontal vector (RotD100)", {}),
    # pulses (Shahi & Baker 2014), per record, at the chosen candidate's orientation
    "is_pulse": (("record",), None, "record is pulse-like (Shahi & Baker 2014)",
                 PULSE_CLASS),
    "pulse_indicator": (("record",), "1", "pulse indicator PI of the chosen candidate (pulse-like if > 0)", {}),
    "pulse_period": (("record",), "s", "pulse period Tp of the first pulse-like candidate", {}),
    "pulse_azimuth": (("record",), "degree", "axis of the chosen pulse, clockwise from north, modulo 180", {}),
    "pulse_late": (("record",), None, "chosen pulse arrives late (Shahi & Baker 2014 rule)",
                   {"flag_values": FLAG3, "flag_meanings": "unavailable early late"}),
    "pulse_ap": (("record",), "m s-2", "peak acceleration of the dominant lobe of the extracted pulse", {}),
    "pulse_tp": (("record",), "s", "duration of the dominant acceleration lobe of the extracted pulse", {}),
    "pulse_beta": (("record",), "1", "fullness factor dv / (a_p t_p) of the dominant lobe", {}),
    "pulse_dv": (("record",), "m s-1", "velocity change over the dominant lobe (signed)", {}),
    "pulse_record_ap": (("record",), "m s-2", "record's own peak acceleration along the pulse during the lobe", {}),
    "pulse_candidate": (("record",), "1", "index (1-based) of the chosen candidate", {}),
    "pulse_method": (("record",), None, "pulse extraction method", {}),
    "pulse_flags": (("record",), None, "flags of the pulse extraction (single component, truncation, failure)", {}),
    # pulses along each block's direction (the strongest pulse axis when blank or unknown); the criterion's input
    "block_pulse_azimuth": (("record", "block"), "degree", "direction the pulse was characterized along", {}),
    "block_pulse_ap": (("record", "block"), "m s-2", "pulse peak acceleration a_p along the block direction", {}),
    "block_pulse_tp": (("record", "block"), "s", "pulse lobe duration t_p along the block direction", {}),
    "block_pulse_beta": (("record", "block"), "1", "pulse fullness factor beta along the block direction", {}),
    "block_pulse_dv": (("record", "block"), "m s-1", "pulse velocity change along the block direction", {}),
    "block_record_ap": (("record", "block"), "m s-2", "record peak acceleration during the lobe, block direction", {}),
    # the reference paper's criterion per (record, block) scene (pipeline.criteria)
    "uplift": (("record", "block"), None, "pulse peak acceleration reaches the uplift acceleration (Eq. 1)",
               TRISTATE),
    "velocity_ratio": (("record", "block"), "1", "pulse velocity increment over the critical velocity (Eqs. 4-5)",
                       {"comment": "the paper's energy criterion holds where this is >= 1"}),
    "energy_ratio": (("record", "block"), "1", "pulse kinetic energy over the energy that overturns, "
                     "(|dv| / v_crit)^2", {}),
    "overturn_criterion": (("record", "block"), None,
                           "overturning by the paper's criterion: uplift, velocity ratio >= 1, below the sliding line",
                           {**TRISTATE,
                            "comment": "not_evaluated: no pulse, or block too squat for pure rocking; a body of a "
                                       "stack (stands_on): of the body alone on the ground, never its verdict"}),
    "stack_overturn": (("record", "block"), None, "a body of the block's stack overturns (stands_on)",
                       {**TRISTATE, "comment": "the same on every body of a stack; not_evaluated: the block is in no "
                                               "stack, or no body overturns and one has no verdict"}),
    "stack_collapse": (("record", "block"), None, "the bottom body of the block's stack overturns: nothing stands",
                       {**TRISTATE, "comment": "the same on every body of a stack; not_evaluated: in no stack, or the "
                                               "bottom body has no verdict"}),
    "stack_fails": (("record", "block"), None, "the block's stack fails by its own rule (stack_rule)",
                    {**TRISTATE, "comment": "the same on every body of a stack: stack_overturn, the top body's "
                                            "verdict or stack_collapse; not_evaluated: in no stack, or no verdict"}),
    "above_sliding_line": (("record", "block"), None, "pulse peak acceleration exceeds mu g (the paper's line)",
                           TRISTATE),
    "criterion_scale": (("record", "block"), "1",
                        "smallest factor on the record that reaches the criterion's overturning boundary",
                        {"comment": "inf where the scaled pulse crosses the sliding line first"}),
    "onset": (("record", "block"), None, "mode at the onset of motion (Zhang & Makris 2001 eq. 7)",
              {**flags(Onset),
               "comment": "slide_rock: mu > tan(alpha) but a pulse arriving at full amplitude needs more friction"}),
    "onset_friction_demand": (("record", "block"), "1",
                              "friction needed to start rocking without sliding, pulse at full amplitude", {}),
    "normalized_acceleration": (("record", "block"), "1", "pulse peak acceleration over the uplift acceleration", {}),
    "normalized_duration": (("record", "block"), "1", "pulse lobe duration over the block's transition duration",
                            {}),
    "closed_form_ratio": (("record", "block"), "1",
                          "pulse peak over the Makris & Roussos (2000) half-sine minimum at the same duration", {}),
    "overturn_closed_form": (("record", "block"), None,
                             "overturning of the equivalent half-sine pulse (Makris & Roussos 2000 eq. 27)",
                             TRISTATE),
    # the run's verdict at its fidelity tier (config [fidelity])
    "overturn": (("record", "block"), None, "overturning verdict at the run's fidelity: the simulation's where it "
                 "ran, else the criterion's", {**TRISTATE,
                                               "comment": "not_evaluated also where the ground's g + a_v reached 0 "
                                                          "before any overturning and the contact model was off "
                                                          "(response free_flight)"}),
    "verdict_source": (("record", "block"), None, "model behind the verdict 'overturn'",
                       flags(VerdictSource, missing="none")),
    # the simulator per (record, block) scene (pipeline.rocking)
    "physics": (("record", "block"), None, "physics simulated for the scene (scene planner)",
                {**flags(Physics),
                 "comment": "none: proven at rest (no uplift and no slip at any sample, vertical included); "
                            "general: pure rocking (or sliding) stopped holding and the general contact model "
                            "(slide, slide-rock, free flight, impacts) decided the verdict; wobbling: a cylinder "
                            "on two horizontals, rocking and rolling on its rim in 3D (orientation axisymmetric); "
                            "rocking3d: a box with a depth and an azimuth on two horizontals of known azimuth, on "
                            "an edge or a corner in 3D (governing_azimuth: where it leant); two_sided: a body given "
                            "by its scan (inventory mesh), rocking in a vertical plane on pivots of its own on each "
                            "side (governing_azimuth: the record's compass direction, over 360 deg; no sliding, no "
                            "flight: friction_exceeded flags them); rolling: a body given by its scan rolling on its "
                            "convex hull in a vertical plane (the default for a mesh, simulation.scanned_model; "
                            "likewise); a plane in which the body is a uniform rectangle gets the planar models; "
                            "contact3d: a rigid convex body in 3D in every contact mode at once (slide, twist, rock, "
                            "roll, lift-off): a cylinder's or a box's scene its exact model stops (simulation."
                            "contact3d), or a body given by its scan with simulation.scanned_model contact3d "
                            "(theta_max: tilt over its smallest static tipping angle; governing_azimuth: where it "
                            "leant); stack: a body of a stack (inventory stands_on), the stack's blocks rocking "
                            "together in a vertical plane, each joint shut or open on a corner (theta_max: the "
                            "body's peak rotation on what it stands on over that joint's tipping angle at rest, to "
                            "the first fall; no sliding: friction_exceeded flags a joint needing more friction "
                            "than it has, the verdict assuming the joint holds)"}),
    "response": (("record", "block"), None, "simulated response class",
                 {**flags(Response),
                  "comment": "slide_rock: slide-rock occurred (physics general); with simulation.contact_model "
                             "off, the friction demand of pure rocking exceeded mu and the pure-rocking verdict "
                             "is kept. free_flight: only with the contact model off: the ground's g + a_v "
                             "reached 0 before any overturning, no verdict"}),
    "contact_modes": (("record", "block"), None, "contact modes the scene went through",
                      {"flag_masks": np.array([m.value for m in ContactMode], dtype="i1"),
                       "flag_meanings": " ".join(m.name for m in ContactMode),
                       "comment": "0: at rest throughout"}),
    "simulation_guard": (("record", "block"), None, "guards of the simulator the scene met",
                         {"flag_masks": np.array([m.value for m in Guard], dtype="i1"),
                          "flag_meanings": " ".join(m.name for m in Guard),
                          "comment": "0: none. Every loop of the simulator advances time or counts against a cap; "
                                     "a scene that meets one says so here. event_cap: impacts and uplifts reached "
                                     "simulation.max_events; tie_hold: many events at one instant on a flat block "
                                     "(a tie between two models), held at rest to the next sample; stalled, "
                                     "step_cap: ended there, the verdict from the state reached (the energy of its "
                                     "free rocking); tail_cap: motion after the record followed to its cap; "
                                     "model_limit: a 3D model (a cylinder, a box in 3D) stopped where its base "
                                     "would slide or lift off (not modeled in 3D), or a scanned body's model "
                                     "(rolling or two-sided) met a ground flight or its caps: no verdict. "
                                     "The orientation scan ORs the planes simulated"}),
    "overturn_simulated": (("record", "block"), None, "overturning by the nonlinear time history",
                           {**TRISTATE,
                            "comment": "scenes proven at rest are false without integration; not_evaluated: "
                                       "not simulated, or free flight before any overturning with "
                                       "simulation.contact_model off"}),
    "theta_max": (("record", "block"), "1", "peak rotation over alpha, max |theta| / alpha", {}),
    "n_impacts": (("record", "block"), "1", "impacts during the record (and the one before an escape after it)",
                  {}),
    "time_overturn": (("record", "block"), "s",
                      "time |theta| reached pi/2, or end of the record when the free motion escapes", {}),
    "friction_demand": (("record", "block"), "1", "peak |f_x / f_z| along the rocking trajectory", {}),
    "friction_exceeded": (("record", "block"), None, "friction demand of pure rocking exceeded mu",
                          TRISTATE),
    "sliding_max": (("record", "block"), "m", "peak sliding displacement relative to the ground",
                    {"comment": "sliding scenes: the Coulomb slip; general scenes: the net slip of the base (the "
                                "contact point's slip in slide and slide-rock, the base's travel in flight); a body "
                                "of a stack: its base's slip on what it stands on in the stack's contact model (NaN: "
                                "that model did not run)"}),
    "free_flight": (("record", "block"), None, "loss of contact with the base",
                    {**flags(FreeFlight),
                     "comment": "ground_flight: the ground's g + a_v reached 0; block_liftoff: the block's own "
                                "contact force reached 0. Both are simulated by the general contact model "
                                "(physics general); with simulation.contact_model off, ground flight stops the "
                                "simulation and a lift-off is only flagged. Physics contact3d: block_liftoff where "
                                "the body lost every contact and rose more than 10 um clear of the ground"}),
    "floor_pga": (("record", "block"), "m s-2", "peak acceleration of the floor the block stands on, horizontal "
                  "vector (NaN on the ground)", {}),
    "floor_pgv": (("record", "block"), "m s-1", "peak velocity of the floor the block stands on, horizontal vector "
                  "(NaN on the ground)", {}),
    "slides_off_base": (("record", "block"), None, "the block's net slip exceeds its base margin (it slides off)",
                        {**TRISTATE, "comment": "not_evaluated: no base_margin_m in the inventory, or not simulated"}),
    "time_free_flight": (("record", "block"), "s", "time the ground's g + a_v reached 0 (free flight)", {}),
    "governing_azimuth": (("record", "block"), "degree",
                          "azimuth of the rocking plane whose result is reported, clockwise from north, modulo 180",
                          {"comment": "for orientation scanned_relative: relative to the record's first component "
                                      "taken as 0 deg; for orientation axisymmetric (a cylinder in 3D) and given_3d (a "
                                      "box in 3D): the azimuth it leant toward at its peak tilt, in [0, 360) (NaN: "
                                      "it never lifted); for given_certified: the azimuth of the box's width"}),
    "orientation": (("record", "block"), None, "how the rocking plane was chosen",
                    {**flags(Orientation),
                     "comment": "scanned: worst of every plane k * simulation.orientation_step_deg and the pulse "
                                "axis that moves the block, refined around the worst standing plane; "
                                "scanned_relative: the same on a record of unknown absolute azimuth; "
                                "axisymmetric: a cylinder on two horizontals, one 3D run (no plane); given_3d: a box "
                                "with a depth and an azimuth on two horizontals of known azimuth, one 3D run at "
                                "that azimuth (both horizontals and the vertical; for both, no run where the record "
                                "provably leaves it at rest, planes_simulated 0); given_certified: the same box "
                                "judged in the plane of its width, its other base axis certified never to lift nor "
                                "slip under the record (the 3D model then follows the same equation)"}),
    "planes_simulated": (("record", "block"), "1", "rocking planes integrated for the scene (-1: not simulated)",
                         {}),
    # the verdict under declared uncertainty ([uncertainty]; pipeline.uncertainty)
    "p_overturn": (("record", "block"), "1", "probability of overturning under the declared uncertainty, in the "
                   "orientation found worst: fraction of the samples with a verdict that overturn",
                   {"comment": "samples: lognormal factors (median 1) on the record's amplitude, restitution, "
                               "friction, height and width, normal scatter of a given azimuth (the file's "
                               "uncertainty_* attributes); common random numbers across records and blocks. A "
                               "blank azimuth: the plane of the scan's grid or the pulse axis (p_overturn_azimuth) "
                               "with the largest fraction on one set of draws, its probability estimated on "
                               "independent draws; a narrower window of worse orientations between grid planes, "
                               "or a tie broken on too few draws, can be missed. NaN: not sampled "
                               "(samples = 0, criterion tier) or no sample had a verdict"}),
    "p_overturn_azimuth": (("record", "block"), "degree", "rocking plane p_overturn is for (clockwise from north; "
                           "the given azimuth, or the orientation found worst for a blank one)",
                           {"comment": "NaN: not sampled; relative to the first component on a record of unknown "
                                       "absolute azimuth"}),
    "p_overturn_random_orientation": (("record", "block"), "1", "probability of overturning of a block whose "
                                      "orientation is unknown (uniform on [0, 180) deg): the average over the "
                                      "scan's grid of planes",
                                      {"comment": "equal to p_overturn for a given azimuth or one recorded "
                                                  "horizontal"}),
    "p_overturn_random_orientation_low": (("record", "block"), "1", "lower bound of the two-sided Wilson interval "
                                          "on p_overturn_random_orientation (on the per-draw fractions)", {}),
    "p_overturn_random_orientation_high": (("record", "block"), "1", "upper bound of the two-sided Wilson "
                                           "interval on p_overturn_random_orientation", {}),
    "p_overturn_low": (("record", "block"), "1", "lower bound of the two-sided Wilson interval on p_overturn, the "
                       "samples without a verdict counted as standing",
                       {"comment": "confidence: [uncertainty] confidence (default 0.90)"}),
    "p_overturn_high": (("record", "block"), "1", "upper bound of the two-sided Wilson interval on p_overturn, the "
                        "samples without a verdict counted as overturning", {}),
    "robustness": (("record", "block"), None, "how firmly the declared uncertainty decides the verdict",
                   {**flags(Robustness),
                    "comment": "robust_stand: interval below [uncertainty] robust_below and fewer than one "
                               "sample in ten without a verdict; robust_overturn: above "
                               "robust_above; sensitive: otherwise (the verdict can flip under the declared "
                               "uncertainty). Sampling stops once the interval decides the class"}),
    "samples_drawn": (("record", "block"), "1", "samples drawn for the scene (sequential stop; -1: not sampled)",
                      {}),
    "samples_overturned": (("record", "block"), "1", "samples that overturned (-1: not sampled)", {}),
    "samples_without_verdict": (("record", "block"), "1", "samples without a verdict, unknown: the model stopped "
                                "where the base would slide, twist or lift off, the ground fell faster than gravity "
                                "(contact model off), or a cap (-1: not sampled)",
                                {"comment": "p_overturn_low counts them as standing, p_overturn_high as "
                                            "overturning; never counted as standing in p_overturn"}),
    "sample_simulations": (("record", "block"), "1", "rocking or sliding planes integrated over the samples "
                           "(samples proven at rest cost none; -1: not sampled)", {}),
    # per record and component
    "component_code": (("record", "component"), None, "channel or component code in the file", {}),
    "component_azimuth": (("record", "component"), "degree", "component azimuth clockwise from north", {}),
    "component_pga": (("record", "component"), "m s-2", "peak absolute acceleration of the component", {}),
    "component_header_pga": (("record", "component"), "m s-2", "peak acceleration stated in the file header", {}),
    # per block
    "block_name": (("block",), None, "block name", {}),
    "site": (("block",), None, "site or collection of the block", {}),
    "height": (("block",), "m", "full block height 2h", {}),
    "width": (("block",), "m", "full base width 2b in the rocking plane (a cylinder's diameter)", {}),
    "shape": (("block",), None, "kind of body",
              {**flags(ShapeKind, missing=None),
               "comment": "box: on two horizontals of known azimuth where its depth and azimuth are given, in "
                          "3D (orientation given_3d) or in the plane of its width where its other axis is "
                          "certified (given_certified), else judged in the plane of its width (its other base axis and "
                          "corners not modeled); "
                          "cylinder: in 3D on two horizontals (orientation axisymmetric), in its plane on one"}),
    "depth": (("block",), "m", "a box's base dimension perpendicular to its width (NaN: not given)", {}),
    "half_height": (("block",), "m", "half-height h (centre-of-mass height)", {}),
    "half_width": (("block",), "m", "half-width b", {}),
    "corner_distance": (("block",), "m", "R = sqrt(b^2 + h^2), base corner to centre of mass", {}),
    "slenderness": (("block",), "rad", "alpha = atan(b/h)", {}),
    "frequency_parameter": (("block",), "rad s-1", "p = sqrt(3 g / (4 R)); a cylinder's p = sqrt(g R / (I_G / m + "
                            "R^2)), I_G / m = b^2/4 + h^2/3", {}),
    "restitution": (("block",), "1", "angular-velocity restitution across an impact (Housner where not given)", {}),
    "mu": (("block",), "1", "friction coefficient between block and base", {}),
    "block_sha256": (("block",), None, "SHA-256 of the block's inventory entry (what its results depend on)",
                     {}),
    "base_margin": (("block",), "m", "free distance from the block's footprint to the edge of its base", {}),
    "building": (("block",), None, "the building the block stands in (empty: on the ground)", {}),
    "floor_height": (("block",), "m", "height of its floor above the building's base (NaN: on the ground)", {}),
    "block_azimuth": (("block",), "degree", "rocking direction clockwise from north (NaN: worst orientation)", {}),
    "stands_on": (("block",), None, "the body the block stands on (empty: the ground, or its floor)", {}),
    "stack_id": (("block",), None, "the stack the block is a body of, named by its bottom body (empty: none)", {}),
    "stack_base_centre": (("block",), "m", "a stack's body at rest: its base's centre in its rocking plane, from the "
                          "bottom body's (NaN: not a stack's body)", {}),
    "stack_base_height": (("block",), "m", "a stack's body at rest: its base's height above the stack's (NaN: not a "
                          "stack's body)", {}),
    "stack_rule": (("block",), None, "what fails the block's stack as a whole (inventory stack_verdict): any (a "
                   "body falls), top (the top body falls) or collapse (the bottom body falls); empty: in no stack",
                   {}),
    "joint_opening": (("block",), "1", "a stack's body: the ground's |a_h| / (g + a_v) at which the joint under it "
                      "starts to open at rest, the bodies above with it (NaN: not a stack's body)", {}),
    "uplift_acceleration": (("block",), "m s-2", "ground acceleration that starts rocking (Eq. 1)", {}),
    "critical_velocity": (("block",), "m s-1", "pulse velocity increment that overturns (Eq. 4)", {}),
    "transition_period": (("block",), "s", "the paper's transition period pi / p of a half-sine pulse (Eq. 9)", {}),
    "governing_record": (("block",), None, "record whose scene is worst for the block (simulated overturn, then "
                         "criterion overturn, then max theta/alpha, then velocity ratio)", {}),
    "overturn_scale": (("block",), "1", "margin by the criterion: smallest factor on the governing record that "
                       "reaches the criterion's boundary (closed form)",
                       {"comment": "inf: the scaled pulse crosses the sliding line first; NaN: not evaluated"}),
    "overturn_scale_simulated": (("block",), "1", "margin by simulation: first factor of an upward scan on the "
                                 "governing record (1 % steps to x1.5, up to 10 % above), in its rocking plane, "
                                 "under which the block overturns",
                                 {"comment": "<= 1 where the governing scene overturns; also < 1 for a standing "
                                             "scene with a window of overturning below the nominal amplitude "
                                             "(overturns_below_nominal). inf: none up to "
                                             "simulation.margin_max_factor; NaN: the rocking model does not apply "
                                             "(the block slides or is squat), free flight, or no record"}),
    "margin_simulations": (("block",), "1", "scenes simulated by the margin scan, sampled scans included "
                           "(-1: none)", {}),
    "p_overturn_governing": (("block",), "1", "fraction of the samples that overturn on the governing record at "
                             "factor 1 (its scene's p_overturn)", {"comment": "NaN: not sampled"}),
    "overturn_scale_median": (("block",), "1", "median over uncertainty.margin_samples samples (block and "
                              "amplitude, common random numbers) of the simulated margin on the governing record",
                              {"comment": "as a factor on the nominal record; NaN: not computed "
                                          "(uncertainty.margin_samples = 0 or samples = 0) or no sample in the "
                                          "rocking model"}),
    "overturns_below_nominal": (("block",), None, "the governing scene stands, yet a smaller factor on the "
                                "record overturns the block (margin below 1)",
                                {**TRISTATE,
                                 "comment": "overturning is not monotonic in amplitude: a window of overturning "
                                            "below the nominal amplitude"}),
    "rocking_applicable": (("block",), None, "pure-rocking model applies (Housner e > 0, alpha < 54.7 deg)",
                           TRUE_FALSE),
}

COMPONENTS = ("h1", "h2", "v")


#: Prefix of the variables that carry the inventory's extra columns (asset value, location, ...), as given.
INVENTORY_PREFIX = "inventory_"


def inventory_variable(column: str) -> str:
    """The screening.nc variable of an extra inventory column."""
    return INVENTORY_PREFIX + re.sub(r"[^A-Za-z0-9_]", "_", column.strip())


def entry(name: str, table: dict | None = None) -> tuple | None:
    """The schema entry of a variable (dims, units, long_name, attributes), or None if it has none."""
    table = SCHEMA if table is None else table
    if name in table:
        return table[name]
    if table is SCHEMA and name.startswith(INVENTORY_PREFIX):
        return (("block",), None, f"inventory column '{name[len(INVENTORY_PREFIX):]}', as given", {})
    return None


#: Units entry meaning "the unit of the run's intensity measure" (global attribute ``im_units``).
IM_UNITS = "<units of the IM>"


def apply_schema(ds: xr.Dataset, table: dict | None = None) -> xr.Dataset:
    """Attach units, long names and flags from ``table`` (default :data:`SCHEMA`) to every known variable
    and coordinate."""
    for name in ds.variables:
        found = entry(str(name), table)
        if found is not None:
            _, units, long_name, extra = found
            if units == IM_UNITS:
                units = ds.attrs["im_units"]
            ds[name].attrs.update({"long_name": long_name, **extra, **({"units": units} if units else {})})
    return ds


#: Per-sample variables of ``pulses.nc`` (CF contiguous ragged array, one series per record).
PULSE_SERIES = {
    "velocity": {"units": "m s-1", "long_name": "ground velocity along the chosen pulse orientation"},
    "pulse": {"units": "m s-1", "long_name": "extracted velocity pulse (sum of 10 db4 wavelets)"},
}
#: Group ``floors`` of ``pulses.nc``: one series per (record, floor blocks stand on), the floor's motion by the
#: building's modes; per-sample variables, then per-series ones.
FLOOR_PULSE_SERIES = {
    "velocity": {"units": "m s-1", "long_name": "floor velocity along the floor motion's chosen pulse orientation"},
    "pulse": {"units": "m s-1", "long_name": "extracted velocity pulse of the floor motion (sum of 10 db4 wavelets)"},
}
FLOOR_PULSE_STATION: dict[str, dict] = {
    "record_id": {"long_name": "ground record"},
    "building": {"long_name": "building id (--buildings)"},
    "floor_height": {"units": "m", "long_name": "height of the floor above the building's base"},
    "is_pulse": {"long_name": "floor motion is pulse-like (Shahi & Baker 2014)", **PULSE_CLASS},
    "pulse_indicator": {"units": "1", "long_name": "pulse indicator PI of the floor motion's chosen candidate"},
    "pulse_period": {"units": "s", "long_name": "pulse period Tp of the floor motion"},
    "pulse_azimuth": {"units": "degree", "long_name": "axis of the floor motion's chosen pulse, clockwise from north, "
                      "modulo 180"},
}
class ResultTable(IntEnum):
    """The tables of one record's screening result (``screening.RecordResult``), each named by the schema: a
    variable's dimensions say which table holds it, so the scene cache writes the schema's own names."""

    values = 1         # (record,): the record's scalars
    components = 2     # (record, component)
    blocks = 3         # (record, block): one column per block
    series = 4         # the pulse series of pulses.nc (PULSE_SERIES)


_TABLE_OF_DIMS = {("record",): ResultTable.values, ("record", "component"): ResultTable.components,
                  ("record", "block"): ResultTable.blocks}
#: A floor's series and values in a cache entry: ``floor@<building>@<height [m]>@<name>`` (building ids, from a
#: CSV cell, may hold anything but a line break; the name and the height hold no ``@``)
_FLOOR_KEY = re.compile(r"floor@(?P<building>.*)@(?P<height>[^@]+)@(?P<name>[^@]+)", re.DOTALL)


def result_table(name: str) -> ResultTable:
    """The table of a record's result that holds variable ``name``.

    Raises
    ------
    ValueError
        When ``name`` is neither a per-record, per-component or per-block variable of :data:`SCHEMA` nor a
        series of :data:`PULSE_SERIES` (an entry of another layout).
    """
    if name in PULSE_SERIES:
        return ResultTable.series
    table = _TABLE_OF_DIMS.get(SCHEMA[name][0]) if name in SCHEMA else None
    if table is None:
        raise ValueError(f"{name!r} is not a per-record, per-component or per-block variable of the schema")
    return table


def floor_key(building: str, height_m: float, name: str) -> str:
    """The cache entry's name of a floor's series or value ``name`` (:data:`FLOOR_PULSE_SERIES`,
    :data:`FLOOR_PULSE_VALUES`, ``dt``)."""
    return f"floor@{building}@{height_m!r}@{name}"


def parse_floor_key(key: str) -> tuple[str, float, str] | None:
    """(building, height [m], name) of a :func:`floor_key`, or None for any other name."""
    m = _FLOOR_KEY.fullmatch(key)
    return None if m is None else (m["building"], float(m["height"]), m["name"])


#: Per-sample variables of ``histories.nc`` (one series per block at risk).
HISTORY_SERIES = {
    "theta_over_alpha": {"units": "1", "long_name": "rotation over slenderness, theta / alpha, governing scene",
                         "comment": "NaN after overturning"},
    "lean_azimuth": {"units": "degree", "long_name": "compass azimuth the block leans toward, governing scene",
                     "comment": "clockwise from north, as the record's components; kept for a solid judged on two "
                                "horizontals (orientation axisymmetric, given_3d or given_certified); NaN at rest, "
                                "after overturning, and for a planar scene (it leans along its plane, "
                                "governing_azimuth)"},
}


def check(ds: xr.Dataset, table: dict | None = None) -> list[str]:
    """Where ``ds`` departs from the schema: unknown variables, other dimensions, units, long names
    or flags, and stored flag values outside their ``flag_values``. Empty when it conforms."""
    table = SCHEMA if table is None else table
    problems = []
    for name, var in ds.variables.items():
        found = entry(str(name), table)
        if found is None:
            problems.append(f"{name}: not in the schema")
            continue
        dims, units, long_name, extra = found
        if units == IM_UNITS:
            units = ds.attrs.get("im_units")
        if tuple(var.dims) != dims:
            problems.append(f"{name}: dims {var.dims}, schema {dims}")
        if var.attrs.get("units") != units:
            problems.append(f"{name}: units {var.attrs.get('units')!r}, schema {units!r}")
        if var.attrs.get("long_name") != long_name:
            problems.append(f"{name}: long_name differs from the schema")
        if "flag_values" in extra:
            allowed = set(np.asarray(extra["flag_values"]).tolist())
            if var.attrs.get("flag_meanings") != extra["flag_meanings"]:
                problems.append(f"{name}: flag_meanings differ from the schema")
            if var.dtype.kind not in "iu":
                problems.append(f"{name}: flags stored as {var.dtype}, expected an integer type")
            elif not set(np.unique(var.values).tolist()) <= allowed:
                problems.append(f"{name}: values {sorted(set(np.unique(var.values).tolist()) - allowed)} "
                                "outside flag_values")
    return problems


#: ``chart.nc`` (``screen chart``): the stability chart of one block and, optionally, records as points.
CHART: dict[str, tuple[tuple[str, ...], str | None, str, dict]] = {
    "period": (("period",), "s", "pulse period T = 2 t_p", {"standard_name": "period"}),
    "critical_acceleration": (("period",), "m s-2", "smallest overturning pulse amplitude by the paper's criterion",
                              {}),
    "critical_acceleration_small_angle": (("period",), "m s-2",
                                          "the paper's Eq. 7 as printed: alpha g max(1 / (p beta t_p), 1)", {}),
    "energy_acceleration": (("period",), "m s-2", "energy hyperbola v_crit / (beta t_p) (Eq. 5)", {}),
    "closed_form_acceleration": (("period",), "m s-2", "closed-form minimum overturning amplitude, linear model",
                                 {"comment": "half-sine: Makris & Roussos (2000) eq. 27; step: Housner (1963) "
                                             "eq. 9; NaN where none is published"}),
    "normalized_period": (("period",), "1", "period over the criterion's transition period", {}),
    "critical_acceleration_normalized": (("period",), "1", "critical acceleration over the uplift acceleration", {}),
    "uplift_acceleration": ((), "m s-2", "uplift acceleration (Eq. 1)", {}),
    "sliding_acceleration": ((), "m s-2", "the paper's sliding line mu g (mu / alpha in units of alpha g)", {}),
    "critical_velocity": ((), "m s-1", "critical velocity (Eq. 4)", {}),
    "critical_acceleration_simulated": (("period",), "m s-2",
                                        "first overturning amplitude, nonlinear rigid rocking simulation", {}),
    "record": (("record",), None, "record identifier", {"cf_role": "timeseries_id"}),
    "record_ap": (("record",), "m s-2", "pulse peak acceleration", {}),
    "record_tp": (("record",), "s", "pulse lobe duration", {}),
    "record_beta": (("record",), "1", "pulse fullness factor", {}),
    "record_dv": (("record",), "m s-1", "pulse velocity increment", {}),
    "record_period": (("record",), "s", "period of the chart's pulse shape with the same a_p and dv",
                      {"comment": "2 t_p beta / beta_shape (the paper's Fig. 6 normalization)"}),
    "record_energy_ratio": (("record",), "1", "pulse kinetic energy over the energy that overturns", {}),
    "record_normalized_acceleration": (("record",), "1", "pulse peak acceleration over the uplift acceleration",
                                       {}),
    "record_normalized_duration": (("record",), "1", "pulse lobe duration over the transition duration", {}),
    "record_overturn_criterion": (("record",), None, "overturning by the paper's criterion",
                                  TRISTATE),
    "record_is_pulse": (("record",), None, "record is pulse-like (Shahi & Baker 2014)",
                        PULSE_CLASS),
    "record_overturn_simulated": (("record",), None, "overturning of this block by the nonlinear simulation of "
                                  "the whole record (-1: no verdict or not simulated)", TRISTATE),
}

_INFER_DIMS = ("observation", "azimuth", "duration", "acceleration")
#: ``infer.nc`` (``screen infer``): pulses consistent with observed toppling and standing.
INFER: dict[str, tuple[tuple[str, ...], str | None, str, dict]] = {
    "observation": (("observation",), None, "block id of the observation", {}),
    "azimuth": (("azimuth",), "degree", "pulse axis azimuth, mod 180", {}),
    "duration": (("duration",), "s", "pulse duration t_p (half period)", {}),
    "acceleration": (("acceleration",), "m s-2", "pulse peak acceleration a_p", {}),
    "observation_holds_criterion": (_INFER_DIMS, None,
                                    "the observation holds under the pulse, by the paper's criterion", TRUE_FALSE),
    "observation_holds_simulation": (_INFER_DIMS, None,
                                     "the observation holds under the pulse, by the rocking simulation", TRUE_FALSE),
    "consistent_criterion": (_INFER_DIMS[1:], None, "every observation holds, by the paper's criterion", TRUE_FALSE),
    "consistent_simulation": (_INFER_DIMS[1:], None, "every observation holds, by the rocking simulation",
                              TRUE_FALSE),
    "observations_holding_simulation": (_INFER_DIMS[1:], "1",
                                        "number of observations that hold, by the rocking simulation", {}),
    "toppled": (("observation",), None, "the block toppled", TRUE_FALSE),
    "displaced": (("observation",), None, "the body was found standing, moved on what it stands on by at least the "
                  "attribute displaced_min_m", TRUE_FALSE),
    "fall_azimuth": (("observation",), "degree", "observed fall azimuth, mod 180", {}),
    "height": (("observation",), "m", "full block height", {}),
    "width": (("observation",), "m", "full base width", {}),
    "mu": (("observation",), "1", "friction coefficient", {}),
    "block_azimuth": (("observation",), "degree", "rocking plane azimuth (NaN: any plane)", {}),
}


#: ``fragility.nc`` (``screen fragility``): stripes, fits, IM ranking and the hazard integral.
FRAGILITY: dict[str, tuple[tuple[str, ...], str | None, str, dict]] = {
    "block": SCHEMA["block"],
    "record": SCHEMA["record"],
    "im_level": (("im_level",), IM_UNITS, "level of the intensity measure each stripe's records are scaled to", {}),
    "im": (("im",), None, "intensity measure compared (pga, pgv, pgv_pga, sa, arias, ap, tp, velocity_ratio)", {}),
    "fraction_overturned": (("block", "im_level"), "1", "mean over the stripe's records of the overturn outcome "
                            "(nominal verdict, or p_overturn when sampled)", {}),
    "n_records": (("block", "im_level"), "1", "records with a verdict in the stripe", {}),
    "n_scaled": (("block", "im_level"), "1", "records scaled to the level, with a verdict or without", {}),
    "n_unjudged": (("block", "im_level"), "1", "records without a verdict in the stripe (a sampled scene counts "
                   "by its fraction of samples without a verdict)",
                   {"comment": "unknown, never standing: the median_unjudged_* fits count them both ways"}),
    "n_sliding": (("block", "im_level"), "1", "records whose nominal scene slides or slide-rocks at the level", {}),
    "median_unjudged_overturn": (("block",), IM_UNITS, "median of the fit with the records and samples without a "
                                 "verdict counted as overturning (the lower bound they allow)", {}),
    "beta_unjudged_overturn": (("block",), "1", "dispersion of that fit", {}),
    "median_unjudged_stand": (("block",), IM_UNITS, "median of the fit with the records and samples without a "
                              "verdict counted as standing (the upper bound they allow)", {}),
    "beta_unjudged_stand": (("block",), "1", "dispersion of that fit", {}),
    "overturned_sum": (("block", "im_level"), "1", "sum of the outcomes in the stripe (the fit's successes)", {}),
    "median": (("block",), IM_UNITS, "median theta of the lognormal fragility, maximum likelihood on the stripes "
               "(Baker 2015)", {"comment": "inf: nothing overturns at any level; 0: everything overturns at "
                                           "every level"}),
    "beta": (("block",), "1", "lognormal dispersion beta of the fragility", {}),
    "fit_status": (("block",), None, "how the fit ended", flags(FitStatus, missing=None)),
    "median_low": (("block",), IM_UNITS, "lower bound of the bootstrap interval on the median (records "
                   "resampled)", {}),
    "median_high": (("block",), IM_UNITS, "upper bound of the bootstrap interval on the median", {}),
    "beta_low": (("block",), "1", "lower bound of the bootstrap interval on beta", {}),
    "beta_high": (("block",), "1", "upper bound of the bootstrap interval on beta", {}),
    "scale_factor": (("record", "im_level", "block"), "1", "factor on the record (all components) that brings "
                     "its IM to the level", {"comment": "NaN: the record's IM is zero or undefined"}),
    "outcome": (("record", "im_level", "block"), None, "nominal overturning verdict of the scaled record",
                TRISTATE),
    "p_overturn": (("record", "im_level", "block"), "1", "probability of overturning of the scaled record under "
                   "the declared uncertainty", {}),
    "beta_im": (("block", "im"), "1", "dispersion of a lognormal fit of the same outcomes against each IM "
                "(efficiency: smaller is better)", {"comment": "inf: the IM does not raise the probability"}),
    "median_im": (("block", "im"), None, "median of that fit, in the IM's own SI unit (see im_units_by_im)", {}),
    "sufficiency_p": (("block", "im"), "1", "p-value of adding ln(t_p) to the fit (likelihood ratio; small: the "
                      "outcome still depends on the pulse period given the IM)", {}),
    "im_rank": (("block", "im"), "1", "rank of the IM by beta_im (1: most efficient; -1: no fit)", {}),
    "annual_rate_overturn": (("block",), "yr-1", "mean annual rate of overturning: integral of the fragility over "
                             "the site's hazard curve",
                             {"comment": "NaN for a block that can rock but overturned at no level tested (raise the "
                                         "levels; annual_rate_overturn_upper bounds it); 0 only for a block that "
                                         "cannot rock. Read with fit_status: not_bounded and extrapolated medians "
                                         "lie outside the levels tested"}),
    "p_overturn_50yr": (("block",), "1", "probability of overturning in 50 years (Poisson)", {}),
    "annual_rate_overturn_upper": (("block",), "yr-1", "upper bound of the rate of overturning: the fragility "
                                   "below the top level tested and overturning certain above it",
                                   {"comment": "the conservative reading of levels never tested; for a block that "
                                               "overturned at no level, the hazard's rate of exceeding the top level"}),
    "p_overturn_50yr_upper": (("block",), "1", "upper bound of the probability of overturning in 50 years", {}),
    "block_period": (("block",), "s", "the block's Sa period 2 pi / p", {}),
    "can_rock": (("block",), None, "the block can rock: it tips before it slides (mu > tan alpha) and is slender "
                 "enough (alpha < 54.7 deg)", {**TRUE_FALSE, "comment": "a block that cannot rock only slides or "
                                                                         "stands: no level overturns it"}),
    "hazard_period": (("block",), "s", "period of the Sa hazard curve the block is integrated against", {}),
    "hazard_period_ratio": (("block",), "1", "that curve's period over the block's own Sa period",
                            {"comment": "1 where a curve of the block's own period was given"}),
}


#: ``event.nc`` (``screen event``): each asset's probability of overturning in one earthquake, from the event's
#: ShakeMap and the assets' fragilities. Dimension ``block`` as in screening.nc.
EVENT: dict[str, tuple[tuple[str, ...], str | None, str, dict]] = {
    "block": SCHEMA["block"],
    "p_overturn_event": (("block",), "1", "probability of overturning in the event: the fragility convolved with "
                         "the lognormal shaking at the site, Phi(ln(m e^(k sigma) / theta) / sqrt(beta^2 + sigma^2))",
                         {"comment": "NaN where the fragility did not bound its median (basis bounds_only): read "
                                     "p_overturn_event_low and _high"}),
    "p_overturn_event_low": (("block",), "1", "lower bound of that probability (the bootstrap interval of the "
                             "fragility's median; 0 where nothing overturned at any level tested)", {}),
    "p_overturn_event_high": (("block",), "1", "upper bound of that probability (overturning certain above the "
                              "top level tested where nothing overturned)", {}),
    "basis": (("block",), None, "what the probability rests on", flags(Basis, missing=None)),
    "level": (("block",), None, "inspection level (thresholds: global attributes level_low, level_medium, "
              "level_high)", {**flags(Level, missing=None),
                              "comment": "never none where the asset slid at the site's shaking (sliding_risk) or "
                                         "where P is unknown; records without a verdict are ranked as overturning"}),
    "sliding_risk": (("block",), None, "the site's median shaking reaches a level at which the asset slid in the "
                     "fragility's stripes", TRUE_FALSE),
    "level_previous": (("block",), None, "the level in the previous version of the same event's ShakeMap run into "
                       "this output", flags(Level, missing="not_evaluated")),
    "priority": (("block",), "1", "rank in the inspection list (1: first): by the governing probability "
                 "(governed_by), the ShakeMap's taken at its upper bound where it is not given", {}),
    "shaking_median": (("block",), IM_UNITS, "median of the ShakeMap field at the site (bilinear in ln IM)", {}),
    "shaking_log_sd": (("block",), "1", "standard deviation of ln IM at the site", {}),
    "log_sd_source": (("block",), None, "where that standard deviation comes from",
                      {"flag_values": np.array([0, 1, 2], dtype="i1"),
                       "flag_meanings": "shakemap_grid uncertainty_file configured_default"}),
    "shakemap_field": (("block",), None, "the ShakeMap field read (PGA, PGV, PSA03, PSA10, PSA30)", {}),
    "shakemap_period": (("block",), "s", "period of that PSA field (NaN: PGA or PGV)", {}),
    "block_period": (("block",), "s", "the block's Sa period 2 pi / p, the fragility's own for Sa", {}),
    "fragility_median": (("block",), IM_UNITS, "median theta of the block's fragility (fragility.nc)", {}),
    "fragility_beta": (("block",), "1", "dispersion beta of the block's fragility", {}),
    "fit_status": (("block",), None, "how the fragility's fit ended", flags(FitStatus, missing=None)),
    "lon": (("block",), "degrees_east", "longitude of the asset", {"standard_name": "longitude"}),
    "lat": (("block",), "degrees_north", "latitude of the asset", {"standard_name": "latitude"}),
    "epicentral_distance": (("block",), "km", "distance from the asset to the epicentre (great circle)", {}),
    "most_efficient_im": (("block",), None, "the ShakeMap IM (pga, pgv, sa) whose fit of the block's outcomes has "
                          "the smallest dispersion in the fragility run (fragility.nc beta_im)", {}),
    "most_efficient_beta": (("block",), "1", "that dispersion", {}),
    "station_record": (("block",), None, "the event's record of the nearest station within station_radius_km "
                       "(screen event --records; empty: none)", {}),
    "station_distance": (("block",), "km", "distance from the asset to that station", {}),
    "p_overturn_record": (("block",), "1", "probability of overturning under that record, screened directly "
                          "(OUT/records/screening.nc)", {}),
    "governed_by": (("block",), None, "which probability sets the level and priority: the larger of the ShakeMap's "
                    "and the record's", {"flag_values": np.array([0, 1], dtype="i1"),
                                         "flag_meanings": "shakemap record"}),
}


#: ``constrain.nc`` (``screen constrain``): the constraint standing fragile rocks put on a hazard model's end
#: branches. Levels and fragility medians in the IM's SI unit (global attribute ``im_units``).
CONSTRAIN: dict[str, tuple[tuple[str, ...], str | None, str, dict]] = {
    "rock": (("rock",), None, "rock id (the fragility run's block id)", {}),
    "branch": (("branch",), None, "end branch of the hazard model's logic tree (OpenQuake realization, or curve "
               "file)", {}),
    "im_level": (("im_level",), IM_UNITS, "IM level every branch's curve covers", {}),
    "fractile": (("fractile",), "1", "fractile of the branches' hazard", {}),
    "target_rate": (("target_rate",), "yr-1", "annual rate of exceedance at which the hazard's change is read", {}),
    "branch_path": (("branch",), None, "the branch's path through the logic tree, as the file gives it", {}),
    "branch_name": (("branch",), None, "the branch's name: its branches' IDs in the logic-tree files beside an "
                    "OpenQuake export (joined by ' · '), else its path", {}),
    "prior_weight": (("branch",), "1", "the branch's weight in the hazard model", {}),
    "posterior_weight": (("branch",), "1", "the branch's weight given that the rocks stood through their ages "
                         "(Bayes' rule)", {}),
    "likelihood": (("branch",), "1", "probability that the rocks stood through their ages under the branch, the "
                   "rocks combined as the global attribute combine says", {}),
    "likelihood_rock": (("rock", "branch"), "1", "probability that the rock stood through its age under the branch: "
                        "exp(-rate T) averaged over the age and the fragility's draws", {}),
    "posterior_weight_rock": (("rock", "branch"), "1", "the branch's posterior weight given this rock alone", {}),
    "toppling_rate": (("rock", "branch"), "yr-1", "annual rate of toppling: the fitted fragility integrated over "
                      "the branch's hazard curve", {}),
    "toppling_rate_low": (("rock", "branch"), "yr-1", "5th percentile of the toppling rate over the fragility's "
                          "draws", {}),
    "toppling_rate_high": (("rock", "branch"), "yr-1", "95th percentile of the toppling rate over the fragility's "
                           "draws", {}),
    "toppling_rate_upper": (("rock", "branch"), "yr-1", "upper bound of the toppling rate: the fragility below the "
                            "top level tested and toppling certain above it",
                            {"comment": "NaN where the top level tested is not known (a fragility table)"}),
    "hazard_rate": (("branch", "im_level"), "yr-1", "the branch's annual rate of exceedance", {}),
    "age_mean": (("rock",), "year", "mean exposure age of the rock", {}),
    "age_sd": (("rock",), "year", "standard deviation of the exposure age", {}),
    "fragility_median": (("rock",), IM_UNITS, "median of the rock's lognormal fragility", {}),
    "fragility_beta": (("rock",), "1", "dispersion of the rock's lognormal fragility", {}),
    "fragility_median_draws_low": (("rock",), IM_UNITS, "5th percentile of the fragility median's draws", {}),
    "fragility_median_draws_high": (("rock",), IM_UNITS, "95th percentile of the fragility median's draws", {}),
    "fragility_top_level": (("rock",), IM_UNITS, "largest IM level the fragility was tested at",
                            {"comment": "inf: not known (a fragility table)"}),
    "fit_status": (("rock",), None, "how the fragility's fit ended", flags(FitStatus, missing=None)),
    "mean_rate_prior": (("im_level",), "yr-1", "mean hazard curve of the prior weights", {}),
    "mean_rate_posterior": (("im_level",), "yr-1", "mean hazard curve of the posterior weights", {}),
    "fractile_rate_prior": (("fractile", "im_level"), "yr-1", "fractile hazard curves of the prior weights", {}),
    "fractile_rate_posterior": (("fractile", "im_level"), "yr-1", "fractile hazard curves of the posterior weights",
                                {}),
    "mean_level_prior": (("target_rate",), IM_UNITS, "IM level of the prior mean curve at the target rate",
                         {"comment": "NaN: the curve does not reach the rate within its levels"}),
    "mean_level_posterior": (("target_rate",), IM_UNITS, "IM level of the posterior mean curve at the target rate",
                             {"comment": "NaN: the curve does not reach the rate within its levels"}),
    "fractile_level_prior": (("fractile", "target_rate"), IM_UNITS, "IM level of each prior fractile curve at the "
                             "target rate", {}),
    "fractile_level_posterior": (("fractile", "target_rate"), IM_UNITS, "IM level of each posterior fractile curve "
                                 "at the target rate", {}),
    "mean_level_change": (("target_rate",), "1", "relative change of the mean hazard's level at the target rate "
                          "(posterior / prior - 1)", {}),
    "range_change": (("target_rate",), "1", "relative change of the width of the 5-95 % fractile range of levels at "
                     "the target rate (posterior / prior - 1)", {}),
}
