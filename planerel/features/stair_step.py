"""``stair_step/2``: two planes of one object one staircase step apart.

Its own module because it asks both the step test of :mod:`planerel.features.relations` and
the plan-view overlap of :mod:`planerel.features.plan_overlap` (which itself builds on
relations).  See docs/predicates.md and docs/objects.md "A flight's steps as a relation".
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.open_treads import open_tread_pairs
from planerel.features.open_walls import top_level
from planerel.features.plan_overlap import OVER_SHARE, plan_overlap
from planerel.features.proposal_params import ProposalParams
from planerel.features.step_chains import (
    OPEN_THICK,
    OPEN_TILT,
    STAIR_RISE,
    STAIR_RUN,
    _step_kind,
    step_chain_pairs,
)

__all__ = ["stair_steps"]


def stair_steps(planes, labels, params: ProposalParams | None = None,
                by_label: dict | None = None, xyz=None) -> frozenset:
    """The ``stair_step/2`` pairs of the planes ``labels`` of one object: ``(lower, higher)``
    labels of two parallel treads or two risers one staircase step apart, the higher one
    :data:`~planerel.features.step_chains.STAIR_RISE` above and
    :data:`~planerel.features.step_chains.STAIR_RUN` beyond the lower one, their extents across
    that direction overlapping (:func:`~planerel.features.step_chains.step_chain_pairs` without
    its chain test, the next face only: never one two rises away); with
    ``params.open_treads``, the consecutive treads of an open-riser flight's row too
    (:func:`planerel.features.open_treads.open_tread_pairs`: strips 15-55 degrees off
    horizontal at range); never two whose footprints seen from above overlap by
    :data:`~planerel.features.plan_overlap.OVER_SHARE` of the larger (a shelf's boards:
    ``over/2``); with ``params.riser_walls`` and the points, never two risers the lower of
    which is a wall rising to the higher one's top (:func:`_wall_pair`: an open basket's near
    wall seen from outside and its far wall seen from inside over the rim; riser92).  A
    pairwise relation of two planes, not a class: a carton one stair rise above and one run
    behind another makes one too.

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
    params : ProposalParams, optional
    by_label : dict, optional
        ``{label: Plane}`` of ``planes`` (built here when not given; a caller asking for
        many objects of one scene builds it once).
    xyz : ndarray (H, W, 3), optional
        The organized points (``planes.labels``' grid), for the risers' tops; without them no
        riser pair is refused as a wall pair.

    Returns
    -------
    frozenset of (int, int)
    """
    labels = tuple(labels)
    if len(labels) < 2:
        return frozenset()
    p = params or ProposalParams()
    if by_label is None:
        by_label = {q.label: q for q in planes}
    # an exact early out: a step needs two treads or two risers (within step_tilt of level or
    # riser_tilt of vertical), an open-riser row three slabs (within OPEN_TILT of level)
    mine = [by_label[k] for k in labels if k in by_label]
    kinds = [_step_kind(q, p.step_tilts) for q in mine]
    treads, risers = kinds.count("tread"), kinds.count("riser")
    # (the slabs' own test is on |normal . up| >= cos(OPEN_TILT); a hair of slack for rounding)
    slabs = sum(q.incline <= OPEN_TILT + 1e-6 for q in mine) if p.open_treads else 0
    if treads < 2 and risers < 2 and slabs < 3:
        return frozenset()
    # one span only: the next face, not the one after it with a face between
    out = set()
    if treads >= 2 or risers >= 2:
        out = {(int(lo), int(hi)) for lo, hi, _r, _d, span, _g in step_chain_pairs(
            planes, labels, STAIR_RISE, STAIR_RUN, p.step_overlap or 0.5, p.concave_tol,
            tilt=p.step_tilts, skip=False, cut_long_side=p.cut_long_side,
            tread_axes=p.step_tread_axes, chain=False, cut_top=p.step_cut_top,
            tread_pieces=p.step_tread_pieces) if span == 1}
    if slabs >= 3:
        # an open-riser flight's treads, fitted as strips tilted off horizontal at range
        rows = {(int(lo), int(hi)) for lo, hi in open_tread_pairs(
            planes, labels, (p.step_rise_min, p.step_rise_max), p.step_run_max, OPEN_THICK,
            OPEN_TILT)}
        # the next tread only: a pair two rises apart with the tread between also in the row
        # is no step
        out |= {(lo, hi) for lo, hi in rows
                if not any((lo, m) in rows and (m, hi) in rows for _, m in rows)}
    if not out:
        return frozenset()
    lab = getattr(planes, "labels", None)
    if (p.riser_walls and risers >= 2 and xyz is not None and lab is not None
            and lab.shape == xyz.shape[:2]):
        tops: dict = {}
        out = {pair for pair in out
               if not _wall_pair(planes, by_label, labels, pair, p, lab, xyz, tops)}
    # a shelf's boards lie stacked over each other in plan view, a flight's treads side by side
    # (an open-riser row lets a slab's near edge lie over the one below it)
    return frozenset((lo, hi) for lo, hi in out
                     if plan_overlap(by_label[lo].hull3d, by_label[hi].hull3d, planes.up)
                     < OVER_SHARE)


#: Metres: a riser's surface rises to the next riser's top when a piece of it (a plane of
#: the object within ``concave_tol`` of parallel and this far along its normal) has its top
#: within :data:`RISER_TOPS_LEVEL` of that top.
WALL_COPLANAR = 0.03

#: Metres: half the lowest stair rise (:data:`~planerel.features.step_chains.STAIR_RISE`).
RISER_TOPS_LEVEL = 0.5 * STAIR_RISE[0]


def _wall_pair(planes, by_label, labels, pair, params, lab, xyz, tops) -> bool:
    """True when the step ``pair`` is two risers (within ``params.step_tilts``) and the lower
    one's surface rises to the higher one's top: a plane of the object's ``labels`` parallel
    to the lower riser (within ``params.concave_tol``), within :data:`WALL_COPLANAR` of its
    plane, has its seen top within :data:`RISER_TOPS_LEVEL` of the higher riser's seen top
    (tops: :func:`planerel.features.open_walls.top_level`, cached in ``tops``).  A flight's
    riser ends at its nosing, one rise under the next riser's top; an open basket's near wall,
    whose face may come in pieces, goes up to the rim its far wall ends at."""
    lo, hi = by_label[pair[0]], by_label[pair[1]]
    if (_step_kind(lo, params.step_tilts) != "riser"
            or _step_kind(hi, params.step_tilts) != "riser"):
        return False
    up = np.asarray(planes.up, float)

    def top(k):
        if k not in tops:
            tops[k] = top_level(lab, xyz, up, k)
        return tops[k]

    t_hi, seen = top(hi.label)
    if not seen or t_hi is None:
        return False
    n = np.asarray(lo.normal, float)
    c = np.asarray(lo.centroid, float)
    cos_par = math.cos(math.radians(params.concave_tol))
    for k in labels:
        q = by_label.get(k)
        if q is None or k == hi.label or abs(float(n @ np.asarray(q.normal, float))) < cos_par:
            continue
        if abs(float(n @ (np.asarray(q.centroid, float) - c))) > WALL_COPLANAR:
            continue
        t, seen_q = top(k)
        if seen_q and t is not None and abs(t - t_hi) <= RISER_TOPS_LEVEL:
            return True
    return False
