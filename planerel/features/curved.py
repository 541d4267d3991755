"""Curved and unexplained surfaces: their own object proposals, and each object's planar fraction.

A plane segmentation explains a box with a few large flat planes; a round object (bowl, mug,
standing or lying cylinder) comes out either as a fan of narrow *facets* that meet at small
angles, or as points no plane explains.  This module tells the two apart, so the learner can
tell a bowl from a box and ``other`` can be the answer for it.

The rule (:func:`curved_objects`), with the parameters of :class:`CurvedParams`:

1. **Facets.**  Among the non-support planes, link two adjacent planes (``relate``: touching
   in the grid or hulls within the adjacency gap) whose angle lies in ``[facet_min_angle,
   facet_max_angle]`` (5-50 degrees: neighbouring strips of one round surface; the faces of a
   box meet at about 90, a ramp's slope and its platform form a chain of two).  Every plane in
   a linked group with at least ``facet_min_planes`` (3) distinct normal directions (normals
   within ``facet_min_angle`` count once: two pieces of one box face linked through a sliver
   are one direction) is a facet of a curved surface.  A plane at least ``facet_max_width``
   (0.05 m) wide and ``facet_wide_ratio`` (1.5) times wider than every plane it links to is a
   flat face, in no link (2026-11-29): a real carpeted stair's rounded nosings are narrow
   strips between its wide treads and risers, and through them the whole flight read as
   round.
   **Islands** (``island_faces``, 2026-12-01): so is a plane at least ``facet_max_width`` wide
   that touches none of the planes it links to in the grid (a depth step all round: a
   carton's top lying on a pile in a bin); a round surface's strips touch each other.
   **Rough planes** (``flat_bend``, 2026-11-30): a group whose points (every plane's, together)
   fit a quadric that turns by less than ``flat_bend`` over their extent
   (:func:`surface_bend`: about 0.02 for a RealSense box top cut into 8 bumps' flanks 5-28
   degrees apart, 0.16 and more for the round objects of the real table-top frames) and
   whose planes are all narrower than ``flat_piece_width`` (0.12 m) is one rough plane, not
   facets.
   **Within objects** (facets22, 2026-11-28): a link between planes of two object proposals
   counts only when both proposals are *soft* (every plane a facet of the links of every pair,
   linked to a plane of its own proposal, or under ``small_area``).  A proposal that holds a
   flat face is a solid object: its face 2-5 cm from a lying cylinder's strip, or from the
   face of a box turned on it, is two objects side by side, and read as a facet it made a box
   look round (planar fraction 0.16-0.55 on the table-top sets).  A bowl's inside strips, each
   a proposal of its own (cut at their concave edges), stay linked.
2. **Unexplained points.**  Valid pixels that are in no plane, or in a plane smaller than
   ``tiny_area`` m^2, and not on a support plane, are opened morphologically by
   ``open_px`` pixels (thin strips along box edges and occluding borders vanish), then grouped
   into clusters connected in the image grid with neighbours within ``edge_depth * max(1, z)``
   metres in 3-D.  A cluster counts when its area (each pixel's footprint ``z^2 / (fx fy)`` at
   its measured depth, :func:`pixel_areas`; not a pixel count) is at least ``min_area`` m^2
   (0.01: smaller clusters are mostly noise of far surfaces).
   **Grown back** (``regrow_px`` = 3; 2026-11-28, seventh pass): each cluster so found grows
   back ``regrow_px`` steps (4-neighbours, same connection rule) into the unexplained pixels
   *before* the opening, and clusters that meet there become one.  The opening cuts a small
   unsegmented box at 3-4 m into its top and its front (the pixels that connect them lie
   along its outline, in strips one or two pixels wide, which the opening removes) and shaves
   its rim; which clusters exist is still decided on the opened pixels (no new cluster from
   specks).  Growing back whole components instead (an opening by reconstruction) found the
   same boxes but crawled along the unexplained rims of planes: in office1 it joined a door's
   outline, a floor strip and a wall's edge into one proposal.
   **Nested parts** (``nest_depth``, ``nest_px``, ``nest_credit``; 2026-11-29): near
   components too small to keep that lie within ``nest_px`` pixels and ``nest_depth`` x depth
   of each other (a mug's outside and its inside seen over the rim, apart across the sensor's
   band of no depth) count together, with the area of a small one-plane proposal beside them;
   a part of at least half ``near_min_area`` joins the one kept cluster it reaches.
3. **Merging.**  A cluster joins every proposal it touches (grid neighbours within
   ``edge_depth``) whose planes are all facets or smaller than ``small_area`` m^2 (the rest
   of a round object); touching no such proposal, it is a proposal of its own (with the tiny
   planes inside it, which have no proposal).  Clusters joined to one proposal merge.
4. **Attributes.**  ``planar_fraction``: the fraction of an object's points (its planes'
   points plus its cluster pixels) that lie in *flat* planes: not facets, at least
   ``tiny_area`` m^2.  ``curved``: ``planar_fraction < curved_below`` (0.8).
On the shared mOSD frames the boxes of ``learn0-5`` keep a planar fraction of 1.00 and the
three cylinders of ``test31`` have 0.16, 0.26 and 0.66 (all curved); docs/objects.md gives the
figures and the commands.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError, check_bools
from planerel.features.planes import label_max
from planerel.features.relations import Components, adjacent_only
from planerel.io.cloud import Cloud
from planerel.segment.absorb import FACET_MAX_ANGLE, FACET_MIN_ANGLE

__all__ = ["CurvedParams", "CurvedObject", "facet_planes", "surface_bend", "skirt_faces", "pixel_areas", "join_parts",
           "unexplained_clusters", "curved_objects"]


@dataclass(frozen=True)
class CurvedParams:
    """Parameters of :func:`curved_objects` (see the module docstring for the rule).

    Parameters
    ----------
    facet_min_angle, facet_max_angle : float
        Degrees: two adjacent planes at an angle in this range are neighbouring facets.
    facet_min_planes : int
        Planes linked this way in a group with at least this many distinct normal directions
        are facets (curved).
    facet_max_width, facet_wide_ratio : float
        Metres, a ratio: a plane at least ``facet_max_width`` wide (its hull's shorter side,
        ``Plane.width``) and ``facet_wide_ratio`` times wider than every plane it is linked to
        is a flat face, never a facet, and facet links do not pass through it.  A real
        carpeted staircase's rounded nosings segment into strips 2-9 cm wide, 11-65 degrees
        from each other and from the tread and riser they join: the links ran through them
        into the 0.14-0.28 m wide treads and risers, and the whole flight read as round
        (planar fraction 0.06, the stairs answer refused; stair-perception ``0000``,
        benchmarks/real_stairs.py).  A round object's strips are alike in width, however
        wide: 2-4 cm on the mOSD cylinders, 0.11-0.13 m on a 0.15 m cylinder at 2 m, 0.137 m
        on the synthetic worlds' 16-sided drums of radius 0.35.  ``facet_max_width`` 0 = no
        such face (before 2026-11-29).  0.05 since 2026-11-30 (0.12 before): a milk carton's
        faces (0.096-0.099 m wide at 1 m, a Kinect frame nobody on the team had made) meet
        at a 1.2-1.4 cm strip the segmentation cuts along their edge, 20-27 degrees from each;
        linked through it, the carton read as round (planar fraction 0.00, the box answer
        refused).  The strips of one round surface stay alike in width (ratio under 1.5).
    flat_bend : float
        Radians (a turn over one standard deviation of extent, :func:`surface_bend`): a facet
        group whose points turn by less than this is a rough plane in pieces, not facets
        (0 = no such test, before 2026-11-30).  A RealSense 0.63 m over a wooden block lays
        bumps of 1.9 mm RMS and ~2 cm across over its top; region growing cut the top into 8
        pieces 5-28 degrees apart, a fan of facets (planar fraction 0.39: the box answer
        refused; hidden26's ycb3, a frame nobody on the team had made).  Their points
        together turn by 0.02; every facet group of a round object in the real table-top
        frames (mOSD, OSD, UOIS: cans, mugs, bowls) turns by at least 0.16 (most are too
        thick to be a sheet at all: ``inf``).  A group is measured from at most
        ``BEND_POINTS`` of its points, only when ``facet_planes`` has the cloud.
    flat_piece_width : float
        Metres: a group with a plane at least this wide (``Plane.width``) is never a rough
        plane (no bump tilts a face that wide; the bumps' flanks of the RealSense top are
        0.02-0.08 m wide).  The furniture in the corner of the shared Kinect frame
        ``frame_20121214T142255`` shows two faces 0.18 and 0.21 m wide 6.4 degrees apart and
        a strip 17-22 degrees from them, at 1.2 m: a crease, over which a quadric turns by
        0.085 only; without this bound it read flat and the corner rule made it a second
        ``box`` in that frame.
    tiny_area : float
        m^2: planes smaller than this are not flat planes; their pixels count as unexplained.
    open_px : int
        Pixels: radius of the morphological opening of the unexplained pixels (0 = none).
    edge_depth : float
        Metres at 1 m (scaled by the depth): grid neighbours farther apart in 3-D are not
        connected.
    min_area : float
        m^2: smallest surface area of a cluster of unexplained points that is kept.
    small_area : float
        m^2: a cluster joins a touching proposal whose planes are all facets or smaller than this.
    join_area : float
        m^2: a cluster that touches one proposal only (support planes aside), made of one plane
        smaller than this, joins it when they touch along at least ``join_touch`` grid pixel
        pairs: the rest of a round object one flat-looking piece of which the segmentation made
        a plane (a cylinder's side seen at 3 m; a small box's face beside its unexplained
        top); 0 = only the ``small_area`` rule.
    join_touch : int
        Grid pixel pairs (within two pixels, ``edge_depth``) such a cluster and plane touch
        along at least.
    bridge_area : float
        m^2: a cluster that joins nothing else and touches exactly two proposals (support
        aside), each along at least ``bridge_touch`` grid pixel pairs and each with planes of
        ``bridge_min`` to under this area in all, and has at most as many pixels as their
        planes together, joins both: the unsegmented faces between two faces of one
        object (an open box's end walls between its long walls, a closed flight's middle
        risers between its top tread and its lower steps, a shelf's back and boards between
        its side panels; synth22r).  0 = off (before synth22r).
    bridge_touch : int
        Grid pixel pairs such a cluster touches each of the two proposals along at least (3,
        as ``join_parts``: a face's unsegmented neighbour meets it along its edge band, which
        the clusters' opening narrows).
    bridge_min : float
        m^2: the least area of each proposal ``bridge_area`` joins (0.03).  A table-top
        object's faces are smaller, and there a lying cylinder's unexplained side touching its
        own top strip and a box beside it made one proposal, answered ``stairs`` (table-top
        seed 11 ``t0005``, planes of 0.018 and 0.075 m^2); the room-scale joins it is for had
        0.049-0.44 m^2 (synth22r).
    curved_below : float
        An object is ``curved`` when its planar fraction is below this.
    enabled : bool
        False: no cluster proposals (planar fractions are still measured).
    regrow_px : int
        Pixels: each cluster kept (``min_area`` on the opened pixels) grows back this many
        steps into the unexplained pixels before the opening (4-neighbours within
        ``edge_depth``); clusters that meet there become one.  0: the opened pixels'
        components (before the seventh pass).
    stepped_clusters : bool
        Clusters of unexplained points that lie on a staircase's profile become its treads and
        risers, one proposal (:mod:`planerel.features.stairfit`; applied by
        :func:`planerel.features.facts.describe_scene` when it proposes the objects).
    near_min_area, near_depth : float
        m^2, metres: a cluster whose pixels' mean depth is at most ``near_depth`` is kept from
        ``near_min_area`` (0.004: a mug or a can at 0.6-1.5 m shows 0.004-0.01 m^2; the
        sensor's noise at that range makes few specks that survive the opening);
        ``near_depth`` = 0: ``min_area`` everywhere (before tabletop22).
    nest_depth : float
        Metres at 1 m (scaled by the depth): near clusters each too small to keep that touch in
        the grid with their points at most this far apart in 3-D count together, and are kept
        as one cluster when their areas together reach ``near_min_area`` (0.1).  The outside of
        a mug and the inside wall seen over its rim touch in the image across a depth jump of
        2-8 cm, wider than ``edge_depth``: each part alone (0.002-0.004 m^2 at 0.8-1.1 m) was
        under ``near_min_area``, so the mug had no proposal (2026-11-29).  A part of at least
        half ``near_min_area`` linked to one kept cluster joins it; kept clusters never join
        each other.  0: off (and ``nest_credit`` with it).
    nest_px : int
        Pixels: such parts join when pixels of both lie within this many grid pixels (4): a
        depth sensor leaves no depth in a band 1-5 px wide at the jump (the rim occluding the
        inside), so the two parts do not touch in the image.
    nest_credit : float
        m^2: parts linked the same way (``nest_px``, ``nest_depth``) to the plane of a
        proposal made of that plane alone, of at most this area (0.008), and to no kept
        cluster, count that plane's area too; kept so, they join its proposal.  A mug whose
        bottom or a flat-looking strip of its side is a small plane, its other points in parts
        under ``near_min_area``.  0: off.
    join_parts : bool
        After the clusters (and the raised groups), each connected part of the unassigned
        pixels that no proposal holds (4-neighbours within ``edge_depth``) joins the one
        proposal it touches (at least 3 grid pixel pairs within two pixels and
        ``edge_depth``; no other proposal touched at all) when it has at most as many pixels
        as that proposal (:func:`join_parts`): a chair's or a table's legs, 3-5 pixels wide,
        which the clusters' opening removes, and a seat's edge (synth22q: seed 33 ``s0040``'s
        chair, IoU 0.49 -> 0.90).  It widens the proposal's pixels only: the planar
        fraction and ``curved`` stay as they were.  Off by default: it found 3 more objects on
        five synthetic seeds and 11 on two table-top sets; compiled (join22) it costs
        0.35-1.2 ms a 640x480 frame and ~4 ms on ``office1`` (numpy: 1.7-4.9 and 22 ms), not
        yet the ~0.3 ms wanted of a default (docs/objects.md, "Synthetic misses (synth22q)"
        and "join_parts compiled (join22)").
    join_facets : bool
        Proposals made only of facets (and planes under ``small_area``) that hold two facets
        linked by the facet rule (adjacent, ``facet_min_angle``-``facet_max_angle`` apart) are
        one proposal: the strips of a bowl's inside meet at concave edges, which the proposal
        rule cuts, and each was a curved proposal of its own (tabletop22).
    island_faces : bool
        A plane at least ``facet_max_width`` wide that touches none of the planes the facet
        rule links it to (every link across a depth step, through the hulls' adjacency gap
        only) is a flat face, in no link: a carton's top lying on a pile in a bin, 1.5-3 cm
        above the tilted pieces around it, was a facet of the pile and the carton one of 18
        proposals merged into one curved object (bin37, docs/objects.md "A carton's top on a
        pile").  A round surface's strips touch each other.  False: the rule before.
    """

    facet_min_angle: float = FACET_MIN_ANGLE
    facet_max_angle: float = FACET_MAX_ANGLE
    facet_min_planes: int = 3
    facet_max_width: float = 0.05
    facet_wide_ratio: float = 1.5
    flat_bend: float = 0.1
    flat_piece_width: float = 0.12
    tiny_area: float = 0.0005
    open_px: int = 2
    edge_depth: float = 0.02
    min_area: float = 0.01
    small_area: float = 0.002
    join_area: float = 0.25
    bridge_area: float = 0.5
    bridge_touch: int = 3
    bridge_min: float = 0.03
    join_touch: int = 10
    curved_below: float = 0.8
    enabled: bool = True
    stepped_clusters: bool = True
    regrow_px: int = 3
    join_facets: bool = True
    near_min_area: float = 0.004
    near_depth: float = 1.5
    nest_depth: float = 0.1
    nest_px: int = 4
    nest_credit: float = 0.008
    join_parts: bool = False
    skirt_faces: bool = True
    island_faces: bool = True

    def __post_init__(self) -> None:
        for name in ("facet_min_angle", "facet_max_angle", "facet_max_width", "facet_wide_ratio",
                     "flat_bend", "flat_piece_width", "tiny_area", "edge_depth", "min_area",
                     "small_area", "join_area", "bridge_area", "bridge_min", "curved_below", "near_min_area", "near_depth",
                     "nest_depth", "nest_credit"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
                raise InputError(f"{name} must be a number >= 0, got {v!r}")
        if not self.facet_min_angle <= self.facet_max_angle <= 90:
            raise InputError(f"facet angles must satisfy 0 <= facet_min_angle <= facet_max_angle "
                             f"<= 90, got {self.facet_min_angle!r} and {self.facet_max_angle!r}")
        for name, lo, hi in (("facet_min_planes", 2, 1000), ("open_px", 0, 10), ("regrow_px", 0, 50), ("nest_px", 1, 20),
                             ("join_touch", 0, 10 ** 9), ("bridge_touch", 0, 10 ** 9)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
                raise InputError(f"{name} must be an integer in {lo}..{hi}, got {v!r}")
        if self.curved_below > 1:
            raise InputError(f"curved_below is a fraction in [0, 1], got {self.curved_below!r}")
        check_bools(self)


@dataclass(frozen=True, eq=False)
class CurvedObject:
    """One object proposal with its unexplained pixels and planar fraction.

    Attributes
    ----------
    planes : tuple of int
        Plane labels (sorted).
    mask : ndarray (H, W) bool or None
        Unexplained pixels that belong to the object (None: none).
    planar_fraction : float
        Fraction of the object's points in flat planes, 0..1.
    curved : bool
        ``planar_fraction < curved_below``.
    n_points : int
        Points of the planes plus pixels of the mask.
    """

    planes: tuple
    mask: np.ndarray | None
    planar_fraction: float
    curved: bool
    n_points: int


#: Largest ratio of a group's thickness to its middle extent (standard deviations along its
#: least and middle principal axes) that :func:`surface_bend` fits: the bumpy RealSense top
#: of hidden26's ycb3 block is 0.08, an arc of a cylinder of +-alpha about 0.26 alpha (0.2 at
#: +-45 degrees); a thicker group is no sheet and turns (``inf``).
BEND_THICK = 0.2


def surface_bend(xyz) -> float:
    """How far a surface sampled by ``xyz`` may turn over its extent: ``max |k| * s``.

    A quadric ``w = a u^2 + b u v + c v^2 + d u + e v + f`` is fitted by least squares in the
    points' principal frame (``w`` along the least principal axis, ``u``, ``v`` along the
    others); ``k`` are the eigenvalues of its Hessian ``[[2a, b], [b, 2c]]`` (the principal
    curvatures, 1/m) and ``s`` the points' standard deviation along their longest axis (m).
    The product bounds the angle (radians) the surface's normal turns over one standard
    deviation of its extent: about ``alpha / sqrt(3)`` for an arc of a cylinder seen over
    ``+-alpha`` and no longer along its axis than across, whatever its radius (more for a
    longer one); near 0 for a plane, even a rough one (a rough plane's bumps are no one
    curvature).

    Parameters
    ----------
    xyz : ndarray, shape (N, 3)
        Finite points, N >= 6.

    Returns
    -------
    float
        Dimensionless; ``inf`` for fewer than 6 points, a degenerate fit, or points thicker
        than ``BEND_THICK`` times their middle extent (standard deviations along the least
        and the middle principal axis): no thin sheet, so no height field to fit.
    """
    pts = np.asarray(xyz, float)
    if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) < 6:
        return float("inf")
    # (the centred points and the quadric's terms filled in compiled loops, into arrays
    # numpy allocates: the same floats as numpy's mean, differences and products, about
    # 0.2 ms a group less; a layout those loops do not reproduce takes numpy's own)
    fast = pts.flags.c_contiguous
    if fast:
        from planerel.features._curved_kernels import center_rows, quadric_terms

        c = np.empty_like(pts)
        center_rows(pts, c)
    else:
        c = pts - pts.mean(0)
    ev, vec = np.linalg.eigh(c.T @ c / len(pts))
    if not ev[2] > 0 or ev[0] > (BEND_THICK ** 2) * ev[1]:
        # no thin sheet: no height field over its principal plane (a cylinder seen from
        # above its side turns through 180 degrees)
        return float("inf")
    loc = c @ vec
    w = loc[:, 0]
    if fast and loc.flags.c_contiguous:
        a = np.empty((len(loc), 6))
        quadric_terms(loc, a)
    else:
        v, u = loc[:, 1], loc[:, 2]
        a = np.stack([u * u, u * v, v * v, u, v, np.ones_like(u)], 1)
    # the normal equations (6 x 6): a least-squares solve of the N x 6 system took 4 ms a
    # group under load
    coef, _, rank, _ = np.linalg.lstsq(a.T @ a, a.T @ w, rcond=None)
    if rank < 6:
        return float("inf")
    hess = np.array([[2 * coef[0], coef[1]], [coef[1], 2 * coef[2]]])
    # the larger principal curvature over the longest extent: the most the normal may turn
    # (each curvature over the spread along its own direction made the far walls of a
    # RealSense frame, bent by the sensor, rough planes too, and inclined: two more false
    # ramp answers on UOIS image_0008)
    return float(np.max(np.abs(np.linalg.eigvalsh(hess))) * np.sqrt(ev[2]))


#: Points at most that :func:`surface_bend` reads of one facet group (an even sample).
BEND_POINTS = 3000


def _group_points(comp, byl, labels, xyz) -> np.ndarray:
    """The finite points of the planes ``comp`` (labels) in ``labels``, read within the
    planes' pixel boxes, at most about ``BEND_POINTS`` of them (every k-th).

    One compiled pass with a label lookup table
    (:func:`planerel.features._curved_kernels.group_points`) for labels of non-negative
    integers and float64 points; :func:`_group_points_isin` (numpy's ``isin``, the same
    points in the same order: ``tests/test_curved.py`` compares) otherwise."""
    boxes = [byl[x].bbox for x in comp]
    r0, c0 = min(b[0] for b in boxes), min(b[1] for b in boxes)
    r1, c1 = max(b[2] for b in boxes), max(b[3] for b in boxes)
    ids = [int(x) for x in comp]
    if (ids and min(ids) >= 0 and labels.ndim == 2 and labels.dtype.kind in "iu"
            and xyz.dtype == np.float64 and xyz.ndim == 3 and xyz.shape[:2] == labels.shape):
        from planerel.features._curved_kernels import group_points

        lut = np.zeros(max(ids) + 1, np.bool_)
        lut[ids] = True
        # the box as slicing takes it (negative bounds from the end, clipped to the image)
        y0, y1, _ = slice(int(r0), int(r1)).indices(labels.shape[0])
        x0, x1, _ = slice(int(c0), int(c1)).indices(labels.shape[1])
        return group_points(labels, xyz, y0, y1, x0, x1, lut, BEND_POINTS)
    return _group_points_isin(comp, labels, xyz, (r0, c0, r1, c1))


def _group_points_isin(comp, labels, xyz, box) -> np.ndarray:
    """:func:`_group_points` with numpy's ``isin`` over the box ``(r0, c0, r1, c1)``."""
    r0, c0, r1, c1 = box
    lab = labels[r0:r1, c0:c1]
    sel = np.isin(lab, np.fromiter(comp, dtype=np.int64))
    pts = xyz[r0:r1, c0:c1][sel]
    step = max(1, len(pts) // BEND_POINTS)
    pts = pts[::step]
    return pts[np.isfinite(pts).all(axis=1)]


def _facet_groups(planes, links, params: CurvedParams, surface=None, bends=None) -> set:
    """Planes of the groups that ``links`` (pairs of labels) join with at least
    ``facet_min_planes`` distinct normal directions, and, with ``surface`` = ``(labels,
    xyz)`` and ``params.flat_bend`` > 0, whose points turn by at least ``flat_bend``
    (:func:`surface_bend`; ``bends``, ``{frozenset of labels: bend}``, keeps each group's
    measure for a later call on the same planes)."""
    bends = {} if bends is None else bends
    byl = {p.label: p for p in planes}
    if params.facet_max_width > 0:
        # a plane this wide, and much wider than every plane it links to, is a flat face (a
        # step's tread or riser beside its rounded nosing's strips), never a facet, and links
        # through it do not join strips; a round object's strips are alike in width
        near: dict = {}
        for a, b in links:
            near[a] = max(near.get(a, 0.0), byl[b].width)
            near[b] = max(near.get(b, 0.0), byl[a].width)
        wide = {x for x, w in near.items() if byl[x].width >= params.facet_max_width
                and byl[x].width >= params.facet_wide_ratio * w}
        links = [(a, b) for a, b in links if a not in wide and b not in wide]
    g = Components()
    g.add_edges(links)
    cos_min = np.cos(np.radians(params.facet_min_angle))
    out: set = set()
    for comp in g.groups():
        # distinct directions: nearly parallel planes linked through a sliver are one face
        dirs: list = []
        for x in sorted(comp, key=lambda x: (-byl[x].n_points, x)):
            n = np.asarray(byl[x].normal, float)
            if all(abs(float(n @ d)) < cos_min for d in dirs):
                dirs.append(n)
        if len(dirs) < params.facet_min_planes:
            continue
        if (surface is not None and params.flat_bend > 0 and all(x in byl for x in comp)
                and max(byl[x].width for x in comp) < params.flat_piece_width):
            # a rough plane cut into pieces (a RealSense box top): its pieces' normals
            # scatter, but the surface as a whole does not turn; a piece as wide as a face
            # is tilted by no bump (a Kinect frame's furniture: faces 0.18-0.21 m wide
            # 6 degrees apart, a crease a quadric hardly bends over)
            key = frozenset(comp)
            if key not in bends:
                bends[key] = surface_bend(_group_points(comp, byl, *surface))
            if bends[key] < params.flat_bend:
                continue
        out.update(comp)
    return out


#: Share of a skirt's top's extent its face may reach past the top's ends for the two to be
#: flat faces (:func:`skirt_faces`).
FLUSH_BEYOND = 0.25


def skirt_faces(planes, relations, cloud, tilt: float | None = None,
                profiles: dict | None = None) -> set:
    """Labels of the planes that are a box's flat top and side: the two planes of a ``skirt``
    pair (or of a pair only a step denied, :attr:`~planerel.features.relations.Relations.skirt_steps`)
    whose top is horizontal or leans at most ``tilt`` degrees towards the face
    (:func:`~planerel.features.relations.leans_towards`; default the relations'
    ``skirt_top_tilt``) and whose face ends where the top ends: it reaches at most
    ``FLUSH_BEYOND`` of the top's extent along their edge past the top's ends.

    A box's top and side meet at a rounded edge (a cereal box, a carton, a plastic
    container); segmented, the edge is one or two narrow strips 30-60 degrees from both, and
    top, strips and side linked 5-50 degrees apart made a fan of four directions: the top (and
    a narrow side) read as facets of a round surface, the box's planar fraction fell to
    0.0-0.7 and the planar gate refused ``box`` (real OSD and RealSense frames, realbox).  A
    lying cylinder's top strip and its end face pass ``skirt`` too, but the end face reaches
    past both ends of the strip; a tilted top (a tilted box's, or a lying cylinder's strip
    seen aslant) counts no plane flat.  Without the cloud (an unorganized one) nothing is
    measured and no plane is flat.  ``profiles``: the faces' profiles already measured along
    ``planes.up`` in ``planes.labels`` and ``cloud.xyz`` (:func:`~planerel.features.relations.relate`'s
    ``profiles``), ``{label: FaceProfile}``; the others are measured here.
    """
    from planerel.features.relations import leans_towards
    from planerel.features.solid import PROFILE_POINTS, _skirt_geometry, face_profile_of

    labels = getattr(planes, "labels", None)
    if cloud is None or labels is None:
        return set()
    if tilt is None:
        tilt = getattr(getattr(relations, "params", None), "skirt_top_tilt", 0.0)
    denied = getattr(relations, "skirt_steps", {})
    # the relations' profile sample (relate's profiles are measured on it)
    points = getattr(getattr(relations, "params", None), "profile_points", PROFILE_POINTS)
    byl = {p.label: p for p in planes}
    up = np.asarray(planes.up, float)
    xyz = np.asarray(cloud.xyz, float)
    out: set = set()
    # (the skirt pairs first, in their order, when no pair was denied: most relations are none)
    for r in (relations if denied else [r for r in relations if r.skirt]):
        if not (r.skirt or (r.a, r.b) in denied) or r.a not in byl or r.b not in byl:
            continue
        top, face = byl[r.a], byl[r.b]
        if face.orientation != "vertical":
            continue
        if top.orientation != "horizontal" and not (top.incline <= tilt
                                                     and leans_towards(top, face, up)):
            continue
        prof = profiles.get(face.label) if profiles else None
        if prof is None:
            prof = face_profile_of(face, up, labels, xyz, points)
        _, _, beyond, span = _skirt_geometry(top, up, prof)
        if span is not None and beyond <= FLUSH_BEYOND * (span[3] - span[2]):
            out.update((r.a, r.b))
    return out


def facet_planes(planes, relations, candidates=None, params: CurvedParams | None = None,
                 proposals=None, flat=(), cloud=None, labels=None) -> set:
    """Labels of the planes that are facets of a curved surface (rule step 1).

    Parameters
    ----------
    planes : PlaneSet
    relations : Relations
    candidates : iterable of int, optional
        Labels considered (default every plane).
    proposals : sequence of sequence of int, optional
        Plane labels per object proposal.  With them a link between planes of two proposals
        counts only when both proposals are *soft*: made of facets (of the links of every
        pair), planes linked to a plane of their own proposal and planes under ``small_area``
        alone.  A proposal that holds a flat face is a
        solid object; a link from it to a plane of another object is two objects side by
        side (a box's top beside a lying cylinder's strip), not one curved surface
        (facets22).  Links within a proposal, and of planes in no proposal, always count.
    flat : iterable of int, optional
        Labels of planes that are flat faces, never facets (:func:`skirt_faces`).
    cloud : Cloud, optional
        With it (organized) a group whose points turn by less than ``params.flat_bend``
        (:func:`surface_bend`), its planes all narrower than ``params.flat_piece_width``, is
        a rough plane in pieces, not facets; without it no group is measured.
    labels : ndarray, shape (H, W), int, optional
        The plane labels of ``cloud``'s pixels (default ``planes.labels``).

    Returns
    -------
    set of int
    """
    params = params or CurvedParams()
    cand = {p.label for p in planes} if candidates is None else set(candidates)
    cand -= set(flat)
    lo, hi = params.facet_min_angle, params.facet_max_angle
    rels = [r for r in adjacent_only(relations)
            if r.a < r.b and r.adjacent and r.a in cand and r.b in cand and lo <= r.angle <= hi]
    if params.island_faces and params.facet_max_width > 0 and rels:
        # a face at least facet_max_width wide that touches none of the planes it links to (a
        # depth step all round: a carton's top lying on a pile) is a flat face, in no link
        touches: dict = {}
        for r in rels:
            for x in (r.a, r.b):
                touches[x] = touches.get(x, False) or bool(r.touching)
        width = {p.label: p.width for p in planes if p.label in touches}
        island = {x for x, t in touches.items() if not t and width.get(x, 0.0) >= params.facet_max_width}
        rels = [r for r in rels if r.a not in island and r.b not in island]
    links = [(r.a, r.b) for r in rels]
    surface = None
    if labels is None:
        labels = getattr(planes, "labels", None)
    if params.flat_bend > 0 and cloud is not None and labels is not None and links:
        xyz = np.asarray(cloud.xyz, float)
        if xyz.ndim == 3 and np.shape(labels) == xyz.shape[:2]:
            surface = (np.asarray(labels), xyz)
    bends: dict = {}  # each group's surface_bend, for the second call below
    out = _facet_groups(planes, links, params, surface, bends)
    if proposals is None or not out:
        return out
    byl = {p.label: p for p in planes}
    owner = {int(x): k for k, g in enumerate(proposals) for x in g}
    # planes linked to a plane of their own proposal: strips of one round surface, even when
    # too few directions made them facets (a mug's two strips beside a third in another
    # proposal)
    inner = {x for a, b in links if a in owner and b in owner and owner[a] == owner[b]
             for x in (a, b)}
    soft = [all(x in out or x in inner or (x in byl and byl[x].area < params.small_area)
                for x in g) for g in proposals]
    kept = [(a, b) for a, b in links
            if a not in owner or b not in owner or owner[a] == owner[b]
            or (soft[owner[a]] and soft[owner[b]])]
    if len(kept) == len(links):
        return out
    return _facet_groups(planes, kept, params, surface, bends)


def _pitch(xyz, axis: int) -> float:
    """Angular size of one pixel along image ``axis`` (1: along a row, 0: along a column):
    the median of ``|d(x / z)|`` (``|d(y / z)|``) between valid grid neighbours, ``1 / fx``
    (``1 / fy``) of a pinhole camera; 0 when no two neighbours are valid."""
    with np.errstate(invalid="ignore", divide="ignore"):
        q = xyz[..., 0 if axis == 1 else 1] / xyz[..., 2]
    d = np.abs(np.diff(q, axis=axis))
    d = d[np.isfinite(d)]
    return float(np.median(d)) if d.size else 0.0


def _pitches_at(xyz, r, c) -> tuple[float, float]:
    """The pitches along a row and a column measured at pixels ``(r, c)`` and their next
    neighbour along each axis (the whole image's where none has a valid one), from one pass
    over the pixels (:func:`planerel.features._curved_kernels.pitch_diffs_both`)."""
    from planerel.features._curved_kernels import pitch_diffs_both

    d1, d0 = pitch_diffs_both(np.asarray(xyz, dtype=np.float64), np.asarray(r, dtype=np.int64),
                              np.asarray(c, dtype=np.int64))
    return _pitches_of(xyz, d1, d0)


def _pitches_of(xyz, d1, d0) -> tuple[float, float]:
    """The pitches along a row and a column from their pixels' values (``pitch_diffs``
    along axes 1 and 0): their medians, the whole image's where there are none."""
    from planerel.features._relation_kernels import median

    return (float(median(d1)) if d1.size else _pitch(xyz, 1),
            float(median(d0)) if d0.size else _pitch(xyz, 0))


def _areas_at(xyz, r, c, pitch) -> np.ndarray:
    """Footprint (m^2) of pixels ``(r, c)``: ``z^2 * pitch_x * pitch_y``."""
    z = np.abs(xyz[r, c, 2])
    return z * z * pitch[0] * pitch[1]


def pixel_areas(xyz) -> np.ndarray:
    """Area each pixel covers at its measured depth (m^2).

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3)
        Organized points, NaN invalid.

    Returns
    -------
    ndarray, shape (H, W)
        ``z^2 * px * py``: ``px``, ``py`` the angular pixel size along x and y, measured on the
        cloud itself (:func:`_pitch`: ``1 / fx``, ``1 / fy`` of a pinhole camera), so a pixel at
        depth z on a surface facing the sensor covers ``(z / f)^2`` (a slanted surface more:
        this is the area facing the sensor, unaffected by depth noise).  0 at invalid pixels.
    """
    xyz = np.asarray(xyz, float)
    valid = np.isfinite(xyz).all(axis=2)
    out = np.zeros(xyz.shape[:2])
    r, c = np.nonzero(valid)
    if len(r):
        out[r, c] = _areas_at(xyz, r, c, (_pitch(xyz, 1), _pitch(xyz, 0)))
    return out


def _shift_all(mask, r: int, axis: int, erode: bool) -> np.ndarray:
    """AND (erode) or OR (dilate) of ``mask`` shifted by -r..r along ``axis`` (outside the
    image counts as unset)."""
    out = mask.copy()
    n = mask.shape[axis]

    def part(sl):  # the index of ``sl`` along ``axis``
        return (slice(None), sl) if axis == 1 else (sl, slice(None))

    for k in range(1, r + 1):
        if k >= n:  # every shifted copy is all outside
            if erode:
                out[...] = False
            continue
        for sgn in (1, -1):
            src = slice(k, None) if sgn > 0 else slice(None, n - k)
            dst = slice(None, n - k) if sgn > 0 else slice(k, None)
            if erode:
                out[part(dst)] &= mask[part(src)]
                out[part(slice(n - k, None) if sgn > 0 else slice(None, k))] = False
            else:
                out[part(dst)] |= mask[part(src)]
    return out


def _components(mask, xyz, edge_depth: float) -> tuple[np.ndarray, int]:
    """Connected components of ``mask`` over 4-neighbours within ``edge_depth * max(1, z)``
    in 3-D; returns ``(ids (H, W) int, -1 outside, numbered by first pixel; count)``."""
    from planerel.features._curved_kernels import grid_components

    # a window of the cloud is passed as it is (no copy)
    out, k = grid_components(np.asarray(mask, dtype=np.bool_), np.asarray(xyz, dtype=np.float64),
                             float(edge_depth))
    return out, int(k)


def unexplained_clusters(cloud, labels, planes, support=(), params: CurvedParams | None = None,
                         pixels=None):
    """Clusters of points no flat plane explains (rule step 2).

    Parameters
    ----------
    cloud : Cloud
        Organized cloud ``(H, W, 3)``.
    labels : ndarray, shape (H, W), int
        Plane labels, -1 unassigned.
    planes : PlaneSet
    support : iterable of int
        Support plane labels (their pixels are never unexplained).
    pixels : (ndarray, ndarray), optional
        The valid pixels (rows, columns, row-major) of ``labels`` of no plane of ``tiny_area``
        m^2 or more, support planes included (the stairfit stage's list): opened from it
        without scanning the image (the same clusters).

    Returns
    -------
    list of ndarray (H, W) bool
        One mask per cluster of at least ``min_area`` m^2 (opened pixels), ordered by their
        first opened pixel (row-major; clusters joined by ``regrow_px``: the first one's).
    """
    return _clusters(cloud, labels, planes, support, params, pixels)[0]


def _distinct(ids: np.ndarray) -> np.ndarray:
    """``np.unique(ids)`` of a 1-D array of non-negative integers below a small bound (a
    frame's cluster ids): the ids whose count is not zero, ascending, int64 (the same array
    without numpy's sort; ``tests/test_curved.py`` compares)."""
    return np.flatnonzero(np.bincount(ids))


def _clusters(cloud, labels, planes, support=(), params: CurvedParams | None = None, pixels=None,
              credit=None, bounds=None):
    """:func:`unexplained_clusters`, and for each cluster the plane it was kept with.

    ``credit`` maps plane labels to areas (m^2): planes that are a proposal alone, small enough
    that near parts too small to keep on their own count with them (``CurvedParams.nest_credit``).
    Returns ``(masks, planes)``: ``planes[i]`` is the credited plane whose area kept cluster ``i``
    (-1: none).  ``bounds``: a list, given ``(y0, y1)`` per returned mask (its pixels lie in
    rows ``y0..y1-1``).
    """
    params = params or CurvedParams()
    xyz = np.asarray(cloud.xyz, float)
    lab = np.asarray(labels)
    if lab.shape != xyz.shape[:2]:
        raise InputError(f"labels {lab.shape} and cloud {xyz.shape[:2]} differ in shape")
    from planerel.features._curved_kernels import (
        list_areas_depths,
        list_components_pitch,
        open_mask,
        open_pixel_list,
        unexplained_mask,
        unexplained_open,
    )
    from planerel.segment._label_kernels import mask_pixels

    flat = {p.label for p in planes if p.area >= params.tiny_area}
    # the explained labels (the kernels take any label past the array as not explained:
    # the label image's largest label is not needed)
    known = [x for x in (*flat, *support) if x >= 0]
    explained = np.zeros(max(known, default=-1) + 1, bool)
    explained[known] = True
    # valid pixels (finite depth) of no label or of a label not explained, in one pass,
    # opened (an opening keeps no pixel that was not set: the depth stays finite)
    # a Cloud's invalid pixels are all NaN: its valid mask tells a finite depth (one byte a
    # pixel read, not the point)
    if pixels is not None and isinstance(cloud, Cloud) and cloud.valid.shape == lab.shape:
        # the same opening from the list of the pixels of no flat plane: the support planes'
        # pixels dropped from it
        sup = [x for x in support if x >= 0]
        drop = np.zeros(max(sup, default=-1) + 1, bool)
        drop[sup] = True
        # (open_pixel_list: open_pixels' list from the rows' runs, without its images)
        rows, cols = open_pixel_list(pixels[0], pixels[1], lab, drop, lab.shape[0], lab.shape[1],
                                     int(params.open_px))
    elif isinstance(cloud, Cloud) and cloud.valid.shape == lab.shape:
        # the mask, its opening and its pixels in one pass (sparse: a few % of the image)
        un, rows, cols = unexplained_open(cloud.valid, lab, explained, int(params.open_px))
    else:
        un = open_mask(unexplained_mask(xyz, lab, explained), int(params.open_px))
        rows, cols = mask_pixels(un)
    if not len(rows):
        return [], []
    # the components from the pixel list (grid_components of the mask, without its map)
    # and the pixel pitches (_pitches_at) from the same reads of the points
    ids, k, d1, d0 = list_components_pitch(rows, cols, xyz, float(params.edge_depth),
                                           lab.shape[0])
    pitch = _pitches_of(xyz, d1, d0)
    # the areas, and each component's depth sum and count, in one pass over the pixels
    area, zsum, zcnt = list_areas_depths(xyz, rows, cols, ids, pitch[0], pitch[1], k)
    lim = np.full(k, float(params.min_area))
    if params.near_depth > 0 and k:
        # near clusters (mean depth within near_depth) need only near_min_area
        zc = zsum / np.maximum(zcnt, 1)
        lim[zc <= params.near_depth] = min(float(params.near_min_area), float(params.min_area))
    # each kept component's group: the component it is kept with (itself, or the cluster a
    # nested part joins); -1: not kept
    rep = np.where(area >= lim, np.arange(k), -1)
    kept_with = np.full(k, -1, np.int64)  # the credited plane a kept group was kept with
    if params.nest_depth > 0 and params.near_depth > 0 and (k > 1 or (k and credit)):
        _nested_groups(rep, ids, rows, cols, xyz, area, lim, zc, params, lab.shape, lab,
                       credit or {}, kept_with)
    kept = np.nonzero(rep >= 0)[0]
    gmin = np.full(k, k, np.int64)
    np.minimum.at(gmin, rep[kept], kept)  # a group's first opened pixel: its smallest id
    order = _distinct(rep[kept])
    order = order[np.argsort(gmin[order], kind="stable")]
    index = np.full(k, -1, np.int64)
    index[order] = np.arange(len(order))
    cluster = np.full(k, -1, np.int64)
    cluster[kept] = index[rep[kept]]
    keep = np.arange(len(order))
    plane_of = kept_with[order]  # per cluster index: its group's representative's plane
    out = []
    if params.regrow_px > 0 and params.open_px > 0 and len(keep):
        # the kept clusters grown back regrow_px steps into the pixels before the opening,
        # clusters meeting there joined (module rule step 2)
        from planerel.features._curved_kernels import (
            grow_box,
            grow_clusters,
            grow_in_box,
            list_mask,
            unexplained_valid,
        )

        kid = cluster[ids]
        sel = kid >= 0
        steps = int(params.regrow_px)
        if pixels is not None and isinstance(cloud, Cloud) and cloud.valid.shape == lab.shape:
            # the pixels before the opening from the list too (its opening with radius 0),
            # only in the box the clusters can grow into
            H, W = lab.shape
            y0, y1, x0, x1 = grow_box(rows[sel], cols[sel], H, W, steps)
            full, nf = list_mask(pixels[0], pixels[1], lab, drop, y0, y1, x0, x1)
            gr, gc, grp = grow_in_box(rows[sel], cols[sel], kid[sel], len(keep), full, y0, x0,
                                      H, W, xyz, float(params.edge_depth), steps, nf)
        else:
            if isinstance(cloud, Cloud) and cloud.valid.shape == lab.shape:
                full = unexplained_valid(cloud.valid, lab, explained)
            else:
                full = unexplained_mask(xyz, lab, explained)
            gr, gc, grp = grow_clusters(rows[sel], cols[sel], kid[sel], len(keep), full, xyz,
                                        float(params.edge_depth), steps,
                                        int(np.count_nonzero(full)))
        gs = _distinct(grp)
        for g in gs:  # the smallest member's id: their first opened pixel's order
            m = np.zeros(lab.shape, bool)
            s = grp == g
            r = gr[s]
            m[r, gc[s]] = True
            out.append(m)
            if bounds is not None:
                bounds.append((int(r.min()), int(r.max()) + 1))
        return out, [int(plane_of[g]) for g in gs]
    kid = cluster[ids]
    for c in keep:
        m = np.zeros(lab.shape, bool)
        sel = kid == c
        r = rows[sel]
        m[r, cols[sel]] = True
        out.append(m)
        if bounds is not None:
            bounds.append((int(r.min()), int(r.max()) + 1))
    return out, [int(x) for x in plane_of]


def _nested_groups(rep, ids, rows, cols, xyz, area, lim, zc, params: CurvedParams, shape, lab,
                   credit: dict, kept_with) -> None:
    """Join near components too small to keep (``rep`` -1) whose pixels come within
    ``nest_px`` grid pixels and ``nest_depth`` (x depth) in 3-D of another near component:
    parts linked to one kept cluster join it (``rep`` = its id); parts linked to none that
    reach ``near_min_area`` together become one cluster (``rep`` = their smallest id); parts
    linked to two kept clusters stay out, and kept clusters never join each other.  The parts
    of one round object seen over its rim, apart in the image by the band of invalid pixels a
    depth sensor leaves at the jump (``CurvedParams.nest_depth``).  ``zc``: each component's
    mean depth.  With ``credit`` (plane label -> area), parts linked that way to one such
    plane and no kept cluster count its area too, and ``kept_with[rep]`` records the plane
    (``CurvedParams.nest_credit``)."""
    from planerel.features._curved_kernels import nest_links

    k = len(area)
    # parts from a quarter of the near limit make up a new cluster; only those from half of it
    # join a kept one (a quarter let a bowl's rim piece join a lying cylinder beside it)
    near = (zc <= params.near_depth) & (area >= 0.25 * params.near_min_area)  # no specks
    part = near & (rep < 0)
    big_part = part & (area >= 0.5 * params.near_min_area)
    if not part.any():
        return
    nl = max(credit, default=-1) + 1
    can = np.zeros(nl, np.bool_)
    parea = np.zeros(nl)
    for x, a in credit.items():
        can[x], parea[x] = True, a
    grp = nest_links(rows, cols, ids, near, part, xyz, shape[0], shape[1], int(params.nest_px),
                     float(params.nest_depth), lab if nl else np.full((1, 1), -1, np.int64), can)
    ng = k + nl  # group ids are node ids (the smallest of the group: a component's when it has one)
    kept = near & (rep >= 0)
    n_kept = np.bincount(grp[:k][kept], minlength=ng)
    n_part = np.bincount(grp[:k][part], minlength=ng)
    total = np.bincount(grp[:k][part], weights=area[part], minlength=ng)
    linked = np.zeros(nl, np.bool_)
    if nl:
        linked = can & (grp[k:] != np.arange(k, k + nl))  # a credited plane a part reached
    n_plane = np.bincount(grp[k:][linked], minlength=ng)
    total += np.bincount(grp[k:][linked], weights=parea[linked], minlength=ng)
    plane = np.full(ng, -1, np.int64)
    plane[grp[k:][linked]] = np.nonzero(linked)[0]
    anchor = np.full(ng, -1, np.int64)
    anchor[grp[:k][kept]] = np.nonzero(kept)[0]  # the kept cluster of a group that has one
    first = np.full(ng, k, np.int64)
    np.minimum.at(first, grp[:k][part], np.nonzero(part)[0])
    # (a credited plane is only ever linked through a part)
    alone = ((n_kept == 0) & (n_plane <= 1) & ((n_part >= 2) | (n_plane == 1))
             & (total >= lim[part].min(initial=np.inf)))
    g = grp[:k]
    joined = big_part & (n_kept == 1)[g]
    rep[joined] = anchor[g[joined]]
    new = part & alone[g]
    rep[new] = first[g[new]]
    kept_with[first[g[new]]] = plane[g[new]]



def join_parts(cobjs, xyz, labels, edge_depth: float = 0.02, min_touch: int = 3) -> list:
    """``cobjs`` with the parts of the unassigned pixels that touch one proposal only joined
    to it (``CurvedParams.join_parts``).

    Parameters
    ----------
    cobjs : list of CurvedObject
        The proposals (their planes and masks).
    xyz : ndarray, shape (H, W, 3)
        Organized points (NaN invalid).
    labels : ndarray, shape (H, W), int
        Plane labels, -1 unassigned.
    edge_depth : float
        Metres at 1 m: grid neighbours within two pixels and this 3-D distance (scaled by the
        depth) touch; within one pixel and it, they are one part.
    min_touch : int
        Fewest touching pixel pairs.

    Returns
    -------
    list of CurvedObject
        The same proposals in their order; a part joined is in its proposal's mask (and
        ``n_points``), not in its planar fraction or ``curved``: a part the clusters left is
        thin (a leg) or a rim, no evidence of a curved surface, and a box whose unsegmented
        face joined so would read as round.
    """
    from planerel.features._curved_kernels import join_owners, join_part_targets, mark_held

    lab = np.asarray(labels)
    xyz = np.asarray(xyz, float)
    if not cobjs or lab.shape != xyz.shape[:2]:
        return list(cobjs)
    H, W = lab.shape
    nl = max(int(lab.max()) + 1, 1)
    lut = np.full(nl, -1, np.int64)
    for k, c in enumerate(cobjs):
        for x in c.planes:
            if 0 <= int(x) < nl:
                lut[int(x)] = k
    # compiled passes: each pixel's proposal (its plane's) and the unassigned pixels with a
    # depth; those a proposal's mask holds (clusters, raised groups) are its, the first
    # mask's; the rest form parts, their touches decide whom they join
    own, rows, cols = join_owners(lab, lut, xyz)
    if not len(rows):
        return list(cobjs)
    for k, c in enumerate(cobjs):
        if c.mask is not None:
            mark_held(np.asarray(c.mask, dtype=np.bool_), own, k)
    npts = np.array([int(c.n_points) for c in cobjs], np.int64)
    dest, grown_n = join_part_targets(rows, cols, own, xyz, float(edge_depth), npts,
                                      int(min_touch))
    out = list(cobjs)
    grown = np.nonzero(grown_n != npts)[0]
    if not len(grown):
        return out
    j = np.nonzero(dest >= 0)[0]
    j = j[np.argsort(dest[j], kind="stable")]
    start = np.searchsorted(dest[j], np.arange(len(cobjs) + 1))
    for k in grown:
        c = out[int(k)]
        g = np.zeros((H, W), bool) if c.mask is None else np.array(c.mask, dtype=bool)
        sel = j[start[k]:start[k + 1]]
        g[rows[sel], cols[sel]] = True
        out[int(k)] = CurvedObject(c.planes, g, c.planar_fraction, c.curved, int(grown_n[k]))
    return out


def _span_union(a, b):
    """The rows ``(y0, y1)`` two masks' union holds (``None``: no mask)."""
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), max(a[1], b[1]))


def _touching_labels(mask, lab, xyz, edge_depth: float, nlab: int | None = None,
                     rows: tuple = (0, -1)) -> dict:
    """``{label: number of grid neighbour pairs}`` of the planes touching ``mask`` (within
    two pixels, 3-D distance within ``edge_depth * max(1, z)``).  ``nlab``: more than the
    largest label of ``lab`` (default ``label_max(lab) + 1``, a pass over the image when the
    label image is not remembered: callers with many masks take it once).  ``rows``: the mask
    holds pixels only in rows ``rows[0]..rows[1]-1`` (default: any row)."""
    from planerel.features._curved_kernels import touching_counts

    lab = np.asarray(lab)
    n = touching_counts(np.asarray(mask, dtype=np.bool_), lab, np.asarray(xyz, float),
                        float(edge_depth), label_max(lab) + 1 if nlab is None else int(nlab),
                        int(rows[0]), int(rows[1]))
    return {int(x): int(n[x]) for x in np.nonzero(n)[0]}


def _join_facet_proposals(props, facets, byl, relations, params) -> list:
    """``props`` with the proposals made only of facets (or planes under ``small_area``) that
    two linked facets join merged into the first of them (``CurvedParams.join_facets``); the
    merged ones are left empty, so indices keep their meaning."""
    owner = {x: k for k, g in enumerate(props) for x in g}
    soft = [len(g) > 0 and all(x in facets or byl[x].area < params.small_area for x in g)
            for g in props]
    lo, hi = params.facet_min_angle, params.facet_max_angle
    g = Components(range(len(props)))
    g.add_edges((owner[r.a], owner[r.b]) for r in adjacent_only(relations)
                if r.a < r.b and r.adjacent and lo <= r.angle <= hi
                and r.a in facets and r.b in facets and r.a in owner and r.b in owner
                and owner[r.a] != owner[r.b] and soft[owner[r.a]] and soft[owner[r.b]])
    out = [tuple(p) for p in props]
    for comp in g.groups():
        if len(comp) < 2:
            continue
        k0 = min(comp)
        out[k0] = tuple(sorted({x for k in comp for x in props[k]}))
        for k in comp:
            if k != k0:
                out[k] = ()
    return out


def curved_objects(planes, relations, proposals, cloud=None, labels=None, support=(),
                   params: CurvedParams | None = None, pixels=None,
                   profiles: dict | None = None,
                   label_bound: int | None = None) -> list[CurvedObject]:
    """Proposals with their unexplained points and planar fractions (the module's rule).

    Parameters
    ----------
    planes : PlaneSet
    relations : Relations
    proposals : sequence of sequence of int
        Plane labels per proposal (e.g. :func:`planerel.features.proposals.propose_objects`).
    cloud : Cloud, optional
        Without it (or without ``labels``) no clusters are made; planar fractions count plane
        points only.
    labels : ndarray, shape (H, W), int, optional
        Plane labels of the segmentation (default ``planes.labels``).
    support : iterable of int
        Support plane labels.
    pixels : (ndarray, ndarray), optional
        Passed to :func:`unexplained_clusters`.
    profiles : dict, optional
        Passed to :func:`skirt_faces` (the face profiles :func:`~planerel.features.relations.relate`
        measured for ``planes`` in ``cloud``).
    label_bound : int, optional
        More than every label ``labels`` holds at a valid pixel of ``cloud`` (the clusters'
        touching planes are counted there only); default ``label_max(labels) + 1``, a pass
        over the image unless ``labels`` is ``planes.labels``
        (:func:`~planerel.features.facts.describe_scene` gives its planes' own bound).

    Returns
    -------
    list of CurvedObject
        The given proposals in their order (with the clusters they absorbed), then the
        clusters that stand alone, ordered by their first pixel.
    """
    params = params or CurvedParams()
    byl = {p.label: p for p in planes}
    support = set(support)
    props = [tuple(sorted(int(x) for x in g)) for g in proposals]
    flat = skirt_faces(planes, relations, cloud, profiles=profiles) if params.skirt_faces else ()
    facets = facet_planes(planes, relations, [p.label for p in planes if p.label not in support],
                          params, props, flat, cloud, labels)
    if params.join_facets and facets and len(props) > 1:
        props = _join_facet_proposals(props, facets, byl, relations, params)
    masks: list = [None] * len(props)
    # each mask's rows (y0, y1): the kernels below read only those rows of the masks
    spans: list = [None] * len(props)
    alone: list = []
    if labels is None:
        labels = getattr(planes, "labels", None)
    if params.enabled and cloud is not None and labels is not None:
        lab = np.asarray(labels)
        xyz = np.asarray(cloud.xyz, float)
        owner = {x: k for k, g in enumerate(props) for x in g}
        soft = [all(x in facets or byl[x].area < params.small_area for x in g) and len(g) > 0
                for g in props]
        # one-plane proposals small enough that near parts count with them (nest_credit)
        credit = {g[0]: byl[g[0]].area for g in props
                  if len(g) == 1 and byl[g[0]].area <= params.nest_credit}
        bounds: list = []
        masks_, kept_with = _clusters(cloud, lab, planes, support, params, pixels, credit, bounds)
        if masks_:
            # once for every cluster's touching planes
            nlab = label_max(lab) + 1 if label_bound is None else int(label_bound)
        for m, with_plane, span in zip(masks_, kept_with, bounds, strict=True):
            touch = _touching_labels(m, lab, xyz, params.edge_depth, nlab, span)
            joined = sorted({owner[x] for x in touch if x in owner and soft[owner[x]]})
            if not joined and with_plane >= 0 and with_plane in owner:
                # kept with that plane's area: the rest of its object, across the rim's band
                joined = [owner[with_plane]]
            if not joined and params.join_area > 0:
                # the rest of a one-plane proposal it alone touches (module rule step 3)
                near = {owner[x] for x in touch if x in owner}
                if len(near) == 1:
                    k = next(iter(near))
                    if (len(props[k]) == 1 and byl[props[k][0]].area < params.join_area
                            and touch.get(props[k][0], 0) >= params.join_touch):
                        joined = [k]
            if not joined and params.bridge_area > 0:
                # the unexplained part between two small proposals it touches (module rule
                # step 3): faces of one object whose connecting faces were not segmented
                per: dict = {}
                for x, c in touch.items():
                    if x in owner:
                        per[owner[x]] = per.get(owner[x], 0) + c
                near = sorted(k for k, c in per.items() if c >= params.bridge_touch)
                if (len(near) == 2 and len(per) == 2 and all(
                        params.bridge_min <= sum(byl[x].area for x in props[k]) < params.bridge_area
                        for k in near)
                        and int(m.sum()) <= sum(byl[x].n_points for k in near for x in props[k])):
                    joined = near
            if joined:
                # every soft proposal the cluster touches becomes one object
                k0 = joined[0]
                for k in joined[1:]:
                    props[k0] = tuple(sorted(set(props[k0]) | set(props[k])))
                    if masks[k] is not None:
                        masks[k0] = masks[k] if masks[k0] is None else masks[k0] | masks[k]
                        spans[k0] = _span_union(spans[k0], spans[k])
                    props[k], masks[k], spans[k], soft[k] = (), None, None, False
                for x in props[k0]:
                    owner[x] = k0
                masks[k0] = m if masks[k0] is None else masks[k0] | m
                spans[k0] = _span_union(spans[k0], span)
            else:
                from planerel.features._curved_kernels import mask_values

                # lab[m] from the mask's rows that hold a pixel
                vals = mask_values(m, lab, span[0], span[1])
                inside = tuple(sorted(x for x in np.unique(vals) if x >= 0 and x in byl
                                      and x not in owner and x not in support))
                alone.append((inside, m, span))
    out = []
    for g, m, span in list(zip(props, masks, spans, strict=True)) + alone:
        if not g and m is None:
            continue
        extra = 0
        if m is not None:
            from planerel.features._curved_kernels import count_outside

            lab = np.asarray(labels)
            # the pixels of m outside the object's planes (np.isin(lab, g or [-2]) before)
            member = np.zeros(max([-1, *g]) + 1, dtype=bool)
            member[list(g)] = True
            y0, y1 = (0, -1) if span is None else span
            extra = int(count_outside(np.asarray(m, dtype=np.bool_), lab, member,
                                      -(1 << 40) if g else -2, y0, y1))
        n_pl = sum(byl[x].n_points for x in g if x in byl)
        n_flat = sum(byl[x].n_points for x in g
                     if x in byl and x not in facets and byl[x].area >= params.tiny_area)
        total = n_pl + extra
        frac = n_flat / total if total else 0.0
        out.append(CurvedObject(g, m, float(frac), bool(frac < params.curved_below), int(total)))
    return out
