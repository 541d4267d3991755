"""One tread seen as several coplanar pieces side by side, taken whole for the step tests.

A tread the segmentation leaves in two or three pieces along its length (a gap of missing
depth across it, a rail's post, the far end of a long tread at low resolution) fails the
step tests piece by piece: a piece spans half the flight's width, so its extent across the
flight overlaps the whole tread below it by under half (dev_sr i0008: 0.48), and its area is
a third of that tread's.  :func:`tread_unions` finds such pieces and gives their union as one
plane; :func:`planerel.features.relations.step_chain_pairs` tests steps with the union and
names each piece in the pairs it returns.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from planerel.features.step_geometry import _horizontal_basis, _tread_depth_axis

__all__ = ["tread_unions", "PIECE_RISE", "PIECE_GAP", "PIECE_DEPTH"]

#: Metres: two pieces of one tread lie level with each other within this (a step rises 8 cm
#: at least; a piece's height is a plane fit's, within a centimetre of the other's)
PIECE_RISE = 0.03
#: Metres: the gap between two pieces along the tread's length (dev_sr i0008: 0.15 of
#: missing depth between two pieces of a 1.18 m tread)
PIECE_GAP = 0.25
#: Their extents across the tread's length (along the step direction) overlap by at least
#: this (interval IoU): one strip, not one tread behind the other
PIECE_DEPTH = 0.5
#: Their extents along the tread's length overlap by at most this share of the shorter one's:
#: side by side, not one over the other
PIECE_SIDE = 0.1


def _interval(H, axis) -> tuple[float, float]:
    v = H @ axis
    return float(v.min()), float(v.max())


def _pieces(a, b, up, cos_tol: float) -> bool:
    """True when the treads ``a`` and ``b`` lie as two pieces of one tread side by side."""
    if abs(a.height - b.height) > PIECE_RISE:
        return False
    if abs(float(np.asarray(a.normal, float) @ np.asarray(b.normal, float))) < cos_tol:
        return False
    big = a if a.area >= b.area else b
    depth, elong = _tread_depth_axis(big, up)
    if elong <= 0:
        return False
    length = np.cross(np.asarray(up, float), depth)
    Ha, Hb = np.asarray(a.hull3d, float), np.asarray(b.hull3d, float)
    (a0, a1), (b0, b1) = _interval(Ha, depth), _interval(Hb, depth)
    union = max(a1, b1) - min(a0, b0)
    if union <= 0 or (min(a1, b1) - max(a0, b0)) / union < PIECE_DEPTH:
        return False
    (a0, a1), (b0, b1) = _interval(Ha, length), _interval(Hb, length)
    gap = max(a0, b0) - min(a1, b1)  # > 0: apart; < 0: overlapping by -gap
    return -PIECE_SIDE * min(a1 - a0, b1 - b0) <= gap <= PIECE_GAP


def _union(group, up, label: int):
    """One plane standing for the pieces ``group`` (a list of Plane): the horizontal convex
    hull of their hulls, their areas summed, centroid and height weighted by area; None when
    the hull is degenerate."""
    from scipy.spatial import ConvexHull, QhullError

    pts = np.concatenate([np.asarray(p.hull3d, float) for p in group])
    e1, e2 = _horizontal_basis(up)
    flat = np.stack([pts @ e1, pts @ e2], 1)
    try:
        order = ConvexHull(flat).vertices  # counter-clockwise
    except (QhullError, ValueError):
        return None
    w = np.array([p.area for p in group], float)
    if w.sum() <= 0:
        return None
    big = group[int(np.argmax(w))]
    normals = np.array([np.asarray(p.normal, float) for p in group])
    normals *= np.sign(normals @ np.asarray(big.normal, float))[:, None]
    normal = (w[:, None] * normals).sum(0)
    normal /= np.linalg.norm(normal)
    centroid = (w[:, None] * np.array([np.asarray(p.centroid, float) for p in group])).sum(0) / w.sum()
    hull3d = pts[order]
    depth, _ = _tread_depth_axis(big, up)
    length = np.cross(np.asarray(up, float), depth)
    boxes = np.array([p.bbox for p in group])
    return dataclasses.replace(
        big, label=label, n_points=int(sum(p.n_points for p in group)), normal=normal,
        centroid=centroid, hull3d=hull3d, area=float(w.sum()),
        height=float((w * [p.height for p in group]).sum() / w.sum()),
        length=float(np.ptp(hull3d @ length)), width=float(np.ptp(hull3d @ depth)),
        bbox=(int(boxes[:, 0].min()), int(boxes[:, 1].min()), int(boxes[:, 2].max()),
              int(boxes[:, 3].max())),
        touches_border=any(p.touches_border for p in group))


def tread_unions(treads, up, cos_tol: float, first_label: int) -> dict:
    """Groups of treads lying as pieces of one tread side by side, each as one plane.

    Two treads are pieces of one when they lie level within :data:`PIECE_RISE`, their
    normals agree within ``cos_tol`` (a cosine), their extents along the larger one's step
    direction (:func:`~planerel.features.step_geometry._tread_depth_axis`) overlap by
    :data:`PIECE_DEPTH` (interval IoU) and along its length they lie side by side: a gap of at
    most :data:`PIECE_GAP`, an overlap of at most :data:`PIECE_SIDE` of the shorter one's
    extent.  Groups are the connected sets of such pairs.

    Parameters
    ----------
    treads : sequence of Plane
        Level faces (the step candidates that are treads).
    up : ndarray, shape (3,)
    cos_tol : float
        The cosine two pieces' normals reach at least.
    first_label : int
        The label of the first union; the next take the following integers (labels no
        plane of the scene has).

    Returns
    -------
    dict
        ``{label: (union Plane, tuple of the pieces' labels)}``, in the order of the
        pieces' first labels.
    """
    treads = list(treads)
    n = len(treads)
    if n < 2:
        return {}
    root = list(range(n))

    def find(i):
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    for i in range(n):
        for j in range(i + 1, n):
            if _pieces(treads[i], treads[j], up, cos_tol):
                root[find(j)] = find(i)
    groups: dict = {}
    for i in range(n):
        groups.setdefault(find(i), []).append(treads[i])
    out: dict = {}
    label = first_label
    for members in groups.values():
        if len(members) < 2:
            continue
        u = _union(members, up, label)
        if u is None:
            continue
        out[label] = (u, tuple(p.label for p in members))
        label += 1
    return out
