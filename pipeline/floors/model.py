"""Modes of the continuous shear-flexural cantilever (Miranda & Taghavi 2005).

A flexural cantilever (bending stiffness EI) and a shear cantilever (shear stiffness GA) deform together,
uniform mass and stiffness over the height H. With x = z / H and the lateral-stiffness ratio
alpha = H sqrt(GA / EI) (0: pure flexure; large: pure shear), a mode shape phi(x) satisfies

    phi'''' - alpha^2 phi'' - lambda^4 phi = 0,      lambda^4 = rho omega^2 H^4 / EI,

whose solutions are phi = A sin(gamma x) + B cos(gamma x) + C sinh(beta x) + D cosh(beta x) with
beta^2 - gamma^2 = alpha^2 and beta gamma = lambda^2 (computed with e^(beta (x - 1)) and e^(-beta x) in place
of sinh and cosh, which stay bounded for a large alpha). The base is fixed (phi = phi' = 0 at x = 0); the top
is free of moment and of shear (phi'' = 0 and phi''' - alpha^2 phi' = 0 at x = 1). These four conditions
have a non-zero solution where their determinant vanishes (:func:`characteristic`);
its roots gamma_1 < gamma_2 < ... give the modes, and omega_i / omega_1 = (beta_i gamma_i) / (beta_1 gamma_1).

Limits (tests): pure flexure, 1 + cos(gamma) cosh(gamma) = 0, T1/T2 = 6.267 and T1/T3 = 17.547; pure shear,
T1/T2 -> 3, T1/T3 -> 5, and the roof participation Gamma_1 phi_1(1) -> 4 / pi.

Participation factor of mode i (uniform mass): Gamma_i = integral phi_i dx / integral phi_i^2 dx; its share of
the mass Gamma_i integral phi_i dx (the shares of all modes add up to 1).

References
----------
Miranda, E. & Taghavi, S. (2005). Approximate floor acceleration demands in multistory buildings. I:
Formulation. J. Struct. Eng. 131(2), 203-211. Miranda, E. & Reyes, C. J. (2002). Approximate lateral drift
demands in multistory buildings with nonuniform stiffness. J. Struct. Eng. 128(7), 840-849 (the model).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.optimize import brentq

from ..errors import ParameterError

#: The modes kept reach at least this share of the mass.
MASS_SHARE = 0.95
#: Points of the x grid on which mode shapes are integrated (Simpson's rule needs an odd count).
GRID_POINTS = 2001
#: Step of the scan for sign changes of the characteristic function in gamma, and its upper bound.
SCAN_STEP, SCAN_MAX_MODES = 0.01, 12


class Modes(NamedTuple):
    """The modes of a shear-flexural cantilever.

    Attributes
    ----------
    alpha : float
        Lateral-stiffness ratio [-].
    gamma, beta : ndarray
        The roots of the characteristic equation and beta = sqrt(alpha^2 + gamma^2) [-].
    period_ratio : ndarray
        T_1 / T_i [-] (1 for the first mode).
    participation : ndarray
        Gamma_i, with each shape normalized to phi_i(1) = 1 at the top [-].
    mass_share : ndarray
        Each mode's share of the mass [-].
    """

    alpha: float
    gamma: np.ndarray
    beta: np.ndarray
    period_ratio: np.ndarray
    participation: np.ndarray
    mass_share: np.ndarray

    def shape(self, i: int, x) -> np.ndarray:
        """Mode ``i``'s shape at heights x = z / H, normalized to 1 at the top [-]."""
        return mode_shape(self.gamma[i], self.beta[i], np.asarray(x, dtype=float))


