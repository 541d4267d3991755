"""An open object seen over its near wall: the near wall's outside and the far wall's inside.

Seen from above its rim, an open box (a shelf seen from its side, a crate, a bin) shows the
*outside* of its near wall and, over that wall's rim, the *inside* of its far wall: two
parallel vertical faces turned the same way (towards the sensor), one behind the other by the
object's depth, their tops level (the rim all round), overlapping across.  They share no edge:
the near wall hides the bottom and the foot of the far wall (an occluding edge only), so no
cavity rule (:mod:`planerel.features.cavities`, whose channels need the faces turned towards
each other or a bottom between them) and no convexity test joins them: each wall was a
proposal of its own, the object found by neither.

**Rule** (:func:`open_wall_objects`, ``ProposalParams.open_walls``): two vertical planes of
different proposals join those proposals when they are parallel (within ``concave_tol``), the
far one lies ``WALL_DEPTH`` behind the near one along their normal, their tops are level
(within ``WALL_LEVEL`` at 1 m, scaled by the range), their extents across overlap by
``WALL_OVERLAP`` (interval IoU), each one's top is seen (at most ``TOP_CUT`` of its highest
points at the image's border: two faces cut by the border show no rim), no horizontal plane at
that level lies between them and neither wall's proposal holds one.  Two closed boxes one
behind the other, as high as each other, show the near one's top between the faces and the far
one's top on its proposal (mOSD ``test61``: a box's front behind a lower box's side); the open
object shows nothing but its thin rim.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.curved import CurvedObject
from planerel.features.vectors import cross3

__all__ = ["TOP_CUT", "WALL_DEPTH", "WALL_LEVEL", "WALL_OVERLAP", "open_wall_objects", "top_level"]

#: Metres: the far wall lies this far behind the near one along their normal (the object's
#: depth: a crate's 5 cm walls apart at least, a deep shelf's 0.6 m at most).
WALL_DEPTH = (0.05, 0.6)

#: Metres at 1 m (scaled by the far wall's range beyond 1 m): the two tops are level.
WALL_LEVEL = 0.05

#: Interval IoU of the two walls' extents across (along the horizontal in their plane).
WALL_OVERLAP = 0.5

#: Fraction: a wall's top is seen when at most this of its highest points (the top 5 % of its
#: heights) lie at the image's border.
TOP_CUT = 0.25


def _joined(members, curved_below):
    """One CurvedObject of the proposals ``members``: their planes and masks together."""
    total = sum(o.n_points for o in members)
    flat = sum(o.planar_fraction * o.n_points for o in members)
    mask = None
    for o in members:
        if o.mask is not None:
            mask = o.mask.copy() if mask is None else mask | o.mask
    frac = flat / total if total else 0.0
    return CurvedObject(tuple(sorted({x for o in members for x in o.planes})), mask,
                        float(frac), bool(frac < curved_below), int(total))


def join_groups(objects, pairs, curved_below) -> list:
    """``objects`` with the proposals that ``pairs`` (index pairs) link made one object each:
    the objects not joined, then one object per group."""
    parent = list(range(len(objects)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in pairs:
        parent[root(i)] = root(j)
    groups: dict = {}
    for k in range(len(objects)):
        groups.setdefault(root(k), []).append(k)
    groups = [g for g in groups.values() if len(g) > 1]
    if not groups:
        return objects
    taken = {k for g in groups for k in g}
    out = [o for k, o in enumerate(objects) if k not in taken]
    out += [_joined([objects[k] for k in g], curved_below) for g in groups]
    return out


def open_wall_objects(planes, objects, params, curved_below: float = 0.8, xyz=None) -> list:
    """The proposals with each open object's near and far walls made one (the module's rule).

    Parameters
    ----------
    planes : PlaneSet
        With ``labels`` (the label image) for the tops' border test.
    objects : sequence of CurvedObject
    params : ProposalParams
        ``open_walls`` (False = off), ``concave_tol``.
    curved_below : float
        ``CurvedParams.curved_below``: a joined object is curved below this planar fraction.
    xyz : ndarray, shape (H, W, 3), optional
        The organized points; without them nothing is joined.

    Returns
    -------
    list of CurvedObject
        ``objects`` itself when nothing is joined.
    """
    lab = getattr(planes, "labels", None)
    if (not params.open_walls or xyz is None or len(objects) < 2 or lab is None
            or lab.shape != xyz.shape[:2]):
        return objects
    owner = {x: k for k, o in enumerate(objects) for x in o.planes}
    verts = [p for p in planes if p.orientation == "vertical" and p.label in owner]
    if len(verts) < 2:
        return objects
    cos_par = math.cos(math.radians(params.concave_tol))
    normals = np.array([np.asarray(p.normal, float) for p in verts])
    own = np.array([owner[p.label] for p in verts])
    # a cheap first test of every pair at once: only pairs of two proposals whose normals
    # come within a hair of parallel are looked at one by one (the exact test below decides,
    # as before), in the order of the walls and then of the other walls
    near = (normals @ normals.T >= cos_par - 1e-9) & (own[:, None] != own[None, :])
    cand_i, cand_j = np.nonzero(near)
    if not len(cand_i):
        return objects
    up = np.asarray(planes.up, float)
    flats = [p for p in planes if p.orientation == "horizontal"]
    byl = {p.label: p for p in planes}
    seen: dict = {}

    def top_seen(p) -> bool:
        if p.label not in seen:
            seen[p.label] = top_level(lab, xyz, up, p.label)[1]
        return seen[p.label]

    pairs = []
    i_at = -1
    for i, j in zip(cand_i.tolist(), cand_j.tolist(), strict=True):
        if i != i_at:
            # the near wall's own measures, taken once for all its pairs (when one needs them)
            i_at, a, na, da, geom = i, verts[i], normals[i], None, None
        b = verts[j]
        if float(na @ normals[j]) < cos_par:
            continue  # not parallel, or turned the other way
        if da is None:
            da = abs(float(na @ np.asarray(a.centroid, float)))
        cb = np.asarray(b.centroid, float)
        depth = abs(float(na @ cb)) - da
        if not WALL_DEPTH[0] <= depth <= WALL_DEPTH[1]:
            continue  # b is not behind a
        if geom is None:
            ha = np.asarray(a.hull3d, float)
            ta = float((ha @ up).max())
            across = cross3(up, na)
            norm = float(np.linalg.norm(across))
            if norm == 0:
                geom = False
            else:
                across = across / norm
                geom = (ta, across, float((ha @ across).min()), float((ha @ across).max()))
        if geom is False:
            continue
        ta, across, a0, a1 = geom
        hb = np.asarray(b.hull3d, float)
        tol = WALL_LEVEL * max(1.0, float(np.linalg.norm(cb)))
        if abs(ta - float((hb @ up).max())) > tol:
            continue
        b0, b1 = float((hb @ across).min()), float((hb @ across).max())
        inter = min(a1, b1) - max(a0, b0)
        if inter <= 0 or inter / (max(a1, b1) - min(a0, b0)) < WALL_OVERLAP:
            continue
        if any(_top_between(f, up, na, da, depth, ta, tol, across, a0, a1) for f in flats):
            continue  # a closed box's top: two boxes one behind the other
        if any(abs(float(np.asarray(byl[x].centroid, float) @ up) - ta) <= tol
               for x in (*objects[owner[a.label]].planes, *objects[owner[b.label]].planes)
               if byl[x].orientation == "horizontal"):
            continue  # a wall with a top of its own at that level: a closed box's face
        if not (top_seen(a) and top_seen(b)):
            continue
        pairs.append((owner[a.label], owner[b.label]))
    return join_groups(objects, pairs, curved_below) if pairs else objects


def top_level(lab, xyz, up, label: int) -> tuple[float | None, bool]:
    """``(level, seen)`` of the plane ``label``'s top: the 95th percentile of its points'
    heights along ``up`` (None with no finite point), and whether that top is seen (at most
    :data:`TOP_CUT` of its points at or over that level lie within a pixel of the image's
    border: a face the border cuts shows no top).

    Parameters
    ----------
    lab : ndarray (H, W) int
        The label image.
    xyz : ndarray (H, W, 3)
        The organized points.
    up : ndarray (3,)
    label : int
    """
    H, W = lab.shape
    r, c = np.nonzero(lab == label)
    h = xyz[r, c] @ up
    ok = np.isfinite(h)
    r, c, h = r[ok], c[ok], h[ok]
    if not len(h):
        return None, False
    level = float(np.percentile(h, 95.0))
    hi = h >= level
    edge = (r[hi] <= 1) | (r[hi] >= H - 2) | (c[hi] <= 1) | (c[hi] >= W - 2)
    return level, float(edge.mean()) <= TOP_CUT


def _top_between(f, up, na, da, depth, level, tol, across, a0, a1) -> bool:
    """Horizontal plane ``f`` at ``level`` (within ``tol``) lies between the near wall (at
    ``da`` along ``na``) and the far one (``depth`` behind it), across the near wall's extent."""
    cf = np.asarray(f.centroid, float)
    if abs(float(cf @ up) - level) > tol:
        return False
    d = abs(float(na @ cf)) - da
    if not -0.02 <= d <= depth + 0.02:
        return False
    hf = np.asarray(f.hull3d, float) @ across
    return min(a1, float(hf.max())) - max(a0, float(hf.min())) > 0
