"""Where a sloping plane's low end lies: on the floor, above it in plain view, or under it.

A ramp is a walked-on slope that rises from the floor: the low end of its slope meets the floor
(the floor's level, :attr:`planerel.features.planes.PlaneSet.floor_level`).  Real rooms show
inclined planes that no floor leads onto: the top of a sofa's back, a far table top the sensor
bends by 27 degrees, a far shelf (their low edge 0.3-0.8 m over the floor, nothing in front of
it), and far floor strips that a structured-light sensor bends through the floor (reaching 0.1 m
under it).  :func:`slope_foot` measures a plane's low end; the decision's foot gate
(:func:`planerel.ilp.metrics.foot_refusals`) refuses ``ramp`` for a proof whose sloping plane
stands on no floor.

The low end may be out of sight: cut by the image border, next to pixels with no depth, or
behind a nearer surface (the truncation test of :func:`planerel.features.facts.truncated_planes`:
a valid point within ``band`` pixels nearer by more than ``jump * max(1, range)``).  Then the
plane may go on down to the floor behind, and its seen low end says nothing.  Without a floor
in the scene nothing is measured.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Foot", "slope_foot", "FOOT_BAND", "FOOT_FRONT", "FOOT_PERCENTILE"]

#: Metres: the plane's points within this height of its lowest point make its low end.
FOOT_BAND = 0.05
#: Metres (times the range, at least 1 m) a point must lie on the sensor's side of the plane to
#: hide it (:func:`slope_foot`'s ``front``).
FOOT_FRONT = 0.03
#: Percentile of the plane's point heights taken as its lowest point (a few flying pixels at
#: an edge do not decide it).
FOOT_PERCENTILE = 1.0


@dataclass(frozen=True)
class Foot:
    """A plane's low end.

    Attributes
    ----------
    low : float
        Height of the plane's lowest point above the floor's level, metres (negative: under it).
    hidden : float
        Share (0..1) of the low end's outline pixels that are out of sight: within ``band``
        pixels of the image border, of a pixel with no depth, or of a surface in front.
    pixels : int
        Outline pixels of the low end (the plane's pixels within ``FOOT_BAND`` of its lowest
        point with a 4-neighbour outside it).
    depth : float
        Median range of the low end's points, metres.
    """

    low: float
    hidden: float
    pixels: int
    depth: float


def slope_foot(planes, label: int, xyz, *, labels=None, band: int = 2, jump: float = 0.05,
               front: float = FOOT_FRONT, foot_band: float = FOOT_BAND) -> Foot | None:
    """The low end of plane ``label`` of ``planes`` (a :class:`~planerel.features.planes.PlaneSet`
    whose ``labels`` is the label image of the organized points ``xyz``).

    Parameters
    ----------
    planes : PlaneSet
        Its ``up``, ``floor_level`` and ``labels`` are read.
    label : int
        The plane's label.
    xyz : ndarray, shape (H, W, 3)
        Organized points, NaN (or z <= 0) where there is no depth.
    labels : ndarray, shape (H, W), optional
        The label image the plane's label indexes (a scene description's ``labels``: split
        stepped planes' levels); ``planes.labels`` when not given.
    band : int
        Pixels around a low-end pixel looked at for the image border, missing depth or a
        nearer surface (``TRUNC_BAND`` of :mod:`planerel.features.facts`).
    jump : float
        A point nearer the sensor by more than ``jump * max(1, range)`` hides the plane
        (``TRUNC_JUMP``).
    front : float
        So does a point of another plane (or of none) lying on the sensor's side of the
        plane by more than ``front * max(1, range)`` metres: a block's top edge right before
        a slope's low end is hardly nearer than the slope, but it stands in front of it.
    foot_band : float
        Metres over the lowest point that count as the low end.

    Returns
    -------
    Foot or None
        None when the scene has no floor (heights then count from the lowest support, which
        may be a wall's foot far over a ramp's), the plane has no valid point or the shapes
        do not match.
    """
    if planes.floor is None:
        return None
    lab = np.asarray(planes.labels if labels is None else labels)
    pts = np.asarray(xyz, dtype=np.float64)
    if lab.ndim != 2 or pts.shape != lab.shape + (3,):
        return None
    mask = lab == int(label)
    z = pts[..., 2]
    valid = np.isfinite(z) & (z > 0)
    mask &= valid
    if not mask.any():
        return None
    up = np.asarray(planes.up, dtype=np.float64)
    plane = planes.by_label(int(label))
    normal, offset = np.asarray(plane.normal, dtype=np.float64), float(plane.offset)
    rows, cols = np.nonzero(mask)
    heights = pts[rows, cols] @ up - float(planes.floor_level)
    low = float(np.percentile(heights, FOOT_PERCENTILE))
    # the low end's outline: its pixels with a 4-neighbour outside the plane (or the image)
    H, W = lab.shape
    inner = np.zeros_like(mask)
    inner[1:-1, 1:-1] = (mask[1:-1, 1:-1] & mask[:-2, 1:-1] & mask[2:, 1:-1]
                         & mask[1:-1, :-2] & mask[1:-1, 2:])
    sel = (heights <= low + foot_band) & ~inner[rows, cols]
    rows, cols = rows[sel], cols[sel]
    rng = np.linalg.norm(pts[rows, cols], axis=1)
    hidden = np.zeros(rows.size, bool)
    # within ``band`` pixels of the image border
    hidden |= (rows < band) | (rows >= H - band) | (cols < band) | (cols >= W - band)
    for dr in range(-band, band + 1):
        for dc in range(-band, band + 1):
            if dr == 0 and dc == 0:
                continue
            r2, c2 = rows + dr, cols + dc
            inside = (r2 >= 0) & (r2 < H) & (c2 >= 0) & (c2 < W)
            r2c, c2c = np.clip(r2, 0, H - 1), np.clip(c2, 0, W - 1)
            nv = valid[r2c, c2c]
            # no depth next to the low end: what lies there is not seen
            hidden |= inside & ~nv
            # a nearer point of another plane (or of none), or one in front of the plane
            other = pts[r2c, c2c]
            scale = np.maximum(1.0, rng)
            near = nv & (lab[r2c, c2c] != int(label)) & (
                (np.linalg.norm(other, axis=1) < rng - jump * scale)
                | (other @ normal + offset > front * scale))
            hidden |= inside & near
    return Foot(low, float(hidden.mean()) if hidden.size else 0.0, int(rows.size),
                float(np.median(rng)) if rng.size else 0.0)
