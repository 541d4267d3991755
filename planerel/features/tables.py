"""A table standing in the room: its top is support for what stands on it and an object too.

:func:`~planerel.features.proposals.support_planes` makes a table top seen with the room's floor
in view support (``ProposalParams.table_area``): what stands on it is proposed apart, as on the
floor.  The table itself is then in no proposal, though it is an object in the room (a robot
walks around it, a chair is pushed under it).  This module gives it back its proposal without
taking the top's support role away (``ProposalParams.table_legs``):

1. **Tables.**  The horizontal support planes at least ``table_height`` above the floor and
   under ``support_min_area`` (only :func:`~planerel.features.proposals.support_planes`' table
   rule makes such planes support), grouped by their plane (within ``floor_gap``: a top cut in
   pieces by the objects on it); a group whose largest plane has ``table_area`` or more is a
   table top.
2. **What is under it.**  An object proposal all of whose planes, and the points of its
   unexplained pixels, lie under the top (their highest point at most ``edge_depth`` above the
   top's level and at most ``TABLE_REACH`` below it, their centre within ``TABLE_MARGIN`` of the
   outline of the top's largest plane seen from above): the top's edge faces, an apron, legs.
   What stands on the top rises above it; a box stored low under the table does not reach up
   to it.
3. **Standing in the room.**  When a leg or an apron is among them (a vertical plane reaching
   at least ``table_legs`` below the top, deeper than a top's edge; or a connected part of
   unexplained pixels (4-neighbours within ``edge_depth`` in 3-D), at least ``MIN_LEG_PIXELS``, that reaches as far and is taller than it
   is wide: a post), the top, its pieces within its outline and those proposals are one
   object, which takes their places.  A top whose legs and apron are out of view (a table-top
   frame seen from close by) stays support only.
"""

from __future__ import annotations

import numpy as np

from planerel.features.curved import CurvedObject
from planerel.features.open_walls import join_groups
from planerel.features.proposals import _floor_offset
from planerel.features.step_geometry import _horizontal_basis

__all__ = ["MIN_LEG_PIXELS", "POST_HEIGHT", "POST_LEVEL", "POST_SLICE", "POST_WIDTH", "TABLE_MARGIN", "TABLE_REACH",
           "leg_objects", "table_objects"]

#: Metres: a plane under a table top has its centroid within this of the top's outline, seen
#: from above (the top's edge faces lie on the outline, its legs inside it).
TABLE_MARGIN = 0.05

#: Metres: a plane under a table top reaches up to within this of the top's level (a leg or an
#: apron meets the top's underside; the top is 2-5 cm thick).
TABLE_REACH = 0.15


#: Pixels: the fewest of a part of unexplained pixels that counts as a leg.
MIN_LEG_PIXELS = 10


def _table_groups(planes, support, params) -> list[list]:
    """Groups of the table tops' support planes (step 1), each ordered largest first."""
    up = np.asarray(planes.up, float)
    byl = {p.label: p for p in planes}
    flat = sorted((byl[s] for s in support if s in byl and byl[s].orientation == "horizontal"
                   and byl[s].height >= params.table_height
                   and byl[s].area < params.support_min_area),
                  key=lambda p: (-p.area, p.label))
    groups: list[list] = []
    for p in flat:
        for g in groups:
            if _floor_offset(p, g[0], up) <= params.floor_gap:
                g.append(p)
                break
        else:
            groups.append([p])
    return [g for g in groups if g[0].area >= params.table_area]


