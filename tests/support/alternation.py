"""What the tests of the hand-back to a 3D exact model (:mod:`pipeline.rocking.solids.alternate`) share: a sine of the
ground that stops, and one scene run both ways, handed back and by the contact model alone."""

from __future__ import annotations

import math

import numpy as np

from pipeline.constants import G
from pipeline.rocking.solids.alternate import ExactModel, alternate
from pipeline.rocking.solids.contact3d import Contact3DOutcome, simulate_contact3d
from pipeline.rocking.solids.contact_scene import handoff

DT_S = 0.01


def sine_then_still(amplitude_g: float, frequency_hz: float, azimuth_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Three seconds of a sine of the ground along ``azimuth_deg``, then 9 s still, sampled at :data:`DT_S`."""
    t = np.arange(0.0, 12.0, DT_S)
    a = amplitude_g * G * np.sin(2.0 * math.pi * frequency_hz * t) * (t < 3.0)
    return a * math.cos(math.radians(azimuth_deg)), a * math.sin(math.radians(azimuth_deg))


def handed_and_alone(ax, ay, body, exact, model: ExactModel) -> tuple[Contact3DOutcome, Contact3DOutcome]:
    """The scene from where the exact run ``exact`` of ``body`` stopped: handed back to ``model``, and by the contact
    model alone."""
    start = handoff(exact, body, 0.0, DT_S)
    handed = alternate(ax, ay, None, DT_S, model, 0.0, start, g_ms2=G)
    return handed, simulate_contact3d(ax, ay, None, DT_S, body.convex(), start=start)
