"""The planar rocking kernel's rectangle as the reference of the scanned-body models (two-sided, rolling): the
half-sine pulses both are checked on, and Housner's block under one of them."""

from __future__ import annotations

import math

import numpy as np

from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import rock

G = 9.80665
DT = 0.005
#: (amplitude [g], period [s]) of the half-sine-lobed pulses: below uplift, rocking, and overturning
PULSES = [(0.22, 0.5), (0.25, 0.6), (0.28, 0.7), (0.3, 0.8), (0.5, 0.5), (0.24, 1.2)]
#: The rectangle [m]: width, height
RECTANGLE = (0.3, 1.5)


def pulse(amp_g: float, period_s: float, n: int = 1600) -> np.ndarray:
    """One sine cycle of ``period_s`` and ``amp_g``, then rest, sampled at :data:`DT` [m s-2]."""
    t = np.arange(n) * DT
    return np.where(t < period_s, amp_g * G * np.sin(2 * np.pi * t / period_s), 0.0)


def housner_block(a: np.ndarray, width_m: float, height_m: float):
    """The planar kernel's rectangle under ``a`` (Housner's restitution, every flight stepped)."""
    alpha, R = math.atan2(width_m / 2, height_m / 2), math.hypot(width_m / 2, height_m / 2)
    return rock(a, DT, p=math.sqrt(0.75 * G / R), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2, R_m=R,
                settings=SimulationConfig(closed_form_chatter=False))
