"""A table standing in the room: its top is support for what stands on it and an object too.

:func:`~planerel.features.relations.support_planes` makes a table top seen with the room's floor
in view support (``ProposalParams.table_area``): what stands on it is proposed apart, as on the
floor.  The table itself is then in no proposal, though it is an object in the room (a robot
walks around it, a chair is pushed under it).  This module gives it back its proposal without
taking the top's support role away (``ProposalParams.table_legs``):

1. **Tables.**  The horizontal support planes at least ``table_height`` above the floor and
   under ``support_min_area`` (only :func:`~planerel.features.relations.support_planes`' table
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

__all__ = ["MIN_LEG_PIXELS", "TABLE_MARGIN", "TABLE_REACH", "table_objects"]

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
    from planerel.features.relations import _floor_offset

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
        Support plane labels (:func:`~planerel.features.relations.support_planes`).
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

    from planerel.features.curved import CurvedObject
    from planerel.features.relations import _horizontal_basis

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
