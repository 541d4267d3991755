"""``over/2``: one horizontal plane lies over another in plan view (a shelf's boards).

A shelf's boards and a flight's treads are both horizontal planes one above another, and
``above``, ``parallel`` and ``rise`` say the same of both.  What parts them is where they lie
seen from above: a shelf's boards are stacked, each over the one below, while each tread of a
flight lies one run further back than the one below it, next to it in plan view and over it
only by the nosing (a few cm of a 22-35 cm run).  On six of the varied world's held-out sets
this split them all but one: 43 of the 44 shelves with two boards in view had a pair
overlapping by 0.5 or more of the larger board (median 0.89), no flight (515), table or chair
had one (median 0.00-0.03, 90th percentile at most 0.11; docs/results.md, "Shelves against
stairs").  The larger one, not the smaller: a descending flight's lowest tread lies wholly over
the lower floor, which is part of the flight's object.

``over(P, Q)``: P and Q are horizontal, P's centroid lies more than ``above_tol`` above Q's
(the ``above`` relation), and the plan-view footprints of their convex hulls (the hulls
projected along ``up``) overlap by at least :data:`OVER_SHARE` of the larger footprint (so of
each).
"""

from __future__ import annotations

import numpy as np

from planerel.features.step_geometry import _horizontal_basis

__all__ = ["OVER_SHARE", "over_pairs", "plan_overlap", "plan_overlap_xy"]

#: The least overlap of two footprints, as a share of the larger one, for ``over``.
OVER_SHARE = 0.5


def plan_overlap(hull_a, hull_b, up) -> float:
    """The overlap of two point sets' convex hulls seen along ``up``, over the larger one.

    Parameters
    ----------
    hull_a, hull_b : array_like, shape (N, 3)
        3-D points (a plane's convex-hull vertices, metres).
    up : array_like, shape (3,)
        Gravity up.

    Returns
    -------
    float
        ``area(A ∩ B) / max(area(A), area(B))`` of the plan-view footprints, in 0..1; 0 when
        either footprint has no area.
    """
    up = np.asarray(up, float)
    e = np.stack(_horizontal_basis(up / np.linalg.norm(up)), axis=1)  # (3, 2)
    return plan_overlap_xy(np.asarray(hull_a, float) @ e, np.asarray(hull_b, float) @ e)


def over_pairs(planes, pairs, share: float = OVER_SHARE) -> set:
    """The ``(a, b)`` of ``pairs`` for which ``over(a, b)`` holds.

    Parameters
    ----------
    planes : PlaneSet
        The planes (orientation, hull, ``up``).
    pairs : iterable of Relation
        Relations to look at (those written as facts); only pairs with ``above`` and two
        horizontal planes are measured.
    share : float
        The least overlap over the larger footprint.

    Returns
    -------
    set of (int, int)
    """
    by_label = {p.label: p for p in planes}
    todo = [(r.a, r.b) for r in pairs if r.above
            and by_label[r.a].orientation == "horizontal"
            and by_label[r.b].orientation == "horizontal"]
    if not todo:
        return set()
    e = np.stack(_horizontal_basis(planes.up), axis=1)
    flat: dict = {}

    def footprint(label):
        if label not in flat:
            xy = np.asarray(by_label[label].hull3d, float) @ e
            flat[label] = (xy, xy.min(axis=0), xy.max(axis=0))
        return flat[label]

    out = set()
    for a, b in todo:
        xa, lo_a, hi_a = footprint(a)
        xb, lo_b, hi_b = footprint(b)
        # the boxes' overlap bounds the footprints' (a flight's treads side by side: no
        # polygon is built)
        w = np.minimum(hi_a, hi_b) - np.maximum(lo_a, lo_b)
        if w[0] <= 0 or w[1] <= 0:
            continue
        if plan_overlap_xy(xa, xb) >= share:
            out.add((a, b))
    return out


def plan_overlap_xy(xy_a, xy_b) -> float:
    """:func:`plan_overlap` of points already in the plan view, shape (N, 2)."""
    from shapely.geometry import MultiPoint

    fa = MultiPoint(np.asarray(xy_a, float)).convex_hull
    fb = MultiPoint(np.asarray(xy_b, float)).convex_hull
    if min(fa.area, fb.area) <= 0:
        return 0.0
    return float(min(1.0, fa.intersection(fb).area / max(fa.area, fb.area)))
