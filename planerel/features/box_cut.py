"""A box inside a merged proposal: the solid a box proof's planes make, as an object of its own
(core49, ``decision.cut_boxes``; docs/objects.md "Boxes lost inside a merged proposal").

A proposal holds a box together with what it stands on or touches (a stool, a bag, a
neighbouring carton, tools on a table) when the segmentation joins them.  Then the box rules
may prove it, but the decision refuses them (the proposal's planar fraction holds the
neighbour's round or broken surface), or the answer's pixels lie mostly outside the box.

:func:`box_solids` finds, among a proposal's planes, the *seeds* a box proof is made of (the
two planes of a ``skirt`` or a ``face_pair``; a ``tall_face`` or a ``lying`` top alone seeds
none: one plane is no solid) and grows each into the solid it belongs to: the proposal's
planes that meet it at a convex box edge (``skirt``, ``corner``, ``face_pair`` relations), as
long as the solid stays within ``reach`` metres (the diagonal of its planes' hulls' bounding
box).  A solid two of whose faces meet at a facet's angle is none, and so is one whose faces go
on into the proposal's other planes at a facet's angle (a mug's rim and side; with
``decision.cut_corner`` a solid of that many planes or more is kept).  :func:`cut_object` makes the solid a
:class:`~planerel.features.facts.SceneObject` with its own planar fraction: its planes'
points against the proposal's unexplained pixels that lie within its bounds.  The
classifier then decides that object with the model's rules and every gate, as any proposal
(:meth:`planerel.classify.classifier.Classifier.answer_description`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["box_solids", "cut_object", "one_box_in_pieces", "EDGES", "PIECES", "SEEDS",
           "SURFACE_OFFSET"]

#: relations that join two faces of one solid at a convex box edge
EDGES = ("skirt", "corner", "face_pair")
#: default of :func:`box_solids`' ``pieces`` (``decision.cut_pieces``)
PIECES = 15.0
#: relations whose two planes seed a solid (a box proof's pairs)
SEEDS = ("skirt", "face_pair")
#: metres: two parallel planes each within this of the other's plane are one surface
#: (:func:`one_box_in_pieces`)
SURFACE_OFFSET = 0.02


def _extent(planes, labels) -> float:
    """Diagonal (m) of the bounding box of the hull vertices of ``labels``."""
    pts = [np.asarray(planes.by_label(x).hull3d, float).reshape(-1, 3) for x in labels]
    pts = np.concatenate([p for p in pts if p.size] or [np.zeros((1, 3))])
    return float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))


def box_solids(desc, planes, reach: float, facet: tuple = (5.0, 50.0), corner: int = 0,
               pieces: float = PIECES) -> list:
    """The solids a box proof's planes make among ``planes`` (labels of one proposal).

    Parameters
    ----------
    desc : planerel.features.facts.SceneDescription
    planes : sequence of int
        The proposal's plane labels.
    reach : float
        Metres: a plane joins a solid only while the solid's extent stays within this.
    facet : (float, float)
        Degrees (``CurvedParams.facet_min_angle``, ``facet_max_angle``): two adjacent planes
        at an angle in this range are neighbouring facets of a round surface.  A solid two
        of whose planes are is left out (at ``pieces`` degrees or more: under it they are
        pieces of one broken face); so is a solid of fewer than ``corner`` planes with a
        plane adjacent to one of the proposal's other planes at such an angle: two faces that
        go on into a round surface (a mug's rim and side, a canister's) are no solid of their
        own.
    corner : int
        0 (none) or the number of planes from which a solid (3: a top and two sides, three
        faces at a box's corner) is kept beside a round neighbour's facets (a container with
        a toy brick and a marker touching it; ``decision.cut_corner``).
    pieces : float
        Degrees: two planes of a solid at a facet's angle under this are pieces of one face
        the sensor's noise broke (hunt48's tops read 5-12 degrees off level, docs/objects.md
        "tilt36"); at this or more, a round surface's neighbouring strips
        (``decision.cut_pieces``).

    Returns
    -------
    list of tuple of int
        Distinct solids (sorted labels), largest (points) first; none equals ``planes``
        (then there is nothing to cut) and every one is a proper subset of it.
    """
    own = set(int(x) for x in planes)
    edges: dict[int, set] = {x: set() for x in own}
    seeds = []
    for r in desc.relations:
        if r.a not in own or r.b not in own or r.a == r.b:
            continue
        if any(getattr(r, n, False) for n in EDGES):
            edges[r.a].add(r.b)
            edges[r.b].add(r.a)
        if any(getattr(r, n, False) for n in SEEDS):
            seeds.append((r.a, r.b))
    # a single plane (a ``tall_face``, a ``lying`` top) is no evidence of a solid of its own:
    # the rules that take it hold an object-level guard (``nhorizontal(A,0)``,
    # ``oblique_share``) that a part cut out of the proposal would pass by construction
    ps = desc.planes
    smooth: dict[int, set] = {x: set() for x in own}
    bent: dict[int, set] = {x: set() for x in own}
    for r in desc.relations:
        if (r.a in own and r.b in own and r.a != r.b and r.adjacent
                and facet[0] <= r.angle <= facet[1]):
            smooth[r.a].add(r.b)
            if r.angle >= pieces:
                bent[r.a].add(r.b)
    out = []
    for seed in seeds:
        solid = set(seed)
        if _extent(ps, solid) > reach:
            continue
        grown = True
        while grown:
            grown = False
            for x in sorted({y for s in solid for y in edges[s]} - solid):
                if _extent(ps, solid | {x}) <= reach:
                    solid.add(x)
                    grown = True
        t = tuple(sorted(solid))
        if any(bent[x] & solid for x in solid):
            continue   # two of its faces meet as a round surface's facets do
        if (not corner or len(t) < corner) and any(smooth[x] - solid for x in solid):
            continue   # two faces going on into the proposal's round surface
        if len(t) < len(own) and t not in out:
            out.append(t)
    out.sort(key=lambda t: (-sum(ps.by_label(x).n_points for x in t), t))
    return out


def cut_object(desc, parent, solid, object_id: str, xyz, *, tiny_area: float,
               curved_below: float, margin: float):
    """``solid`` (labels, a proper subset of ``parent``'s planes) as an object of its own.

    Its planar fraction is its flat points over its planes' points plus the parent's
    unexplained pixels (``parent.mask`` off every plane) that lie in its planes' image
    rectangle and within ``margin`` m of its planes' 3-D bounding box: what of the parent's
    round or broken surface lies where the box is.  Its flat points are its planes' points of
    planes of ``tiny_area`` m^2 or more, but never more than the parent's flat points
    (``parent.planar_fraction`` times its points): the facet test is not run again, and a
    solid of two facets of a mug (a parent of planar fraction 0) has none.

    Returns
    -------
    planerel.features.facts.SceneObject
    """
    from planerel.features.facts import SceneObject

    ps = desc.planes
    lab = np.asarray(desc.labels)
    n_pl = sum(ps.by_label(x).n_points for x in solid)
    n_flat = sum(ps.by_label(x).n_points for x in solid if ps.by_label(x).area >= tiny_area)
    extra = 0
    mask = getattr(parent, "mask", None)
    if parent.planar_fraction is not None:
        # the parent's flat points bound the solid's: planes the parent's facet test took for
        # facets of a round surface (a mug's, a bowl's) are no flat faces in the solid either
        whole = sum(ps.by_label(x).n_points for x in parent.planes)
        if mask is not None:
            whole += int((np.asarray(mask, bool) & ~np.isin(lab, list(parent.planes))).sum())
        n_flat = min(n_flat, int(np.floor(parent.planar_fraction * whole + 0.5)))
    if mask is not None and xyz is not None:
        m = np.asarray(mask, bool) & (lab < 0)
        if m.any():
            own = np.isin(lab, list(solid))
            rows, cols = np.nonzero(own)
            box = np.zeros_like(m)
            box[rows.min():rows.max() + 1, cols.min():cols.max() + 1] = True
            m &= box
            pts = np.asarray(xyz, float)
            hull = np.concatenate([np.asarray(ps.by_label(x).hull3d, float).reshape(-1, 3)
                                   for x in solid])
            lo, hi = hull.min(axis=0) - margin, hull.max(axis=0) + margin
            p = pts[m]
            extra = int(np.all((p >= lo) & (p <= hi), axis=1).sum())
    total = n_pl + extra
    frac = n_flat / total if total else 0.0
    return SceneObject(object_id, tuple(solid), None, None, float(frac),
                       bool(frac < curved_below))


def one_box_in_pieces(desc, solids) -> bool:
    """True when two of ``solids`` (label tuples of boxes cut from one proposal,
    ``decision.cut_split``) are one box in pieces: a top of one (a plane not vertical) and a
    top of the other are one surface (``parallel``, the scene's relation, and each centroid
    within :data:`SURFACE_OFFSET` m of the other's plane).

    A box that a nearer thing cuts in two, or whose top the sensor broke in two, shows one
    top in both pieces (mOSD's occluded frames, OSD test64); two boxes of a pile have their
    tops at their own levels (two in a row may share a front, not a top).  Two touching boxes
    of one height, their tops flush, are not told from one box so: they stay one answer.
    """
    ps = desc.planes

    def tops(labels):
        return [x for x in labels if ps.by_label(x).orientation != "vertical"]

    def same(x, y):
        if not desc.relations.get(x, y).parallel:
            return False
        p, q = ps.by_label(x), ps.by_label(y)
        d = np.asarray(q.centroid, float) - np.asarray(p.centroid, float)
        return (abs(float(np.asarray(p.normal, float) @ d)) <= SURFACE_OFFSET
                and abs(float(np.asarray(q.normal, float) @ d)) <= SURFACE_OFFSET)

    return any(same(x, y) for i, a in enumerate(solids) for b in solids[i + 1:]
               for x in tops(a) for y in tops(b))
