"""One tread seen as several coplanar pieces side by side, taken whole for the step tests.

A tread the segmentation leaves in two or three pieces along its length (a gap of missing
depth across it, a rail's post, the far end of a long tread at low resolution) fails the step
tests piece by piece: a piece spans half the flight's width, so its extent across the flight
overlaps the whole tread below it by under half (dev_sr i0008: 0.48), and its area is a third
of that tread's.  :func:`tread_unions` finds such pieces and gives their union as one plane;
:func:`planerel.features.step_chains.step_chain_pairs` tests steps with the union and names the
pieces in the pairs it returns.

Risers were tested the same way too (a riser's length and up as its frame) and left out: no
line of the main check moved, they were nine in ten of the pairs tested on the shared frames
(a room's upright faces are many and parallel), and flush carton fronts in a row would make
one "riser" of them.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from planerel.features.components import Components
from planerel.features.step_geometry import _extent, _tread_depth_axis
from planerel.features.vectors import cross3, vec_norm

__all__ = ["tread_unions", "PIECE_LEVEL", "PIECE_GAP", "PIECE_DEPTH", "PIECE_SIDE",
           "PIECE_SHARE"]

#: Metres: two pieces of one tread lie level within this (a step rises 8 cm at least, a
#: piece's plane fit is within a centimetre of the other's)
PIECE_LEVEL = 0.03
#: Metres: the gap between two pieces along the tread's length (dev_sr i0008: 0.15 of missing
#: depth between two pieces of a 1.18 m tread)
PIECE_GAP = 0.25
#: Their extents along the step direction overlap by at least this (interval IoU): one strip,
#: not one tread behind the other
PIECE_DEPTH = 0.5
#: Their extents along the tread's length overlap by at most this share of the shorter one's:
#: side by side, not one over the other
PIECE_SIDE = 0.1
#: Each is at least this share of the two's summed length: pieces, not a tread and a sliver
#: beside it (active-stereo treads break into strips a tenth as long, dev_sts i0028)
PIECE_SHARE = 0.25


def _axes(tread, up) -> tuple[np.ndarray, np.ndarray] | None:
    """The tread's ``(length, depth)`` unit axes ``(3,)``: its step direction
    (:func:`~planerel.features.step_geometry._tread_depth_axis`) and the level line across it
    (along the nosing).  None for a degenerate tread."""
    up = np.asarray(up, float)
    depth, elong = _tread_depth_axis(tread, up)
    if elong <= 0:
        return None
    length = cross3(up, depth)
    norm = vec_norm(length)
    if norm < 1e-6:
        return None
    return length / norm, depth


#: Verdicts and unions already computed, keyed by the Plane objects themselves (identity: a
#: scene's step chains ask the same faces four or five times, over other label subsets);
#: emptied past :data:`_MEMO_SIZE` entries.
_MEMO: dict = {}
_MEMO_SIZE = 4096


def _remembered(key, make):
    """``_MEMO[key]``, made by ``make()`` the first time."""
    if key not in _MEMO:
        if len(_MEMO) >= _MEMO_SIZE:
            _MEMO.clear()
        _MEMO[key] = make()
    return _MEMO[key]


def _pieces(a, b, cos_tol: float, axes_of) -> bool:
    """True when the treads ``a`` and ``b`` lie as two pieces of one tread side by side
    (``axes_of(tread)``: :func:`_axes`, remembered a tread).  The tests on Python floats come
    first: most pairs of a scene fail the level or the normals."""
    if abs(a.height - b.height) > PIECE_LEVEL:
        return False
    na, nb = a.normal, b.normal
    if abs(float(na[0]) * float(nb[0]) + float(na[1]) * float(nb[1])
           + float(na[2]) * float(nb[2])) < cos_tol:
        return False
    axes = axes_of(a if a.area >= b.area else b)
    if axes is None:
        return False
    length, depth = axes
    (a0, a1), (b0, b1) = _extent(a, depth), _extent(b, depth)
    union = max(a1, b1) - min(a0, b0)
    if union <= 0 or (min(a1, b1) - max(a0, b0)) / union < PIECE_DEPTH:
        return False
    (a0, a1), (b0, b1) = _extent(a, length), _extent(b, length)
    short = min(a1 - a0, b1 - b0)
    if short < PIECE_SHARE * ((a1 - a0) + (b1 - b0)):
        return False
    gap = max(a0, b0) - min(a1, b1)  # > 0: apart; < 0: overlapping by -gap
    return -PIECE_SIDE * short <= gap <= PIECE_GAP


def _union(group, label: int, axes_of):
    """One plane standing for the pieces ``group`` (a list of Plane): the convex hull of their
    hulls in the larger piece's ``(length, depth)`` frame (``axes_of``, as :func:`_pieces`),
    their areas summed, centroid and height weighted by area; None when the hull is
    degenerate."""
    from scipy.spatial import ConvexHull, QhullError

    w = np.array([p.area for p in group], float)
    if w.sum() <= 0:
        return None
    big = group[int(np.argmax(w))]
    axes = axes_of(big)
    if axes is None:
        return None
    length, depth = axes
    pts = np.concatenate([np.asarray(p.hull3d, float) for p in group])
    try:
        order = ConvexHull(np.stack([pts @ length, pts @ depth], 1)).vertices
    except (QhullError, ValueError):
        return None
    normals = np.array([np.asarray(p.normal, float) for p in group])
    normals *= np.sign(normals @ np.asarray(big.normal, float))[:, None]
    normal = (w[:, None] * normals).sum(0)
    normal /= np.linalg.norm(normal)
    centroid = (w[:, None] * np.array([np.asarray(p.centroid, float) for p in group])).sum(0) \
        / w.sum()
    hull3d = pts[order]
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

    Two treads are pieces of one when they lie level within :data:`PIECE_LEVEL`, their normals
    agree within ``cos_tol`` (a cosine), their extents along the larger one's step direction
    overlap by :data:`PIECE_DEPTH` (interval IoU), and along its length they lie side by side:
    a gap of at most :data:`PIECE_GAP`, an overlap of at most :data:`PIECE_SIDE` of the
    shorter one's extent, each at least :data:`PIECE_SHARE` of the two's summed length.
    Groups are the connected sets of such pairs
    (:class:`~planerel.features.components.Components`).

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
        ``{label: (union Plane, tuple of the pieces' labels, the largest by area first)}``, in
        the order of the pieces' first labels.
    """
    faces = list(treads)
    n = len(faces)
    if n < 2:
        return {}
    upkey = np.asarray(up, float).tobytes()

    def axes_of(face):
        return _remembered(("axes", face, upkey), lambda: _axes(face, up))

    g = Components(range(n))
    g.add_edges((i, j) for i in range(n) for j in range(i + 1, n)
                if _remembered(("pair", faces[i], faces[j], cos_tol, upkey),
                               lambda a=faces[i], b=faces[j]: _pieces(a, b, cos_tol, axes_of)))
    out: dict = {}
    label = first_label
    for group in g.groups():
        members = [faces[i] for i in group]
        if len(members) < 2:
            continue
        u = _remembered(("union", tuple(members), label, upkey),
                        lambda m=members, k=label: _union(m, k, axes_of))
        if u is None:
            continue
        big_first = sorted(members, key=lambda p: (-p.area, p.label))
        out[label] = (u, tuple(p.label for p in big_first))
        label += 1
    return out