class _Top:
    """One table top: its level along ``up`` and its outline seen from above."""

    def __init__(self, top, up, e1, e2, params):
        from scipy.spatial import ConvexHull

        self.up, self.e1, self.e2, self.params = up, e1, e2, params
        self.level = float(np.asarray(top.centroid, float) @ up)
        hull = np.asarray(top.hull3d, float)
        self.eq = ConvexHull(np.stack([hull @ e1, hull @ e2], 1)).equations  # unit normals

    def inside(self, c) -> bool:
        """Point ``c`` within ``TABLE_MARGIN`` of the outline, seen from above."""
        c = np.asarray(c, float)
        return float((self.eq @ np.array([c @ self.e1, c @ self.e2, 1.0])).max()) <= TABLE_MARGIN

    def under(self, heights, centre) -> bool:
        """Points (their heights along up, their centre) under the top: reaching up to within
        ``TABLE_REACH`` of it, no higher than ``edge_depth`` above it, centred in its outline."""
        top = float(np.max(heights))
        return (self.level - TABLE_REACH <= top <= self.level + self.params.edge_depth
                and self.inside(centre))

    def reaches(self, heights) -> bool:
        """Their lowest point at least ``table_legs`` below the top."""
        return self.level - float(np.min(heights)) >= self.params.table_legs

    def plane(self, q) -> tuple[bool, bool]:
        """(under the top, a leg or apron: vertical and reaching) for plane ``q``."""
        h = np.asarray(q.hull3d, float) @ self.up
        ok = self.under(h, q.centroid)
        return ok, ok and q.orientation == "vertical" and self.reaches(h)

    def post(self, pts) -> bool:
        """A leg among unexplained points: under the top, reaching, taller than it is wide."""
        h = pts @ self.up
        wide = max(float(np.ptp(pts @ self.e1)), float(np.ptp(pts @ self.e2)))
        return self.under(h, pts.mean(0)) and self.reaches(h) and float(np.ptp(h)) >= wide

    def mask(self, m, xyz) -> tuple[bool, bool]:
        """(under the top, a leg among its connected parts) for the pixels of mask ``m``."""
        from planerel.features._curved_kernels import list_components

        rows, cols = np.nonzero(m)
        pts = xyz[rows, cols]
        fin = np.isfinite(pts).all(1)
        if not fin.any() or not self.under(pts[fin] @ self.up, pts[fin].mean(0)):
            return False, False
        # the parts as the curved stage numbers its clusters (4-neighbours within edge_depth)
        ids, n = list_components(rows, cols, xyz, float(self.params.edge_depth), m.shape[0])
        for k in range(int(n)):
            q = pts[(ids == k) & fin]
            if len(q) >= MIN_LEG_PIXELS and self.post(q):
                return True, True
        return True, False


def table_objects(planes, support, objects, params, curved_below: float = 0.8, xyz=None) -> list:
    """The proposals with each table standing in the room made one object (the module's rule).

    Parameters
    ----------
    planes : PlaneSet
    support : iterable of int
        Support plane labels (:func:`~planerel.features.proposals.support_planes`).
    objects : sequence of CurvedObject
        The proposals (:func:`~planerel.features.curved.curved_objects`, raised and joined parts
        included).
    params : ProposalParams
        ``table_legs`` (0 = off), ``table_area``, ``table_height``, ``support_min_area``,
        ``floor_gap``, ``edge_depth``.
    curved_below : float
        ``CurvedParams.curved_below``: the table's object is curved below this planar fraction.
    xyz : ndarray, shape (H, W, 3), optional
        The organized points: an object with unexplained pixels (a leg no plane explains) is
        judged by their points as well; without them such objects are never taken.

    Returns
    -------
    list of CurvedObject
        ``objects`` itself when no table stands in view; else the objects not taken, then one
        object per table (its top's planes and the proposals under it, their masks joined).
    """
    from scipy.spatial import QhullError

    if params.table_legs <= 0 or not objects:
        return objects
    groups = _table_groups(planes, support, params)
    if not groups:
        return objects
    up = np.asarray(planes.up, float)
    e1, e2 = _horizontal_basis(up)
    byl = {p.label: p for p in planes}
    objects = list(objects)
    taken: set = set()
    tables = []
    for g in groups:
        try:
            top = _Top(g[0], up, e1, e2, params)
        except (QhullError, ValueError):
            continue
        mine, legs = [], False
        for k, o in enumerate(objects):
            if k in taken or not (o.planes or o.mask is not None):
                continue
            if not all(x in byl for x in o.planes):
                continue
            judged = [top.plane(byl[x]) for x in o.planes]
            if o.mask is not None:
                if xyz is None:
                    continue
                judged.append(top.mask(o.mask, xyz))
            if all(ok for ok, _ in judged):
                mine.append(k)
                legs = legs or any(leg for _, leg in judged)
        if not legs:
            continue
        taken.update(mine)
        # the top's pieces within its outline (a plane at its level beyond it, a chair's seat
        # pushed to the table, is not the top)
        tables.append(([g[0], *(p for p in g[1:] if top.inside(p.centroid))], mine))
    if not tables:
        return objects
    out = [o for k, o in enumerate(objects) if k not in taken]
    for g, mine in tables:
        top_pts = sum(p.n_points for p in g)
        n_flat = top_pts + sum(objects[k].planar_fraction * objects[k].n_points for k in mine)
        total = top_pts + sum(objects[k].n_points for k in mine)
        mask = None
        for k in mine:
            m = objects[k].mask
            if m is not None:
                mask = m.copy() if mask is None else mask | m
        frac = n_flat / total if total else 0.0
        members = tuple(sorted({p.label for p in g} | {x for k in mine for x in objects[k].planes}))
        out.append(CurvedObject(members, mask, float(frac), bool(frac < curved_below), int(total)))
    return out


