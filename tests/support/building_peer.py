"""An independent building model for tests only: a multi-degree-of-freedom wall-frame in OpenSees (openseespy,
an optional test dependency; the native library needs the system's BLAS and LAPACK, ``make peers`` installs
them).

The continuous shear-flexural cantilever of Miranda & Taghavi (2005) discretized as its physical picture: a
flexural column (elastic beam-column elements, bending stiffness EI) and a shear column (elastic beam-column
elements whose nodes cannot rotate, each storey a shear spring GA / h) side by side, tied at every level by
axially rigid links (equal horizontal displacement), fixed at the base, with the mass lumped at the levels
(half a segment's at the top). Its modes come from OpenSees' own eigen-analysis; its stiffness is scaled so
that its first period is the building's; every mode gets the building's damping ratio (OpenSees' modal
damping over all the modes of the lateral degrees of freedom); the ground acceleration is applied as a uniform
excitation, linear between samples, and integrated by Newmark's average-acceleration method on sub-steps.
Nothing of rockscreen's model (characteristic equation, shapes, participation factors, the exact oscillator
step) is used.
"""

from __future__ import annotations

import math

import numpy as np
from peers import missing_peer

#: Segments over the height: the discrete model's modes converge to the continuous model's as this grows.
SEGMENTS = 40
#: Newmark sub-steps per record sample.
SUBSTEPS = 4


def opensees():
    """The openseespy module, or a skip (a failure where ROCKSCREEN_REQUIRE_PEERS=1, as in CI)."""
    try:
        import openseespy.opensees as ops
    except (ImportError, RuntimeError) as exc:      # RuntimeError: the native library lacks libblas / liblapack
        message = (f"openseespy cannot be imported ({exc}): the comparison with an independent MDOF building "
                   "model is SKIPPED (pip install openseespy, or the project's test extras; on Debian, "
                   "'make peers' installs the BLAS and LAPACK it needs)")
        missing_peer(message)
    return ops


def _build(ops, *, height_m: float, stiffness_ratio: float, segments: int, stiffness_scale: float) -> int:
    """The wall-frame; returns the number of lateral degrees of freedom (one per level above the base)."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    h = height_m / segments
    ei = stiffness_scale
    ga = stiffness_ratio ** 2 * ei / height_m ** 2           # alpha = H sqrt(GA / EI)
    shear = stiffness_ratio > 0
    ops.geomTransf("Linear", 1)
    for k in range(segments + 1):
        ops.node(1 + k, 0.0, k * h)
        if shear:
            ops.node(10001 + k, 1.0, k * h)
    ops.fix(1, 1, 1, 1)
    if shear:
        ops.fix(10001, 1, 1, 1)
    for k in range(1, segments + 1):
        ops.fix(1 + k, 0, 1, 0)                              # axially rigid: lateral behaviour only
        if shear:
            ops.fix(10001 + k, 0, 1, 1)                      # no rotation: each storey a shear spring
            ops.equalDOF(1 + k, 10001 + k, 1)                # the rigid link
        ops.mass(1 + k, h * (0.5 if k == segments else 1.0), 0.0, 0.0)
    for k in range(segments):
        ops.element("elasticBeamColumn", 1 + k, 1 + k, 2 + k, 1.0, 1.0, ei, 1)
        if shear:                                            # 12 E I / h^3 = GA / h
            ops.element("elasticBeamColumn", 10001 + k, 10001 + k, 10002 + k, 1.0, 1.0, ga * h * h / 12.0, 1)
    return segments


def floor_accelerations(ground_ms2: np.ndarray, dt_s: float, *, period_s: float, damping: float,
                        stiffness_ratio: float, height_m: float, heights_m: list[float],
                        segments: int = SEGMENTS, substeps: int = SUBSTEPS) -> tuple[np.ndarray, np.ndarray]:
    """Total accelerations [m s-2] at ``heights_m`` (levels of the discretization) under the ground acceleration,
    shape (len(heights_m), npts); and the model's periods [s], longest first."""
    ops = opensees()
    kw = dict(height_m=height_m, stiffness_ratio=stiffness_ratio, segments=segments)
    _build(ops, stiffness_scale=1.0, **kw)
    omega1 = math.sqrt(ops.eigen("-fullGenLapack", 1)[0])
    n_lateral = _build(ops, stiffness_scale=(2 * math.pi / period_s / omega1) ** 2, **kw)
    periods = 2 * math.pi / np.sqrt(np.asarray(ops.eigen("-fullGenLapack", n_lateral)))
    ops.modalDamping(damping)
    ops.timeSeries("Path", 1, "-dt", dt_s, "-values", *np.asarray(ground_ms2, dtype=float).tolist())
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("FullGeneral")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.algorithm("Linear")
    ops.analysis("Transient")
    levels = [1 + round(z / height_m * segments) for z in heights_m]
    for z, node in zip(heights_m, levels):
        if not math.isclose((node - 1) * height_m / segments, z, abs_tol=1e-9):
            raise ValueError(f"{z} m is not a level of the {segments}-segment model")
    out = np.zeros((len(levels), ground_ms2.size))
    for k in range(1, ground_ms2.size):
        if ops.analyze(substeps, dt_s / substeps) != 0:
            raise RuntimeError(f"OpenSees failed at step {k}")
        out[:, k] = [ops.nodeAccel(node, 1) for node in levels]   # relative to the ground
    ops.wipe()
    return out + ground_ms2, periods
