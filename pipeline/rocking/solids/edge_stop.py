"""Where the 3D contact model (:mod:`.contact3d`) stops for an exact model to go on (:mod:`.alternate`): the body
turning on one of the exact model's places (a pair of vertices: a box's base edge, a cylinder's rim points; a pair
(i, i), the vertex i alone) without slipping for a whole sampling interval, the vertices of that pair loaded inside
their friction cone and every other vertex without impulse.
"""

from __future__ import annotations

import math

from ...compiled import jit_inline


@jit_inline
def on_edge(impulses, edges, mu):
    """The pair of ``edges`` that alone carries the last step's impulses (every other vertex none), each of its two
    with a normal impulse inside its friction cone (sticking: |P_t| < mu P_n), or the pair (i, i) where the vertex i
    alone carries them so; -1 where none."""
    loaded, first, second = 0, -1, -1
    for i in range(impulses.shape[0]):
        if impulses[i, 0] != 0.0 or impulses[i, 1] != 0.0 or impulses[i, 2] != 0.0:
            if impulses[i, 2] <= 0.0 or math.hypot(impulses[i, 0], impulses[i, 1]) >= mu * impulses[i, 2]:
                return -1
            loaded += 1
            first, second = (i, second) if first < 0 else (first, i)
    if loaded == 1:
        second = first
    elif loaded != 2:
        return -1
    for e in range(edges.shape[0]):
        if (edges[e, 0] == first and edges[e, 1] == second) or (edges[e, 0] == second and edges[e, 1] == first):
            return e
    return -1


@jit_inline
def handback(impulses, edges, mu, stuck, counts, at_sample, n_sub, span):
    """The steps in a row turning on a pair of ``edges`` without slipping (:func:`on_edge`), this one (``span``
    steps taken as one) included where it ``counts`` (a step during the record, whole or in parts: the impulses of its
    last part; else none), and the edge where that reaches a whole sampling interval (``n_sub`` steps) ``at_sample``
    (-1: not yet)."""
    if not counts or edges.shape[0] == 0:
        return 0, -1
    on = on_edge(impulses, edges, mu)
    stuck = stuck + span if on >= 0 else 0
    return stuck, on if stuck >= n_sub and at_sample else -1