#: Metres: a post (a leg seen without its top) is at most this wide across (its points' 5th to
#: 95th percentile along two horizontal axes; a table's leg 5 cm, a chair's 3.5 cm).
POST_WIDTH = 0.08

#: Metres: a post is at least this tall (5th to 99th percentile of its heights) and three times
#: as tall as it is wide.
POST_HEIGHT = 0.25

#: Metres at 1 m (scaled by the post's range beyond 1 m): a post stands on the floor when its
#: lowest point lies within this of the floor's plane; two posts are level when their tops are.
POST_LEVEL = 0.05

#: Metres: a post's top is where its column, in slices this high from its middle up, first
#: grows wider than 1.5 ``POST_WIDTH`` (its seen top when it never does).
POST_SLICE = 0.05


def _post(pts, up, e1, e2, floor_level) -> float | bool | None:
    """The top's height above the floor of the post the points ``pts`` (N, 3) of one proposal
    or one part of it make; False when they make none, and None when no part of them can
    (they span less than ``POST_HEIGHT`` or their lowest point is off the floor)."""
    h = pts @ up
    lo_h = float(h.min())
    sq = (pts * pts).sum(1)
    # necessary, and cheap: the percentile spans below are no longer than the whole ones, the
    # median range no farther than the farthest point
    if (float(h.max()) - lo_h < POST_HEIGHT
            or lo_h - floor_level > POST_LEVEL * max(1.0, float(np.sqrt(sq.max())))):
        return None  # nor a part of them: each would span less, or lie higher, or be nearer
    a, b = pts @ e1, pts @ e2
    lo, hi = np.percentile(h, (1.0, 99.0))
    low = h <= 0.5 * (lo + hi)  # the lower half: a leg meets the top's edge or apron above
    if int(low.sum()) < MIN_LEG_PIXELS:
        low = np.ones(len(h), bool)
    wide = max(float(np.subtract(*np.percentile(a[low], (95.0, 5.0)))),
               float(np.subtract(*np.percentile(b[low], (95.0, 5.0)))))
    tall = float(hi - lo)
    rng = max(1.0, float(np.median(np.sqrt(sq))))
    if not (wide <= POST_WIDTH and tall >= POST_HEIGHT and tall >= 3.0 * wide
            and lo_h - floor_level <= POST_LEVEL * rng):
        return False
    top = float(hi)
    # the top of its narrow column: one leg's post may hold a corner of the table's top
    # (unexplained pixels joined with the leg's), as high as the top's upper face
    for z in np.arange(0.5 * (lo + hi), hi, POST_SLICE):
        sl = (h >= z) & (h < z + POST_SLICE)
        if int(sl.sum()) < MIN_LEG_PIXELS:
            continue
        w = max(float(np.subtract(*np.percentile(a[sl], (95.0, 5.0)))),
                float(np.subtract(*np.percentile(b[sl], (95.0, 5.0)))))
        if w > 1.5 * POST_WIDTH:
            top = float(z)
            break
    return top - floor_level


def _pixels(m) -> tuple[np.ndarray, np.ndarray]:
    """``np.nonzero(m)`` of a 2-D mask, looked for within its rows' and columns' bounds only
    (the same pixels in the same order; a cluster covers a small box of a Kinect frame)."""
    r = np.flatnonzero(m.any(1))
    if not len(r):
        return r, r
    c = np.flatnonzero(m[r[0]:r[-1] + 1].any(0))
    rows, cols = np.nonzero(m[r[0]:r[-1] + 1, c[0]:c[-1] + 1])
    return rows + r[0], cols + c[0]


