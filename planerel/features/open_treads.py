"""Join the treads of an open-riser flight: thin slabs in a regular row that do not touch.

An open-riser staircase (floating treads, no risers: offices, industrial stairs, a rescue
arena's step field) shows each tread as a thin slab: its top, its front edge, from below its
underside.  No two treads share an edge, so each is a proposal of its own, and seen at range
(the PCL Kinect room, ``tutorials/pairwise/capture0001-0005``, 1.7-3 m: docs/objects.md "Open-riser
flights") the top and the front edge of a tread near the sensor's level are fitted as one
strip tilted 25-55 degrees from horizontal, so the step chains
(:func:`planerel.features.step_chains.step_chain_pairs`, treads within ``step_tilt`` of
horizontal) and the shelf boards (:func:`planerel.features.boards.stacked_board_pairs`) see no
row.  :func:`open_tread_pairs` takes any plane that is a *slab*: at most ``thick`` metres high
along ``up`` and at most ``tilt`` degrees from horizontal, wide across; it measures each
slab's *level* as the top of its hull (a front edge's top is its tread's top) and joins slabs
at regular levels, one rise apart (or two: a tread not segmented), overlapping across the
flight and following each other along it (each one's near edge no more than ``back`` metres
behind the one below it): three levels or more, as the step chains need three faces.

What it does not join: two boxes one behind the other (two levels), the faces of a desk
pedestal or a cabinet (vertical: over ``tilt``, and higher than ``thick``), a shelf's side
or back panel.  A shelf's boards are slabs at regular levels too, and are joined (as
:func:`~planerel.features.boards.stacked_board_pairs` already joins them when they are
horizontal): the rules tell a shelf from a staircase, the proposal does not.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.step_geometry import _cut_lengthwise, _tread_depth_axis
from planerel.features.vectors import cross3

__all__ = ["slab_level", "open_tread_pairs"]


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / max(float(np.linalg.norm(v)), 1e-12)


def slab_level(p, up) -> float:
    """The top of a plane's hull above the floor (metres): ``p.height`` (its centroid's) plus
    the hull's reach above its centroid along ``up`` ``(3,)``."""
    u = _unit(up)
    h = np.asarray(p.hull3d, float).reshape(-1, 3) @ u
    return float(p.height) + float(h.max()) - float(np.asarray(p.centroid, float) @ u)


def _slabs(planes, want, up, thick: float, tilt: float, min_width: float) -> list:
    cos_t = math.cos(math.radians(tilt))
    out = []
    for p in planes:
        if want and p.label not in want:
            continue
        if abs(float(np.asarray(p.normal, float) @ up)) < cos_t:
            continue
        # the hull lies in its length x width rectangle: no extent beyond its diagonal (an
        # exact early out for the many small planes of a table-top frame)
        if math.hypot(float(p.length), float(p.width)) < min_width:
            continue
        H = np.asarray(p.hull3d, float).reshape(-1, 3)
        if len(H) < 3 or float(np.ptp(H @ up)) > thick:
            continue
        hor = H - np.outer(H @ up, up)
        # the longest horizontal extent (its width across the flight, for a tread)
        d = hor[:, None, :] - hor[None, :, :]
        if float(np.sqrt((d * d).sum(-1)).max()) < min_width:
            continue
        out.append((p, slab_level(p, up), hor))
    return out


def _shallow(p, hor, up, run_max: float) -> bool:
    """A tread is one step deep: its horizontal extent across its depth axis at most
    ``run_max`` (not a landing, a floor the flight goes down to, a table top)."""
    da, _e = _tread_depth_axis(p, up)
    return float(np.ptp(hor @ da)) <= run_max


