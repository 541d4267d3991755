"""Object proposals: which planes of a scene make one object.

Object proposals (:func:`propose_objects`): support planes are dropped (the floor, horizontal
planes at floor level, and planes of at least ``support_min_area`` m^2 that are vertical or
horizontal, except a vertical one that is the side of a stepped structure: :mod:`planerel.features.walls`),
then each connected component of the adjacency graph of the remaining planes is a
candidate object, except components made only of vertical planes that reach the image border
(walls behind the object, seen in part).

Also the support planes (:func:`support_planes`), the join rules' edge measures
(:func:`edge_means`, :func:`seen_behind`, :func:`floor_beyond`), the convexity rule
(:func:`convex_pairs`, LCCP's criteria) and its cuts (:func:`shared_top_cuts`), and the
scoring against ground-truth objects (:func:`objects_from_truth`, :func:`proposal_match`).
The settings are :class:`~planerel.features.proposal_params.ProposalParams`; the step chains
are :mod:`planerel.features.step_chains`.  Moved out of :mod:`planerel.features.relations`
(split95), which still gives every name here.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.errors import InputError
from planerel.features.boards import stacked_board_pairs
from planerel.features.cavities import (
    cavity_pairs,
    group_channel_pairs,
    occluded_channel_pairs,
    split_panel_pairs,
)
from planerel.features.components import Components
from planerel.features.concave_cut import concave_cuts
from planerel.features.gaps import gap_in_front, occluded_piece_pairs
from planerel.features.open_treads import open_tread_pairs
from planerel.features.planes import _boundary, _boundary_pixels, _boundary_tiles, label_max
from planerel.features.proposal_params import ProposalParams
from planerel.features.relations import Relations
from planerel.features.solid import inclined_beside, top_slopes
from planerel.features.step_chains import (
    OPEN_THICK,
    OPEN_TILT,
    _regular_step,
    _step_like,
    _surely_deep,
    step_chain_pairs,
)
from planerel.features.step_geometry import _extent, _horizontal_basis, _tread_depth_axis
from planerel.features.vectors import cross3, lo_hi
from planerel.features.walls import flight_side, room_wall, stepped_side, top_line

__all__ = [
    "ProposalParams",
    "propose_objects",
    "shares_edge",
    "support_planes",
    "edge_means",
    "convex_pairs",
    "objects_from_truth",
    "proposal_match",
]


def support_planes(planes, params: ProposalParams | None = None, relations: Relations | None = None,
                   cloud=None) -> list[int]:
    """Labels of support planes: the floor, horizontal planes at floor level, large walls,
    table tops (``params.table_area``, :func:`_tables`).

    With ``relations`` and ``cloud`` (and the planes' label image), a large vertical plane that
    is the side of a stepped structure is no wall (``params.wall_test``,
    :mod:`planerel.features.walls`).
    """
    params = params or ProposalParams()
    tol = planes.params.floor_tol
    byl = {p.label: p for p in planes}
    floor = byl.get(planes.floor) if planes.floor is not None else None
    tread = (params.floor_tread and floor is not None and relations is not None
             and _floor_is_tread(planes, floor, relations, params))
    out = []
    for p in planes:
        if tread and p is floor:
            continue  # the lowest tread in view of a flight whose floor is not seen
        floorish = p.is_floor or (floor is not None and p.orientation == "horizontal"
                                  and abs(p.height) <= tol
                                  and _floor_offset(p, floor, planes.up) <= params.floor_gap)
        large = (p.area >= params.support_min_area and p.orientation in ("vertical", "horizontal")
                 and not _shallow_ramp(p, floor, planes.up, params))
        if floorish or large:
            out.append(p.label)
    if params.table_area > 0 and floor is not None and relations is not None:
        out += _tables(planes, floor, set(out), relations, params)
    lab = getattr(planes, "labels", None)
    if (params.wall_test and relations is not None and cloud is not None and lab is not None
            and lab.shape == cloud.xyz.shape[:2]):
        out = [x for x in out if not _stepped_side(planes, byl[x], set(out), relations, cloud, params)]
    if params.flight_sides and cloud is not None and lab is not None and lab.shape == cloud.xyz.shape[:2]:
        sup = set(out)
        out = [x for x in out
               if not (byl[x].orientation == "vertical" and byl[x].area >= params.support_min_area
                       and _flight_side(planes, byl[x], [q for q in planes if q.label not in sup],
                                        cloud, params))]
    if params.wedge_side_max > 0 and cloud is not None and lab is not None \
            and lab.shape == cloud.xyz.shape[:2]:
        sides = wedge_sides(planes, [x for x in out if byl[x].orientation == "vertical"],
                            relations, cloud, params.wedge_side_max)
        out = [x for x in out if x not in sides]
    return out


#: A wedge's side (:func:`wedge_sides`) has its straight top edge measured in at least this many
#: of the edge's :data:`planerel.features.solid.TOP_EDGE_BINS` (16) bins: half of them.  The
#: independent sets' ramp sides seen from a low camera: 11-16; a descending flight's side wall
#: seen from its landing, its edge seen in 6 bins: a run of 4 (wedge96).
WEDGE_SIDE_POINTS = 8


def wedge_sides(planes, candidates, relations, cloud, max_slope: float) -> set:
    """Of the vertical planes ``candidates``, those that are a wedge's side
    (``ProposalParams.wedge_side_max``, wedge96): the top edge seen straight over half a metre
    or more and in :data:`WEDGE_SIDE_POINTS` of its bins or more, sloping at most
    ``max_slope`` degrees, and the face lying under it
    (:func:`planerel.features.solid.top_slopes`, the test of ``top_slope/2``).  A ramp seen
    from its side by a camera lower than its top shows that triangle and nothing of its slope;
    a room wall's top is level or out of view.  Neither support nor a border wall.

    Parameters
    ----------
    planes : PlaneSet
        With ``labels`` of ``cloud``'s grid.
    candidates : iterable of int
    relations : Relations or None
        For the inclined planes adjacent to a face (``top_slopes``' ``beside``).
    cloud : Cloud
        Organized.
    max_slope : float
        Degrees.
    """
    only = set(candidates)
    if not only:
        return set()
    beside = inclined_beside(planes, relations) if relations is not None else None
    return {x for x, slope in top_slopes(planes, planes.labels, cloud.xyz, only=only,
                                         beside=beside, min_points=WEDGE_SIDE_POINTS)
            if slope <= max_slope}


#: Metres: a step counts towards a flight's side face (``ProposalParams.flight_sides``) when its
#: hull comes within this of the face's plane: the flight beside it, whose treads a balustrade hides
#: near it (0.55 m high, it hides 0.8 m of them from a camera looking 35 degrees down).
FLIGHT_SIDE_REACH = 1.0


def _flight_steps(planes, face, candidates, params) -> list:
    """Of ``candidates``, the steps beside vertical plane ``face``: treads, and risers across
    it (vertical, normals within 20 degrees of perpendicular to its), smaller than
    ``support_min_area``, within ``FLIGHT_SIDE_REACH`` of its plane and overlapping its
    extent along it (widened by 0.3 m)."""
    up = np.asarray(planes.up, float)
    n = np.asarray(face.normal, float)
    along = cross3(up, n)
    norm = float(np.linalg.norm(along))
    if norm < 1e-6:
        return []
    along = along / norm
    c = np.asarray(face.centroid, float)
    fa = np.asarray(face.hull3d, float) @ along
    lo, hi = float(fa.min()) - 0.3, float(fa.max()) + 0.3
    across = math.sin(math.radians(20.0))
    out = []
    for q in candidates:
        if q.label == face.label or q.area >= params.support_min_area:
            continue
        if q.orientation == "vertical":
            if abs(float(np.asarray(q.normal, float) @ n)) > across:
                continue
        elif q.orientation != "horizontal":
            continue
        hull = np.asarray(q.hull3d, float)
        qa = hull @ along
        if qa.max() < lo or qa.min() > hi:
            continue
        if float(np.abs((hull - c) @ n).min()) <= FLIGHT_SIDE_REACH:
            out.append(q)
    return out


def _without_room_walls(planes, pairs, cloud) -> set:
    """``pairs`` (wall, member) of :func:`group_channel_pairs` without those whose wall is a
    room wall beside the flight (``ProposalParams.channel_room_walls``,
    :func:`planerel.features.walls.room_wall`): its top out of view at the image border."""
    byl = {p.label: p for p in planes}
    verdict: dict = {}
    out = set()
    for w, m in pairs:
        if w not in verdict:
            face = byl[w]
            verdict[w] = face.orientation == "vertical" and room_wall(face, planes.up, cloud.xyz, planes.labels)
        if not verdict[w]:
            out.add((w, m))
    return out


def _flight_side(planes, face, candidates, cloud, params) -> bool:
    """Vertical plane ``face``'s top rises with the flight of the steps among ``candidates``
    (``params.flight_sides``; :func:`planerel.features.walls.flight_side`)."""
    steps = _flight_steps(planes, face, candidates, params)
    if len(steps) < 2:
        return False
    return flight_side(face, steps, planes.up, cloud.xyz, planes.labels, params.side_wall_follow,
                       params.step_rise_min, params.side_wall_rise_max, params.wall_tol)


#: Metres: a plane a table top carries stands at least this far inside the top's outline (its
#: centroid, seen from above): a panel or wall beside a box stands on the top's edge.
TABLE_INSET = 0.05


def _tables(planes, floor, support, relations, params) -> list[int]:
    """Labels of table tops (``params.table_area``): horizontal planes, not support, at least
    ``table_area`` m^2 and ``table_height`` m above the floor (higher than one step, so no
    flight's lowest tread), that carry something (a plane that meets the top, lies above it
    and stands ``TABLE_INSET`` inside its horizontal outline), and that are no level of a flight (no other
    horizontal plane of at least half their area lies ``step_rise_min``-``step_rise_max``
    above or below them); and the horizontal planes on a table top's plane (within
    ``floor_gap`` of it, its pieces cut off by the objects on it)."""
    from scipy.spatial import ConvexHull, QhullError

    up = np.asarray(planes.up, float)
    e1, e2 = _horizontal_basis(up)
    flat = [p for p in planes if p.orientation == "horizontal" and p.label not in support]
    tops = []
    for t in flat:
        if t.area < params.table_area or t.height < params.table_height:
            continue
        if any(u is not t and u.area >= 0.5 * t.area
               and params.step_rise_min <= abs(u.height - t.height) <= params.step_rise_max
               for u in flat):
            continue
        hull = np.asarray(t.hull3d, float)
        try:
            eq = ConvexHull(np.stack([hull @ e1, hull @ e2], 1)).equations  # unit normals
        except (QhullError, ValueError):
            continue
        base = float(np.asarray(t.centroid, float) @ up)
        for q in planes:
            if q is t or q.label in support:
                continue
            try:
                if not relations.get(t.label, q.label).adjacent:
                    continue
            except KeyError:
                continue
            if float((np.asarray(q.hull3d, float) @ up).min()) < base - params.edge_depth:
                continue
            c = np.asarray(q.centroid, float)
            if float((eq @ np.array([c @ e1, c @ e2, 1.0])).max()) <= -TABLE_INSET:
                tops.append(t)  # inside the outline, not on its edge (a panel beside a box)
                break
    out = {t.label for t in tops}
    for p in flat:
        if p.label not in out and any(_floor_offset(p, t, up) <= params.floor_gap for t in tops):
            out.add(p.label)
    return sorted(out)


def _floor_is_tread(planes, floor, relations, params) -> bool:
    """The plane taken as the floor is the lowest tread in view of a flight (``floor_tread``).

    A camera close to a staircase (a robot on its lower steps) sees no floor: the lowest
    horizontal plane is a tread.  It is one when it is step-shaped (1.5 times longer than deep
    across its shortest extent, at most ``step_run_max`` deep), and a regular step of a flight
    rises from it: a riser meets it (vertical, adjacent) whose height range is the rise, within
    30 %, up to a tread (horizontal, parallel step direction, ``step_rise_min`` -
    ``step_rise_max`` above it and ``step_run_min`` - ``step_run_max`` beyond it, the two
    overlapping by half across the flight) that the riser meets too, and that tread has a riser
    above it (vertical, adjacent, parallel to the first, rising from it) of that height
    again, within 30 %.  A floor has nothing of this: a box on a floor strip has no second
    riser of its front's height rising from its top (a wall behind it is far higher).
    """
    up = np.asarray(planes.up, float)
    if floor.orientation != "horizontal":
        return False
    if _surely_deep(floor, up, params.step_run_max):
        return False  # deeper than a step across every direction: the test below fails
    f_dir, f_elong = _tread_depth_axis(floor, up)
    if f_elong < 1.5 or np.ptp(np.asarray(floor.hull3d, float) @ f_dir) > params.step_run_max:
        return False
    cos_dir = math.cos(math.radians(25.0))
    cos_par = math.cos(math.radians(params.concave_tol))

    def adjacent(a, b) -> bool:
        try:
            return relations.get(a.label, b.label).adjacent
        except KeyError:
            return False

    def high(p) -> float:
        return float(np.ptp(np.asarray(p.hull3d, float) @ up))

    verts = [p for p in planes if p.orientation == "vertical" and p is not floor]
    for t in planes:
        if t is floor or t.orientation != "horizontal":
            continue
        dv = t.height - floor.height
        if not params.step_rise_min <= dv <= params.step_rise_max:
            continue
        t_dir, t_elong = _tread_depth_axis(t, up)
        if t_elong < 1.5 or abs(float(t_dir @ f_dir)) < cos_dir:
            continue
        d = np.asarray(t.centroid, float) - np.asarray(floor.centroid, float)
        run = abs(float(d @ f_dir))
        if not params.step_run_min <= run <= params.step_run_max:
            continue
        across = cross3(up, f_dir)
        a0, a1 = _extent(floor, across)
        b0, b1 = _extent(t, across)
        union = max(a1, b1) - min(a0, b0)
        if union <= 0 or (min(a1, b1) - max(a0, b0)) / union < 0.5:
            continue
        for r1 in verts:
            if not (adjacent(r1, floor) and adjacent(r1, t)
                    and abs(high(r1) - dv) <= 0.3 * dv):
                continue
            n1 = np.asarray(r1.normal, float)
            for r2 in verts:
                if (r2 is not r1 and r2.height > t.height and adjacent(r2, t)
                        and abs(float(np.asarray(r2.normal, float) @ n1)) >= cos_par
                        and abs(high(r2) - high(r1)) <= 0.3 * max(high(r1), high(r2))):
                    return True
    return False


def _shallow_ramp(p, floor, up, params) -> bool:
    """A large nearly-horizontal plane, not the floor, tilted at least ``params.ramp_tilt``
    degrees against the floor's plane and with its centroid at least ``params.ramp_rise``
    above it: a shallow ramp rising from the floor (4-5 degrees, 5-9 cm up in the varied
    world), not a floor piece (on the floor's plane) or a landing (level with it)."""
    if floor is None or p.is_floor or p.orientation != "horizontal" or params.ramp_tilt <= 0:
        return False
    cos = abs(float(np.asarray(p.normal, float) @ np.asarray(floor.normal, float)))
    tilt = math.degrees(math.acos(min(1.0, cos)))
    return tilt >= params.ramp_tilt and _floor_offset(p, floor, up) >= params.ramp_rise


def _stepped_side(planes, face, support, relations, cloud, params) -> bool:
    """A large vertical, non-floor plane that is the side of a stepped (or sloped) structure."""
    if face.orientation != "vertical" or face.is_floor:
        return False
    nbrs = [q for q in planes if q.label not in support and q.label != face.label
            and relations.get(face.label, q.label).adjacent
            and relations.get(face.label, q.label).perpendicular]
    # two steps, or one slope (it gives a cap per part of its extent along the face)
    enough = len(nbrs) >= 2 or any(q.orientation == "inclined" for q in nbrs)
    return enough and stepped_side(face, nbrs, planes.up, cloud.xyz, planes.labels,
                                           params.wall_tol, params.wall_window, params.step_rise_min)


def _floor_offset(p, floor, up) -> float:
    """Distance (m) of plane ``p``'s centroid from the floor's plane: a piece of the floor cut
    off by an object lies on it (within a few mm), an open box's bottom or a laptop's base
    lies 1-2 cm above it.  The floor's own plane is used, not the height along ``up``, so a
    floor tilted a degree against ``up`` does not lift its far pieces."""
    n = np.asarray(floor.normal, float)
    if float(n @ np.asarray(up, float)) < 0:
        n = -n
    return abs(float((np.asarray(p.centroid, float) - np.asarray(floor.centroid, float)) @ n))


def edge_means(labels, xyz, pairs, band: int = 3, depth: float = 0.03) -> dict:
    """Mean 3-D points of each plane near its shared edge with another.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
        Plane labels, -1 unassigned.
    xyz : ndarray, shape (H, W, 3)
        Organized points (NaN invalid).
    pairs : iterable of (int, int)
        Unordered label pairs to measure.
    band : int
        Pixel offsets 1..band in four grid directions (right, down, both diagonals down) from
        each boundary pixel: every pixel pair within the band is seen once.
    depth : float
        Pixel pairs farther apart than ``depth * max(1, z)`` metres are left out.

    Returns
    -------
    dict
        ``{(a, b): (mean point of a near b (3,), mean point of b near a (3,), count)}`` for
        the pairs with at least one such pixel pair (keys as given).
    """
    lab = np.asarray(labels)
    want = {(min(a, b), max(a, b)) for a, b in pairs}
    if not want or lab.size == 0:
        return {}
    from planerel.features._relation_kernels import edge_sums_pairs_with_tiles

    n = label_max(lab) + 1
    sums = {}
    # only boundary pixels can have another plane within the band: look around them alone;
    # every (boundary pixel, pixel within the band) pair of two labels of a wanted pair in
    # one compiled pass (edge_sums' sums of those pairs; a pixel whose band meets no
    # boundary pixel of a partner of its label is not read)
    r0, c0 = _boundary_pixels(lab)
    partner = np.zeros((max(n, 1), max(n, 1)), np.bool_)
    for lo, hi in want:
        if 0 <= lo < n and 0 <= hi < n:
            partner[lo, hi] = partner[hi, lo] = True
    # (the tiles the relations' touch test read, remembered with the label image)
    cnt, acc_a, acc_b = edge_sums_pairs_with_tiles(np.ascontiguousarray(lab),
                                                   np.ascontiguousarray(xyz, dtype=np.float64),
                                                   np.asarray(r0, np.int64),
                                                   np.asarray(c0, np.int64), _boundary_tiles(lab),
                                                   partner, int(band), float(depth))
    for lo, hi in want:
        c = cnt[lo * n + hi] if lo < n and hi < n else 0
        if c > 0:
            sums[(lo, hi)] = (acc_a[lo * n + hi] / c, acc_b[lo * n + hi] / c, int(c))
    return sums


def seen_behind(labels, xyz, group, reach: int = 3, margin: float = 0.05) -> float:
    """Fraction of the valid pixels just outside a group of planes that lie behind it.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
        Plane labels.
    xyz : ndarray, shape (H, W, 3)
        Organized points (NaN invalid).
    group : iterable of int
        Plane labels of the group.
    reach : int
        Pixels: from each outline pixel of the group, the pixels 1 and ``reach`` steps away in
        the four grid directions that are not in the group are looked at.
    margin : float
        Metres (at 1 m; scaled by the range): a pixel is behind when its range exceeds the
        outline pixel's by more than ``margin * max(1, range)``.

    Returns
    -------
    float
        Behind / valid outside pixels looked at (0 when there are none).
    """
    lab = np.asarray(labels)
    inside = np.isin(lab, list(group))
    H, W = lab.shape
    r0, c0 = np.nonzero(inside & _boundary(lab))
    if r0.size == 0:
        return 0.0
    rng0 = np.linalg.norm(xyz[r0, c0], axis=1)
    lim = rng0 + margin * np.maximum(1.0, rng0)
    n_valid = n_behind = 0
    for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
        for k in sorted({1, reach}):
            r, c = r0 + dy * k, c0 + dx * k
            ok = (r >= 0) & (r < H) & (c >= 0) & (c < W)
            ok[ok] = ~inside[r[ok], c[ok]]
            rng = np.linalg.norm(xyz[r[ok], c[ok]], axis=1)
            valid = np.isfinite(rng)
            n_valid += int(valid.sum())
            n_behind += int((rng[valid] > lim[ok][valid]).sum())
    return n_behind / n_valid if n_valid else 0.0


def floor_beyond(labels, xyz, plane, floors, margin: float = 0.05) -> float:
    """Pixels of the ``floors`` lying beyond ``plane``'s plane, per point of ``plane``.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
        Plane labels.
    xyz : ndarray, shape (H, W, 3)
        Organized points (NaN invalid).
    plane : Plane
        A (vertical) plane: its normal, centroid and point count.
    floors : sequence of Plane
        The horizontal support planes (their labels, pixel boxes and hulls are used).
    margin : float
        Metres (at 1 m; scaled by the range): a floor pixel is beyond the plane when it lies
        farther from the sensor than the plane's plane by more than ``margin * max(1, range)``.

    Returns
    -------
    float
        Floor pixels beyond the plane / ``plane.n_points`` (0 when it has none).
    """
    if plane.n_points <= 0:
        return 0.0
    n = np.asarray(plane.normal, float)
    c = np.asarray(plane.centroid, float)
    if float(n @ c) > 0:
        n = -n  # turned towards the sensor
    lab = np.asarray(labels)
    count = 0
    for f in floors:
        # no hull vertex beyond the plane by half the margin: no pixel is (the hull holds the
        # plane's pixels but for its simplification, a few millimetres)
        if float(((c - np.asarray(f.hull3d, float)) @ n).max()) <= 0.5 * margin:
            continue
        r0, c0, r1, c1 = f.bbox
        pts = np.asarray(xyz)[r0:r1, c0:c1][lab[r0:r1, c0:c1] == f.label]
        d = (c - pts) @ n  # NaN for invalid points: never beyond
        far = d > margin
        if far.any():
            rng = np.linalg.norm(pts[far], axis=1)
            count += int(np.count_nonzero(d[far] > margin * np.maximum(1.0, rng)))
    return count / plane.n_points


#: Fewest edge pixel pairs (:func:`edge_means`) for two planes to share an edge.
MIN_EDGE = 5


def convex_pairs(planes, pairs, edges=None, concave_tol: float = 10.0,
                 step_overlap: float | None = 0.8, min_edge: int = MIN_EDGE,
                 riser_max: float | None = None, coplanar_depth: float | None = None,
                 sanity_angle: float = 0.0, flight_riser_max: float | None = None,
                 seat_depth: float | None = None, stacked_overlap: float = 0.0,
                 stacked_parallel: bool = False, top_rise: float = 0.0,
                 riser_min: float = 0.0, riser_floor: bool = False,
                 riser_pieces: bool = False, concave_band: float = 1.0,
                 top_rise_edge: float = 0.0) -> set:
    """The pairs whose shared edge is convex seen from outside (LCCP's rule, Stein et al. 2014).

    For planes ``a`` and ``b`` with unit normals ``n_a``, ``n_b`` turned towards the sensor
    and points ``x_a``, ``x_b`` near their shared edge (:func:`edge_means`; the centroids when
    the planes do not touch in the grid), the edge is convex when
    ``(n_a - n_b) . (x_a - x_b) >= 0`` (each face bends away from the other, as two faces of
    one box, or nearly so at a shared edge: a cosine above -0.1 between ``n_a - n_b`` and
    ``x_a - x_b``, where noise decides the sign), concave otherwise (a box on another box, beside another, against
    a wall), except that normals within ``concave_tol`` degrees count as convex (one noisy surface)
    and that a concave edge between a horizontal or inclined plane and a vertical one whose
    extents along the edge overlap by at least ``step_overlap`` (interval IoU) stays joined: a
    tread and the riser above it (the concave edges of a staircase), a slope and the face at
    its end (None: no exception).  When ``edges`` are given, a pair with fewer than
    ``min_edge`` edge pixel pairs there shares no edge (its planes only come near in 3-D, e.g.
    a face seen behind another object's top across an occluding edge): its sign is taken from
    the centroids and the tread-and-riser exception does not apply.  With ``riser_max``
    (metres; :func:`propose_objects` passes 1.5 x ``step_rise_max``) the exception also needs
    the vertical plane no higher than that or 1.5 times the other plane's height range (a
    wall behind a flight's lowest tread is no riser; a ramp's end face is as high as its slope).
    With ``coplanar_depth`` (metres at 1 m), nearly parallel planes count as one surface only
    when their points lie within ``coplanar_depth * max(1, z)`` of the other's plane
    (:func:`_step_apart`; LCCP's smoothness check): parallel faces a step apart are faces of two
    objects (one convex object has no two faces with one outward normal), or of a non-convex
    one (a staircase's treads, which the step chains join).  With ``sanity_angle`` (degrees,
    LCCP's sanity criterion) a pair whose sign is no evidence (no shared edge, or within the
    noise band) stays joined only when its points' offset makes at least
    :func:`_sanity_limit` degrees with the line ``n_a x n_b`` where the planes meet: faces of
    one object meet along that line, two objects touching at a corner have their points'
    offset along it.  With ``stacked_overlap`` > 0 (a fraction; it also turns on
    ``_regular_step``'s ``turned`` test), two vertical planes that are not
    parallel are never joined when their height ranges (their hulls along
    up) overlap by less than ``stacked_overlap`` of the shorter one's: the side faces of one
    box meet along a vertical edge and span the same heights, a face standing on another
    object's face (a box stacked on a box at another yaw, or set back) begins where the
    lower one ends (tabletop22); not when the upper plane is higher than ``riser_max`` (a
    flight's side wall seen above its lowest riser).  With ``stacked_parallel`` (and
    ``stacked_overlap`` > 0) the same holds for parallel vertical planes within the coplanar
    depth whose height ranges meet (a gap of at most ``STACK_MEET`` = 1 cm between them): an
    upper box's face standing on the lower box's face when the two are aligned, the upper at
    most ``STACK_WIDER`` = 1.5 times as wide as the lower (tabletop22b; coplanar pieces with a
    gap between them, or a table's edge over one of its legs, stay joined).  With ``top_rise`` > 0 (metres), a horizontal and a vertical plane that share
    no edge are not joined when the vertical one's top (its hull along up) rises more than
    ``top_rise`` above the horizontal one's centroid: the top of a convex object lies at the
    top of its faces, and a face rising above a horizontal plane without meeting it along an
    edge is another object's (a box standing on the lower box whose top is seen behind it).
    With ``riser_min`` > 0 (metres) the tread-and-riser exception needs a vertical plane over
    a horizontal one at least that high: a flight's riser rises a step (pairs22).  With
    ``riser_floor``, ``_regular_step`` measures the riser below a tread no higher than the
    tread's height above the floor (synth22r).  ``concave_band`` (a fraction of the noise band)
    is how far below zero the sign of a pair sharing an edge may be and still count as convex:
    1 joins the whole band's concave side (the sign within noise), 0 asks a sign of zero or more
    (``ProposalParams.concave_band``).

    Returns
    -------
    set of (int, int)
        The convex pairs among ``pairs`` (as given).
    """
    byl = {p.label: p for p in planes}
    up_v = getattr(planes, "up", None)
    stacked = stacked_overlap > 0 and up_v is not None
    if stacked or ((top_rise > 0 or top_rise_edge > 0) and up_v is not None):
        up_l = np.asarray(up_v, float).tolist()
        spans: dict = {}

        def span(p):
            if p.label not in spans:
                h = np.asarray(p.hull3d, float) @ np.asarray(up_l)
                spans[p.label] = lo_hi(h) if h.size else (0.0, 0.0)
            return spans[p.label]
    cos_tol = math.cos(math.radians(concave_tol))
    pairs = list(pairs)
    nbrs: dict = {}
    for a, b in pairs:
        nbrs.setdefault(a, []).append(b)
        nbrs.setdefault(b, []).append(a)
    out = set()
    # each plane's normal turned towards the sensor and centroid as Python floats, once
    vecs: dict = {}
    for k in nbrs:
        p = byl[k]
        c = np.asarray(p.centroid, float).tolist()
        nk = np.asarray(p.normal, float).tolist()
        vecs[k] = ([-v for v in nk] if _dot(nk, c) > 0 else nk, c)
    # per pair a few 3-vector products, in Python floats (numpy's call overhead is most of
    # their time; the sums' order may differ from numpy's in the last bit)
    for a, b in pairs:
        pa, pb = byl[a], byl[b]
        (na, xa), (nb, xb) = vecs[a], vecs[b]
        e = (edges or {}).get((min(a, b), max(a, b)))
        if e is not None and e[2] < min_edge:
            e = None  # a pixel pair or two across an occluding edge: no shared edge
        if e is not None:
            xa, xb = (e[0], e[1]) if a < b else (e[1], e[0])
            xa, xb = np.asarray(xa, float).tolist(), np.asarray(xb, float).tolist()
        dx = [xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]]
        if abs(_dot(na, nb)) >= cos_tol:
            if (stacked and stacked_parallel and pa.orientation == "vertical"
                    and pb.orientation == "vertical" and _stacked_spans(span(pa), span(pb),
                                                                        stacked_overlap, riser_max)
                    and min(span(pa)[1], span(pb)[1]) - max(span(pa)[0], span(pb)[0]) >= -STACK_MEET
                    and _upper_not_wider(pa, pb, span(pa)[1] >= span(pb)[1], up_l)):
                continue  # a face over another: an aligned box standing on a box
            # one surface only when coplanar: parallel faces a step apart face each other (a
            # box's top seen behind another's, a lower top next to a higher one); one convex
            # object has no two faces with one outward normal (LCCP's smoothness check)
            if coplanar_depth is None or min(abs(_dot(na, dx)), abs(_dot(nb, dx))) <= (
                    coplanar_depth * max(1.0, 0.5 * abs(xa[2] + xb[2]))):
                out.add((a, b))
            continue
        if stacked and pa.orientation == "vertical" and pb.orientation == "vertical":
            if _stacked_spans(span(pa), span(pb), stacked_overlap, riser_max):
                continue  # one face stands on the other: two objects, one on the other
        if top_rise > 0 and up_v is not None and edges is not None and e is None and {
                pa.orientation, pb.orientation} == {
                "horizontal", "vertical"}:
            hp, vp = (pa, pb) if pa.orientation == "horizontal" else (pb, pa)
            if span(vp)[1] - _dot(np.asarray(hp.centroid, float).tolist(), up_l) > top_rise:
                continue  # a face rising above a top it does not meet: another object's
        # the step exception needs a shared edge: planes whose outlines only come near in 3-D
        # (one behind the other across an occluding edge) are no tread and riser
        shared = edges is None or e is not None
        # the sign, as the cosine between the normals' difference and the shared edge's
        # points' offset: within +-0.1 (84-96 degrees) the offset lies along the edge (a
        # corner, a few pixel pairs) and noise decides the sign: no evidence of a cut
        dn = [na[0] - nb[0], na[1] - nb[1], na[2] - nb[2]]
        scale = 0.1 * math.sqrt(_dot(dn, dn)) * math.sqrt(_dot(dx, dx)) if e is not None else 0.0
        sign = _dot(dn, dx)
        # where the sign is no evidence (no shared edge: centroids; or inside the noise band),
        # the connection must cross the planes' line of intersection (LCCP's sanity criterion):
        # two objects touching at a corner have their points' offset along it
        sane = (sanity_angle <= 0 or (e is not None and abs(sign) > scale)
                or _crossing_angle_f(na, nb, dx) >= _sanity_limit_f(na, nb, sanity_angle))
        by_sign = sign >= -concave_band * scale and sane
        if (by_sign and top_rise_edge > 0 and up_v is not None and e is not None
                and {pa.orientation, pb.orientation} == {"horizontal", "vertical"}):
            hp, vp = (pa, pb) if pa.orientation == "horizontal" else (pb, pa)
            level = _dot(np.asarray(hp.centroid, float).tolist(), up_l)
            # a top seen from above (under the eye); a table's underside seen from below is
            # met by its own legs and apron rising to its top
            by_sign = level >= 0 or span(vp)[1] - level <= top_rise_edge
        if by_sign or (step_overlap is not None and shared
                                         and _step_like(pa, pb, step_overlap,
                                                        getattr(planes, "up", None), riser_max,
                                                        riser_min)
                                         and _regular_step(pa, pb, byl, nbrs, cos_tol,
                                                           flight_riser_max, seat_depth,
                                                           stacked_overlap > 0, riser_floor,
                                                           riser_pieces)):
            out.add((a, b))
    return out


STACK_MEET = 0.01  # metres: a face standing on another begins within this of the other's top
STACK_WIDER = 1.5  # the upper face of a stack at most this times as wide as the lower one


def _upper_not_wider(pa, pb, a_upper: bool, up) -> bool:
    """The upper of two parallel vertical planes at most 1.5 times as wide (its hull along the
    horizontal line in its plane) as the lower one: a box standing on a box is no wider than
    the lower box (give or take), a table's edge over one of its legs is."""
    n = np.asarray(pa.normal, float)
    t = np.cross(np.asarray(up, float), n)
    if not np.any(t):
        return False
    hi, lo = (pa, pb) if a_upper else (pb, pa)
    wu = float(np.ptp(np.asarray(hi.hull3d, float) @ t))
    wl = float(np.ptp(np.asarray(lo.hull3d, float) @ t))
    return wu <= STACK_WIDER * wl


def _stacked_spans(sa, sb, overlap: float, riser_max: float | None) -> bool:
    """Height ranges ``sa``, ``sb`` (low, high) of two vertical planes overlapping by less than
    ``overlap`` of the shorter one's, the upper plane at most ``riser_max`` high: one face
    standing on the other (``stacked_overlap`` of :func:`convex_pairs`)."""
    (lo_a, hi_a), (lo_b, hi_b) = sa, sb
    short = min(hi_a - lo_a, hi_b - lo_b)
    upper = (hi_a - lo_a) if hi_a >= hi_b else (hi_b - lo_b)
    return (short > 0 and min(hi_a, hi_b) - max(lo_a, lo_b) < overlap * short
            and (riser_max is None or upper <= riser_max))


def _normal_out(p) -> list:
    """A plane's unit normal turned towards the sensor (the origin), as Python floats."""
    n = np.asarray(p.normal, float).tolist()
    if _dot(n, np.asarray(p.centroid, float).tolist()) > 0:
        n = [-v for v in n]
    return n


def shared_top_cuts(planes, joined, concave, edges, concave_tol: float = 10.0,
                    max_cos: float = -0.5) -> set:
    """The joined pairs to cut so that a top shared by two objects stays with one of them.

    A horizontal plane ``P`` joined (in ``joined``, the convex pairs) to planes ``a`` and
    ``b`` that meet each other at a shared concave edge (a pair of ``concave``, at least
    :data:`MIN_EDGE` edge pixel pairs in ``edges``, normals more than ``concave_tol`` apart,
    not horizontal) whose sign is clearly concave (cosine between ``n_a - n_b`` and the edge
    points' offset at most ``max_cos``; the noise band of :func:`convex_pairs` is +-0.1),
    both with their centroids lower than ``P``'s (faces hanging below a top), while ``a`` and
    ``b`` are not joined without ``P``: one convex object has no two faces
    meeting at a concave edge, so ``P`` is the top of two objects that the segmentation made
    one plane (two boxes of one height side by side).  ``P`` keeps its pairs with the group
    (the planes joined to ``a`` or ``b`` without ``P``) it shares more edge pixel pairs with;
    its pairs with the other group are returned (ties: the group of the smaller label).

    Returns
    -------
    set of (int, int)
        Pairs of ``joined`` (as given) to drop.
    """
    byl = {p.label: p for p in planes}
    joined = list(joined)
    nbrs: dict = {}
    for a, b in joined:
        nbrs.setdefault(a, set()).add(b)
        nbrs.setdefault(b, set()).add(a)
    cos_tol = math.cos(math.radians(concave_tol))
    cut: set = set()
    for a, b in sorted(concave):
        e = edges.get((min(a, b), max(a, b)))
        if e is None or e[2] < MIN_EDGE:
            continue
        pa, pb = byl[a], byl[b]
        if pa.orientation == "horizontal" or pb.orientation == "horizontal":
            continue
        na, nb = _normal_out(pa), _normal_out(pb)
        if abs(_dot(na, nb)) >= cos_tol:
            continue
        xa, xb = (e[0], e[1]) if a < b else (e[1], e[0])
        dx = [float(xa[i]) - float(xb[i]) for i in range(3)]
        dn = [na[i] - nb[i] for i in range(3)]
        norm = math.sqrt(_dot(dn, dn) * _dot(dx, dx))
        if norm == 0 or _dot(dn, dx) / norm > max_cos:
            continue
        for top in sorted(nbrs.get(a, set()) & nbrs.get(b, set())):
            # a top over both: a and b hang below it (their centroids lower); a tread joined
            # to a riser or side face rising above it is no such top
            if byl[top].orientation != "horizontal" or not (
                    pa.height < byl[top].height and pb.height < byl[top].height):
                continue
            # the two groups without the top (and without pairs already cut)
            g = Components(k for k in nbrs if k != top)
            g.add_edges((x, y) for x, y in joined if top not in (x, y)
                        and (x, y) not in cut and (y, x) not in cut)
            if g.together(a, b):
                continue
            side = {}
            for k in nbrs[top]:
                if g.together(k, a):
                    side[k] = a
                elif g.together(k, b):
                    side[k] = b
            weight = {a: 0, b: 0}
            for k, s_ in side.items():
                weight[s_] += (edges.get((min(top, k), max(top, k))) or (0, 0, 0))[2]
            keep = a if (weight[a], -a) > (weight[b], -b) else b
            for k, s_ in side.items():
                if s_ != keep:
                    cut.add((top, k) if (top, k) in set(joined) else (k, top))
    return cut


def _dot(u, v) -> float:
    """Dot product of two 3-sequences of Python floats."""
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _crossing_angle_f(na, nb, dx) -> float:
    """:func:`_crossing_angle` of 3-lists of Python floats."""
    s = [na[1] * nb[2] - na[2] * nb[1], na[2] * nb[0] - na[0] * nb[2],
         na[0] * nb[1] - na[1] * nb[0]]
    den = math.sqrt(_dot(s, s)) * math.sqrt(_dot(dx, dx))
    if den <= 0:
        return 90.0
    return math.degrees(math.acos(min(1.0, abs(_dot(s, dx)) / den)))


def _sanity_limit_f(na, nb, angle: float) -> float:
    """:func:`_sanity_limit` of 3-lists of Python floats."""
    beta = math.degrees(math.acos(min(1.0, abs(_dot(na, nb)))))
    return angle / (1.0 + math.exp(-0.25 * (beta - 25.0)))


def _step_apart(na, nb, xa, xb) -> float:
    """Metres between two (nearly) parallel planes along their normals: the smaller of the
    distances of each plane's point from the other's plane (LCCP's smoothness check)."""
    d = np.asarray(xa, float) - np.asarray(xb, float)
    return min(abs(float(na @ d)), abs(float(nb @ d)))


def _crossing_angle(na, nb, dx) -> float:
    """Degrees (0-90) between the offset ``dx`` of two planes' points and their line of
    intersection ``na x nb`` (90 when either is zero)."""
    s = np.cross(na, nb)
    den = float(np.linalg.norm(s) * np.linalg.norm(dx))
    if den <= 0:
        return 90.0
    return math.degrees(math.acos(min(1.0, abs(float(s @ dx)) / den)))


def _sanity_limit(na, nb, angle: float) -> float:
    """LCCP's sanity threshold (degrees): ``angle / (1 + exp(-0.25 (beta - 25)))`` for normals
    ``beta`` degrees apart (60 at 90 degrees with ``angle`` = 60; ~1 at 10 degrees, where the
    intersection line is ill-defined anyway)."""
    beta = math.degrees(math.acos(min(1.0, abs(float(na @ nb)))))
    return angle / (1.0 + math.exp(-0.25 * (beta - 25.0)))


def shares_edge(n_edge: int, gap: float, adjacency_gap: float, apart_edge: int = 0) -> bool:
    """Whether an adjacent pair stays a pair for the convexity rule: its hulls come within
    ``adjacency_gap`` metres, or it shares an edge of at least :data:`MIN_EDGE` pixel pairs
    (:func:`edge_means`), at least ``apart_edge`` when its hulls lie farther apart than that (a
    few pixel pairs within ``edge_depth`` across an occluding edge are no shared edge: a
    table's frame 6.4 cm from an open box behind it at 2.4 m, 8 pixel pairs, seed 32
    ``s0014``)."""
    if gap <= adjacency_gap:
        return True
    return n_edge >= max(MIN_EDGE, apart_edge)


def propose_objects(planes, relations: Relations, params: ProposalParams | None = None,
                    cloud=None, support=None) -> list[tuple[int, ...]]:
    """Candidate objects: connected components of the convex adjacency of the non-support planes.

    Support planes (:func:`support_planes`; or ``support``, their labels when already found
    with the same planes, relations, parameters and cloud) are dropped; of the adjacent pairs
    left, those meeting at a concave edge (:func:`convex_pairs`, with the edge points of
    :func:`edge_means` when ``cloud`` and the planes' label image are given) are cut unless
    ``params.split_concave`` is False; each connected component is a candidate.

    Returns
    -------
    list of tuple of int
        Plane labels per object, each sorted; objects ordered by their smallest label.
    """
    params = params or ProposalParams()
    drop = set(support_planes(planes, params, relations, cloud) if support is None else support)
    concave: list = []
    room_walls: set = set()  # walls a flight's channel test found to be a stairwell's (walls36)
    g = Components(p.label for p in planes if p.label not in drop)
    pairs = [(a, b) for a, b in relations.adjacent_pairs() if a not in drop and b not in drop]
    if params.split_concave and pairs:
        edges = None
        lab = getattr(planes, "labels", None)
        if cloud is not None and lab is not None and lab.shape == cloud.xyz.shape[:2]:
            edges = edge_means(lab, cloud.xyz, pairs, params.edge_band, params.edge_depth)
            # a pair adjacent only through the grid's loose depth tolerance (within 5 % of the
            # depth), sharing no edge and with hulls apart, is one face seen behind another
            # (a box behind a table's frame), not two faces of one object
            # (the limits taken once, not once a pair)
            adj_gap, apart = relations.params.adjacency_gap, round(params.apart_edge * lab.shape[1] / 320)
            rel_of = relations.get
            pairs = [(a, b) for a, b in pairs
                     if shares_edge(edges.get((min(a, b), max(a, b)), (0, 0, 0))[2],
                                    rel_of(a, b).gap, adj_gap, apart)]
            if params.apart_gap > 0 or params.touch_gap > 0:
                # a pair that neither touches nor shares an edge: adjacent only by its hulls'
                # gap, which must be small for two faces of one object (see apart_gap); one
                # that does: its hulls still meet (see touch_gap)
                dist = {p.label: math.hypot(*np.asarray(p.centroid, float).tolist()) for p in planes}
                wavy_frame: list = []

                def wavy() -> bool:
                    # measured once, and only when a skirt pair lies beyond touch_gap
                    if not wavy_frame:
                        from planerel.segment.noise import estimate_noise

                        wavy_frame.append(bool(getattr(cloud, "organized", False))
                                          and estimate_noise(cloud, waviness=True).wavy)
                    return wavy_frame[0]
                intr = getattr(cloud, "intrinsics", None)
                footprint = 1.0 / (intr.fx if intr is not None else 525.0)  # metres a pixel at 1 m

                def near(a, b) -> bool:
                    r = relations.get(a, b)
                    z = 0.5 * (dist[a] + dist[b])
                    if r.touching or edges.get((min(a, b), max(a, b)), (0, 0, 0))[2] >= MIN_EDGE:
                        if params.touch_gap <= 0 or r.gap <= params.touch_gap * footprint * z:
                            return True
                        # a box's top and the side hanging below its edge on a wavy sensor,
                        # apart by the band its smeared edge leaves unsegmented
                        return (params.skirt_gap > 0 and r.gap <= params.skirt_gap * max(1.0, z)
                                and (r.skirt or relations.get(b, a).skirt) and wavy())
                    return params.apart_gap <= 0 or r.gap <= params.apart_gap * max(1.0, z)

                pairs = [(a, b) for a, b in pairs if near(a, b)]
            if params.cut_apart_parallel:
                # parallel faces that neither touch in the image nor share an edge, adjacent
                # only because their hulls come within adjacency_gap, with no occluder in
                # front of them between them in the image: two coplanar faces side by side
                # (two boxes in a row), not one surface (whose pieces touch, or have
                # something in front of it between them)
                byl0 = {p.label: p for p in planes}

                def one_surface(a, b) -> bool:
                    ba, bb = byl0[a].bbox, byl0[b].bbox
                    box = (min(ba[0], bb[0]), min(ba[1], bb[1]), max(ba[2], bb[2]), max(ba[3], bb[3]))
                    f = gap_in_front(lab, cloud.xyz, a, b, window=box)
                    return f is None or f >= 0.5

                pairs = [(a, b) for a, b in pairs
                         if edges.get((min(a, b), max(a, b)), (0, 0, 0))[2] >= MIN_EDGE
                         or relations.get(a, b).touching or not relations.get(a, b).parallel
                         or one_surface(a, b)]
        joined = convex_pairs(planes, pairs, edges, params.concave_tol,
                              params.step_overlap or None,
                              riser_max=params.riser_max,
                              coplanar_depth=params.coplanar_depth,
                              sanity_angle=params.sanity_angle,
                              flight_riser_max=1.5 * params.step_rise_max,
                              seat_depth=params.step_run_max,
                              stacked_overlap=params.stacked_faces,
                              stacked_parallel=params.stacked_parallel,
                              top_rise=params.top_rise,
                              top_rise_edge=params.top_rise_edge,
                              riser_min=params.riser_min,
                              riser_floor=params.riser_floor,
                              riser_pieces=params.riser_pieces,
                              concave_band=params.concave_band)
        if params.cavities and edges is not None:
            # the inside of one open object (a shelf, an open box): a channel or an inside
            # corner of shared concave edges (planerel.features.cavities)
            concave = [(a, b) for a, b in pairs if (a, b) not in joined
                       and edges.get((min(a, b), max(a, b)), (0, 0, 0))[2] >= MIN_EDGE]
            cav = concave
            if params.cavity_skip_walls and params.drop_border_walls and concave:
                # a plane the border-wall test drops when alone (a room wall seen at the
                # border with nothing behind it) is no side of an open object's cavity
                byl1 = {p.label: p for p in planes}
                walls = {k for k in {x for pr in concave for x in pr}
                         if byl1[k].orientation == "vertical" and byl1[k].touches_border
                         and byl1[k].area >= params.border_wall_area
                         and (params.wall_behind >= 1
                              or seen_behind(lab, cloud.xyz, (k,)) <= params.wall_behind)}
                cav = [pr for pr in concave if not (walls and (pr[0] in walls or pr[1] in walls))]
            joined |= cavity_pairs(planes, cav, params.concave_tol, params.cavity_overlap)
            if params.occluded_channels and concave:
                # a channel whose near wall shows its outside and hides the bottom
                joined |= occluded_channel_pairs(planes, concave, lab, cloud.xyz, params.concave_tol,
                                                 params.cavity_overlap)
            if params.split_panels and concave:
                # a panel in coplanar pieces (cut by a board) along one plane's concave edge
                joined |= split_panel_pairs(planes, concave, lab, cloud.xyz, params.concave_tol,
                                            params.coplanar_depth or 0.0, params.cavity_overlap)
        if params.shared_top and edges is not None:
            # a top joined to two planes that meet at a concave edge: the tops of two objects
            # side by side made one plane stay with one of them
            cc = [(a, b) for a, b in pairs if (a, b) not in joined]
            if cc:
                joined -= shared_top_cuts(planes, joined, cc, edges, params.concave_tol)
        if params.concave_cut > 0 and edges is not None:
            # two planes at a clear concave edge joined through other planes: the group is
            # cut where it is weakest between them (planerel.features.concave_cut)
            cc = [(a, b) for a, b in pairs if (a, b) not in joined]
            if cc:
                joined -= concave_cuts(planes, joined, cc, edges, params.concave_cut)
        pairs = sorted(joined)
    g.add_edges(pairs)
    lab = getattr(planes, "labels", None)
    if (params.split_concave and params.cavities and params.occluded_pieces and cloud is not None
            and lab is not None and lab.shape == cloud.xyz.shape[:2]):
        # pieces of one surface seen on both sides of something in front of it (not adjacent)
        exclude = None
        if params.occluded_flat and params.skin_height > 0 and drop:
            # a piece of the support's surface (a bend the skin rule drops when alone) is no
            # piece of an object's top: two such pieces joined would make a proposal
            byl2 = {p.label: p for p in planes}

            def exclude(k) -> bool:
                return _support_skin(byl2[k], drop, byl2, relations, params, planes.floor)
        g.add_edges(occluded_piece_pairs(planes, relations, lab, cloud.xyz, drop, params.concave_tol,
                                         params.coplanar_depth or 0.0,
                                         relations.params.adjacency_gap, params.piece_gap,
                                         together=g.together, flat=params.occluded_flat,
                                         near=params.occluded_near, flat_depth=params.piece_depth,
                                         exclude=exclude))
    if params.step_chains:
        g.add_edges(step_chain_pairs(
            planes, g.nodes, (params.step_rise_min, params.step_rise_max),
            (params.step_run_min, params.step_run_max), params.step_overlap or 0.5,
            params.concave_tol, tilt=params.step_tilts, cut_long_side=params.cut_long_side,
            skip_missing=params.skip_missing, tread_axes=params.step_tread_axes,
            cut_top=params.step_cut_top, cut_chain=params.step_cut_chain,
            tread_pieces=params.step_tread_pieces, two_risers=params.step_two_risers))
    if params.stacked_boards:
        # a shelf's boards, one over another at regular heights (planerel.features.boards)
        g.add_edges(stacked_board_pairs(planes, g.nodes, (params.step_rise_min, params.board_rise_max),
                                        params.board_overlap, params.concave_tol, params.step_tilt))
    if params.open_treads:
        # an open-riser flight's treads: slabs at regular levels that do not touch
        # (planerel.features.open_treads)
        g.add_edges(open_tread_pairs(planes, g.nodes, (params.step_rise_min, params.step_rise_max),
                                     params.step_run_max, OPEN_THICK, OPEN_TILT))
    if params.split_concave and params.cavities and params.group_channels and concave:
        # side walls facing each other across a group of joined planes that together span
        # them (a flight between its side walls; planerel.features.cavities)
        group_of = {k: i for i, c in enumerate(g.groups()) for k in c}
        chan = group_channel_pairs(planes, concave, group_of, params.concave_tol,
                                   params.cavity_overlap, params.side_wall_members,
                                   params.side_wall_rise_max, params.side_wall_follow,
                                   None if cloud is None else cloud.xyz,
                                   params.step_rise_min, params.wall_window)
        if (params.channel_room_walls and chan and cloud is not None and lab is not None
                and lab.shape == cloud.xyz.shape[:2] and getattr(planes, "up", None) is not None):
            # a stairwell's room walls (their top out of view at the image border) are no
            # sides of the flight they face across (walls36)
            kept = _without_room_walls(planes, chan, cloud)
            room_walls = {w for w, _m in chan} - {w for w, _m in kept}
            chan = kept
        g.add_edges(chan)
    byl = {p.label: p for p in planes}
    if params.flight_sides and cloud is not None and lab is not None and lab.shape == cloud.xyz.shape[:2]:
        # a flight's side face (no support, or under support_min_area: a far balustrade's
        # inside) joins the flight whose nosings its top follows
        kept = [p for p in planes if p.label not in drop]
        for v in kept:
            if v.orientation != "vertical" or v.area < params.border_wall_area:
                continue
            near = _flight_steps(planes, v, kept, params)
            if len(near) < 2:
                continue
            line = None
            for grp in g.groups():
                if v.label in grp:
                    continue
                inside = set(grp)
                steps = [q for q in near if q.label in inside]
                if len(steps) < 2:
                    continue
                if line is None:
                    line = top_line(v, planes.up, cloud.xyz, lab)
                    if line is None:
                        break  # no top edge seen: nothing to follow
                if flight_side(v, steps, planes.up, cloud.xyz, lab, params.side_wall_follow,
                               params.step_rise_min, params.side_wall_rise_max, params.wall_tol,
                               line=line):
                    g.add_edges([(v.label, steps[0].label)])
    comps = [tuple(sorted(c)) for c in g.groups()]
    comps = [c for c in comps if sum(byl[x].n_points for x in c) >= params.min_points]
    if room_walls:
        # a stairwell's room wall left alone (with small vertical pieces at most): environment
        comps = [c for c in comps if not (room_walls.intersection(c) and all(
            x in room_walls or (byl[x].orientation == "vertical"
                                and byl[x].area < params.border_wall_area) for x in c))]
    if params.drop_border_walls:
        lab = getattr(planes, "labels", None)
        grid = cloud is not None and lab is not None and lab.shape == cloud.xyz.shape[:2]
        look = params.wall_behind < 1 and grid
        floors = [byl[s] for s in drop if s in byl and byl[s].orientation == "horizontal"] if grid else []

        def floor_behind(c) -> bool:
            """A wall-sized plane of ``c`` has the floor beyond it (wall_floor_behind)."""
            return (params.wall_floor_behind > 0 and bool(floors)
                    and any(floor_beyond(lab, cloud.xyz, byl[x], floors) >= params.wall_floor_behind
                            for x in c if byl[x].area >= params.border_wall_area))

        def wedge_side(c) -> bool:
            """A wall-sized plane of ``c`` is a wedge's side (wedge_side_max)."""
            return (params.wedge_side_max > 0 and grid
                    and bool(wedge_sides(planes, [x for x in c
                                                  if byl[x].area >= params.border_wall_area],
                                         relations, cloud, params.wedge_side_max)))

        def border_wall(c) -> bool:
            return (all(byl[x].orientation == "vertical" for x in c)
                    and any(byl[x].touches_border for x in c)
                    and max(byl[x].area for x in c) >= params.border_wall_area
                    and (not look or seen_behind(lab, cloud.xyz, c) <= params.wall_behind)
                    and not floor_behind(c) and not wedge_side(c))

        comps = [c for c in comps if not border_wall(c)]
    if params.min_border_area > 0:
        comps = [c for c in comps
                 if not (len(c) == 1 and byl[c[0]].touches_border
                         and byl[c[0]].area < params.min_border_area)]
    if params.skin_height > 0 and drop:
        comps = [c for c in comps
                 if not (len(c) == 1 and _support_skin(byl[c[0]], drop, byl, relations, params, planes.floor))]
    return sorted(comps, key=lambda c: c[0])


#: A piece lying whole above the support (``ProposalParams.skin_lifted``): its hull's lowest point at
#: least this fraction of its highest (a slab parallel to the support, not a bend rising from it).
SKIN_LIFT = 0.5


def _support_skin(p, support, byl, relations: Relations, params: ProposalParams, floor=None) -> bool:
    """``p`` is a piece of a horizontal support plane's surface (``params.skin_height``): not
    vertical, at most ``skin_angle`` degrees from such a plane that is the floor (label
    ``floor``) or adjacent to it, and its hull within ``skin_height * max(1, z)`` of that
    plane (z: p's distance from the sensor)."""
    if p.orientation == "vertical":
        return False
    scale = max(1.0, math.hypot(*np.asarray(p.centroid, float).tolist()))
    hull = np.asarray(p.hull3d, float)
    for s in support:
        q = byl.get(s)
        if q is None or q.orientation != "horizontal":
            continue
        try:
            r = relations.get(p.label, s)
        except KeyError:
            continue
        if not (r.adjacent or s == floor) or r.angle > params.skin_angle:
            continue
        n = np.asarray(q.normal, float)
        h = np.abs((hull - np.asarray(q.centroid, float)) @ n)
        top, low = float(h.max()), float(h.min())
        if top <= params.skin_height * scale:
            if params.skin_lifted and low >= params.skin_height and low >= SKIN_LIFT * top:
                continue  # lying whole above the surface: a thing on it (a laptop's base), no bend
            return True
    return False


def objects_from_truth(labels, gt_labels, gt_object_of_label, min_fraction: float = 0.5) -> list[tuple[int, ...]]:
    """Group (segmented) planes by the ground-truth object they mostly cover.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
        Plane labels (a segmentation, or the ground truth itself).
    gt_labels : ndarray, shape (H, W), int
        Ground-truth plane labels.
    gt_object_of_label : mapping or sequence
        Ground-truth object id (>= 0) of each ground-truth plane label; < 0 or missing =
        support / no object.
    min_fraction : float
        A plane joins an object when at least this fraction of its pixels lies on that
        object's ground-truth planes.

    Returns
    -------
    list of tuple of int
        Plane labels per ground-truth object, ordered by object id (objects with no plane are
        left out).
    """
    lab = np.asarray(labels)
    gt = np.asarray(gt_labels)
    if lab.shape != gt.shape:
        raise InputError(f"label image {lab.shape} and ground truth {gt.shape} differ in shape")
    if isinstance(gt_object_of_label, dict):
        getobj = gt_object_of_label.get
    else:
        seq = list(gt_object_of_label)

        def getobj(k, default=-1):
            return seq[k] if 0 <= k < len(seq) else default
    gmax = int(gt.max()) + 1 if gt.size and gt.max() >= 0 else 0
    obj_map = np.full(gmax + 1, -1, np.int64)
    for k in range(gmax):
        o = getobj(k, -1)
        obj_map[k] = -1 if o is None else int(o)
    objpix = np.where(gt >= 0, obj_map[np.where(gt >= 0, gt, gmax)], -1)
    groups: dict[int, list[int]] = {}
    sel = lab >= 0
    if not sel.any():
        return []
    L = lab[sel].astype(np.int64)
    obj = objpix[sel]
    nobj = int(obj.max()) + 2
    code = L * nobj + (obj + 1)
    uniq, cnt = np.unique(code, return_counts=True)
    total = np.bincount(L)
    best: dict[int, tuple[int, int]] = {}
    for cde, c in zip(uniq.tolist(), cnt.tolist(), strict=True):
        lbl, o = divmod(cde, nobj)
        o -= 1
        if lbl not in best or c > best[lbl][1]:
            best[lbl] = (o, c)
    for lbl, (o, c) in sorted(best.items()):
        if o >= 0 and c >= min_fraction * total[lbl]:
            groups.setdefault(o, []).append(lbl)
    return [tuple(sorted(groups[o])) for o in sorted(groups)]


def proposal_match(labels, proposals, truth, min_iou: float = 0.8) -> dict:
    """How well proposals match true objects, by pixels.

    Parameters
    ----------
    labels : ndarray, shape (H, W)
        Plane labels the proposals refer to.
    proposals : list of tuple of int
        Plane labels per proposed object.
    truth : ndarray, shape (H, W), int
        True object id per pixel (-1 = no object).
    min_iou : float
        A true object is matched when some proposal covers it with at least this pixel IoU.

    Returns
    -------
    dict
        ``n_true``, ``n_proposals``, ``matched`` (true objects matched), ``ious`` (best IoU per
        true object, by object id order).
    """
    lab = np.asarray(labels)
    tr = np.asarray(truth)
    if lab.shape != tr.shape:
        raise InputError(f"label image {lab.shape} and true objects {tr.shape} differ in shape")
    prop_img = np.full(lab.shape, -1, np.int64)
    for k, plist in enumerate(proposals):
        prop_img[np.isin(lab, list(plist))] = k
    ids = [int(x) for x in np.unique(tr) if x >= 0]
    ious = []
    for o in ids:
        m = tr == o
        best = 0.0
        cand = np.unique(prop_img[m])
        for k in cand[cand >= 0]:
            pm = prop_img == k
            inter = np.count_nonzero(pm & m)
            union = np.count_nonzero(pm | m)
            best = max(best, inter / union if union else 0.0)
        ious.append(best)
    matched = sum(1 for x in ious if x >= min_iou)
    return {"n_true": len(ids), "n_proposals": len(proposals), "matched": matched, "ious": ious}