def leg_objects(planes, objects, params, curved_below: float = 0.8, xyz=None) -> list:
    """The proposals with the legs of one table or chair seen without its top made one object.

    A low camera sees a table's or a chair's legs with the top out of view (above the image,
    hidden, or too thin and far to segment): each leg is a proposal of its own, a false one,
    and the piece of furniture is found by none.  A *post* is a proposal of vertical planes
    and unexplained pixels (or a part of those pixels, 4-neighbours within ``edge_depth``)
    no wider than ``POST_WIDTH``, at least ``POST_HEIGHT`` tall and three times as tall as
    wide, whose lowest point lies on the floor (within ``POST_LEVEL``, scaled by its range).
    Posts whose feet lie at most ``params.legs_apart`` apart seen from above and whose tops
    are level (within ``POST_LEVEL``, scaled by the farther one's range) are the legs of one
    thing: their proposals become one object.  A door's edge (2 m) and a chair's leg (0.4 m)
    beside a table's (0.7 m) are not level with it.

    Parameters
    ----------
    planes : PlaneSet
    objects : sequence of CurvedObject
        The proposals (after :func:`table_objects`).
    params : ProposalParams
        ``legs_apart`` (0 = off), ``edge_depth``.
    curved_below : float
        ``CurvedParams.curved_below``: the joined object is curved below this planar fraction.
    xyz : ndarray, shape (H, W, 3), optional
        The organized points; without them nothing is joined.

    Returns
    -------
    list of CurvedObject
        ``objects`` itself when no two posts are joined; else the objects not taken, then one
        object per group of legs.
    """
    from planerel.features._curved_kernels import mask_points

    if params.legs_apart <= 0 or xyz is None or len(objects) < 2 or planes.floor is None:
        return objects
    byl = {p.label: p for p in planes}
    floor = byl.get(planes.floor)
    lab = getattr(planes, "labels", None)
    if floor is None or lab is None or lab.shape != xyz.shape[:2]:
        return objects
    up = np.asarray(planes.up, float)
    e1, e2 = _horizontal_basis(up)
    floor_level = float(np.asarray(floor.centroid, float) @ up)
    # the proposals that may be posts, by the tests that read no point: a join needs two
    # posts, so with fewer such proposals nothing is joined (no point is read)
    maybe = []
    for k, o in enumerate(objects):
        if not (o.planes or o.mask is not None):
            continue
        if any(x not in byl or byl[x].orientation != "vertical" for x in o.planes):
            continue
        if o.planes:
            # a cheap bound first: the planes' outlines no wider than a post and a half
            hull = np.concatenate([np.asarray(byl[x].hull3d, float) for x in o.planes])
            if max(float(np.ptp(hull @ e1)), float(np.ptp(hull @ e2))) > 2.0 * POST_WIDTH:
                continue
        maybe.append(k)
    if len(maybe) < 2:
        return objects
    posts = []  # (object index, foot, top, range)
    for k in maybe:
        o = objects[k]
        if o.planes:
            m = np.isin(lab, o.planes)
            if o.mask is not None:
                m |= o.mask
            rows, cols = _pixels(m)
            pts = xyz[rows, cols]
            fin = np.isfinite(pts).all(1)
            if int(fin.sum()) < MIN_LEG_PIXELS:
                continue
            p = pts[fin]
        else:
            m = o.mask
            # the same pixels, flags and finite points in one pass over the mask's rows
            rows, cols, fin, p = mask_points(m, xyz)
            if len(p) < MIN_LEG_PIXELS:
                continue
        top = _post(p, up, e1, e2, floor_level)
        if top is False and not o.planes:
            # unexplained pixels only: two legs, one behind the other, are one proposal;
            # each of its parts a post (as table_objects' parts: 4-neighbours within edge_depth)
            from planerel.features._curved_kernels import list_components

            ids, n = list_components(rows, cols, xyz, float(params.edge_depth), m.shape[0])
            ids = ids[fin]
            order = np.argsort(ids, kind="stable")
            ends = np.cumsum(np.bincount(ids, minlength=int(n)))
            tops = []
            for i in range(int(n)):
                q = p[order[ends[i - 1] if i else 0:ends[i]]]
                if len(q) < MIN_LEG_PIXELS:
                    continue
                t = _post(q, up, e1, e2, floor_level)
                if t is None or t is False:
                    tops = []
                    break
                tops.append(t)
            top = max(tops) if tops else None
        if top is not None and top is not False:
            foot = np.array([float((p @ e1).mean()), float((p @ e2).mean())])
            posts.append((k, foot, top, max(1.0, float(np.median(np.sqrt((p * p).sum(1)))))))
    pairs = []
    for i in range(len(posts)):
        for j in range(i + 1, len(posts)):
            (ka, fa, ta, ra), (kb, fb, tb, rb) = posts[i], posts[j]
            if (float(np.hypot(*(fa - fb))) <= params.legs_apart
                    and abs(ta - tb) <= POST_LEVEL * max(ra, rb)):
                pairs.append((ka, kb))
    return join_groups(objects, pairs, curved_below) if pairs else objects