def open_tread_pairs(planes, labels=(), rise=(0.08, 0.30), run_max: float = 0.60,
                     thick: float = 0.15, tilt: float = 60.0, min_width: float = 0.3,
                     min_overlap: float = 0.5, back: float = 0.05, regular: float = 0.3,
                     max_ratio: float = 4.0) -> set:
    """Pairs of slabs that are consecutive treads of an open-riser flight (rows of >= 3 levels).

    Parameters
    ----------
    planes : PlaneSet
        With ``up``; each plane's ``hull3d`` ``(K, 3)``, ``normal``, ``centroid``, ``height``.
    labels : iterable of int
        The planes to consider (the non-support planes); empty = all.
    rise : (float, float)
        Metres: the range of one step's rise (a pair two rises apart is a step too).
    run_max : float
        Metres: the most a slab's near edge lies beyond the one below it (one step's run).
    thick, tilt, min_width : float
        A slab is at most ``thick`` m high along ``up``, at most ``tilt`` degrees from
        horizontal, and at least ``min_width`` m across (its longest horizontal extent).
    min_overlap : float
        The two slabs' extents across the flight (horizontal, perpendicular to the lower
        slab's depth axis) overlap by at least this (interval IoU).
    back : float
        Metres: the upper slab's near edge may lie at most this much *before* the lower one's
        (noise); the flight's direction is the one in which the row's near edges advance.
    regular : float
        The rises of two consecutive steps of a row agree within this fraction.
    max_ratio : float
        The two slabs' areas differ by at most this factor (one flight's treads are alike; a
        tread seen at a grazing angle shows less of itself).

    A slab is also at most ``run_max`` deep (its horizontal extent across its own depth
    axis): a landing, the floor a flight goes down to, a table top are no treads; nor is one
    the image border cuts along its length (``_cut_lengthwise`` of the step chains), nor one
    whose level lies within ``rise[0]`` of the floor's (a piece of the floor: a patch beside
    a carton pile made a row with two carton tops, pallet_b).

    Returns
    -------
    set of (int, int)
        ``(lower, upper)`` label pairs of the steps of rows of three levels or more.
    """
    up = _unit(planes.up)
    want = set(labels)
    # three tests of each slab alone, each keeping the others' order; a row needs three
    # slabs, so fewer left after any test is no row (an exact early out: the cheapest test
    # first, the depth axis of _shallow, 30-300 us a plane, only when a row is still possible)
    # a tread lies a rise or more above (or below) the floor: a slab at floor level is a piece
    # of the floor (a patch the segmentation tilted beside a carton pile), not a first step
    slabs = [s for s in _slabs(planes, want, up, thick, tilt, min_width) if abs(s[1]) >= rise[0]]
    if len(slabs) < 3:
        return set()
    slabs = [s for s in slabs if _shallow(s[0], s[2], up, run_max)]
    if len(slabs) < 3:
        return set()
    # a slab the image border cuts along its length (the floor or landing the camera stands
    # on, seen to the bottom edge) shows no depth: no tread (as in the step chains)
    cut = _cut_lengthwise([s[0] for s in slabs], True, getattr(planes, "labels", None))
    slabs = [s for s in slabs if s[0].label not in cut]
    if len(slabs) < 3:
        return set()
    slabs.sort(key=lambda s: (s[1], s[0].label))
    cos_dir = math.cos(math.radians(25.0))
    steps = []  # (lower label, upper label, rise per step, unit depth axis (signed), k)
    for i, (pa, la, ha) in enumerate(slabs):
        da, _ea = _tread_depth_axis(pa, up)
        across = cross3(up, da)
        for pb, lb, hb in slabs[i + 1:]:
            dv = lb - la
            if dv > 2 * rise[1]:
                break
            if max(pa.area, pb.area) > max_ratio * min(pa.area, pb.area):
                continue  # one flight's treads are alike
            k = next((k for k in (1, 2) if rise[0] <= dv / k <= rise[1]), None)
            if k is None:
                continue
            a0, a1 = float((ha @ across).min()), float((ha @ across).max())
            b0, b1 = float((hb @ across).min()), float((hb @ across).max())
            union = max(a1, b1) - min(a0, b0)
            if union <= 0 or (min(a1, b1) - max(a0, b0)) / union < min_overlap:
                continue
            ta, tb = ha @ da, hb @ da
            for sign in (1.0, -1.0):
                # near edges along the flight's direction (sign): the upper no more than
                # ``back`` before the lower one, no more than k runs beyond it
                near_a = float((sign * ta).min())
                near_b = float((sign * tb).min())
                adv = near_b - near_a
                if -back <= adv <= k * run_max:
                    steps.append((pa.label, pb.label, dv / k, sign * da, k))
    out = set()
    for s1 in steps:
        for s2 in steps:
            if s1[1] != s2[0]:
                continue
            if float(s1[3] @ s2[3]) < cos_dir:
                continue
            if not (1 - regular) <= s1[2] / s2[2] <= 1 / (1 - regular):
                continue
            out.add((s1[0], s1[1]))
            out.add((s2[0], s2[1]))
    return out
