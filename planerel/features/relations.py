"""Pairwise plane relations and the scene graph.

For every unordered pair of planes ``(p, q)`` of a :class:`~planerel.features.planes.PlaneSet`,
:func:`relate` computes (in both directions, see :class:`Relation`):

================ =========================================================================
``angle``        angle between the two planes (their normals, unoriented), 0..90 degrees
``parallel``     ``angle <= parallel_tol``
``perpendicular`` ``angle >= 90 - perpendicular_tol``
``gap``          closest distance between the two 3-D convex hulls, metres (0 when they
                 touch or cross)
``touching``     the planes touch in the image grid: pixels of both labels lie within
                 ``grid_gap`` pixels of each other and within ``max(touch_depth,
                 touch_rel * z)`` metres in 3-D (z: the pixel's depth; one pixel on a surface
                 seen at a grazing angle spans several cm, while an occluding edge in front of
                 a far wall jumps by much more, so it does not touch)
``adjacent``     ``touching or gap <= adjacency_gap``
``rise``         ``up . (centroid_q - centroid_p)``: how far q's centroid is above p's, metres
``above``        p is above q: ``-rise > above_tol``
``in_front_of``  p is nearer the sensor than q along the horizontal viewing direction
                 (the camera's optical axis with its up component removed) by ``front_tol``
``skirt``        p is horizontal (or inclined at most ``skirt_top_tilt`` towards q: a
                 narrow top whose fit the rounded edge above q tilts; plus the tilt
                 ``skirt_top_noise`` times p's fit RMS across its width makes, at most
                 ``skirt_top_tilt`` more), q vertical and
                 adjacent, and q hangs below p as a box's side below its top: q's top edge at p's level, q reaching down at least
                 ``skirt_reach``, or ``skirt_reach_share`` of p's length when that is less
                 (a box lying flat on a table), and, halfway down, covering ``skirt_cover`` of p's extent
                 along their edge where it can be seen, ending within ``skirt_beyond``
                 of where p ends; not a riser: q does not stand on a step (a horizontal
                 plane at its foot reaching at most ``skirt_step`` out from it) and no
                 vertical plane parallel to q, at least ``riser_width`` wide, rises
                 from p (the next riser); a q that stands on the ground (the floor, or a
                 table reaching farther than a tread, level with its foot) need reach only
                 ``skirt_grounded_reach`` (a box lying flat)
                 (:mod:`planerel.features.solid`; needs the cloud and its camera); with
                 ``skirt_own_steps``, a step or riser of another object (a riser: of one
                 with a top at the riser's top) does not say so
                 (:func:`skirts_within_objects`: a box standing on another box, or beside a
                 lower one, is proposed apart from it and is no flight of steps)
``corner``       p and q are vertical, adjacent and perpendicular walls of one solid: each
                 at least ``corner_width`` wide, their top edges within ``corner_tol`` of
                 each other, and (with ``corner_slope`` set, off by default) neither top
                 edge rising ``corner_slope`` degrees where it is seen (a ramp's side face
                 seen with its high end, ramp42;
                 :func:`~planerel.features.solid.top_edge`; :mod:`planerel.features.solid`;
                 needs the cloud)
``face_pair``    p and q are vertical, adjacent walls of one solid meeting at an outside
                 corner of at least ``face_pair_angle`` degrees, each at least
                 ``face_pair_width`` wide, their tops and their bottoms each within
                 ``face_pair_level`` of each other and within ``face_pair_level_share`` of
                 the shorter face's height: a narrow box seen level, no top and no
                 ground in view (pair41; :mod:`planerel.features.solid`; needs the cloud)
``facing``       p and q are vertical, parallel and *not* adjacent walls facing each other
                 across one solid or open box: one at least ``corner_width`` wide, the other
                 at least ``facing_width``, their top edges within ``corner_tol`` of each
                 other (``facing_narrow_tol`` when one is narrower than ``corner_width``),
                 the shorter one's extent along the walls overlapping the other's by at
                 least ``facing_overlap`` of it
                 (:mod:`planerel.features.solid`; needs the cloud)
================ =========================================================================

Which pairs reach the facts is decided in :mod:`planerel.features.facts`: all ordered pairs within an
object, and the adjacent pairs across the scene.

Split out of this module (split95), each name still importable from here (:data:`_MOVED`):
``tall_face/1`` (:mod:`planerel.features.tall_face`), ``lying/1``
(:mod:`planerel.features.lying`), the object proposals (:mod:`planerel.features.proposals`,
their settings :mod:`planerel.features.proposal_params`) and the step chains and flight tests
(:mod:`planerel.features.step_chains`).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field, replace

import numpy as np

from planerel.errors import InputError, check_bools
from planerel.features._defaults import defaults
from planerel.features.cavities import edge_overlap
from planerel.features.components import Components
from planerel.features.planes import _boundary_pixels, _boundary_tiles, label_max
from planerel.features.solid import (
    PROFILE_POINTS,
    _skirt_geometry,
    face_profile_of,
    grounded,
    is_corner,
    is_face_pair,
    is_facing,
    is_skirt,
    on_step,
    rises_from,
    skirt_covered,
    sloped_top,
    top_edge,
)
from planerel.features.step_geometry import (  # noqa: F401 (re-exported: tests, scripts written before)
    _border_pixels,
    _border_share,
    _cut_lengthwise,
    _horizontal_basis,
    _tread_depth_axis,
)
from planerel.features.vectors import vec_norm
from planerel.segment.shape import mask_solidity

# __all__ names public names moved out (split95) too: __getattr__ gives them (_MOVED)
# ruff: noqa: F822
__all__ = [
    "RelationParams",
    "Relation",
    "Relations",
    "relate",
    "skirts_within_objects",
    "tall_faces",
    "lying_tops",
    "top_sized",
    "SMALL_NOISE_LENGTH",
    "leans_towards",
    "hull_gap",
    "noise_tilt",
    "scene_graph",
    "ProposalParams",
    "propose_objects",
    "Components",
    "adjacent_only",
    "shares_edge",
    "support_planes",
    "edge_means",
    "convex_pairs",
    "edge_overlap",
    "objects_from_truth",
    "proposal_match",
    "flight_faces",
    "flight_steps",
    "flight_evidence",
    "steps_of_one_flight",
    "stacked_riser_steps",
    "flight_fragments",
]


def _check_nonneg(obj, names) -> None:
    for name in names:
        v = getattr(obj, name)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            raise InputError(f"{name} must be a non-negative number, got {v!r}")


@dataclass(frozen=True)
class RelationParams:
    """Tolerances of :func:`relate` (degrees, metres, pixels)."""

    parallel_tol: float = 10.0
    perpendicular_tol: float = 10.0
    adjacency_gap: float = 0.05
    grid_gap: int = 2
    touch_depth: float = 0.05
    touch_rel: float = 0.05
    above_tol: float = 0.02
    front_tol: float = 0.05
    skirt_tol: float = 0.08
    skirt_reach: float = 0.07
    skirt_reach_share: float = 0.15
    skirt_cover: float = 0.7
    skirt_beyond: float = 0.4
    skirt_step: float = 0.45
    skirt_own_steps: bool = True
    skirt_top_tilt: float = 10.0
    skirt_top_noise: float = 2.0
    skirt_tilted: float = 30.0
    #: m: the reach asked of a face that stands on the ground (:func:`~planerel.features.solid.grounded`:
    #: a horizontal plane adjacent to it, level with its foot within this, on the floor or
    #: reaching more than ``skirt_step`` out from it): a book or a box lying flat on a table, 2-4 cm high,
    #: whose side is lower than ``skirt_reach_share`` of its top's length.  A slab's edge
    #: (a table top's, a seat's) has no ground at its foot.  0: the reach of before (flat23)
    skirt_grounded_reach: float = 0.02
    #: a plane rising from a skirt's top denies the skirt (the next riser of a flight) only
    #: when it is at least this wide along the face (or half the face's width when that is
    #: less): a flight's next riser is as wide as the one below, a bottle or a post standing
    #: behind a box is not.  0: any width (before flat23)
    riser_width: float = 0.08
    #: m: a plane rising from a skirt's top more than this above it (its
    #: :class:`~planerel.features.solid.FaceProfile` top over the top's level) denies the
    #: skirt only when a horizontal plane adjacent to it lies at its top edge (within
    #: ``skirt_tol``): a flight's next riser rises one step (:data:`STAIR_RISE`, at most
    #: :data:`STEP_WINDOW_RISE`'s 0.35 m) to the next tread; a wall or a cabinet standing behind
    #: a box rises far above its top with no tread on it, or out of view.  0: any rise
    #: (before skirt36)
    riser_rise_max: float = 0.5
    #: m: a ``tall_face`` (:func:`tall_faces`) stands on the ground: a horizontal plane
    #: adjacent to it is level with its foot within this
    #: (:func:`~planerel.features.solid.grounded`: the floor, or a table reaching farther
    #: than a tread from it): a box's side; a chair's back (over its seat), a table's apron
    #: (over open space) stand on nothing.  0: no plane is a tall face (face24)
    standing_foot: float = 0.05
    #: a ``tall_face`` is a rectangle: its hull's area at least this share of its
    #: rectangle's (``plane_length * plane_width``); a ramp's side is a triangle (0.5), a box's
    #: face 0.9-1.0 (face24)
    standing_fill: float = 0.8
    #: m: a ``tall_face`` narrower than ``corner_width`` but at least this wide passes the
    #: shape test when it is flat *across* its width (:func:`face_bend` at most
    #: ``tall_narrow_bend``): a small product box's face (6-8 cm: hunt43's 7 cm cube, bend
    #: 0.19) is flat, a can's, a bottle's or a mug's facet of the same size bends by its
    #: sagitta (0.48-2.7 on the real development frames); the rooms' legs and posts are
    #: under 6 cm (product37).  0: ``corner_width`` for every tall face (before face52;
    #: docs/objects.md "Narrow product faces flat across")
    tall_narrow_width: float = 0.06
    #: the largest :func:`face_bend` (the parabola's sagitta across the face's width over
    #: the fit's residual RMS, unsigned) of a narrow tall face (``tall_narrow_width``)
    tall_narrow_bend: float = 0.3
    #: m: a ``tall_face``'s top edge is no more than this below the sensor's eye level (or
    #: out of the image's top): a box's top is then out of sight; a box seen from above it
    #: shows its top (face24)
    tall_eye: float = 0.1
    #: m: ... out of the image's top (its pixels reach the image's first rows, or its blank
    #: top margin) only when its top edge lies at most this below the eye: a face the image's
    #: top cuts while the sensor looks down on it from higher is a wall's or a cabinet's far
    #: more often than a box's (the real development frames: boxes down to 0.37 m under the
    #: eye, walls and furniture sides from 0.40 m; 0.4 at classify time with ``make demo``'s
    #: model: two real false boxes fewer, nothing lost; learned with it, the box theory
    #: changes and adds three: top98, docs/objects.md "Session 98").  0: no bound, the
    #: image's top alone (the default)
    tall_cut_eye: float = 0.0
    #: a ``tall_face`` is flat: its fit's RMS residual at most this share of its width.  A
    #: curved surface grown into one plane (a cylinder seen as one face at low resolution)
    #: deviates from it by about 0.11 of its width (a half circle against its chord: an RMS
    #: of 0.223 r over a width of 2 r); a box's face by the sensor's noise.  0: no bound
    tall_flat: float = 0.07
    #: ... or its RMS at most this many times the sensor's depth noise at its centroid's
    #: depth (``sigma(z)`` of :func:`planerel.segment.noise.estimate_noise`, when the cloud
    #: measures one): a box's face 3-4 m from a Kinect fits with 1-3 cm of RMS, its noise,
    #: over 0.07 of a 0.15-0.35 m width; a round surface's deviation is its shape's, over
    #: the noise.  0: the width bound only (flat69)
    tall_flat_noise: float = 0.0
    #: a vertical face whose top edge is below ``tall_eye`` is still a ``tall_face`` when a
    #: level strip that is no plane of its own lies on its top edge (:func:`cap_strip`):
    #: a box's top seen so flat that the region grower took none of it (at 160x120 a box
    #: 2-4 m away shows its top in 2-10 rows).  At least this share of the face's columns
    #: show such a strip above their top pixel.  0: off (before indep32)
    tall_cap: float = 0.5
    #: m: a cap strip's points are level with the face's top edge within this
    tall_cap_tol: float = 0.03
    #: m: ... and reach this far behind the face (the 90th percentile over its columns of
    #: the farthest strip point), or ``tall_cap_ratio`` of the face's width along it when
    #: that is less: a box's top is 0.1 m deep or more, a milk carton's as deep as its face
    #: is wide; a door's, a sill's or a partition's top edge (3-8 cm under a face 0.3-1.3 m
    #: wide) is no lid.  Either 0: no depth asked
    tall_cap_depth: float = 0.1
    tall_cap_ratio: float = 0.3
    #: m: a vertical face that no adjacent horizontal plane grounds still stands on the floor
    #: (:func:`floor_foot`) when its foot is level with the floor plane's fit (extrapolated
    #: under it) within this: a box seen from a camera 0.1-0.3 m over the floor, which sees the
    #: floor at a grazing angle and segments it only nearer (low42: true boxes of dev_low
    #: 0.003-0.029 m, one 0.047; a chair's back over its seat 0.05-0.07).  0: off (before low42)
    tall_floor_fit: float = 0.03
    #: ... when at least this share of its middle pixel columns show, in the rows under its
    #: lowest pixel, the floor (within ``standing_foot`` of the fit, no farther than the face)
    #: or nothing measured (the grazing floor); a table's or a chair's open space shows the
    #: room behind, a riser the tread in front of it above the floor
    tall_floor_share: float = 0.5
    #: ... and when its pixels fill at least this share of each of its rows' spans (a solid
    #: face; a table's legs that the region grower took as one plane fill 0.2, a chair's
    #: back and legs 0.3-0.7)
    tall_floor_solid: float = 0.8
    #: m: a vertical face that no plane grounds still stands on the floor when it stands on a
    #: low base with openings there, a pallet (:func:`~planerel.features.tall_face.base_foot`,
    #: pallet97): its foot more than ``tall_floor_fit`` and at most this over the floor's fit,
    #: the base's edge right under it flush with it (at most ``tall_base_back`` behind its
    #: plane, at most ``tall_base_front`` in front), the floor reached at the base's foot, and
    #: the base's openings (fork pockets) seen between: a load or a carton on a pallet (EUR
    #: 0.144 m, others 0.10-0.16).  0: off
    tall_base: float = 0.2
    #: m: ... the base's edge at most this behind the face's plane (a cabinet's plinth is
    #: recessed 3-6 cm behind its doors)
    tall_base_back: float = 0.02
    #: m: ... and at most this in front of it (a pallet a few cm larger than its load; a
    #: flight's first riser lies a run, 0.22 m or more, in front of the second)
    tall_base_front: float = 0.15
    #: m: a vertical face that no plane grounds still stands on the ground (:func:`level_ground`,
    #: ground75) when the points under its foot lie level with it and reach this far nearer
    #: to the sensor than the face in at least ``tall_floor_share`` of its middle columns:
    #: a floor the region grower made no plane of (a dark or speckled floor under a level
    #: view).  ``skirt_step``'s reach for a plane (a tread or a seat reaches less).  0: off
    tall_level_ground: float = 0.45
    #: m: a skirt's top (:meth:`_Solid.top_candidate`) lies at most this far above the
    #: sensor's eye (its centroid's level along ``up``, the camera at the origin): a plane
    #: seen from below is an underside -- a shelf's, a table's, a seat's -- and a box's top is
    #: never seen from below (furn44: a bookcase's shelves over its books 0.64 and 1.17 m above
    #: the eye, a table's top 0.48 m, seen from 0.1-2 m; every true box's top on the
    #: independent sets 0.087 m or more below it; a real carton's top read 0.21 m above it under
    #: a gravity estimated 15 degrees off, gqcnn PhoXi).  0: off (before furn44)
    skirt_top_eye: float = 0.3
    #: a skirt's top whose normal, oriented towards the sensor, points below the horizon
    #: (``normal . up < 0``) is seen from below: an underside, whatever its level (under80: a
    #: bookcase's shelf 0.17 m above a camera 0.56 m up, its lip hanging under it, answered
    #: ``box``).  A gravity estimate off by less than 90 degrees keeps a top seen from above
    #: on the upper side, where ``skirt_top_eye``'s level can move by the distance times the
    #: error (gqcnn's carton, above).  False: the level alone (before under80)
    skirt_underside: bool = True
    #: share: a skirt's top whose pixels fill less than this of their convex hull in the image
    #: (:func:`image_solidity`) is a ring, not a top: an open tote's or tray's rim seen from
    #: above, its inner wall hanging under it (spurious81: the tote's rim and wall answered
    #: ``box`` in 22 of dev_tote's 30 scenes, their tops filling 0.07-0.21 of their hulls; the
    #: skirt tops of the boxes answered right on five independent sets fill 0.40-1.0, a box's
    #: top filling its outline but for what lies on it).  0: off (before spurious81)
    skirt_top_solid: float = 0.3
    #: m: with no floor plane found at all (a camera lying on the floor: the floor returns no
    #: depth), a virtual floor level at the lowest level shared within this by the feet
    #: (``FaceProfile.bottom``) of at least ``tall_feet_min`` shaped upright planes below the
    #: eye (:func:`feet_level`) stands in for the floor plane in :func:`floor_foot` (feet44).
    #: 0: off (measured in docs/objects.md, "A floor level from the feet of upright faces")
    tall_feet_level: float = 0.0
    #: ... the number of upright planes whose feet must share that level
    tall_feet_min: int = 2
    #: m: with no floor plane found at all, a floor measured only as speckle (a camera a few
    #: decimetres over it sees it at grazing incidence, where the sensor returns scattered
    #: pixels no region grows over: :func:`planerel.features.gravity.speckle_floor`, its
    #: normal within 10 degrees of ``up``, at most this far under the camera) stands in for
    #: the floor plane in :func:`floor_foot` (sparse49: docs/objects.md "A floor seen only as
    #: speckle").  0: off
    tall_speckle_floor: float = 0.35
    #: m: a ``tall_face`` candidate whose top is hidden (over the eye) is refused when a
    #: nearer surface covers its top edge: in at least half of its middle pixel columns the
    #: first point measured over its top pixel is nearer than the face by more than this
    #: (:func:`top_covered`; a wall's lower part seen under a table's top between its legs,
    #: sparse49).  A box's top edge shows what lies behind it, or nothing measured.  0: off
    tall_top_cover: float = 0.1
    #: a taller upright plane adjacent to a ``tall_face`` candidate refuses it (the face is
    #: no free-standing solid's: a wall, a partition or a taller cabinet it belongs to)
    #: unless it is a solid standing beside the face (:func:`_stands_beside`): its foot
    #: level with the face's within ``standing_foot``, and its extent along the face
    #: (2nd-98th percentile of its points on the face's horizontal axis) overlapping the
    #: face's by at most this share of the face's width.  A taller box touching a lower
    #: one's end, or a wall meeting a box's side at its end, stands beside the face (ibox48:
    #: 0.00-0.10 on the independent sets, feet 0-0.02 m apart for boxes); a wall behind a
    #: box or a cabinet's body over its plinth overlaps it (0.5-1.0); a sofa's back, a bed's
    #: headboard, a cabinet over an alcove's doors rise from 0.34-0.65 m higher.  0 (the
    #: default): every taller plane refuses; 0.25 measured +10 boxes on the independent sets,
    #: none on real frames and one false box more on a judge set of real frames (off)
    tall_beside_overlap: float = 0.0
    #: m: ... and a parallel plane within this of the face's plane (its centroid along the
    #: face's normal) is the same surface going on (a wall in two pieces) and refuses it
    #: wherever it lies
    tall_beside_step: float = 0.02
    #: a taller upright plane adjacent to a ``tall_face`` candidate does not refuse it when
    #: both run out of the image's top (their top pixel rows within 2 of it): their measured
    #: tops are then where the border cuts each, not their edges (lead61: a tall box's two
    #: faces and the wall behind it seen from a low camera, the border cutting each 0.1 m
    #: apart).  False: every taller plane refuses, as before
    tall_cut_tops: bool = True
    #: m: an upright plane adjacent to a ``tall_face`` candidate across a corner (their
    #: normals 45 degrees or more apart) whose foot lies more than this below the face's
    #: refuses it: the face stands on ground that plane reaches under, the end of a wall
    #: going on past a floor's edge (a descending flight's side wall seen past its landing,
    #: sunk79), not a solid on that ground, whose sides share its foot.  A parallel plane
    #: under it (a shelf's lip under a box's front) does not count.  0: off
    tall_sunk: float = 0.1
    #: m: a ``lying`` plane (:func:`lying_tops`) stands at least this far above the ground
    #: it lies on (or ``lying_snr`` times its own fit's RMS, when more): a book's or
    #: a flat box's top 2-8 cm over the table; a floor's far piece that the sensor bends is
    #: level with the floor within its noise.  0: no plane is ``lying`` (top25)
    lying_rise: float = 0.015
    #: a ``lying`` plane's rise over its ground is at least this many times its own fit's
    #: RMS residual (the sensor's depth noise where it lies, or its curvature): a detection
    #: clear of the noise.  Real books and boxes on tables rise 9-86 times their RMS (every
    #: true ``lying`` proof of the real checks 9.65-85.7 on 2026-12-01); a round base's rim
    #: and inclined patches 5 cm over the floor in hunt25's room frames 2.1-3.6 times (2 before
    #: 2026-11-30, when those three passed); a monitor's round foot plate 2.4 cm over a desk,
    #: its domed top fitting with 4.2 mm of RMS where the flat tops beside it have 2.4-2.7,
    #: 5.9 times (5 before fbox40, 2026-12-01, when it passed: docs/objects.md "A domed
    #: plate is no flat thing's top")
    lying_snr: float = 7.5
    #: m: ... and at most this far (a book or a box lying flat; a chair's seat, a shelf's
    #: board, a landing, a table's top stand higher over what is under them) (top25)
    lying_rise_max: float = 0.12
    #: m: a ``lying`` plane is at most this long (``plane_length``): something one can
    #: lift, not a platform or a low stage (top25)
    lying_length: float = 0.6
    #: m: ... and at least this long and ``lying_width`` wide (``plane_length``,
    #: ``plane_width``): a book or a flat box; a strip along a wall's foot or a step's edge
    #: is narrower, a shoe's toe shorter (top25)
    lying_min_length: float = 0.12
    lying_width: float = 0.05
    #: m: a smaller top, down to this long and ``lying_small_width`` wide, is ``lying`` too
    #: when it is level within ``lying_small_tilt`` degrees (a product box lying flat, 11 x 4
    #: cm: its top parallel to the board under it; a drill's flank, a sliver at a floor's
    #: edge are tilted 15-20 degrees).  0: no smaller top (top25's bounds) (lying56; 0.10 x
    #: 0.035 m until small65 took it down to 0.05 x 0.03 m: product packs of 5-10 cm lying flat,
    #: docs/objects.md "Small packs lying flat"; 0.03 x 0.02 m since tote67: the tops of toy
    #: blocks and wooden cubes of 2.5-4 cm seen from above, docs/objects.md "Blocks seen from
    #: above")
    lying_small_length: float = 0.03
    lying_small_width: float = 0.02
    lying_small_tilt: float = 5.0
    #: a smaller top (``lying_small_length``) tilted more than ``lying_small_tilt`` degrees,
    #: up to twice that, and at most ``lying.SMALL_NOISE_LENGTH`` (6 cm) long, is level within
    #: its own noise when the rise the tilt makes along its length, ``tan(incline) x
    #: length``, is at most this many times its RMS fit residual: a 2.5-4.6 cm block top seen
    #: from 1 m measures 3-10 degrees off the board it stands on with 1.5-2.7 mm of RMS, a
    #: rise of 0.3-4 times its RMS (level100).  0: off
    lying_small_noise: float = 3.0
    #: m: a tiny top, down to this long (and ``lying_small_width`` wide), under
    #: ``lying_small_length``, is ``lying`` too when it is squat: its rise over its ground at
    #: most ``lying_tiny_squat`` times its length (a 2.5 cm cube's 2.4-3 cm top, 2-2.5 cm up,
    #: seen from 1 m; a standing cylinder 2.9 cm across and 6 cm tall, a peg or a marker, is
    #: slender).  0: off (tiny102)
    lying_tiny_length: float = 0.025
    lying_tiny_squat: float = 1.5
    #: the ground a ``lying`` plane lies on is at least this many times its area (a table
    #: or the floor under a book, not a tread beside a tread) (top25)
    lying_ground: float = 3.0
    #: degrees: a ``lying`` top is within this of parallel to the ground it lies on (the
    #: angle between their normals): a flat thing lying on a table or the floor rests on
    #: it.  0: off (the top's own incline is bounded by ``skirt_tilted`` alone).  Off, because
    #: real books leaning on something are boxes too: at 7 or 10 the development frames lose 4
    #: or 2 false lying boxes (tops 7.7-26.7 degrees off their ground) but OSD test63's green
    #: book (15) and biscuit box (24) are lost with them (docs/objects.md, "hunt88")
    lying_tilt: float = 0.0
    #: degrees: a ``lying`` top more than this off parallel to its ground leans on something,
    #: and its whole hull stands at least ``lying_rise`` over the ground (a leaning book's
    #: top is its thickness over the table at its low edge, 3.2-4.7 cm on the real frames); a
    #: patch tipped up from the ground (a smeared depth edge) starts at the ground's level.
    #: 0: off (lean88)
    lying_lean: float = 5.0
    #: pixels (at 640 image columns, scaled with the width): a plane with no ``adjacent``
    #: ground is ``lying`` on a horizontal plane that shows around it across a depth jump:
    #: within this many pixels of its outline, the measured points are at the ground's level
    #: (at least ``lying_ring_ground`` of them) or the top's own, at most
    #: ``lying_ring_between`` in between.  A box seen from straight above hides its sides,
    #: so its top and the board under it never touch; a tin's lid seen from the side has its
    #: wall in between (lie32).  0: adjacent grounds only
    lying_ring: float = 6.0
    lying_ring_ground: float = 0.2
    lying_ring_between: float = 0.1
    #: pixels (at 640 image columns, scaled with the width): the ring starts this far out
    #: from the top's outline; the band hugging it is left out.  There a depth edge's mixed
    #: pixels (a sensor that smears the jump from the top to the floor over 3-6 pixels, depth
    #: aligned to a colour stream) and the top's own side, seen edge-on from above, lie
    #: between the levels; a side in view from the side is wider than the band.  0: the
    #: ring hugs the outline (lie32) (lying56)
    lying_ring_band: float = 5.0
    #: a level in the ring is within 3 times the larger of the top's and the ground's fit
    #: RMS (at least 5 mm, at most a quarter of the rise): a floor fitted with 4 mm of RMS
    #: over a room is that level within its own noise.  False: the top's RMS only (lie32)
    #: (lying56)
    lying_ring_ground_noise: bool = False
    #: a top with no single ground of ``lying_ground`` times its area may lie on several
    #: horizontal pieces at one level under it (a tray's or tote's floor, a pallet that the
    #: segmentation breaks up): the pieces ``t`` lies on (``_lies_on``) whose level under
    #: ``t``'s centroid agrees within 3 times the larger fit RMS (at least 5 mm) count as one
    #: ground of their summed area; one of them adjacent to ``t``, or the ring test against
    #: them, as for one ground (ground56).  False: one plane is the ground
    lying_ground_union: bool = False
    corner_tol: float = 0.08
    corner_width: float = 0.08
    #: ``corner`` (ramp42): neither wall's exposed top edge may rise ``corner_slope`` degrees
    #: or more, measured over at least ``corner_slope_span`` m along it and straight within
    #: ``corner_slope_rms`` m (:func:`planerel.features.solid.top_edge`): a box's upright
    #: faces have level top edges, a ramp's side face (a wedge seen from its side with its high
    #: end) one that follows the slope.  0 = never, the default: measured with 8
    #: (:data:`CORNER_SLOPE`; ``--param relations.corner_slope=8``), the demo's box rule 4
    #: loses its ``angle >= 89`` literal when it learns with it, and that rule answers 4 more
    #: false boxes on real frames (docs/results.md, "A ramp seen from its side", ramp42);
    #: with the rules learned without it, set at classification only, every real check is
    #: unchanged and the independent sets' wedges seen from their side are no box
    corner_slope: float = 0.0
    corner_slope_span: float = 0.5
    corner_slope_rms: float = 0.01
    facing_overlap: float = 0.5
    #: m: the narrower of two ``facing`` walls may be this narrow (the wider one at least
    #: ``corner_width``): an open box's far side seen as a strip over its near side
    #: (docs/results.md, "Open boxes: the far side seen as a strip", held16b; 0.08 before)
    facing_width: float = 0.04
    #: m: with a wall narrower than ``corner_width``, the tops must be within this (not
    #: ``corner_tol``): a riser's foot seen as a strip is level with the riser below only
    #: within its own width
    facing_narrow_tol: float = 0.03
    #: ``face_pair`` (pair41): two upright faces of one solid seen without a top or ground,
    #: narrow faces allowed: each at least ``face_pair_width`` m wide (``Plane.width``), the
    #: angle between them at least ``face_pair_angle`` degrees (real corners open by 1-4
    #: degrees: docs/synthetic-world.md "Block-matching window"; ryesw's carton 86.5-88.9),
    #: their tops and their bottoms each within ``face_pair_level`` m of each other and within
    #: ``face_pair_level_share`` of the shorter face's height (its 2nd-98th percentile span):
    #: two faces of one upright solid span the same heights (a translucent cup's two facets,
    #: hunt33 ucn 000006: tops 1.8 cm apart on a 4.3 cm span; ryesw's carton: at most 1.2 cm
    #: on 22 cm)
    face_pair_width: float = 0.02
    face_pair_angle: float = 85.0
    #: degrees (0 = off; on, 20): a face seen within ``face_pair_graze`` of edge-on (the view ray to
    #: its centroid against its plane) has its normal turned towards the camera by the
    #: sensor's smear of the convex edge it shares with the other face (top44's section of a
    #: RealSense cube: a side 11.5 degrees from edge-on fitted 7-9 degrees off square), so the
    #: pair needs only ``face_pair_graze_angle`` degrees (boxrec59, docs/objects.md "Real
    #: boxes missed, cause by cause")
    face_pair_graze: float = 20.0
    face_pair_graze_angle: float = 80.0
    face_pair_level: float = 0.03
    face_pair_level_share: float = 0.25
    #: m: planes narrower than this (``plane_width``) do not count in ``oblique_share``
    #: (:func:`planerel.features.facts.oblique_share`); 0 = every plane counts
    oblique_min_width: float = 0.025
    #: about how many of a vertical face's points its profile (the 2nd and 98th percentiles
    #: of their heights and of their positions along it) is measured on: every k-th row and
    #: column of its pixel box, k = int(sqrt(n_points / profile_points)) (at least 1)
    #: (:func:`planerel.features.solid.face_profile_of`; 4000 before 2026-11-29)
    profile_points: int = PROFILE_POINTS

    def __post_init__(self) -> None:
        _check_nonneg(self, ("parallel_tol", "perpendicular_tol", "adjacency_gap", "touch_depth",
                             "touch_rel", "above_tol", "front_tol", "skirt_tol", "skirt_reach",
                             "skirt_reach_share", "skirt_cover", "skirt_beyond", "skirt_step", "corner_tol", "corner_width", "corner_slope", "corner_slope_span", "corner_slope_rms",
                             "facing_overlap", "facing_width", "facing_narrow_tol", "face_pair_width", "face_pair_angle", "face_pair_graze", "face_pair_graze_angle", "face_pair_level", "face_pair_level_share", "skirt_top_tilt", "skirt_top_noise", "skirt_tilted", "oblique_min_width",
                             "skirt_grounded_reach", "riser_width", "riser_rise_max", "standing_foot",
                             "standing_fill", "tall_narrow_width", "tall_narrow_bend", "tall_eye", "tall_cut_eye", "tall_flat", "tall_flat_noise", "tall_cap", "tall_cap_tol", "tall_cap_depth", "tall_cap_ratio",
                             "tall_floor_fit", "tall_floor_share", "tall_floor_solid", "tall_level_ground", "tall_base", "tall_base_back", "tall_base_front", "skirt_top_eye", "skirt_top_solid", "tall_feet_level",
                             "tall_speckle_floor", "tall_top_cover", "tall_beside_overlap", "tall_beside_step", "tall_sunk",
                             "lying_rise",
                             "lying_rise_max", "lying_length", "lying_ground", "lying_tilt", "lying_lean",
                             "lying_min_length", "lying_width", "lying_snr", "lying_ring",
                             "lying_ring_ground", "lying_ring_between", "lying_ring_band",
                             "lying_small_length", "lying_small_width", "lying_small_tilt",
                             "lying_small_noise", "lying_tiny_length", "lying_tiny_squat"))
        if self.lying_rise > 0 and self.lying_rise_max <= self.lying_rise:
            raise InputError(f"lying_rise_max must be above lying_rise ({self.lying_rise!r}), got "
                             f"{self.lying_rise_max!r} (lying_rise 0 switches lying/1 off)")
        if self.lying_min_length > self.lying_length:
            raise InputError(f"lying_min_length must be at most lying_length "
                             f"({self.lying_length!r}), got {self.lying_min_length!r}")
        if not isinstance(self.tall_feet_min, int) or self.tall_feet_min < 2:
            raise InputError(f"tall_feet_min is a count of planes, at least 2, got "
                             f"{self.tall_feet_min!r}")
        for name in ("tall_floor_share", "tall_floor_solid", "skirt_top_solid"):
            if getattr(self, name) > 1:
                raise InputError(f"{name} is a share in 0..1, got {getattr(self, name)!r}")
        if self.tall_beside_overlap > 1:
            raise InputError(f"tall_beside_overlap is a share of the face's width in 0..1, got "
                             f"{self.tall_beside_overlap!r}")
        if self.tall_cap > 1:
            raise InputError(f"tall_cap is a share of the face's pixel columns in 0..1, got "
                             f"{self.tall_cap!r}")
        if self.standing_fill > 1:
            raise InputError(f"standing_fill is a share of the plane's rectangle in 0..1, got "
                             f"{self.standing_fill!r}")
        if self.skirt_cover > 1:
            raise InputError(f"skirt_cover is a share of the top's extent in 0..1, got {self.skirt_cover!r}")
        if self.facing_overlap > 1:
            raise InputError("facing_overlap is a share of the shorter wall's extent in 0..1, got "
                             f"{self.facing_overlap!r}")
        if self.parallel_tol >= 45 or self.perpendicular_tol >= 45:
            raise InputError("parallel_tol and perpendicular_tol must be below 45 degrees, got "
                             f"{self.parallel_tol!r} and {self.perpendicular_tol!r}")
        if isinstance(self.grid_gap, bool) or not isinstance(self.grid_gap, int) or not 1 <= self.grid_gap <= 8:
            raise InputError(f"grid_gap must be an integer number of pixels in 1..8, got {self.grid_gap!r}")
        for name in ("skirt_top_tilt", "skirt_tilted"):
            if getattr(self, name) >= 45:
                raise InputError(f"{name} must be below 45 degrees, got {getattr(self, name)!r}")
        check_bools(self)
        if (isinstance(self.profile_points, bool) or not isinstance(self.profile_points, int)
                or self.profile_points < 1):
            raise InputError(f"profile_points must be an integer >= 1, got {self.profile_points!r}")


@dataclass(frozen=True)
class Relation:
    """The relation of plane ``a`` to plane ``b`` (labels); directional fields read "a ... b"."""

    a: int
    b: int
    angle: float
    parallel: bool
    perpendicular: bool
    gap: float
    touching: bool
    adjacent: bool
    rise: float
    above: bool
    in_front_of: bool
    skirt: bool = False
    corner: bool = False
    facing: bool = False
    face_pair: bool = False


@dataclass(frozen=True, eq=False)
class Relations:
    """All ordered pair relations of a scene (``a != b``), sorted by ``(a, b)``.

    Attributes
    ----------
    pairs : tuple of Relation
    params : RelationParams
    skirt_steps : dict
        ``{(top, face): frozenset of (label, riser_top)}``: the pairs that pass every ``skirt``
        test but the step's (``face`` stands on a tread, or a riser parallel to it rises from
        ``top``), with the planes that are that tread (``riser_top`` NaN) or riser (the level
        of its top edge, metres along up) (:func:`skirts_within_objects`).
    """

    pairs: tuple
    params: RelationParams
    skirt_steps: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.pairs)

    def __iter__(self):
        return iter(self.pairs)

    def get(self, a: int, b: int) -> Relation:
        """The relation of ``a`` to ``b`` (``KeyError`` when absent)."""
        pos = getattr(self, "_pos", None)
        if pos is None:
            pos = self._positions()
        if pos:
            # every ordered pair of n labels, sorted (as relate makes them): (a, b) at
            # i (n - 1) + j - (j > i) for the labels' ranks i, j; the relation found there is
            # checked, any other layout is looked up in the dictionary (a few dozen lookups
            # a scene: a dictionary of all n (n - 1) pairs cost more than they do)
            i, j = pos.get(a), pos.get(b)
            if i is not None and j is not None and i != j:
                r = self.pairs[i * (len(pos) - 1) + j - (j > i)]
                if r.a == a and r.b == b:
                    return r
        idx = getattr(self, "_index", None)
        if idx is None:
            idx = {(r.a, r.b): r for r in self.pairs}
            object.__setattr__(self, "_index", idx)
        return idx[(a, b)]

    def _positions(self) -> dict:
        """``{label: rank}`` when :attr:`pairs` may be every ordered pair of ``n`` labels
        sorted by ``(a, b)`` (``n (n - 1)`` of them, the first of each run of ``n - 1`` an
        increasing label), else ``{}``; remembered."""
        m = len(self.pairs)
        n = (1 + math.isqrt(1 + 4 * m)) // 2
        pos: dict = {}
        if n >= 2 and n * (n - 1) == m:
            heads = [r.a for r in self.pairs[::n - 1]]
            if heads == sorted(heads) and len(set(heads)) == n:
                pos = dict(zip(heads, range(n), strict=True))
        object.__setattr__(self, "_pos", pos)
        return pos

    def adjacent_pairs(self) -> list[tuple[int, int]]:
        """Unordered adjacent pairs ``(a, b)`` with ``a < b``."""
        return [(r.a, r.b) for r in self.adjacent_only() if r.a < r.b]

    def adjacent_only(self) -> tuple:
        """The relations of adjacent planes, in :attr:`pairs`' order (remembered: a scene's
        steps each look at these alone, a third or less of every ordered pair)."""
        adj = getattr(self, "_adj", None)
        if adj is None:
            adj = tuple(r for r in self.pairs if r.adjacent)
            object.__setattr__(self, "_adj", adj)
        return adj


def view_angle(plane) -> float:
    """Degrees between the view ray to ``plane``'s centroid (the camera at the origin) and
    its plane: 0 seen edge-on, 90 head-on."""
    c = np.asarray(plane.centroid, float)
    d = float(np.linalg.norm(c))
    if d == 0.0:
        return 90.0
    return math.degrees(math.asin(min(1.0, abs(float(np.asarray(plane.normal, float) @ c)) / d)))


def noise_tilt(rms: float, extent: float, k: float) -> float:
    """Degrees a plane's fit may tilt by its noise alone: the tilt ``k`` times its fit RMS
    (m) makes across ``extent`` (m), ``atan(k rms / extent)``; 0 when ``k`` or ``extent`` is 0
    (a narrow skirt top across its width, :meth:`_Solid.top_tilt`; a small lying top along its
    length, :func:`planerel.features.lying.top_sized`)."""
    if k <= 0 or extent <= 0:
        return 0.0
    return math.degrees(math.atan(k * float(rms) / float(extent)))


def adjacent_only(relations):
    """``relations``' relations of adjacent planes, in order (:meth:`Relations.adjacent_only`),
    or ``relations`` itself when it is a plain sequence (its callers test ``adjacent``
    anyway: the same relations either way)."""
    f = getattr(relations, "adjacent_only", None)
    return f() if f is not None else relations


def hull_gap(pa, pb) -> float:
    """Closest distance between the 3-D convex hulls of two planes.

    Parameters
    ----------
    pa, pb : Plane
        Planes with ``hull3d`` (counter-clockwise vertices in their own plane), ``normal``,
        ``centroid`` and ``axes``.

    Returns
    -------
    float
        Metres; 0 when the polygons touch or cross.
    """
    return float(_gap_matrix([pa, pb])[0, 1])


def _gap_matrix(plist) -> np.ndarray:
    """``(n, n)`` closest hull distances of all plane pairs (one compiled pass,
    :func:`planerel.features._relation_kernels.gap_matrix`).

    The distance between two convex planar polygons is the smallest of: the edge-edge segment
    distances, the distance of a vertex of one polygon to the other polygon's face when it
    projects inside it, and 0 when an edge of one pierces the other's face.  Each hull's
    vertices in its own frame are taken with numpy's matrix product (as before the kernel:
    the same floats).
    """
    from planerel.features._relation_kernels import gap_matrix

    n = len(plist)
    M = max(p.hull3d.shape[0] for p in plist)
    poly2 = np.zeros((n, M, 2))
    isface = np.zeros(n, dtype=bool)
    vstart = np.zeros(n + 1, dtype=np.int64)
    for k, p in enumerate(plist):
        poly = p.hull3d
        vstart[k + 1] = vstart[k] + poly.shape[0]
        if poly.shape[0] >= 3:
            isface[k] = True
            p2 = (poly - p.centroid) @ p.axes.T
            poly2[k, : p2.shape[0]] = p2
            poly2[k, p2.shape[0]:] = p2[-1]
    V = np.ascontiguousarray(np.concatenate([p.hull3d for p in plist]), dtype=float)
    C = np.array([p.centroid for p in plist], dtype=float)
    N = np.array([p.normal for p in plist], dtype=float)
    AX = np.array([p.axes for p in plist], dtype=float)  # (n, 2, 3)
    return gap_matrix(V, vstart, C, N, AX, poly2, isface)


def _touching(planes, params: RelationParams, xyz: np.ndarray) -> set[tuple[int, int]]:
    """Unordered label pairs whose boundary pixels touch in the grid and in 3-D."""
    lab = planes.labels
    if lab is None or lab.shape != xyz.shape[:2]:
        return set()
    from planerel.features._relation_kernels import touch_pairs_with_tiles

    top = label_max(lab)
    known = np.zeros(top + 1 if top >= 0 else 1, dtype=bool)
    for p in planes:
        known[p.label] = True
    brow, bcol = _boundary_pixels(lab)
    # every boundary pixel of lab: touch_pairs' answer, windows that can find nothing new
    # (no boundary pixel of an untested label in the tiles they meet) not read; the tiles
    # remembered for the proposals' edge sums
    m = touch_pairs_with_tiles(np.ascontiguousarray(xyz),
                               np.ascontiguousarray(lab, dtype=np.int32),
                               np.asarray(brow, np.int64), np.asarray(bcol, np.int64),
                               _boundary_tiles(lab), int(params.grid_gap),
                               float(params.touch_depth), float(params.touch_rel), known)
    a, b = np.nonzero(m)  # symmetric: each pair once, a < b
    return {(x, y) for x, y in zip(a.tolist(), b.tolist(), strict=True) if x < y}


def image_solidity(labels, label: int, bbox=None) -> float:
    """The share of the convex hull, in the image, of plane ``label``'s pixels that they fill
    (1 for a filled convex region; a ring's, a frame's or a U's is far less).

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
    label : int
    bbox : (row0, col0, row1, col1), optional
        The plane's pixel box (:class:`~planerel.features.planes.Plane` ``bbox``, ends
        exclusive): only that window is read.

    Returns
    -------
    float
        In (0, 1]; 1.0 for fewer than 3 pixels or pixels on one line (no area to fill).
    """
    labels = np.asarray(labels)
    if bbox is not None:
        r0, c0, r1, c1 = (int(v) for v in bbox)
        labels = labels[max(0, r0):r1, max(0, c0):c1]
    return mask_solidity(labels == label)


class _Solid:
    """``skirt``, ``corner`` and ``facing`` of :func:`relate`
    (:func:`planerel.features.solid.is_skirt`, :func:`~planerel.features.solid.is_corner`,
    :func:`~planerel.features.solid.is_facing`); each face is measured once.  (Their helpers
    are imported with the module: an import statement in a method costs about 0.6 us a call,
    and a scene asks for a face's profile dozens of times.)"""

    def __init__(self, planes, cloud, params: RelationParams, profiles: dict | None = None):
        lab = planes.labels
        ok = cloud is not None and lab is not None and lab.shape == cloud.xyz.shape[:2]
        self.xyz = cloud.xyz if ok else None
        self.intrinsics = getattr(cloud, "intrinsics", None) if ok else None
        self.labels, self.up, self.params = lab, np.asarray(planes.up, float), params
        #: ``{face label: FaceProfile}`` along ``planes.up`` (:func:`relate`'s ``profiles``)
        self._profiles: dict = {} if profiles is None else profiles
        #: ``{label: [planes adjacent to it]}``, filled by :func:`relate`
        self.touching: dict = {}
        #: ``{(top, face): step and riser labels}`` of the skirts only a step denied
        self.steps: dict = {}
        #: ``{face label: TopEdge or None}`` (:meth:`_top_edge`)
        self._edges: dict = {}
        #: ``{label: bool}`` (:meth:`top_candidate`)
        self._tops: dict = {}
        #: ``{label: float}`` (:meth:`solidity`)
        self._solidity: dict = {}
        self.normals = None
        if ok:
            self.normals = np.full((max([label_max(lab) + 1] + [p.label + 1 for p in planes]), 3),
                                   np.nan)
            for p in planes:
                self.normals[p.label] = p.normal

    def _profile(self, face):
        prof = self._profiles.get(face.label)
        if prof is None:
            prof = self._profiles[face.label] = face_profile_of(face, self.up, self.labels,
                                                                self.xyz,
                                                                self.params.profile_points)
        return prof

    def _tilted(self, top) -> bool:
        """True when ``top`` may be a tilted box's top (``skirt_tilted``): inclined at most
        ``skirt_tilted`` degrees and at most ``TILTED_MAX_LENGTH`` long."""
        return (top.orientation == "inclined" and top.incline <= self.params.skirt_tilted
                and top.length <= TILTED_MAX_LENGTH)

    def narrow_top(self, top) -> bool:
        """True when ``top``'s incline is within :meth:`top_tilt` (the noise's allowance is
        measured only for a top past ``skirt_top_tilt`` and within twice it)."""
        bound = self.params.skirt_top_tilt
        return top.incline <= bound or (top.incline <= 2.0 * bound
                                        and top.incline <= self.top_tilt(top))

    def top_tilt(self, top) -> float:
        """Degrees a narrow top may be inclined towards its face: ``skirt_top_tilt`` plus the
        tilt that ``skirt_top_noise`` times the top's own fit RMS across its width makes
        (``atan(k rms / width)``: on a noisy sensor a 5 cm strip's fit says little of its
        tilt), at most ``skirt_top_tilt`` more; a noise-free top gets none."""
        p = self.params
        extra = noise_tilt(top.rms, top.width, p.skirt_top_noise)
        return p.skirt_top_tilt + min(p.skirt_top_tilt, extra)

    def top_candidate(self, top) -> bool:
        """True when ``top`` can be a skirt's top: horizontal, inclined at most
        ``skirt_top_tilt`` degrees (whether it leans towards the face is :meth:`skirt`'s), or
        a tilted box's top (:meth:`_tilted`); and not seen from below: its level at most
        ``skirt_top_eye`` above the sensor's eye and (``skirt_underside``) its normal towards
        the sensor not pointing down (a shelf's or a table's underside).
        Remembered per plane (:func:`relate` asks once a plane, :meth:`skirt` again a pair)."""
        got = self._tops.get(top.label)
        if got is None:
            got = self._tops[top.label] = self._top_candidate(top)
        return got

    def _top_candidate(self, top) -> bool:
        lim = self.params.skirt_top_eye
        if lim > 0 and float(np.asarray(top.centroid, float) @ self.up) > lim:
            return False
        if self.params.skirt_underside and float(np.asarray(top.normal, float) @ self.up) < 0:
            return False
        if top.orientation == "horizontal":
            return True
        return (top.orientation == "inclined" and self.narrow_top(top)) \
            or self._tilted(top)

    def solidity(self, top) -> float:
        """:func:`image_solidity` of ``top``, or a lower bound of it at least
        ``skirt_top_solid`` (its pixels' share of their pixel box); measured once, and only
        for a pair that passes every other test of a level skirt."""
        got = self._solidity.get(top.label)
        if got is None:
            r0, c0, r1, c1 = top.bbox
            box = max(1, (r1 - r0) * (c1 - c0))
            # the hull lies in the pixel box, so filling the box's share is a lower bound of
            # the hull's: a top that fills its box well needs no hull (most tops)
            got = top.n_points / box if top.n_points >= self.params.skirt_top_solid * box \
                else image_solidity(self.labels, top.label, top.bbox)
            self._solidity[top.label] = got
        return got

    def face_candidate(self, face) -> bool:
        """True when ``face`` can be a skirt's face: vertical, or (``skirt_tilted``) steep
        enough to be perpendicular to a tilted top."""
        p = self.params
        return face.orientation == "vertical" or (
            p.skirt_tilted > 0 and face.incline >= 90.0 - p.skirt_tilted - p.perpendicular_tol)

    def tilted_skirt(self, top, face) -> bool:
        """The skirt of a tilted box: the module rule (:func:`~planerel.features.solid.is_skirt`)
        in the top's own frame (its upward normal for ``up``), the face perpendicular to the
        top and reaching at most ``TILTED_BEYOND`` of the top's extent past its ends."""
        p = self.params
        n = np.asarray(top.normal, float)
        if n @ self.up < 0:
            n = -n
        if abs(float(np.dot(n, face.normal))) > np.sin(np.radians(p.perpendicular_tol)):
            return False
        prof = face_profile_of(face, n, self.labels, self.xyz, p.profile_points)
        reach = min(p.skirt_reach, p.skirt_reach_share * top.length) if p.skirt_reach_share else p.skirt_reach
        if self._grounded(top, face, reach):
            # a tilted book's side whose low end stands on the table
            reach = p.skirt_grounded_reach
        # a tilted box's side ends where its top ends; a lying cylinder's end disk reaches
        # past the strip on its top
        ext = np.asarray(top.hull3d, float) @ prof.along
        t0, t1 = float(ext.min()), float(ext.max())
        beyond = max(0.0, t0 - prof.lo) + max(0.0, prof.hi - t1)
        if not beyond <= TILTED_BEYOND * (t1 - t0):
            return False
        return is_skirt(top, face, n, prof, self.labels, self.xyz, self.intrinsics,
                        self.normals, p.parallel_tol, p.skirt_tol, reach,
                        p.skirt_cover, p.skirt_beyond)

    def skirt(self, top, face) -> bool:
        if self.xyz is None or not self.top_candidate(top):
            return False
        if top.orientation != "horizontal":
            # a narrow top whose fit the rounded edge tilts towards its face: the level rule;
            # else a tilted box's (in its top's frame)
            if not (face.orientation == "vertical" and self.narrow_top(top)
                    and leans_towards(top, face, self.up)):
                return self._tilted(top) and self.tilted_skirt(top, face)
        elif face.orientation != "vertical":
            return False
        p = self.params
        prof = self._profile(face)
        # is_skirt's tests in an order of their cost: the offset and the ends first; the
        # reach asked then, the lower grounded reach (its adjacent planes' tests) asked only
        # of a face short of the usual one (the grounded reach only lowers the bar: the
        # same answers); the cover last
        offset, got, beyond, span = _skirt_geometry(top, self.up, prof)
        if not (abs(offset) <= p.skirt_tol and beyond <= p.skirt_beyond):
            return False
        # a low box's side is as low as a slab's edge: the reach asked scales with the top's
        # long side (a table top or a seat is long, a box lying flat is short)
        reach = min(p.skirt_reach, p.skirt_reach_share * top.length) if p.skirt_reach_share else p.skirt_reach
        # a side standing on the floor or a table (a box lying flat, however low) need reach
        # only skirt_grounded_reach
        if not got >= reach and not (got >= p.skirt_grounded_reach
                                     and self._grounded(top, face, reach)):
            return False
        if not skirt_covered(face, self.up, prof, span, self.labels, self.xyz, self.intrinsics,
                             self.normals, p.parallel_tol, p.skirt_cover):
            return False
        if p.skirt_top_solid > 0 and self.solidity(top) < p.skirt_top_solid:
            return False  # a ring (a tote's rim over its inner wall), not a top
        near = self.touching.get(face.label, ())
        nan = float("nan")
        steps = [(h.label, nan) for h in near if h.label != top.label and h.orientation == "horizontal"
                 and on_step(face, prof, h, self.up, p.skirt_tol, p.skirt_step)]
        if steps and not p.skirt_own_steps:
            return False
        cos_par = float(np.cos(np.radians(p.parallel_tol)))
        steps += [(v.label, self._profile(v).top) for v in self.touching.get(top.label, ())
                  if v.label != face.label and v.orientation == "vertical"
                  and abs(float(np.dot(v.normal, face.normal))) >= cos_par
                  and rises_from(top, self._profile(v), self.up, p.skirt_tol, p.skirt_reach)
                  and self._riser_wide(self._profile(v), prof)
                  and self._riser_step(top, v)]
        if steps:
            # a riser's side on a tread, unless the step is another object's
            # (:func:`skirts_within_objects`)
            if p.skirt_own_steps:
                self.steps[(top.label, face.label)] = frozenset(steps)
            return False
        return True

    def _grounded(self, top, face, reach: float) -> bool:
        """True when ``skirt_grounded_reach`` (less than ``reach``, the reach asked otherwise)
        is all ``face`` must reach below ``top``: a horizontal plane adjacent to the face other
        than the top is the ground it stands on (:func:`~planerel.features.solid.grounded`,
        measured along ``up``)."""
        p = self.params
        if not 0 < p.skirt_grounded_reach < reach:
            return False
        near = [h for h in self.touching.get(face.label, ())
                if h.label != top.label and h.orientation == "horizontal"]
        if not near:
            return False
        prof = self._profile(face)
        return any(grounded(face, prof, h, self.up, p.skirt_grounded_reach, p.skirt_tol,
                            p.skirt_step) for h in near)

    def _riser_step(self, top, riser) -> bool:
        """True when ``riser`` (a vertical plane rising from ``top``) may be a flight's next
        riser by its height: it rises at most ``riser_rise_max`` above the top's level, or a
        horizontal plane adjacent to it lies at its top edge (within ``skirt_tol``, the next
        tread or another solid's top).  A wall or a cabinet behind a box rises far higher,
        with nothing on it or its top out of view (skirt36)."""
        p = self.params
        if p.riser_rise_max <= 0:
            return True
        prof = self._profile(riser)
        up = self.up
        level = float(np.asarray(top.centroid, float) @ up)
        if not math.isfinite(prof.top) or prof.top - level <= p.riser_rise_max:
            return True
        return any(h.orientation == "horizontal" and h.label != top.label
                   and abs(float(np.asarray(h.centroid, float) @ up) - prof.top) <= p.skirt_tol
                   for h in self.touching.get(riser.label, ()))

    def _riser_wide(self, riser, face) -> bool:
        """True when a plane rising from a skirt's top (its :class:`FaceProfile` ``riser``)
        is wide enough to be a flight's next riser: at least ``riser_width`` along the face,
        or half as wide as the face (``face``'s profile) when that is less."""
        w = self.params.riser_width
        if w <= 0:
            return True
        width = riser.hi - riser.lo
        if not math.isfinite(width):
            return True
        return bool(width >= min(w, 0.5 * (face.hi - face.lo)))

    def corner(self, a, b) -> bool:
        if self.xyz is None or a.orientation != "vertical" or b.orientation != "vertical":
            return False
        p = self.params
        return is_corner(a, b, self._profile(a), self._profile(b), p.corner_tol,
                         p.corner_width) and not (
            p.corner_slope > 0 and any(sloped_top(self._top_edge(f), p.corner_slope,
                                                  p.corner_slope_span, p.corner_slope_rms)
                                       for f in (a, b)))

    def _top_edge(self, face):
        """:func:`~planerel.features.solid.top_edge` of ``face``, measured once."""
        if face.label not in self._edges:
            self._edges[face.label] = top_edge(face, self.up, self.labels, self.xyz)
        return self._edges[face.label]

    def face_pair(self, a, b, angle) -> bool:
        if self.xyz is None or a.orientation != "vertical" or b.orientation != "vertical":
            return False
        p = self.params
        bound = p.face_pair_angle
        if p.face_pair_graze > 0 and min(view_angle(a), view_angle(b)) < p.face_pair_graze:
            bound = min(bound, p.face_pair_graze_angle)
        return angle >= bound and is_face_pair(
            a, b, self._profile(a), self._profile(b), p.face_pair_level, p.face_pair_width,
            p.face_pair_level_share)

    def facing(self, a, b) -> bool:
        if self.xyz is None or a.orientation != "vertical" or b.orientation != "vertical":
            return False
        p = self.params
        return is_facing(a, b, self._profile(a), self._profile(b), p.corner_tol,
                         p.corner_width, p.facing_overlap, p.facing_width,
                         p.facing_narrow_tol)


#: Degrees: the ``corner_slope`` measured (ramp42; off by default, see
#: :class:`RelationParams`)
CORNER_SLOPE = 8.0

#: Metres: the longest tilted top (``skirt_tilted``): a box one can tip over; a ramp's slope
#: is longer.
TILTED_MAX_LENGTH = 0.5

#: Share of a tilted top's extent its face may reach past the top's ends (``skirt_tilted``).
TILTED_BEYOND = 0.25

#: Cosine of the widest angle between an inclined top's downhill direction and a face's
#: normal (towards the sensor) at which the top leans towards the face (:func:`leans_towards`).
LEAN_COS = math.cos(math.radians(30.0))


def leans_towards(top, face, up) -> bool:
    """True when inclined plane ``top`` slopes down towards vertical ``face``'s seen side: the
    horizontal part of its upward normal within 30 degrees of the face's horizontal normal
    (planerel orients normals towards the sensor, so that is the side the face is seen from).

    A box's top and side meet at a rounded edge; on a narrow top (the 6 cm top of a standing
    cereal box) the edge's points tilt the top's fit by 6-7 degrees towards the side (real
    Kinect and RealSense frames, docs/objects.md "realbox").  A ramp's slope falls along its
    side faces (about 90 degrees from their normals) and away from the face below its high
    end (180 degrees), so neither leans towards its face.
    """
    up = np.asarray(up, float)
    nt = np.asarray(top.normal, float)
    if nt @ up < 0:
        nt = -nt
    h = nt - (nt @ up) * up
    nf = np.asarray(face.normal, float)
    nf = nf - (nf @ up) * up
    hn, fn = vec_norm(h), vec_norm(nf)
    if hn < 1e-9 or fn < 1e-9:
        return False
    return bool(float(h @ nf) / (hn * fn) >= LEAN_COS)


_new = object.__new__
#: The setter of a Relation's instance dictionary (``r.__dict__ = d`` without the frozen
#: class's ``__setattr__``).
_set_dict = next(c.__dict__["__dict__"] for c in Relation.__mro__ if "__dict__" in c.__dict__).__set__


def _relation(a, b, angle, parallel, perpendicular, gap, touching, adjacent, rise, above,
              in_front_of, skirt, corner, facing=False, face_pair=False) -> Relation:
    """``Relation(...)`` without the frozen dataclass's ``__init__`` (14 guarded attribute
    writes): the same fields, in the same order, in the instance dictionary."""
    r = _new(Relation)
    # a dict display, not keywords: no keyword dictionary built and unpacked (0.84 against
    # 1.2 us a relation); set as the instance dictionary through its descriptor, not copied
    # into an empty one (1.93 -> 1.72 us)
    _set_dict(r, {"a": a, "b": b, "angle": angle, "parallel": parallel,
                  "perpendicular": perpendicular, "gap": gap, "touching": touching,
                  "adjacent": adjacent, "rise": rise, "above": above,
                  "in_front_of": in_front_of, "skirt": skirt, "corner": corner,
                  "facing": facing, "face_pair": face_pair})
    return r


def relate(planes, cloud=None, params: RelationParams | None = None,
           profiles: dict | None = None) -> Relations:
    """Relations of every ordered pair of planes.

    Parameters
    ----------
    planes : PlaneSet
        From :func:`planerel.features.planes.measure_planes`.
    cloud : Cloud, optional
        The cloud the planes were measured in; needed for the image-grid ``touching`` test
        (without it, adjacency uses the 3-D hull gap alone) and for ``skirt`` and
        ``corner`` and ``facing`` (False without it).
    params : RelationParams, optional
    profiles : dict, optional
        Filled with the face profiles the skirt, corner and facing tests measured,
        ``{face label: FaceProfile}``
        (:func:`planerel.features.solid.face_profile_of` along ``planes.up`` in
        ``planes.labels`` and ``cloud.xyz``), for later steps that ask for the same
        (:func:`planerel.features.curved.skirt_faces`).

    Returns
    -------
    Relations
        ``n * (n - 1)`` relations for ``n`` planes (none for 0 or 1 plane).
    """
    params = params or defaults(RelationParams)
    plist = list(planes)
    n = len(plist)
    if n < 2:
        return Relations((), params)
    up = np.asarray(planes.up, dtype=float)
    fwd = np.array([0.0, 0.0, 1.0]) - up[2] * up
    if vec_norm(fwd) < 1e-6:  # camera looking straight down/up: use the image's -y
        fwd = np.array([0.0, -1.0, 0.0]) - (-up[1]) * up
    fwd = fwd / vec_norm(fwd)
    touch = _touching(planes, params, cloud.xyz) if cloud is not None else set()
    N = np.array([p.normal for p in plist])
    C = np.array([p.centroid for p in plist])
    cosang = np.minimum(np.abs(N @ N.T), 1.0)  # (np.clip of values >= 0: the same, faster)
    ang = np.degrees(np.arccos(cosang))
    level = C @ up
    depth = C @ fwd
    G = _gap_matrix(plist)
    solid = _Solid(planes, cloud, params, profiles)
    # each plane's adjacent planes (a face's foot, a tread's next riser)
    A = G <= params.adjacency_gap
    pos = {p.label: k for k, p in enumerate(plist)}
    for a, b in touch:
        if a in pos and b in pos:
            A[pos[a], pos[b]] = A[pos[b], pos[a]] = True
    np.fill_diagonal(A, False)
    for i, j in zip(*(x.tolist() for x in np.nonzero(A)), strict=True):  # row-major: i, then j
        solid.touching.setdefault(plist[i].label, []).append(plist[j])
    # per pair the same floats as numpy's (Python floats of the same float64 operations; of
    # each row only the part right of the diagonal, taken row by row)
    lev, dep = level.tolist(), depth.tolist()
    perp_min = 90.0 - params.perpendicular_tol
    # (i, j) in row-major order without the diagonal: index i (n - 1) + j - (j > i)
    out: list = [None] * (n * (n - 1))
    m = n - 1
    par_tol, above_tol, front_tol = params.parallel_tol, params.above_tol, params.front_tol
    skirt, corner_of, facing_of = solid.skirt, solid.corner, solid.facing
    pair_of = solid.face_pair
    # who can be a skirt's top or face, a corner's wall (``_Solid`` answers False otherwise:
    # its calls are left out, not its answers)
    seen = solid.xyz is not None
    horiz = [seen and solid.top_candidate(p) for p in plist]
    vert = [seen and p.orientation == "vertical" for p in plist]
    fcand = [seen and solid.face_candidate(p) for p in plist]
    # (the three matrices as nested lists once: the same Python floats and bools as each
    # row's slice converted, without 3 n conversions)
    Gl, angl, Al = G.tolist(), ang.tolist(), A.tolist()
    for i in range(n):
        pi = plist[i]
        li = pi.label
        hi, vi = horiz[i], vert[i]
        Gi, angi, Ai = Gl[i], angl[i], Al[i]
        for j in range(i + 1, n):
            pj = plist[j]
            lj = pj.label
            gap = Gi[j]
            t = (li, lj) in touch
            adj = Ai[j]  # touching, or hulls within adjacency_gap
            a = angi[j]
            par = a <= par_tol
            perp = a >= perp_min
            rise = lev[j] - lev[i]
            dd = dep[j] - dep[i]
            corner = adj and perp and vi and vert[j] and corner_of(pi, pj)
            facing = not adj and par and vi and vert[j] and facing_of(pi, pj)
            fpair = adj and perp and vi and vert[j] and pair_of(pi, pj, a)
            out[i * m + j - 1] = _relation(li, lj, a, par, perp, gap, t, adj, rise,
                                           -rise > above_tol, dd > front_tol,
                                           adj and hi and fcand[j] and skirt(pi, pj), corner,
                                           facing, fpair)
            out[j * m + i] = _relation(lj, li, a, par, perp, gap, t, adj, -rise,
                                       rise > above_tol, -dd > front_tol,
                                       adj and fcand[i] and horiz[j] and skirt(pj, pi), corner,
                                       facing, fpair)
    if any(plist[k].label >= plist[k + 1].label for k in range(n - 1)):
        out.sort(key=lambda r: (r.a, r.b))
    return Relations(tuple(out), params, solid.steps)


def skirts_within_objects(relations: Relations, objects, planes, support=()) -> Relations:
    """``relations`` with ``skirt`` true for the pairs only another object's step denied.

    :func:`relate` does not know the objects, so a face standing on any horizontal plane that
    looks like a tread, or a top with a parallel face rising from it (the next riser), is no
    skirt.  A box standing on another box, or beside a lower one, is such a riser-and-tread
    pair, but the proposals make the two boxes two objects.  Once the objects are known, a top
    and a face of one object whose skirt was denied only by planes of other objects
    (:attr:`Relations.skirt_steps`) are a skirt, where each such plane is

    - a tread (horizontal): the face stands on another object, or on a support plane (a
      table top, :func:`support_planes`' ``table_area``: in no object, it is the ground the
      object stands on);
    - a riser (vertical) whose top lies within ``skirt_tol`` of a horizontal plane of its own
      object: the side of another solid with a top.  A wall rising behind a desk's top has no
      top of its own and still says no.

    A flight's treads and risers are one object, so its risers stay risers.

    Parameters
    ----------
    relations : Relations
        From :func:`relate`.
    objects : iterable of sequences of int
        Plane labels per object.
    planes : PlaneSet
        The planes ``relations`` relate (levels of the objects' horizontal planes).
    support : iterable of int
        Support plane labels.

    Returns
    -------
    Relations
        ``relations`` itself when nothing changes.
    """
    if not relations.skirt_steps:
        return relations
    owner: dict[int, set] = {}
    for k, o in enumerate(objects):
        for lbl in o:
            owner.setdefault(int(lbl), set()).add(k)
    up = np.asarray(planes.up, float)
    tops: dict[int, list] = {}  # object -> levels of its horizontal planes
    for p in planes:
        if p.orientation == "horizontal":
            for k in owner.get(p.label, ()):
                tops.setdefault(k, []).append(float(np.asarray(p.centroid, float) @ up))
    tol = relations.params.skirt_tol
    support = {int(x) for x in support}

    def apart(label, riser_top, mine) -> bool:
        if label in support and math.isnan(riser_top):
            return True  # a tread that is support: the ground the face stands on
        theirs = owner.get(label, set())
        if not theirs or theirs & mine:
            return False
        return math.isnan(riser_top) or any(abs(riser_top - h) <= tol
                                            for k in theirs for h in tops.get(k, ()))

    now = set()
    for (top, face), steps in relations.skirt_steps.items():
        mine = owner.get(top, set()) & owner.get(face, set())
        if mine and all(apart(label, t, mine) for label, t in steps):
            now.add((top, face))
    if not now:
        return relations
    pairs = tuple(replace(r, skirt=True) if (r.a, r.b) in now else r for r in relations.pairs)
    return Relations(pairs, relations.params, relations.skirt_steps)


def scene_graph(planes, relations: Relations, *, edges: str = "adjacent"):
    """A networkx graph: planes as nodes (attributes from :class:`Plane`), relations as edges.

    Parameters
    ----------
    edges : ``"adjacent"`` or ``"all"``
        Which unordered pairs become edges.  Edge attributes are those of the relation
        ``(a, b)`` with ``a < b`` (``rise`` is ``b`` above ``a``).
    """
    import networkx as nx

    if edges not in ("adjacent", "all"):
        raise InputError(f"edges must be 'adjacent' or 'all', got {edges!r}")
    g = nx.Graph(up=tuple(float(x) for x in planes.up), floor=planes.floor)
    for p in planes:
        g.add_node(p.label, n_points=p.n_points, normal=tuple(p.normal.tolist()),
                   offset=p.offset, centroid=tuple(p.centroid.tolist()), rms=p.rms, area=p.area,
                   length=p.length, width=p.width, incline=p.incline,
                   orientation=p.orientation, height=p.height, distance=p.distance,
                   is_floor=p.is_floor)
    for r in relations:
        if r.a < r.b and (edges == "all" or r.adjacent):
            g.add_edge(r.a, r.b, angle=r.angle, parallel=r.parallel,
                       perpendicular=r.perpendicular, gap=r.gap, touching=r.touching,
                       adjacent=r.adjacent, rise=r.rise)
    return g


#: Module (in ``planerel.features``) of each name moved out of this one (split95):
#: ``relations.X`` and ``from planerel.features.relations import X`` give that module's ``X``,
#: the same object, imported at first use (:func:`__getattr__`): those modules import this one,
#: so this one imports none of them while it loads.
_MOVED = {
    **dict.fromkeys((
        "tall_faces", "SUNK_CORNER", "_sunk_beside", "_tall_flat", "tall_noise", "face_bend",
        "tall_shaped", "_stands_beside", "CAP_BEHIND", "cap_strip", "_next_riser",
        "FLOOR_FOOT_ROWS", "FLOOR_FOOT_MARGIN", "VirtualFloor", "feet_level", "floor_foot",
        "_fills_rows", "level_ground", "level_reach", "top_covered", "_reaches_top_row",
        "BLANK_MARGIN_MAX", "BLANK_MARGIN_SPARSE", "BLANK_MARGIN_EDGE", "_blank_top_rows",
    ), "tall_face"),
    **dict.fromkeys((
        "lying_tops", "_union_grounded", "_lies_on", "_ground_around", "_ring_band", "_ring_width",
        "_boxes_meet", "top_sized", "_small_level", "SMALL_NOISE_LENGTH",
    ), "lying"),
    **dict.fromkeys((
        "ProposalParams",
    ), "proposal_params"),
    **dict.fromkeys((
        "support_planes", "FLIGHT_SIDE_REACH", "_flight_steps", "_without_room_walls",
        "_flight_side", "TABLE_INSET", "_tables", "_floor_is_tread", "_shallow_ramp",
        "_stepped_side", "_floor_offset", "edge_means", "seen_behind", "floor_beyond", "MIN_EDGE",
        "convex_pairs", "STACK_MEET", "STACK_WIDER", "_upper_not_wider", "_stacked_spans",
        "_normal_out", "shared_top_cuts", "_dot", "_crossing_angle_f", "_sanity_limit_f",
        "_step_apart", "_crossing_angle", "_sanity_limit", "shares_edge", "propose_objects",
        "SKIN_LIFT", "_support_skin", "objects_from_truth", "proposal_match",
    ), "proposals"),
    **dict.fromkeys((
        "OPEN_THICK", "OPEN_TILT", "_regular_step", "_step_kind", "_anchor_offset", "SKIP_GRID",
        "_surely_deep", "_some_rise", "flight_faces", "STEP_WINDOW_RISE", "STEP_WINDOW_RUN",
        "STAIR_RISE", "STAIR_RUN", "STEP_AGREE", "flight_steps", "flight_evidence",
        "steps_of_one_flight", "STACK_TOL", "STACK_OVERLAP", "stacked_riser_steps",
        "flight_fragments", "step_offset", "_COS_25", "step_chain_pairs", "TWO_RISER_FOOT",
        "_two_riser_steps", "_spread_steps", "CUT_CHAIN_RISE", "CUT_CHAIN_RUN", "CUT_CHAIN_BORDER",
        "_cut_chain_steps", "_step_faces", "CUT_TOP_SLACK", "_cut_top_steps", "_across_overlap",
        "_step_like",
    ), "step_chains"),
}


def __getattr__(name: str):
    """A name of :data:`_MOVED`, from its module (kept here after the first use)."""
    module = _MOVED.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"planerel.features.{module}"), name)
    globals()[name] = value
    return value