def _boundary_matrix(gamma: float, alpha: float) -> np.ndarray:
    """The four boundary conditions on the coefficients (A, B, P, Q) of
    phi = A sin(gamma x) + B cos(gamma x) + P e^(beta (x - 1)) + Q e^(-beta x); the two exponentials stand
    for sinh and cosh and stay bounded on [0, 1], so the matrix is well conditioned for any alpha.
    Rows: phi(0) = 0, phi'(0) = 0, phi''(1) = 0, and the shear at the top, phi'''(1) - alpha^2 phi'(1) = 0."""
    beta = math.sqrt(alpha * alpha + gamma * gamma)
    s, c, e = math.sin(gamma), math.cos(gamma), math.exp(-beta)
    return np.array([
        [0.0, 1.0, e, 1.0],
        [gamma, 0.0, beta * e, -beta],
        [-gamma * gamma * s, -gamma * gamma * c, beta * beta, beta * beta * e],
        [-gamma * beta * beta * c, gamma * beta * beta * s, beta * gamma * gamma, -beta * gamma * gamma * e],
    ])


def characteristic(gamma: float, alpha: float) -> float:
    """Determinant of the boundary conditions (:func:`_boundary_matrix`), scaled by 1 / (1 + beta)^4 [-]: its
    zeros in gamma are the modes."""
    beta = math.sqrt(alpha * alpha + gamma * gamma)
    return float(np.linalg.det(_boundary_matrix(gamma, alpha))) / (1.0 + beta) ** 4


def mode_shape(gamma: float, beta: float, x: np.ndarray) -> np.ndarray:
    """The mode's shape at x (the null vector of the boundary conditions), 1 at x = 1 [-]."""
    alpha = math.sqrt(max(beta * beta - gamma * gamma, 0.0))
    _, _, vt = np.linalg.svd(_boundary_matrix(gamma, alpha))
    A, B, P, Q = vt[-1]

    def phi(z):
        return A * np.sin(gamma * z) + B * np.cos(gamma * z) + P * np.exp(beta * (z - 1.0)) + Q * np.exp(-beta * z)

    return phi(x) / phi(np.array(1.0))


def modes(alpha: float, *, mass_share: float = MASS_SHARE, at_least: int = 1) -> Modes:
    """The first modes of the cantilever of lateral-stiffness ratio ``alpha``, as many as reach ``mass_share``
    of the mass (and at least ``at_least``).

    Raises
    ------
    ParameterError
        For alpha < 0 or not finite, or when the scan finds too few roots.
    """
    if not (math.isfinite(alpha) and alpha >= 0):
        raise ParameterError(f"stiffness_ratio = {alpha!r}: the lateral-stiffness ratio alpha must be a number >= 0 "
                             "(0: a flexural wall; about 5-20: a frame)")
    x = np.linspace(0.0, 1.0, GRID_POINTS)
    roots: list[float] = []
    shares: list[float] = []
    gammas, betas, parts = [], [], []
    g = SCAN_STEP
    f_prev = characteristic(g, alpha)
    while len(roots) < SCAN_MAX_MODES:
        g_next = g + SCAN_STEP
        f_next = characteristic(g_next, alpha)
        if f_prev == 0.0 or f_prev * f_next < 0:
            root = brentq(characteristic, g, g_next, args=(alpha,), xtol=1e-14, rtol=1e-14)
            roots.append(root)
            beta = math.sqrt(alpha * alpha + root * root)
            phi = mode_shape(root, beta, x)
            integral, square = _simpson(phi, x), _simpson(phi * phi, x)
            gammas.append(root)
            betas.append(beta)
            parts.append(integral / square)
            shares.append(integral * integral / square)
            if len(roots) >= at_least and sum(shares) >= mass_share:
                break
        g, f_prev = g_next, f_next
    if len(roots) < at_least or sum(shares) < mass_share:
        raise ParameterError(f"stiffness_ratio = {alpha}: {len(roots)} modes found reach {sum(shares):.3f} of the "
                             f"mass, below {mass_share}")
    gam, bet = np.array(gammas), np.array(betas)
    lam2 = gam * bet
    return Modes(float(alpha), gam, bet, lam2 / lam2[0], np.array(parts), np.array(shares))


def _simpson(y: np.ndarray, x: np.ndarray) -> float:
    h = x[1] - x[0]
    return float(h / 3.0 * (y[0] + y[-1] + 4.0 * np.sum(y[1:-1:2]) + 2.0 * np.sum(y[2:-1:2])))
