"""Join the boards of a shelf: horizontal planes stacked one above another at regular heights.

A shelf seen from above or from the front shows its boards as horizontal planes; its side and
back panels are thin, far, or hidden by the boards, so the boards often share no edge with
anything and each became a proposal of its own (seed 34 ``s0021``: five boards 0.154 m apart,
five proposals).  The treads of a staircase are horizontal planes at regular heights too, but
each lies one run *beyond* the one below, and the step chains
(:func:`planerel.features.step_chains.step_chain_pairs`) join them.  A shelf's boards lie *over*
each other: seen from the top, the footprint of each board lies on the one above or below it
(the lower boards show the strip in front of the next board up, which lies inside that
board's footprint).  :func:`stacked_board_pairs` joins such planes when at least three of them
make a regular stack, as the step chains need three treads.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.vectors import cross3

__all__ = ["footprint_overlap", "stacked_board_pairs"]


def _horizontal_frame(up) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the horizontal plane (perpendicular to ``up``)."""
    u = np.asarray(up, float)
    u = u / max(float(np.linalg.norm(u)), 1e-12)
    e1 = cross3(u, (1.0, 0.0, 0.0))
    if np.linalg.norm(e1) < 0.1:
        e1 = cross3(u, (0.0, 1.0, 0.0))
    e1 = e1 / np.linalg.norm(e1)
    return e1, cross3(u, e1)


def _seen_from_above(p, frame) -> np.ndarray:
    """A plane's hull vertices in the horizontal frame ``(3, 2)`` (its columns ``e1``, ``e2``):
    ``(n, 2)`` coordinates seen from above."""
    return np.asarray(p.hull3d, float).reshape(-1, 3) @ frame


def _footprint(q):
    """The convex hull (shapely) of ``(n, 2)`` points seen from above."""
    from shapely.geometry import MultiPoint

    return MultiPoint(q).convex_hull


def footprint_overlap(pa, pb, up) -> float:
    """Area of the intersection of two planes' horizontal footprints (the convex hulls of their
    hull vertices seen from above) over the smaller footprint's area; 0 when either footprint
    has no area."""
    frame = np.stack(_horizontal_frame(up), 1)
    fa, fb = _footprint(_seen_from_above(pa, frame)), _footprint(_seen_from_above(pb, frame))
    small = min(fa.area, fb.area)
    if small <= 0:
        return 0.0
    return float(fa.intersection(fb).area / small)


def stacked_board_pairs(planes, labels=(), rise=(0.08, 0.60), min_overlap: float = 0.5,
                        angle_tol: float = 10.0, tilt: float = 12.0, regular: float = 0.3,
                        min_boards: int = 3) -> set:
    """Pairs of horizontal planes that are consecutive boards of one stack (a shelf).

    Two planes within ``tilt`` degrees of horizontal, with normals within ``angle_tol``
    degrees, are consecutive boards when the higher one's centroid lies ``rise[0]``-``rise[1]``
    metres above the lower one's and their horizontal footprints overlap by at least
    ``min_overlap`` of the smaller (:func:`footprint_overlap`): one lies over the other, as a
    staircase's treads, each one run beyond the last, do not.  Such pairs count only in a
    stack of at least ``min_boards`` planes, each linked to the next, the rises of a stack
    within ``regular`` (30 %) of each other: a shelf's boards are evenly spaced.  Two boxes one
    on the other make two planes, not a stack; with a third plane they must be alike in height
    and lie over each other.  The next board of a plane is the nearest one up that overlaps
    it (a plane two boards up overlaps too, at twice the rise).

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
        Planes to consider (the non-support planes); empty = all.

    Returns
    -------
    set of (int, int)
        ``(lower, higher)`` label pairs of the consecutive boards of every stack found.
    """
    if not 0 <= min_overlap <= 1 or rise[0] < 0 or rise[1] < rise[0] or min_boards < 2:
        from planerel.errors import InputError

        raise InputError(f"stacked boards: bad parameters rise={rise!r}, min_overlap={min_overlap!r}, "
                         f"min_boards={min_boards!r}")
    want = set(labels)
    up = np.asarray(planes.up, float)
    up = up / max(float(np.linalg.norm(up)), 1e-12)
    cos_tol = math.cos(math.radians(angle_tol))
    cands = [p for p in planes if (not want or p.label in want)
             and (p.orientation == "horizontal" or p.incline <= tilt)]
    if len(cands) < min_boards:
        return set()
    cands.sort(key=lambda p: (p.height, p.label))
    # heights and normals alone first (Python floats: a few planes, numpy's call overhead is
    # most of the time): without three planes a regular rise apart there is no stack, and no
    # footprint is needed (most frames stop here)
    normals = [[float(v) for v in np.asarray(p.normal, float)] for p in cands]
    heights = [float(p.height) for p in cands]
    above: dict = {}
    for i in range(len(cands)):
        ni = normals[i]
        for j in range(i + 1, len(cands)):
            dv = heights[j] - heights[i]
            if dv > rise[1]:
                break
            nj = normals[j]
            if dv >= rise[0] and abs(ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2]) >= cos_tol:
                above.setdefault(i, []).append((j, dv))
    if min_boards >= 3 and not any(1 - regular <= d2 / d1 <= 1 / (1 - regular)
                                   for ups in above.values() for j, d1 in ups
                                   for _k, d2 in above.get(j, ())):
        return set()
    frame = np.stack(_horizontal_frame(up), 1)
    # each candidate's hull vertices seen from above, made when a pair needs them; the shapely
    # footprint only for pairs that pass the cheaper tests
    pts: dict = {}
    foot: dict = {}

    def seen_from_above(i):
        if i not in pts:
            q = _seen_from_above(cands[i], frame)
            c = np.asarray(cands[i].centroid, float) @ frame
            pts[i] = (q, q.min(0), q.max(0), c)
        return pts[i]

    def fp(i):
        if i not in foot:
            foot[i] = _footprint(seen_from_above(i)[0])
        return foot[i]

    # the next board up of each plane: the nearest plane above within the rise that lies over it
    nxt: dict = {}
    for i, ups in above.items():
        qa, a0, a1, ca = seen_from_above(i)
        for j, dv in ups:
            qb, b0, b1, cb = seen_from_above(j)
            # footprints whose bounding boxes do not meet do not overlap
            if (min(a1[0], b1[0]) <= max(a0[0], b0[0])) or (min(a1[1], b1[1]) <= max(a0[1], b0[1])):
                continue
            # along the horizontal line between the centroids, footprints that overlap by
            # min_overlap of the smaller overlap by at least min_overlap / 2 of the shorter
            # extent (a convex footprint fills at least half of its extent times its width);
            # a staircase's next tread lies beyond the one below along that line
            u = cb - ca
            nu = math.hypot(float(u[0]), float(u[1]))
            if nu > 1e-9:
                ta, tb = qa @ (u / nu), qb @ (u / nu)
                span = min(float(ta.max()), float(tb.max())) - max(float(ta.min()), float(tb.min()))
                if span < 0.5 * min_overlap * min(float(np.ptp(ta)), float(np.ptp(tb))):
                    continue
            fa, fb = fp(i), fp(j)
            small = min(fa.area, fb.area)
            if small > 0 and fa.intersection(fb).area >= min_overlap * small:
                nxt[cands[i].label] = (cands[j].label, dv)
                break
    # stacks: chains of next boards, cut where a rise differs from the stack's first by more
    # than ``regular``
    out: set = set()
    has_lower = {v[0] for v in nxt.values()}
    for start in sorted(nxt):
        if start in has_lower:
            continue
        chain = [start]
        rises: list = []
        while chain[-1] in nxt:
            hi, dv = nxt[chain[-1]]
            chain.append(hi)
            rises.append(dv)
        seg = 0  # index in chain of the current stack's lowest board
        for k in range(1, len(chain) + 1):
            if k < len(chain) and (1 - regular) <= rises[k - 1] / rises[seg] <= 1 / (1 - regular):
                continue
            if k - seg >= min_boards:
                out.update(zip(chain[seg:k - 1], chain[seg + 1:k], strict=True))
            seg = k - 1
    return out
