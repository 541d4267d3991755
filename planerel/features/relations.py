"""Pairwise plane relations, the scene graph, and object proposals.

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

Object proposals (:func:`propose_objects`): support planes are dropped (the floor, horizontal
planes at floor level, and planes of at least ``support_min_area`` m^2 that are vertical or
horizontal, except a vertical one that is the side of a stepped structure: :mod:`planerel.features.walls`),
then each connected component of the adjacency graph of the remaining planes is a
candidate object, except components made only of vertical planes that reach the image border
(walls behind the object, seen in part).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np

from planerel.errors import InputError, check_bools
from planerel.features._defaults import defaults
from planerel.features.boards import stacked_board_pairs
from planerel.features.cavities import (
    cavity_pairs,
    edge_overlap,
    group_channel_pairs,
    occluded_channel_pairs,
    split_panel_pairs,
)
from planerel.features.components import Components
from planerel.features.concave_cut import concave_cuts
from planerel.features.gaps import gap_in_front, occluded_piece_pairs
from planerel.features.open_treads import open_tread_pairs
from planerel.features.planes import (
    _boundary,
    _boundary_pixels,
    _boundary_tiles,
    _measured_noise,
    label_max,
)
from planerel.features.solid import (
    PROFILE_POINTS,
    _skirt_geometry,
    face_profile_of,
    grounded,
    is_corner,
    is_face_pair,
    is_facing,
    is_skirt,
    level_under,
    on_step,
    rises_from,
    skirt_covered,
    sloped_top,
    top_edge,
)
from planerel.features.step_geometry import (  # noqa: F401 (re-exported: tables, plan_overlap, tests)
    _border_pixels,
    _border_share,
    _cut_lengthwise,
    _extent,
    _horizontal_basis,
    _tread_depth_axis,
)
from planerel.features.tread_pieces import tread_unions
from planerel.features.vectors import cross3, lo_hi, vec_norm
from planerel.features.walls import flight_side, room_wall, stepped_side, top_line

__all__ = [
    "RelationParams",
    "Relation",
    "Relations",
    "relate",
    "skirts_within_objects",
    "tall_faces",
    "lying_tops",
    "leans_towards",
    "hull_gap",
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
                             "standing_fill", "tall_narrow_width", "tall_narrow_bend", "tall_eye", "tall_flat", "tall_flat_noise", "tall_cap", "tall_cap_tol", "tall_cap_depth", "tall_cap_ratio",
                             "tall_floor_fit", "tall_floor_share", "tall_floor_solid", "tall_level_ground", "skirt_top_eye", "skirt_top_solid", "tall_feet_level",
                             "tall_speckle_floor", "tall_top_cover", "tall_beside_overlap", "tall_beside_step", "tall_sunk",
                             "lying_rise",
                             "lying_rise_max", "lying_length", "lying_ground", "lying_tilt", "lying_lean",
                             "lying_min_length", "lying_width", "lying_snr", "lying_ring",
                             "lying_ring_ground", "lying_ring_between", "lying_ring_band",
                             "lying_small_length", "lying_small_width", "lying_small_tilt"))
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
    from scipy.spatial import ConvexHull, QhullError

    labels = np.asarray(labels)
    if bbox is not None:
        r0, c0, r1, c1 = (int(v) for v in bbox)
        labels = labels[max(0, r0):r1, max(0, c0):c1]
    m = labels == label
    n = int(m.sum())
    if n < 3:
        return 1.0
    # the hull of the pixels' squares is the hull of each row's outermost squares' corners
    rows, first, last = _row_spans(m)
    pts = np.concatenate([np.stack([rows + dr, col + dc], 1)
                          for dr in (0, 1) for col, dc in ((first, 0), (last, 1))])
    try:
        hull = ConvexHull(pts.astype(float))
    except QhullError:
        return 1.0
    return float(min(1.0, n / hull.volume)) if hull.volume > 0 else 1.0


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
        if p.skirt_top_noise <= 0 or top.width <= 0:
            return p.skirt_top_tilt
        extra = math.degrees(math.atan(p.skirt_top_noise * float(top.rms) / float(top.width)))
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


def tall_faces(planes, relations: Relations, cloud=None, profiles: dict | None = None,
               gravity_params=None) -> frozenset:
    """Labels of the vertical planes that stand on the ground as a solid's side whose top the
    sensor cannot see (``tall_face/1``): what a box seen as one face shows.

    A vertical plane ``f`` is a tall face when

    - it is a rectangle at least ``corner_width`` wide (``Plane.width``: a chair's or a
      table's leg, a post, is narrower; with ``tall_narrow_width`` > 0, at least that wide
      and flat across its width, :func:`face_bend` at most ``tall_narrow_bend``: a small
      product box's face, not a can's facet; :func:`tall_shaped`), its hull's area at least ``standing_fill`` of
      ``plane_length * plane_width`` (a ramp's side is a triangle), and flat: its fit's RMS
      residual at most ``tall_flat`` of its width (a cylinder that a coarse segmentation grew
      into one plane deviates from it by about 0.11 of its width);
    - it stands on the ground: a horizontal plane adjacent to it is level with its foot
      (:func:`planerel.features.solid.grounded` with ``foot`` = ``standing_foot``: that
      plane's level under ``f`` within ``foot`` of ``f``'s bottom, the plane on the floor or
      reaching more than ``skirt_step`` out from ``f``, as a table does and a tread does
      not), or the floor's fit under it (:func:`floor_foot`), or, in a scan with no floor
      plane at all, level ground no plane took reaching ``tall_level_ground`` in front of
      it (:func:`level_ground`).  A chair's back or a table's apron has open space under it;
    - it is free-standing: no vertical plane adjacent to it has its top more than
      ``skirt_tol`` above its own (a wall, a partition or a taller cabinet it belongs to;
      with ``tall_cut_tops``, not when both run out of the image's top: the border cuts
      them, their edges unseen)
      unless (``tall_beside_overlap`` > 0; off by default) that plane is a solid standing
      beside it (:func:`_stands_beside`: its foot
      level with the face's within ``standing_foot``, its extent along the face overlapping
      the face's by at most ``tall_beside_overlap`` of its width, and no parallel plane within
      ``tall_beside_step`` of the face's: a taller box touching a lower one's end, a wall
      meeting a box's side at its end; ibox48);
    - no vertical plane adjacent to it across a corner (normals 45 degrees or more apart)
      has its foot more than ``tall_sunk`` below its own (:func:`_sunk_beside`, sunk79): the
      face is then the end of a wall going on down past a floor's edge (a descending
      flight's side wall seen from its landing), not a solid's side on that floor;
    - its top edge (:class:`~planerel.features.solid.FaceProfile` ``top``, the 98th
      percentile of its points' levels) is at most ``tall_eye`` below the sensor's level
      (the camera at the origin), or its pixels reach the image's top rows (out of view):
      were it a box's side, the box's top could not be seen.  A ramp's back, a laptop's lid
      or a low cylinder's facet seen from above is no tall face; a box seen from above shows
      its top (and its sides are ``skirt``);
    - or, its top edge lower than that, a level strip lies on that edge behind the face in
      at least ``tall_cap`` of its pixel columns (:func:`cap_strip`): the box's top, seen
      so flat (2-10 rows at 160x120) that the region grower made no plane of it, so no
      ``skirt`` holds; the strip reaches at least ``tall_cap_depth`` behind the face, or
      ``tall_cap_ratio`` of its width when less (a door's, a sill's or a partition's top
      edge is thinner than its face is wide), and no parallel plane rises
      from it (:func:`_next_riser`: the strip is then a flight's tread).  A laptop's lid, a
      ramp's back, a panel or a chair's back shows the floor or the wall behind its top
      edge, not a level strip.

    What tells a box's face from the other tall faces (a door, a cabinet's side) is the
    learner's to find.  Measured on the one-face proposals of the judge set indep150
    (docs/results.md, "Boxes seen as one face"; the cap strip: "Boxes whose top is too
    thin a strip to be a plane", indep32).

    Parameters
    ----------
    planes : PlaneSet
        Measured planes (``labels`` and ``up`` set).
    relations : Relations
        From :func:`relate` on ``planes`` (its ``params`` give the tolerances).
    cloud : Cloud, optional
        The cloud ``planes`` were measured in (``xyz`` ``(H, W, 3)``, camera at the origin);
        without it (or with ``standing_foot`` 0) no plane is a tall face.
    profiles : dict, optional
        ``{face label: FaceProfile}`` already measured (:func:`relate`'s); filled with the
        ones measured here.
    gravity_params : GravityParams, optional
        The speckle floor's bounds (``sparse_floor_*``) for the floor that grounds a face
        when no floor plane exists (``tall_speckle_floor``); default the defaults.

    Returns
    -------
    frozenset of int
    """
    from planerel.features.solid import face_profile_of, grounded

    p = relations.params
    lab = getattr(planes, "labels", None)
    if cloud is None or lab is None or p.standing_foot <= 0 or lab.shape != cloud.xyz.shape[:2]:
        return frozenset()
    by_label = {q.label: q for q in planes}
    near: dict[int, list] = {}
    beside: dict[int, list] = {}
    noise = tall_noise(cloud, p)

    shape_of: dict[int, bool] = {}

    def shaped(a):  # once a plane (the narrow clause fits its points)
        if a.label not in shape_of:
            shape_of[a.label] = tall_shaped(a, p, lab, cloud.xyz, planes.up, noise=noise)
        return shape_of[a.label]

    maybe_of: dict[int, bool] = {}

    def may_be_shaped(a):
        # shaped(a) but the narrow face's bend (face_bend, a fit of its points), which only
        # a face that passes every other test below is asked for: the same faces out
        if a.label in shape_of:
            return shape_of[a.label]
        if a.label not in maybe_of:
            maybe_of[a.label] = tall_shaped(a, p, lab, cloud.xyz, planes.up, bend=False,
                                            noise=noise)
        return maybe_of[a.label]

    for r in adjacent_only(relations):
        if r.adjacent:
            a, b = by_label.get(r.a), by_label.get(r.b)
            if a is not None and b is not None and may_be_shaped(a):
                if b.orientation == "horizontal":
                    near.setdefault(r.a, []).append(b)
                elif b.orientation == "vertical":
                    beside.setdefault(r.a, []).append(b)
    # the floor's fit, for the faces no adjacent plane grounds (low42: a low camera sees the
    # floor at a grazing angle and segments it only nearer than the face)
    floor = by_label.get(getattr(planes, "floor", None))
    if floor is not None and floor.orientation != "horizontal":
        floor = None
    up = np.asarray(planes.up, float)
    profiles = {} if profiles is None else profiles

    def profile(face):
        prof = profiles.get(face.label)
        if prof is None:
            prof = profiles[face.label] = face_profile_of(face, up, lab, cloud.xyz,
                                                          p.profile_points)
        return prof

    if floor is None and p.tall_feet_level > 0 and p.tall_floor_fit > 0 \
            and getattr(planes, "floor", None) is None:
        # feet44: no floor plane at all; the level the feet of upright faces share
        found = feet_level([profile(q).bottom for q in planes if shaped(q)],
                           p.tall_feet_level, p.tall_feet_min)
        if found is not None:
            floor = VirtualFloor(up, found[0])
    if floor is None and p.tall_speckle_floor > 0 and p.tall_floor_fit > 0 \
            and getattr(planes, "floor", None) is None:
        from planerel.features.gravity import GravityParams, speckle_floor

        # the gravity stage's speckle bounds (``--param gravity.sparse_floor_*`` reaches here
        # too), the depth under the camera this stage's own
        gp = replace(gravity_params or GravityParams(), sparse_floor=p.tall_speckle_floor)
        found = speckle_floor(cloud, lab, up, 10.0, gp)
        if found is not None:
            floor = VirtualFloor(up, -found[2])
    floors = [] if floor is None else [floor]
    eye = getattr(planes, "camera_height", None)
    if eye is not None and getattr(planes, "floor", None) is None:
        # the caller knows how high the camera stands: the floor is that far under the eye
        # whether or not the sensor measured it (a camera lying on the floor, eye62); a
        # level the scan itself shows (feet, speckle) stays a floor too, as without it
        floors.append(VirtualFloor(up, -float(eye), known=True))
    no_floor = getattr(planes, "floor", None) is None
    if (floors and p.tall_floor_fit > 0) or (no_floor and p.tall_level_ground > 0):
        # faces no adjacent plane grounds may stand on a floor's fit or on unplaned ground
        floor_labels = {f.label for f in floors}
        for q in planes:
            if q.label not in near and q.label not in floor_labels and may_be_shaped(q):
                near[q.label] = []
    if not near:
        return frozenset()

    out = set()
    # the scan's blank top rows, measured only for a face that starts within them
    margin = functools.cache(lambda: _blank_top_rows(cloud.xyz))
    for lbl, grounds in near.items():
        face = by_label[lbl]
        prof = profile(face)
        hidden = (prof.top >= -p.tall_eye or _reaches_top_row(face)
                  or (_reaches_top_row(face, 2 + BLANK_MARGIN_MAX)
                      and _reaches_top_row(face, 2 + margin())))
        if not hidden:
            # seen from above its top: a box's top is in view, but may be too thin a strip
            # to have become a plane; a lid, a ramp's back or a panel shows what lies behind
            # it (the strip first: one compiled pass over the face's columns, where the
            # tests below read profiles)
            if p.tall_cap <= 0:
                continue  # a box's top would be in view
            share, depth = cap_strip(face, lab, cloud.xyz, up, prof.top, p.tall_cap_tol)
            if share < p.tall_cap or not depth >= min(p.tall_cap_depth,
                                                      p.tall_cap_ratio * (prof.hi - prof.lo)):
                continue
        if hidden and p.tall_top_cover > 0 and not _reaches_top_row(face) \
                and top_covered(face, lab, cloud.xyz, p.tall_top_cover):
            continue  # its top edge is a nearer thing's: the face may go on behind it
        if not any(grounded(face, prof, g, up, p.standing_foot, p.skirt_tol, p.skirt_step)
                   for g in grounds) and not (
                p.tall_floor_fit > 0
                and any(floor_foot(face, prof, f, lab, cloud.xyz, up, p) for f in floors)) \
                and not (no_floor and level_ground(face, prof, lab, cloud.xyz, up, p)):
            continue
        # free-standing: no vertical plane adjacent to it rises above its top behind or over
        # it (a wall or a partition it leans on, a cabinet it is part of); a taller solid
        # standing beside it (ibox48) does not make it part of that solid
        cut = p.tall_cut_tops and _reaches_top_row(face)
        if any(profile(q).top > prof.top + p.skirt_tol
               and not (cut and _reaches_top_row(q))
               and not _stands_beside(face, prof, q, profile(q), lab, cloud.xyz, p)
               for q in beside.get(lbl, ())):
            continue
        if p.tall_sunk > 0 and any(_sunk_beside(face, prof, q, profile(q), p.tall_sunk)
                                   for q in beside.get(lbl, ())):
            continue
        if not hidden and _next_riser(face, prof, planes, profile, p):
            continue  # the strip is a flight's tread
        if shaped(face):
            out.add(lbl)
    return frozenset(out)


#: degrees: an upright plane whose normal is this far or more from a face's meets it across a
#: corner (:func:`_sunk_beside`); nearer to parallel, it is a lip or a step under the face
SUNK_CORNER = 45.0


def _sunk_beside(face, prof, q, qprof, sunk: float) -> bool:
    """True when upright plane ``q`` meets ``face`` across a corner (normals
    :data:`SUNK_CORNER` degrees or more apart) and its foot (``qprof.bottom``, the 2nd percentile of its levels) lies more
    than ``sunk`` metres below the face's: ``q`` goes on under the ground the face stands on
    (``tall_sunk``)."""
    if not (np.isfinite(prof.bottom) and np.isfinite(qprof.bottom)):
        return False
    cos = abs(float(np.dot(np.asarray(face.normal, float), np.asarray(q.normal, float))))
    return cos <= math.cos(math.radians(SUNK_CORNER)) and qprof.bottom < prof.bottom - sunk


def _tall_flat(a, p, noise) -> bool:
    """:func:`tall_shaped`'s flatness: ``a``'s RMS within ``tall_flat`` of its width, or
    within ``tall_flat_noise`` sigmas of the measured depth noise at its centroid."""
    if p.tall_flat <= 0 or a.rms <= p.tall_flat * a.width:
        return True
    return (p.tall_flat_noise > 0 and noise is not None
            and a.rms <= p.tall_flat_noise * float(noise.sigma(abs(float(a.centroid[2])))))


def tall_noise(cloud, p):
    """The depth-noise model :func:`tall_shaped` reads (``tall_flat_noise``): the cloud's
    measured one when reliable, as the planes' tilt allowance reads it
    (:func:`planerel.features.planes._measured_noise`), else None (a noise-free or
    unorganized cloud: the width bound only)."""
    return _measured_noise(cloud) if p.tall_flat_noise > 0 else None


def face_bend(face, labels, xyz, up, max_points: int = PROFILE_POINTS) -> float:
    """How much the vertical plane ``face`` bends across its width, against its noise: the
    points' offsets ``d`` from their mean along the face's normal fitted as ``a u^2 + b u +
    c + e v`` (``u`` along the face's horizontal axis ``up x normal``, ``v`` along ``up``),
    the parabola's sagitta over the face's width (2nd-98th percentile of ``u``),
    ``|a| (w / 2)^2``, divided by the fit's residual RMS.  A box's face is flat (its bend is
    the noise's, about 0-0.2), a cylinder's facet (a can, a bottle, a mug) bends by
    ``w^2 / 8r`` (0.5-3 on the real frames of face52); ``inf`` with fewer than 8 points.
    """
    from planerel.features.solid import _percentiles_2_98, face_points

    pts = face_points(face, labels, xyz, max_points)[0]
    if pts.shape[0] < 8:
        return math.inf
    # numpy's floats without its overhead (speed58b): cross3, vec_norm and the compiled
    # percentiles give the same floats as np.cross, np.linalg.norm and np.percentile
    up = np.asarray(up, float)
    n = np.asarray(face.normal, float)
    n = n / vec_norm(n)
    along = cross3(up, n)
    norm = vec_norm(along)
    if not norm > 1e-9:
        return math.inf
    along = along / norm
    rel = pts - pts.mean(axis=0)
    d, u, v = rel @ n, rel @ along, rel @ up
    design = np.stack([u * u, u, np.ones_like(u), v], axis=1)
    coef, *_ = np.linalg.lstsq(design, d, rcond=None)
    (lo, hi), = _percentiles_2_98([u])
    res = float(np.sqrt(np.mean((d - design @ coef) ** 2)))
    sag = abs(float(coef[0])) * ((hi - lo) / 2) ** 2
    return sag / max(res, 1e-9)


def tall_shaped(a, p, labels=None, xyz=None, up=None, bend: bool = True, noise=None) -> bool:
    """:func:`tall_faces`' shape test of the plane ``a`` under the :class:`RelationParams`
    ``p``: vertical, at least ``corner_width`` wide (or, with ``tall_narrow_width`` > 0 and
    ``labels``, ``xyz``, ``up`` given, at least ``tall_narrow_width`` wide and flat across,
    :func:`face_bend` at most ``tall_narrow_bend``), its hull at least ``standing_fill`` of
    its rectangle, its RMS at most ``tall_flat`` of its width (or, with ``tall_flat_noise``
    > 0 and ``noise`` the cloud's measured :class:`~planerel.segment.noise.NoiseModel`, at
    most ``tall_flat_noise`` times ``noise.sigma(z)`` at its centroid's depth).
    ``bend=False``: every test but the narrow face's bend (True where the full test may be;
    its answer when it is False, or when the face needs no bend test)."""
    if not (a.orientation == "vertical" and a.area >= p.standing_fill * a.length * a.width
            and _tall_flat(a, p, noise)):
        return False
    if a.width >= p.corner_width:
        return True
    return (p.tall_narrow_width > 0 and a.width >= p.tall_narrow_width and labels is not None
            and xyz is not None and up is not None
            and (not bend or face_bend(a, labels, xyz, up, p.profile_points)
                 <= p.tall_narrow_bend))


def _stands_beside(face, prof, other, other_prof, labels, xyz, p) -> bool:
    """Whether the upright plane ``other`` (its profile ``other_prof``) is a solid standing
    beside the vertical face ``face`` (its :class:`~planerel.features.solid.FaceProfile`
    ``prof``), not behind or over it: its foot is level with the face's within
    ``standing_foot``, its points' extent along the face's horizontal axis (2nd-98th
    percentile) overlaps the face's ``[lo, hi]`` by at most ``tall_beside_overlap`` of the
    face's width, and it is no parallel plane within ``tall_beside_step`` of the face's plane
    (the same surface).  With ``tall_beside_overlap`` 0, never (:func:`tall_faces` before
    ibox48)."""
    from planerel.features.solid import _percentiles_2_98, face_points

    if p.tall_beside_overlap <= 0:
        return False
    # a solid of its own stands on the ground the face stands on: its foot level with the
    # face's within ``standing_foot`` (a sofa's back or a bed's headboard behind the seat's
    # front, a cabinet over an alcove's doors rise from higher up: 0.34-0.65 m)
    if not abs(other_prof.bottom - prof.bottom) <= p.standing_foot:
        return False
    n = np.asarray(face.normal, float)
    if abs(float(np.dot(n, np.asarray(other.normal, float)))) >= math.cos(math.radians(p.parallel_tol)) \
            and abs(float((np.asarray(other.centroid, float) - np.asarray(face.centroid, float)) @ n)) \
            <= p.tall_beside_step:
        return False
    width = prof.hi - prof.lo
    pts = face_points(other, labels, xyz, p.profile_points)[0]
    if pts.shape[0] < 3 or not width > 0:
        return False
    (lo, hi), = _percentiles_2_98([pts @ np.asarray(prof.along, float)])
    return max(0.0, min(prof.hi, hi) - max(prof.lo, lo)) <= p.tall_beside_overlap * width


def lying_tops(planes, relations: Relations, support=(), cloud=None) -> frozenset:
    """Labels of the planes that lie on the ground as the top of something flat lying there
    (``lying/1``): what a book or a flat box lying on a table shows when its sides are seen
    edge-on (a few pixels, unsegmented) or hidden.

    A plane ``t`` is lying when

    - it is horizontal, or inclined by at most ``skirt_tilted`` degrees (a book leaning on
      another, a box resting on one edge), no support plane itself, ``lying_min_length`` to
      ``lying_length`` long and at least ``lying_width`` wide (a book, a flat box: something
      one can lift; a strip along a wall's foot is narrower), or, level within
      ``lying_small_tilt``, down to ``lying_small_length`` x ``lying_small_width`` (a product
      pack lying flat);
    - a horizontal plane ``g``, at least ``lying_ground`` times its area, lies under it:
      ``t``'s centroid stands over ``g``'s fit (along ``up``, where the line through the
      centroid meets ``g``) by at least ``lying_rise`` (or ``lying_snr`` times ``t``'s RMS
      fit residual, the sensor's depth noise where it lies, when more) and at most
      ``lying_rise_max``, and no point of ``t``'s hull is more than ``lying_rise`` below
      ``g`` (``t`` does not cross it);
    - ``g`` is adjacent to it (the relations' ``adjacent``), or, when no adjacent ground
      passes and ``cloud`` is given, ``g`` shows around it across a depth jump
      (:func:`_ground_around`; its pixel box within ``lying_ring`` pixels of the top's, past
      the ``lying_ring_band`` hugging its outline): a box seen from straight above, its sides
      hidden.

    A table's top (0.45-0.8 m over the floor), a chair's seat, a shelf's board, a landing or
    a tread stand higher over what is under them; a far piece of the floor that the sensor
    bends is level with the floor within the noise; a large platform is too long.  A
    laptop's base or a tin's lid lying on a table is lying too: what tells a book from them
    is the learner's to find (the lid, the curved side).

    Parameters
    ----------
    planes : PlaneSet
        Measured planes (``up`` set; its ``labels`` image for the ring test).
    relations : Relations
        From :func:`relate` on ``planes`` (its ``params`` give the tolerances).
    support : iterable of int
        Labels of the support planes (:func:`support_planes`): they are grounds, not tops.
    cloud : Cloud, optional
        The organized cloud (``xyz`` (H, W, 3)): with it, a top with no adjacent ground may
        lie on one around it (``lying_ring``).

    Returns
    -------
    frozenset of int
    """
    p = relations.params
    if p.lying_rise <= 0:
        return frozenset()
    by_label = {q.label: q for q in planes}
    sup = {int(x) for x in support}

    def top_like(t):
        if t is None or t.label in sup or t.orientation == "vertical" or t.length > p.lying_length:
            return False
        if t.incline <= p.skirt_tilted and t.length >= p.lying_min_length \
                and t.width >= p.lying_width:
            return True
        # a smaller top lying flat (lying56)
        return (p.lying_small_length > 0 and t.incline <= p.lying_small_tilt
                and t.length >= p.lying_small_length and t.width >= p.lying_small_width)

    cand: dict[int, list] = {}
    for r in adjacent_only(relations):
        # adjacent only: a top within a few cm of the table but apart from it in the grid
        # (a tin's lid over its side) is no lying top (top25: with any ground within
        # lying_rise_max, the mOSD set's round objects got 6 box answers)
        if not r.adjacent:
            continue
        t, g = by_label.get(r.a), by_label.get(r.b)
        if not top_like(t) or g is None or g.orientation != "horizontal":
            continue
        if g.area < p.lying_ground * t.area:
            continue
        cand.setdefault(t.label, []).append(g)
    up = np.asarray(planes.up, float)
    out = {lbl for lbl, grounds in cand.items()
           if any(_lies_on(by_label[lbl], g, up, p) for g in grounds)}
    grounds = [g for g in planes if g.orientation == "horizontal"]
    if cloud is None or p.lying_ring <= 0 or planes.labels is None:
        if p.lying_ground_union:
            out |= _union_grounded(planes, relations, by_label, top_like, out, grounds, up,
                                   None, 0, p)
        return frozenset(out)
    k = _ring_width(planes.labels, p) + _ring_band(planes.labels, p)
    for t in planes:
        if t.label in out or not top_like(t):
            continue
        # a ground shows around the top: its pixel box meets the top's grown by the ring
        box = (t.bbox[0] - k, t.bbox[1] - k, t.bbox[2] + k, t.bbox[3] + k)
        under = [g for g in grounds if g.label != t.label and g.area >= p.lying_ground * t.area
                 and _boxes_meet(g.bbox, box) and _lies_on(t, g, up, p)]
        if under and _ground_around(t, under, up, planes, cloud, p):
            out.add(t.label)
    if p.lying_ground_union:
        out |= _union_grounded(planes, relations, by_label, top_like, out, grounds, up,
                               cloud, k, p)
    return frozenset(out)


def _union_grounded(planes, relations, by_label, top_like, done, grounds, up, cloud, k, p):
    """Labels of top-like planes (not in ``done``) that lie on a ground in pieces
    (``lying_ground_union``): horizontal planes ``t`` lies on (:func:`_lies_on`) whose rise
    under ``t``'s centroid agrees within ``max(5 mm, 3 x the larger fit RMS)`` of one
    anchor's form one ground of their summed area (their pixels are disjoint); it must be
    at least ``lying_ground`` times ``t``'s area, and one piece adjacent to ``t`` or the
    ring test (:func:`_ground_around`) against the pieces near it passes (ground56)."""
    adj: dict[int, set] = {}
    for r in adjacent_only(relations):
        if r.adjacent:
            adj.setdefault(r.a, set()).add(r.b)
            adj.setdefault(r.b, set()).add(r.a)
    out = set()
    for t in planes:
        if t.label in done or not top_like(t):
            continue
        box = (t.bbox[0] - k, t.bbox[1] - k, t.bbox[2] + k, t.bbox[3] + k)
        pieces = [g for g in grounds if g.label != t.label and _lies_on(t, g, up, p)]
        if not pieces:
            continue
        tc = np.asarray(t.centroid, float)
        rise = {}
        for g in pieces:
            gn = np.asarray(g.normal, float)
            rise[g.label] = float(gn @ (tc - np.asarray(g.centroid, float))) / float(gn @ up)
        for a in pieces:
            level = [g for g in pieces
                     if abs(rise[g.label] - rise[a.label])
                     <= max(0.005, 3.0 * max(float(g.rms), float(a.rms)))]
            if sum(g.area for g in level) < p.lying_ground * t.area:
                continue
            if any(g.label in adj.get(t.label, ()) for g in level):
                out.add(t.label)
                break
            if cloud is None or p.lying_ring <= 0 or planes.labels is None:
                continue
            near = [g for g in level if _boxes_meet(g.bbox, box)]
            if near and _ground_around(t, near, up, planes, cloud, p):
                out.add(t.label)
                break
    return out


def _lies_on(t, g, up: np.ndarray, p) -> bool:
    """True when ``t``'s centroid rises over ``g``'s fit (along ``up``) within
    ``[max(lying_rise, lying_snr x t.rms), lying_rise_max]`` and no point of ``t``'s hull is
    more than ``lying_rise`` below ``g``, or, when ``t`` is more than ``lying_lean`` degrees off
    parallel to ``g`` (leaning on something), less than ``lying_rise`` above it
    (:func:`lying_tops`)."""
    gn = np.asarray(g.normal, float)
    den = float(gn @ up)
    if abs(den) < 0.5:
        return False
    # cosine of the angle between the top and its ground
    parallel = abs(float(np.asarray(t.normal, float) @ gn))
    if p.lying_tilt > 0 and parallel < math.cos(math.radians(p.lying_tilt)):
        return False  # not parallel to the ground: leaning on something, or no flat thing
    gc = np.asarray(g.centroid, float)
    # the sensor's noise where the plane is: its own fit's RMS residual
    least = max(p.lying_rise, p.lying_snr * float(t.rms))
    rise = float(gn @ (np.asarray(t.centroid, float) - gc)) / den
    if not least <= rise <= p.lying_rise_max:
        return False
    hull = np.asarray(t.hull3d, float)
    if not hull.size:
        return True
    low = float(((hull - gc) @ gn).min()) / den
    if p.lying_lean > 0 and parallel < math.cos(math.radians(p.lying_lean)):
        return low >= p.lying_rise  # leaning: its low edge stands its thickness up
    return low >= -p.lying_rise


def _ground_around(t, grounds, up: np.ndarray, planes, cloud, p) -> bool:
    """True when one of ``grounds`` shows around ``t`` across a depth jump: of the measured
    points within ``lying_ring`` pixels (scaled from 640 columns to the image's width; a
    square neighbourhood) of ``t``'s pixels, ``t``'s own pieces left out (a sliver tilted off
    it, a top in two pieces: planes within ``skirt_tilted`` of its normal whose centroid lies
    within ``lying_rise`` of its fit), at least ``lying_ring_ground`` lie at the ground's
    level and at most ``lying_ring_between`` between the ground's level and ``t``'s (a side
    in view: a tin's wall, a box seen from the side), each level within 3 times ``t``'s RMS
    (at least 5 mm, at most a quarter of ``t``'s rise over the ground).  The points are read
    once for every ground (``_top_kernels.ring_counts``)."""
    from planerel.features._top_kernels import ring_counts

    labels = planes.labels
    H, W = labels.shape
    k = _ring_width(labels, p)
    band = _ring_band(labels, p)
    r0, c0, r1, c1 = (int(v) for v in t.bbox)
    r0, c0 = max(r0 - k - band, 0), max(c0 - k - band, 0)
    r1, c1 = min(r1 + k + band + 1, H), min(c1 + k + band + 1, W)
    tn, tc = np.asarray(t.normal, float), np.asarray(t.centroid, float)
    cos_tilt = math.cos(math.radians(p.skirt_tilted))
    own = [q.label for q in planes
           if q.label != t.label and _boxes_meet(q.bbox, (r0, c0, r1, c1))
           and abs(float(np.asarray(q.normal, float) @ tn)) >= cos_tilt
           and abs(float((np.asarray(q.centroid, float) - tc) @ tn)) <= p.lying_rise]
    gn = np.array([g.normal for g in grounds], float).reshape(-1, 3)
    gc = np.array([g.centroid for g in grounds], float).reshape(-1, 3)
    den = gn @ up
    rise = ((tc - gc) * gn).sum(axis=1) / den
    # a level is a fit within the sensor's noise there (3 x the top's RMS, at least 5 mm),
    # never past a quarter of the rise: a side in view is "between" but for its last rows
    noise = np.full(len(gn), float(t.rms))
    if p.lying_ring_ground_noise:
        noise = np.maximum(noise, np.array([float(g.rms) for g in grounds], float))
    tol = np.minimum(0.25 * rise, np.maximum(0.005, 3.0 * noise))
    counts = ring_counts(labels, cloud.xyz, r0, r1, c0, c1, int(t.label), k,
                         np.asarray(own, np.int64), tn, tc, gn, gc, den, rise, tol, band)
    n = np.maximum(counts[:, 0], 1)
    return bool(((counts[:, 0] > 0) & (counts[:, 1] >= p.lying_ring_ground * n)
                 & (counts[:, 2] <= p.lying_ring_between * n)).any())


def _ring_band(labels: np.ndarray, p) -> int:
    """Pixels: ``lying_ring_band`` (given at 640 columns) at the image's width, 0 when off."""
    if p.lying_ring_band <= 0:
        return 0
    return max(1, int(round(p.lying_ring_band * labels.shape[1] / 640.0)))


def _ring_width(labels: np.ndarray, p) -> int:
    """Pixels: ``lying_ring`` (given at 640 columns) at the image's width, at least 2."""
    return max(2, int(round(p.lying_ring * labels.shape[1] / 640.0)))


def _boxes_meet(a, b) -> bool:
    """True when two pixel boxes ``(row0, col0, row1, col1)`` overlap."""
    return a[0] <= b[2] and b[0] <= a[2] and a[1] <= b[3] and b[1] <= a[3]


#: m: how far behind a vertical face (away from the sensor) a ``tall_cap`` strip's points
#: and a next riser (:func:`_next_riser`) lie: a box's top reaches 0.1-1 m back
CAP_BEHIND = (0.02, 1.5)


def cap_strip(face, labels, xyz, up, top: float, tol: float = 0.03,
              rows: int | None = None, behind: tuple = CAP_BEHIND) -> tuple[float, float]:
    """The level strip on a vertical face's top edge that no plane took: a solid's top seen
    so flat that the region grower left it unassigned (``tall_cap`` of
    :class:`RelationParams`).  A top that is a plane is ``skirt``'s, not this.

    A column of the face's pixel box holds the strip when, among the ``rows`` pixels above
    its top pixel of the face, an unassigned point (label < 0) lies level with the face's
    top edge (within ``tol``) and behind the face (within ``behind``, along its normal away
    from the sensor).

    Parameters
    ----------
    face : Plane
        A vertical plane (``label``, ``normal``, ``centroid``, ``bbox``).
    labels : ndarray (H, W) int
        The segmentation the planes were measured in.
    xyz : ndarray (H, W, 3)
        The cloud's points, camera frame (camera at the origin), NaN = missing.
    up : ndarray (3,)
        Unit up vector, camera frame.
    top : float
        The face's top edge, ``up . x`` (:class:`~planerel.features.solid.FaceProfile`).
    tol : float
        m: a strip point's level ``up . x`` lies within this of ``top``.
    rows : int, optional
        How many pixels above each column's top pixel are looked at; default
        ``max(3, round(H / 24))`` (5 at 120 rows, 20 at 480).
    behind : (float, float)
        m: a strip point lies this far behind the face's plane.

    Returns
    -------
    share : float
        The share (0..1) of the face's pixel columns that hold the strip; 0 when the face
        has no pixel column.
    depth : float
        m: how far behind the face the strip reaches: the 90th percentile, over the columns
        that hold it, of the farthest strip point (0 without any).
    """
    from planerel.features._top_kernels import cap_columns

    H, _W = labels.shape
    k = max(3, round(H / 24)) if rows is None else int(rows)
    r0, c0, r1, c1 = (int(v) for v in face.bbox)
    n = np.asarray(face.normal, float)
    cen = np.asarray(face.centroid, float)
    if n @ cen < 0:
        n = -n                                      # pointing away from the sensor
    share, depth = cap_columns(labels, xyz, r0, r1, c0, c1, int(face.label), k, n,
                               float(n @ cen), np.asarray(up, float), float(top), float(tol),
                               float(behind[0]), float(behind[1]))
    return float(share), float(depth)


def _next_riser(face, prof, planes, profile, p) -> bool:
    """True when a vertical plane parallel to ``face`` rises from its top edge behind it
    (within :data:`CAP_BEHIND`): its bottom within ``skirt_tol`` of ``face``'s top, its top
    at least ``skirt_reach`` higher, at least ``riser_width`` (or half ``face``'s width)
    along it and overlapping it.  The strip on ``face``'s top edge is then a flight's tread
    (the first riser of two steps), not a box's top.

    ``prof`` is ``face``'s :class:`~planerel.features.solid.FaceProfile`, ``profile`` a
    callable giving any vertical plane's, ``p`` the :class:`RelationParams`."""
    n = np.asarray(face.normal, float)
    c = np.asarray(face.centroid, float)
    if n @ c < 0:
        n = -n
    cos_par = math.cos(math.radians(p.parallel_tol))
    for q in planes:
        if q.label == face.label or q.orientation != "vertical":
            continue
        nq = np.asarray(q.normal, float)
        if abs(float(nq @ n)) < cos_par:
            continue
        back = float((np.asarray(q.centroid, float) - c) @ n)
        if not CAP_BEHIND[0] <= back <= CAP_BEHIND[1]:
            continue
        pq = profile(q)
        if not (abs(pq.bottom - prof.top) <= p.skirt_tol and pq.top - prof.top >= p.skirt_reach):
            continue
        s = float(np.asarray(pq.along, float) @ np.asarray(prof.along, float))
        lo, hi = (pq.lo, pq.hi) if s >= 0 else (-pq.hi, -pq.lo)
        if not (math.isfinite(lo) and math.isfinite(hi)):
            continue
        overlap = min(hi, prof.hi) - max(lo, prof.lo)
        if overlap > 0 and hi - lo >= min(p.riser_width, 0.5 * (prof.hi - prof.lo)):
            return True
    return False


#: the rows under a face's lowest pixel that :func:`floor_foot` looks at: this share of the
#: image's height (at least 3): at 480 rows, 19
FLOOR_FOOT_ROWS = 0.04
#: :func:`floor_foot` looks at the middle of the face's columns: this share cut off each side
FLOOR_FOOT_MARGIN = 0.15


class VirtualFloor(NamedTuple):
    """A level plane (normal ``up``) at ``level`` along ``up``: the floor :func:`feet_level`
    finds where no floor plane was segmented; what :func:`floor_foot` reads of a plane."""

    normal: np.ndarray
    level: float
    label: int = -1
    orientation: str = "horizontal"
    #: the caller gave it (the camera's height over the floor, ``PlaneSet.camera_height``): a
    #: face running out of the image's bottom row reaches down to it as far as it is seen
    known: bool = False

    @property
    def centroid(self) -> np.ndarray:
        return np.asarray(self.normal, float) * self.level


def feet_level(bottoms, tol: float, at_least: int = 2) -> tuple[float, float, int] | None:
    """The lowest level (along up, the camera at 0) shared by the feet ``bottoms`` (each a
    face's ``FaceProfile.bottom``) of at least ``at_least`` faces below the eye, all within
    ``tol`` m of each other: ``(median of those feet, their spread, how many)``, or None.

    Parameters
    ----------
    bottoms : iterable of float
        Feet levels (m); ``nan`` and those at or above the eye (>= 0) are ignored.
    tol : float
        Largest spread (max - min) of the feet sharing a level.
    at_least : int
        Fewest feet sharing it.
    """
    b = np.sort(np.asarray([v for v in bottoms if np.isfinite(v) and v < 0], float))
    for i in range(b.size):
        j = int(np.searchsorted(b, b[i] + tol, side="right"))
        if j - i >= at_least:
            grp = b[i:j]
            return float(np.median(grp)), float(grp[-1] - grp[0]), int(grp.size)
    return None


def floor_foot(face, prof, floor, labels, xyz, up, params) -> bool:
    """True when vertical ``face`` stands on the floor plane ``floor`` although they are not
    adjacent (low42): a camera 0.1-0.3 m over the floor sees it at a grazing angle (3-8
    degrees), where the sensor's noise keeps the region grower from the floor's far part, or
    measures nothing; the floor plane then ends short of a box's foot.

    - its foot (``prof.bottom``) is level with ``floor``'s fit under the face's centroid
      (along ``up``) within ``params.tall_floor_fit``;
    - in at least ``tall_floor_share`` of its middle pixel columns (:data:`FLOOR_FOOT_MARGIN`
      cut off each side), the first measured point in the :data:`FLOOR_FOOT_ROWS` rows under
      its lowest pixel lies on the floor's fit (within ``standing_foot``) no farther out than
      the face, or none is measured: the floor in front of its foot.  A table's or a chair's
      open space shows the room behind, a riser the tread in front of it over the floor;
    - its pixels fill at least ``tall_floor_solid`` of each row's span (summed over its rows):
      a solid face; a table's legs that the region grower took as one plane fill 0.2 of it.

    A column whose lowest pixel is the image's last row shows nothing under the face: it
    counts for the floor only when the floor is one the caller gave (``floor.known``, the
    camera's height over it: a box's face close to a low camera runs out of the image's bottom
    a few centimetres over the floor, eye62).
    """
    if not np.isfinite(prof.bottom):
        return False
    level = level_under(floor, face.centroid, up)
    if level is None or abs(prof.bottom - level) > params.tall_floor_fit:
        return False
    c = np.asarray(face.centroid, float)
    pn, fc = np.asarray(floor.normal, float), np.asarray(floor.centroid, float)
    den = float(pn @ up)
    r0, c0, r1, c1 = (int(v) for v in face.bbox)
    m = labels[r0:r1, c0:c1] == face.label
    cols = np.flatnonzero(m.any(axis=0))
    if not _fills_rows(m, params.tall_floor_solid):
        return False
    cut = FLOOR_FOOT_MARGIN * (cols[-1] - cols[0])
    cols = cols[(cols >= cols[0] + cut) & (cols <= cols[-1] - cut)]
    if cols.size == 0:
        return False
    height = labels.shape[0]
    k = max(3, int(round(FLOOR_FOOT_ROWS * height)))
    bottom = r0 + m.shape[0] - 1 - np.argmax(m[::-1, cols], axis=0)  # lowest pixel per column
    # the face's horizontal range from the sensor (at the origin)
    horiz = np.linalg.norm(c - (c @ up) * up)
    good = 0
    for col, rb in zip(cols + c0, bottom, strict=True):
        if rb + 1 >= height:
            # its foot out of the image's bottom: unseen, but at the level a known floor has
            good += bool(getattr(floor, "known", False))
            continue
        seg = xyz[rb + 1:min(height, rb + 1 + k), col]
        ok = np.isfinite(seg).all(axis=1) & (seg[:, 2] > 0)
        if not ok.any():
            good += 1  # nothing measured: the grazing floor
            continue
        q = seg[int(np.argmax(ok))]
        h = float(pn @ (q - fc)) / den
        if abs(h) <= params.standing_foot and np.linalg.norm(q - (q @ up) * up) <= horiz + params.skirt_tol:
            good += 1
    return good >= params.tall_floor_share * cols.size


def _row_spans(m):
    """``(rows, first, last)``: the rows of the mask ``m`` holding a pixel and, per such row,
    its first and last pixel's column."""
    rows = np.flatnonzero(m.any(axis=1))
    sub = m[rows]
    return rows, sub.argmax(axis=1), sub.shape[1] - 1 - sub[:, ::-1].argmax(axis=1)


def _fills_rows(m, share: float) -> bool:
    """True when the mask ``m`` (a face's pixels in its pixel box) spans at least 3 columns
    and 2 rows and its pixels fill at least ``share`` of its rows' spans summed (a solid face:
    :func:`floor_foot`, :func:`level_ground`)."""
    rows, first, last = _row_spans(m)
    if np.flatnonzero(m.any(axis=0)).size < 3 or rows.size < 2:
        return False
    return bool(m.sum() >= share * float((last - first + 1).sum()))


def level_ground(face, prof, labels, xyz, up, params) -> bool:
    """True when vertical ``face`` stands on level ground that no plane took (ground75): in
    at least ``tall_floor_share`` of its middle pixel columns (:data:`FLOOR_FOOT_MARGIN` cut
    off each side) the measured points under its lowest pixel lie level with its foot
    (``prof.bottom``, within ``standing_foot``) and reach at least ``tall_level_ground`` m
    nearer to the sensor (horizontally) than the face's centroid, before two adjacent rows
    both hold a point off that level; its pixels fill ``tall_floor_solid`` of its rows'
    spans; and its top is in view (its pixels start below the image's first ``2 +``
    :data:`BLANK_MARGIN_MAX` rows).  :func:`tall_faces` asks it only in a scan with no floor
    plane at all, as the feet level and the speckle floor.

    A floor the region grower made no plane of (a dark or speckled floor at 1-2 m under a
    level view: hunt45's R200 carton, the ground reaching 0.54 m in front of it) grounds a
    box's face as a floor plane would.  The reach is :func:`~planerel.features.solid.grounded`'s
    ``skirt_step`` for a plane: a riser's tread (0.22-0.35 m) or a chair's seat does not reach
    it; a table's or a chair's open space shows the room behind, not a level surface.  Why
    the two limits: a wall rising out of view over such a floor (hunt45, an R200 facing a
    wall 1.7 m high) shows no edge a box's face would; and where a floor plane exists, the
    unplaned level ground is a far floor the plane's own fit (:func:`floor_foot`) judges
    better (hunt45, a door frame's strip in the next room).

    Parameters
    ----------
    face : Plane
        A vertical plane (``label``, ``bbox``, ``centroid``).
    prof : FaceProfile
        Its profile (``bottom``).
    labels : ndarray, shape (H, W)
    xyz : ndarray, shape (H, W, 3)
        Camera at the origin.
    up : ndarray, shape (3,)
    params : RelationParams
    """
    reach = params.tall_level_ground
    if reach <= 0 or not np.isfinite(prof.bottom) or prof.bottom >= 0 \
            or _reaches_top_row(face, 2 + BLANK_MARGIN_MAX):
        return False
    r0, c0, r1, c1 = (int(v) for v in face.bbox)
    if not _fills_rows(labels[r0:r1, c0:c1] == face.label, params.tall_floor_solid):
        return False
    got = level_reach(face, prof, labels, xyz, up, params.standing_foot)
    return got.size > 0 and int((got >= reach).sum()) >= params.tall_floor_share * got.size


def level_reach(face, prof, labels, xyz, up, tol: float):
    """How far the level ground under vertical ``face``'s foot reaches towards the sensor, per
    middle pixel column (:data:`FLOOR_FOOT_MARGIN` cut off each side): from the row under the
    column's lowest pixel down, the measured points within ``tol`` of the foot's level
    (``prof.bottom``) until two adjacent rows both hold a point off it; the largest horizontal
    distance by which one of them lies nearer to the sensor than the face's centroid.
    :func:`level_ground`; ``benchmarks/grounded_why.py``.

    Returns
    -------
    ndarray, shape (C,)
        Metres per column, ``-inf`` where no level point lies under the foot; empty when the
        face has fewer than 3 columns.
    """
    r0, c0, r1, c1 = (int(v) for v in face.bbox)
    m = labels[r0:r1, c0:c1] == face.label
    cols = np.flatnonzero(m.any(axis=0))
    if cols.size < 3:
        return np.zeros(0)
    cut = FLOOR_FOOT_MARGIN * (cols[-1] - cols[0])
    cols = cols[(cols >= cols[0] + cut) & (cols <= cols[-1] - cut)]
    if cols.size == 0:
        return np.zeros(0)
    bottom = r0 + m.shape[0] - 1 - np.argmax(m[::-1, cols], axis=0)  # lowest pixel per column
    start = int(bottom.min()) + 1
    if start >= labels.shape[0]:
        return np.full(cols.size, -np.inf)
    up = np.asarray(up, float)
    block = xyz[start:, cols + c0]  # (rows under the highest foot, columns, 3)
    below = np.arange(start, labels.shape[0])[:, None] > bottom[None, :]
    ok = below & np.isfinite(block).all(axis=2) & (block[..., 2] > 0)
    level = np.where(ok, block @ up, np.nan)
    on = ok & (np.abs(level - prof.bottom) <= tol)
    # the walk down a column stops where two adjacent rows both hold a point off the level
    off = ok & ~on
    brk = np.zeros_like(off)
    brk[:-1] = off[:-1] & off[1:]
    stop = np.where(brk.any(axis=0), np.argmax(brk, axis=0), brk.shape[0])
    on &= np.arange(brk.shape[0])[:, None] < stop[None, :]
    c = np.asarray(face.centroid, float)
    horiz = float(np.linalg.norm(c - (c @ up) * up))
    flat = block - (block @ up)[..., None] * up
    forward = horiz - np.linalg.norm(np.where(on[..., None], flat, 0.0), axis=2)
    return np.where(on, forward, -np.inf).max(axis=0)


def top_covered(face, labels, xyz, gap: float) -> bool:
    """True when a nearer surface covers ``face``'s top edge: in at least half of its middle
    pixel columns (:data:`FLOOR_FOOT_MARGIN` cut off each side) the first point measured in
    the :data:`FLOOR_FOOT_ROWS` rows over its highest pixel is nearer to the sensor than
    that pixel by more than ``gap`` m (a wall seen under a table's top).  Columns with
    nothing measured over the face count as uncovered.

    Parameters
    ----------
    face : Plane
        A plane (``label``, ``bbox``).
    labels : ndarray, shape (H, W)
    xyz : ndarray, shape (H, W, 3)
    gap : float
    """
    r0, c0, r1, c1 = (int(v) for v in face.bbox)
    m = labels[r0:r1, c0:c1] == face.label
    cols = np.flatnonzero(m.any(axis=0))
    if cols.size < 3:
        return False
    cut = FLOOR_FOOT_MARGIN * (cols[-1] - cols[0])
    cols = cols[(cols >= cols[0] + cut) & (cols <= cols[-1] - cut)]
    if cols.size == 0:
        return False
    k = max(3, int(round(FLOOR_FOOT_ROWS * labels.shape[0])))
    tops = r0 + np.argmax(m[:, cols], axis=0)  # highest pixel per column
    covered = 0
    for col, rt in zip(cols + c0, tops, strict=True):
        if rt == 0:
            continue
        own = float(np.linalg.norm(xyz[rt, col]))
        seg = xyz[max(0, rt - k):rt, col][::-1]  # upwards from the face's top
        ok = np.isfinite(seg).all(axis=1) & (seg[:, 2] > 0)
        if ok.any() and float(np.linalg.norm(seg[int(np.argmax(ok))])) < own - gap:
            covered += 1
    return covered >= 0.5 * cols.size


def _reaches_top_row(face, rows: int = 2) -> bool:
    """True when ``face``'s pixels reach the image's first ``rows`` + 1 rows (its pixel box,
    ``Plane.bbox``): its top edge is out of view."""
    return int(face.bbox[0]) <= rows


#: At most this many blank rows at the top of a scan count as its margin (:func:`_blank_top_rows`).
BLANK_MARGIN_MAX = 8
#: A margin's rows hold at most this share of measured points (a registration margin's edge
#: may be ragged by a pixel) and the row under it at least :data:`BLANK_MARGIN_EDGE`.
BLANK_MARGIN_SPARSE = 0.05
BLANK_MARGIN_EDGE = 0.5


def _blank_top_rows(xyz) -> int:
    """How many rows at the top of the organized cloud ``xyz`` (``(H, W, 3)``) are (nearly)
    blank: the margin a depth image registered to a colour camera leaves (a RealSense's
    aligned depth: 2 rows), where the image's view of the scene really begins.  The margin's
    rows hold at most :data:`BLANK_MARGIN_SPARSE` of their width measured, the row under it at
    least :data:`BLANK_MARGIN_EDGE` (a straight edge), and it is at most
    :data:`BLANK_MARGIN_MAX` rows; otherwise 0 (rows that fill in gradually are the scene out
    of the sensor's range, no margin)."""
    head = xyz[:BLANK_MARGIN_MAX + 1, :, 2]
    share = (np.isfinite(head) & (head > 0)).mean(axis=1)
    for row, s in enumerate(share):
        if s >= BLANK_MARGIN_EDGE:
            return row
        if s > BLANK_MARGIN_SPARSE:
            return 0
    return 0


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


@dataclass(frozen=True)
class ProposalParams:
    """Parameters of :func:`propose_objects`.

    Parameters
    ----------
    support_min_area : float
        Vertical or horizontal planes at least this large (m^2) are support (walls, floors).
    wall_test : bool
        A large vertical plane is a wall only when it reaches above the planes that meet it:
        the side face of a solid staircase, whose top edge follows its steps, is not
        (:func:`planerel.features.walls.stepped_side`; needs the relations and the cloud).
    wall_tol, wall_window : float
        Metres: a step *caps* the face when the face's top over the step's extent (a riser's
        widened to ``+-wall_window``, a tread's shrunk by it) is at most ``wall_tol`` above the
        step's top; two caps ``step_rise_min`` apart in height and no step with the face
        higher than that make the side of a stepped structure.
    floor_gap : float
        Metres: a horizontal plane at floor level (within the planes' ``floor_tol``) other
        than the floor is support only when its centroid lies within this of the floor's
        plane (a piece of the floor cut off by an object); farther, it is an object lying on
        the floor (an open box's bottom, a laptop's base, a shallow ramp: 1-3 cm up).
    drop_border_walls : bool
        Drop components made only of vertical planes of which one reaches the image border
        (walls seen behind the object); objects have a non-vertical plane or lie in view.
    border_wall_area : float
        m^2: such a component is dropped only when its largest plane is at least this large
        (a box seen from the side at the edge of the view shows vertical faces only, smaller
        than a wall); 0 = drop every such component.
    wall_behind : float
        ... and only when at most this fraction of the pixels just outside its planes' outlines
        lies behind them (:func:`seen_behind`): a wall has nothing behind it, an object's face
        has the floor or a wall behind its top and sides; 1 = no such test (needs the cloud).
    wall_floor_behind : float
        Fraction (0 = off): ... and only when, for each of its planes of at least
        ``border_wall_area``, fewer horizontal support pixels (the floor, a table top) than
        this fraction of the plane's points lie beyond its plane (farther from the sensor by
        more than 5 cm at 1 m, scaled by the range beyond 1 m; :func:`floor_beyond`; needs
        the cloud).  A room's wall bounds its floor: the floor lies on the
        sensor's side of it.  A floor seen beyond the plane (past its side, under or over it)
        shows a face standing inside the room: a box or a cabinet whose top is out of view,
        a door leaf, a balustrade, with nothing but the floor around it (synth22t,
        docs/objects.md).
    min_points : int
        Proposals with fewer points in total are dropped.
    split_concave : bool
        Keep an adjacency edge only when the two planes meet convexly (:func:`convex_pairs`):
        stacked boxes, boxes side by side and a box against a wall come apart.
    concave_tol : float
        Degrees: planes whose normals differ by at most this much stay joined whatever the
        sign of their edge (noise on nearly coplanar pieces).
    edge_band : int
        Pixels: edge points of a pair are the pixels of each plane within this many pixels of
        the other in the image grid.
    edge_depth : float
        Metres (at 1 m; scaled by the depth): such a pixel pair counts only when its 3-D
        distance is at most ``edge_depth * max(1, z)`` (an occluding edge is not shared).
    step_overlap : float
        A concave edge between a horizontal or inclined plane and a vertical one stays joined
        when the two planes' extents along it overlap by at least this (interval IoU; a
        staircase's tread and the riser above it); 0 = cut every concave edge.
    min_border_area : float
        m^2: a proposal of one plane that reaches the image border and is smaller than this
        is dropped (a sliver of something cut by the frame, e.g. a table's edge; too little
        of it is seen to name it); 0 = keep them.
    step_chains : bool
        Join parallel treads (or parallel risers) that follow one another as the steps of a
        staircase, whether or not the faces between them are seen (:func:`step_chain_pairs`):
        stairs seen from above show treads only, from below risers only.
    step_rise_min, step_rise_max, step_run_min, step_run_max : float
        Metres: the range of the height and of the horizontal offset between two such faces.
    step_tilt : float
        Degrees: a face within this of horizontal counts as a tread in a step chain (the far
        treads of a flight measure a few degrees off).
    riser_tilt : float
        Degrees (0-45): a face within this of vertical counts as a riser in a step chain.  A
        carpeted riser runs from the nosing above back to the tread below, and building
        codes allow a riser up to 30 degrees off vertical: a real carpeted flight's risers
        measure 11-13 degrees (docs/objects.md "Risers that lean back, and a basket's walls
        that are no risers").
    riser_walls : bool
        ``stair_step/2`` refuses two risers when the lower one's surface (a coplanar piece of
        the object) rises to the higher one's top
        (:func:`~planerel.features.stair_step.stair_steps`): an open basket's near and far walls
        end at one rim, a flight's risers a rise apart.
    split_stepped : bool
        Before proposing, split an inclined plane whose points lie on horizontal levels one
        rise apart (treads joined into one sloping plane, a flight seen from above) into one
        plane a level (:func:`planerel.features.stepped.split_stepped`; applied by
        :func:`planerel.features.facts.describe_scene`).
    coplanar_depth : float or None
        Metres (at 1 m; scaled by the depth like ``edge_depth``): two planes whose normals are
        within ``concave_tol`` stay joined as one noisy surface only when they lie at most this
        far apart along their normals (:func:`convex_pairs`; LCCP's smoothness check): two
        parallel faces a step apart face each other, which no two faces of one convex object
        do (a lower box's top seen behind a taller one's).  None = no check.
    sanity_angle : float
        Degrees (LCCP's sanity criterion, Stein et al. 2014; 0 = off): where the convexity
        sign is no evidence (no shared edge, or inside its noise band) a pair stays joined
        only when the offset of its points makes at least
        ``sanity_angle / (1 + exp(-0.25 (beta - 25)))`` degrees with the planes' line of
        intersection (50 for perpendicular faces; PCL's LCCP uses 60, which cut a paper-world
        flight's side wall touching a riser's end at 58.8 degrees): objects touching at a
        corner are cut.
    cavities : bool
        Join the concave pairs that are the inside of one open object: a *channel* (a plane
        between two parallel planes facing each other across it, both at shared concave
        edges: a shelf's back panel or board between its side panels) or an *inside corner*
        (three planes, each pair at a shared concave edge), every edge *whole*
        (:func:`planerel.features.cavities.cavity_pairs`): a shelf or an open box stays one
        proposal; a box against a wall or a larger box (one concave edge, or two and a
        convex one) still comes apart.
    group_channels : bool
        Also join two parallel planes facing each other across a *group* of joined planes
        that together span them (each wall meeting a member at a shared concave edge; the
        group's extent along that edge overlapping the wall's by ``cavity_overlap``): a
        flight's side walls, which no single tread spans
        (:func:`planerel.features.cavities.group_channel_pairs`; needs ``cavities``).
    occluded_channels : bool
        Also join a channel seen past its near wall: a plane ``B`` meeting ``A`` at a whole
        shared concave edge, and ``C`` parallel to ``A``, facing the same way and standing in
        front of it where ``B`` ends, its back end at ``B``'s plane, spanning ``A`` along the
        edge and hiding ``B`` along an occluding edge (a shelf seen from beside its open side:
        the far side panel's inside, the back panel's inside and the near side panel's
        outside; :func:`planerel.features.cavities.occluded_channel_pairs`; needs
        ``cavities``).
    cavity_skip_walls : bool
        A plane the border-wall test (``drop_border_walls``) drops when alone (vertical, at
        the image border, at least ``border_wall_area``, at most ``wall_behind`` seen behind
        it) takes no part in a channel or an inside corner of :func:`cavity_pairs`: two room
        walls under ``support_min_area`` and a ramp between them make an inside corner with
        whole edges, not an open object.  (The occluded channels keep such planes: a shelf's
        back panel at the border.)
    concave_band : float
        Of :func:`convex_pairs`' noise band (a cosine of 0.1 between the normals' difference and
        the shared edge's points' offset), the part on the concave side that still joins a
        pair sharing an edge: 1 = all of it (a sign within noise is no evidence), 0 = none (a
        pair whose sign is below zero is cut, however slightly).  On the real mOSD frames 13 of
        the 16 pairs sharing an edge whose sign lies in (-0.1, 0) are faces of two objects (a
        box against a box, a carton on a book), 3 of one object (docs/objects.md).
    apart_gap : float
        Metres at 1 m from the sensor (scaled by the pair's mean distance beyond 1 m): a pair
        that neither touches in the image grid nor shares an edge (:data:`MIN_EDGE` pixel
        pairs, :func:`edge_means`) stays a pair only when its hulls come within this (the
        relations' ``adjacency_gap`` otherwise; 0 = off).  On the real mOSD frames faces of
        two objects (a book lying on a tin, a box beside a carton) are adjacent so 2-5 cm
        apart with a depth jump between them, while the faces of one object that share no
        edge (an unsegmented band along a rounded edge) mostly come within 2 cm.
    touch_gap : float
        Pixel footprints (``z / fx`` metres each, z the pair's mean distance; 0 = off): a pair
        that touches in the image grid or shares an edge stays a pair only when its hulls come
        within this many.  Two faces of one object meet (their hulls touch, or are apart by
        the few pixels left unsegmented between them); two objects one in front of the other
        border each other in the image across a depth jump.  On the real mOSD frames (640x480,
        8 footprints = 1.1 cm at 0.75 m) the touching pairs of two objects lie 1-4 cm apart,
        those of one object within 1 cm but 5 (docs/objects.md).
    skirt_gap : float
        Metres at 1 m (scaled by the pair's mean distance beyond 1 m; 0 = off): on a wavy
        frame (an active-stereo sensor's, :attr:`planerel.segment.noise.NoiseModel.wavy`,
        measured only when such a pair comes up) a ``skirt`` pair (a top and the face hanging
        below its edge) that ``touch_gap`` would cut stays a pair when its hulls come within
        this.  The sensor smears a box's edge into a band region growing leaves out or cuts
        into a strip: hidden28's graspnet cracker box (RealSense D435, 0.4 m) has its top and
        broad side 2.5 cm apart (40 px; ``touch_gap`` 5 mm there).  On the real Kinect frames,
        which are not wavy, the skirt pairs ``touch_gap`` cuts are two objects' faces 2.9-4.5
        cm apart (mOSD test59, learn2, test13-15): they stay cut (docs/objects.md, frag31).
    skin_height, skin_angle : float
        Metres at 1 m (scaled by the plane's distance beyond 1 m; 0 = off) and degrees: a
        proposal of one plane that is not vertical, at most ``skin_angle`` from a horizontal
        support plane that is the floor or adjacent to it, with its hull within
        ``skin_height`` of that plane, is a piece of the support's surface (the sensor bends
        a table near the image's corners into small planes tilted 5-20 degrees) and is
        dropped.
    skin_lifted : bool
        A piece that ``skin_height`` would drop is kept when it lies whole above the support:
        its hull's lowest point at least ``skin_height`` (unscaled) above the support's plane
        and at least ``SKIN_LIFT`` (half) of its highest.  A bend of the surface rises from
        it (on the real frames every piece the skin rule drops comes within 0.9 cm of the
        table on mOSD and 1.5 cm on the other real frames at its lowest point); a flat thing
        lying on the floor (a laptop's base or a closed laptop, 2 cm up at 1.4-1.8 m, where
        ``skin_height`` reaches 2-2.7 cm) lies parallel to it, lifted as a whole
        (docs/objects.md, "A slab on the floor is no skin (synth22w)").
    apart_edge : int
        Pixel pairs at 320 pixels wide (scaled by the image width: 5 at 160, 20 at 640): a pair
        adjacent by the grid test whose hulls lie farther apart than the relations'
        ``adjacency_gap`` needs a shared edge of at least this many pixel pairs (at least
        ``MIN_EDGE``) to stay a pair (:func:`shares_edge`).
    cut_long_side : bool
        In the step chains a tread counts as cut along its length by the image border (its
        depth not seen: no member) only by its pixels on the image sides parallel to its pixel
        box's long side (:func:`step_chain_pairs`); False = on any side (a tread the bottom
        edge cuts at its end, seen with the camera rolled, was left out).
    step_tread_axes : bool
        In the step chains two long treads (1.5 times longer than deep, their step directions
        within 25 degrees) measure the step across their own shortest extent (rotating
        calipers over their hulls, :func:`_tread_depth_axis`), not along the line between
        their centroids: a tread partly hidden (a leg on the lower step, the image border) has
        its centroid off to one side, and measured along that slanted line it looked deeper
        than a step and narrower than a flight (the real Kinect v2 staircase seen from above,
        stair-perception ``0000``, benchmarks/real_stairs.py).  False: the centroids' line
        (before 2026-11-29).
    step_cut_top : bool
        In the step chains' two-tread case the higher tread may be one the image border cuts
        along its length, when it lies between the camera and the lower tread and the two are
        seen edge to edge (a flight going down from the landing the camera stands on, its
        risers facing away: :func:`_cut_top_steps`; tread44).  False: a cut tread is never a
        member (before 2026-12-01).
    step_cut_chain : bool
        In the step chains a tread the border cuts along its length extends a counted row when
        its step repeats the row's rise and run and passes every other step test (a flight seen
        at a yaw, its treads running out of the image's bottom edge at a slant:
        :func:`_cut_chain_steps`; cut70).  False: such a tread is no member (before 2026-12-04).
    step_tread_pieces : bool
        In the step chains, treads lying as coplanar pieces of one tread side by side are also
        tested as their union, and a step of the union makes each piece a member (a tread the
        segmentation leaves in two pieces along its length, each half the flight's width:
        :mod:`planerel.features.tread_pieces`; pieces71).  False: each piece alone (before
        2026-12-04).
    step_two_risers : bool
        In the step chains, two risers alone make a step that counts when both are flight-like
        (wider across the flight than ``min_width`` and 1.5 times their height) and the lower
        one stands on a horizontal plane that reaches to its foot from the side the flight
        rises from (:func:`_two_riser_steps`: a two-step flight, or a longer one whose upper
        risers a low camera does not separate, seen level from a low robot, its treads edge
        on; riser73).  False: three risers in a row at least (before 2026-12-04).
    riser_pieces : bool
        The tread-and-riser exception's regularity test (a tread's riser below and riser
        above rise alike, within 30 %) measures the riser below in all its pieces together
        (the parallel vertical neighbours lower than the tread): a real stair's riser under a
        rounded nosing segments as the riser and a 5 cm strip, and the strip alone made the
        step irregular (a real Kinect staircase seen close, elmasry ``1347691665``;
        benchmarks/real_stairs.py).  False: each piece on its own (before 2026-11-29).
    floor_tread : bool
        The plane taken as the floor is no support when it is the lowest tread in view of a
        regular flight (:func:`_floor_is_tread`: step-shaped, a riser of one rise up to a
        tread, and a riser of that height again above it): a camera on or close to a
        staircase sees no floor (a real Kinect staircase seen close, elmasry
        ``1347691665``: its lowest tread was the floor and the flight kept one tread, no
        stairs rule could fire).  False: the floor is always support (before 2026-11-29).
    side_wall_members : int
        With ``group_channels``: one wall alone joins a group when at least this many of the
        group's planes meet it at shared concave edges and the group spans it (a flight seen
        with one side wall, each tread meeting it); 0 = two walls needed (the default: the
        varied world counts a flight's side wall as part of the staircase, the independent
        judge scenes count the room wall beside a flight as environment, and the walls'
        heights above the flights overlap; docs/objects.md, sixth pass).
    side_wall_rise_max : float
        With ``group_channels``: a wall that stands more than this (metres) above the line
        through the group's treads anywhere it is seen (:func:`planerel.features.cavities.wall_rise`)
        is a room wall beside a flight, not the flight's side wall, and does not join it.
        1.1: planerel's own closed sides stand 0.1-0.9 m above the nosings, at most 1.0 m
        above the treads' middles (half a rise, <= 0.105 m, lower); 0 = no test (the rule
        before stairs16r).  docs/results.md, "Independent scenes at 640x480".
    side_wall_follow : float
        With ``group_channels``: one wall alone joins a group when two or more of the group's
        treads meet it at shared concave edges and its top, where in view, stands at one
        height above each of them (a closed side's rail follows the flight; a room wall's top
        is level): the spread of those heights at most this times the spread of the treads'
        tops (:func:`planerel.features.cavities.follows_flight`); 0 = off (the rule before
        synth22q).
    split_panels : bool
        Also join a panel in coplanar pieces to the plane they meet: two parallel, coplanar
        planes (within ``coplanar_depth``) each meeting one plane at a shared concave edge,
        following one another along it within its extent and together spanning it
        (``cavity_overlap``), with something in front of them between them in the image (a
        shelf's back panel above and below an unsegmented board, and its side panel;
        :func:`planerel.features.cavities.split_panel_pairs`; needs ``cavities``).
    occluded_pieces : bool
        Join pieces of one surface seen on both sides of something in front of it: parallel
        planes within ``coplanar_depth`` of each other's plane, their hulls more than the
        relations' ``adjacency_gap`` and at most ``piece_gap`` apart, with at least half of the
        valid pixels between them in the image in front of both (a shelf's back panel seen
        from above between its boards; :func:`planerel.features.gaps.occluded_piece_pairs`;
        needs the cloud and ``cavities``).
    piece_gap : float
        Metres: the largest hull distance of such pieces.
    occluded_flat : bool
        With ``occluded_pieces``, horizontal and inclined pieces too (a box's top seen on
        both sides of a bar lying across it, of a box standing on it), under a stricter test
        than the vertical ones': within ``piece_depth`` of each other's plane, and on the
        image lines between them (the pixels next to either piece left out: an occluder's
        base) at most 2 % of the valid pixels behind the plane through both and either 95 %
        in front of it or half in front of both by ``gap_in_front``'s margin
        (:func:`planerel.features.gaps.occluded_piece_pairs`, ``flat``); a plane that is a
        piece of the support's surface (``skin_height``) is no such piece.  The tops of two
        boxes of one height with the table seen between them are not joined (occl22,
        docs/objects.md).  False: vertical pieces only (before 2026-11-30).
    occluded_near : bool
        With ``occluded_pieces``, pairs whose hulls come within the relations'
        ``adjacency_gap`` too (adjacent, but not touching in the image and not joined: a box
        seen on both sides of a plate standing in front of it, its halves 3-4 cm apart, over
        ``apart_gap``), under the stricter test.  False: hulls beyond ``adjacency_gap`` only.
    piece_depth : float
        Metres at 1 m (scaled by the pair's mean depth beyond 1 m): the stricter test's
        coplanarity (``coplanar_depth`` for two vertical pieces farther apart than
        ``adjacency_gap``).
    shared_top : bool
        A horizontal plane joined (convex edges) to two planes that meet each other at a
        clearly concave shared edge, and through which alone their groups are joined, stays
        with the group it shares more edge pixel pairs with (:func:`shared_top_cuts`): the tops
        of two boxes standing side by side at one height, which the segmentation made one
        plane (seventh pass).
    concave_cut : float
        Two planes that meet at a clearly concave shared edge (at least 5 edge pixel pairs,
        cosine of the convexity test at most -0.5) but are joined through other planes are
        cut apart at the group's weakest place between them (a minimum cut of the joined pairs
        weighted by their edge pixel pairs) when it weighs under ``concave_cut`` times the
        concave edge's pixel pairs, unless their normals are under 50 degrees apart (facets of
        a curved surface), either has under 100 points, or one of the two meets 3 or more
        planes of the group at concave edges (a flight's side wall; :func:`planerel.features.concave_cut.concave_cuts`; eighth
        pass); 0 = no cut.
    cavity_overlap : float
        An edge is whole when the two planes' extents along it overlap by at least this
        (interval IoU, :func:`planerel.features.cavities.edge_overlap`): a board spans its
        shelf's width, the platform a shelf stands on runs far beyond it.
    cut_apart_parallel : bool
        Cut a parallel pair that neither touches in the image nor shares an edge (adjacent
        only because its hulls come within the relations' ``adjacency_gap``) unless at least
        half of the valid pixels on the image lines between them lie in front of both
        (:func:`planerel.features.gaps.gap_in_front`; none valid: kept): two coplanar faces
        side by side with the floor or another face seen between them (two boxes in a row),
        not one surface, whose pieces touch or have an occluder between them.
    ramp_tilt, ramp_rise : float
        Degrees, metres: a horizontal plane of ``support_min_area`` or more that is not the
        floor is no support when it is tilted at least ``ramp_tilt`` against the floor's plane
        and its centroid lies at least ``ramp_rise`` above it: a shallow ramp rising from the
        floor, which the horizontal tolerance calls horizontal; ``ramp_tilt=0`` = no test.
    raised_objects : bool
        Pixels of a horizontal support plane that lie above it in a group (an open box's
        bottom, a laptop's base or a plate the segmentation joined to the floor) join the
        proposals whose planes touch them, or are a proposal of their own
        (:mod:`planerel.features.raised`; applied by :func:`planerel.features.facts.describe_scene`).
    riser_max : float
        Metres: a vertical plane higher than this and 1.5 times the other plane's height range
        is no riser for the tread-and-riser exception of :func:`convex_pairs` (a wall across the
        bottom of a flight; a ramp's end face is as high as its slope).  0.60 since the tenth
        pass (2 x ``step_rise_max``; 0.45 = 1.5 x before): a chair's backrest rises 0.30-0.55 m
        above its seat, which it meets as a riser meets its tread.
    stacked_boards : bool
        Join the boards of a shelf (:func:`planerel.features.boards.stacked_board_pairs`;
        tenth pass): at least three planes within ``step_tilt`` of horizontal, each the next
        one's ``step_rise_min``-``board_rise_max`` metres below it with their horizontal
        footprints overlapping by ``board_overlap`` of the smaller (one lies over the other; a
        staircase's treads lie one run beyond each other), their rises within 30 %.
    board_rise_max, board_overlap : float
        See ``stacked_boards``.
    stacked_faces : float
        Fraction (0 = off): two adjacent vertical, non-parallel planes whose height
        ranges overlap by less than this of the shorter one's are not joined (one object's
        face standing on another's: a box stacked on a box; ``stacked_overlap`` of
        :func:`convex_pairs`, not for an upper plane higher than ``riser_max``; tabletop22,
        docs/objects.md "Table-top judge set").  Above 0
        also: a tread whose vertical neighbours below are all turned against the riser above
        (neither parallel nor perpendicular to it) is no step (``_regular_step``'s
        ``turned``): a box standing turned on another.
    stacked_parallel : bool
        With ``stacked_faces``, parallel vertical planes one over the other are not joined
        either (``stacked_parallel`` of :func:`convex_pairs`): an aligned box on a box, its
        face a few millimetres before or behind the lower one's (tabletop22b).
    top_rise : float
        Metres (0 = off): a vertical plane sharing no edge with a horizontal one is not joined
        to it when its top rises more than this above the horizontal plane (``top_rise`` of
        :func:`convex_pairs`; tabletop22b).
    top_rise_edge : float
        Metres (0 = off; on at 0.02 since lead74): the same for a vertical plane sharing an
        edge with a horizontal one under the camera's eye, joined to it by the edge's convex
        sign alone (``top_rise_edge`` of :func:`convex_pairs`): a tote's wall seen over its
        rim and a block's top inside it, a lower top seen past a higher face's top edge.
    riser_min : float
        Metres (0 = off): the tread-and-riser exception of :func:`convex_pairs` needs the
        vertical plane over a horizontal one at least this high (its hull along up; 0.08 =
        ``step_rise_min``): a flight's riser rises a step, a box's face a few centimetres over
        a lower box's top beside or under it is the side of another object (pairs22).
    riser_floor : bool
        The riser-below test of the tread-and-riser exception (``_regular_step``: the risers
        below and above a tread rise alike) measures the riser below no higher than the
        tread's height above the floor when that is lower than the riser's hull: the hull's
        outliers (flying pixels at its edges) made a 0.11 m box's side 0.13 m and let a box
        next to a taller one pass as a flight's first step (synth22r, docs/objects.md).
        A flight's riser below a tread never rises above the tread's height over the floor.
    table_area, table_height : float
        m^2, metres (``table_area`` 0 = off): a table top seen with the room's floor in view is
        support (:func:`support_planes`, falsecls): a horizontal plane of at least
        ``table_area``, at least ``table_height`` above the floor (higher than one step), that
        carries something (a plane that meets it, lies above it and stands 5 cm inside its
        horizontal outline, ``TABLE_INSET``) and is no level of a flight (no horizontal plane of half its area
        or more ``step_rise_min``-``step_rise_max`` above or below), with the horizontal planes
        on its plane (within ``floor_gap``).  Before, it was a plane of the object proposal of
        what stood on it, and a tin's lid over it proved the demo's stairs rule 4 on real
        OSD and RealSense frames.
    table_legs : float
        Metres (0 = off): a table top made support by ``table_area`` is also an object, with
        the proposals under it (its edge faces, apron and legs), when one vertical plane among
        them reaches at least this below the top: a table standing in the room, seen with a leg
        or its apron (:mod:`planerel.features.tables`, applied by
        :func:`planerel.features.facts.describe_scene`; table22u).  What stands on the top is
        still proposed apart; a top seen without legs or apron stays support only.
    legs_apart : float
        Metres (0 = off): posts standing on the floor (proposals of vertical planes and
        unexplained pixels at most ``POST_WIDTH`` wide, ``POST_HEIGHT`` tall and three times
        as tall as wide) whose feet lie at most this far apart seen from above and whose tops
        are level (within ``POST_LEVEL`` at 1 m, scaled by the range) are one object: the legs
        of a table or a chair seen without its top (:func:`planerel.features.tables.leg_objects`,
        applied by :func:`planerel.features.facts.describe_scene` after ``table_legs``;
        synth22y).  1.8 m: a long table's legs; each leg was a false proposal of its own.
    open_walls : bool
        An open object seen over its near wall (the near wall's outside and the far wall's
        inside: parallel, turned the same way, 5-60 cm apart, tops level and seen, overlapping
        across, no horizontal plane at that level between them) is one object
        (:mod:`planerel.features.open_walls`, applied by
        :func:`planerel.features.facts.describe_scene` after ``legs_apart``; synth22y): an open
        box, a shelf seen from its side.  False: each wall a proposal of its own.
    skip_missing : bool
        The step chains' two-rise steps (a tread between two faces not seen) only where the
        face between is missing: a face between them in height that makes a one-rise step
        with one end and none with the other, the other end off the flight's rises (15 % of
        a rise), ends it (``skip_missing`` of
        :func:`step_chain_pairs`; a box's top two runs before a flight's tread; synth22r).
    flight_sides : bool
        A vertical plane of ``support_min_area`` or more whose seen top edge rises with the
        flight beside it is that flight's side, not a room wall: a solid balustrade's or a
        closed string's face, 2 m^2 and more on a long flight.  Its top edge (where seen: off
        the image border, hidden by nothing in front) is a straight line that stands at one
        height, up to ``side_wall_rise_max`` m, above the nosings of two or more steps near it
        (treads, and risers across it, within ``FLIGHT_SIDE_REACH`` m of its plane) whose
        tops span at least ``step_rise_min``: the heights spread by at most
        ``side_wall_follow`` times the tops' span (:func:`planerel.features.walls.flight_side`).
        A room wall's top is level (or out of view).  Such a plane is no support, and it joins
        the proposal holding those steps; so does any vertical plane of ``border_wall_area`` or
        more whose top follows them (a far balustrade's inside face, seen over the flight).
        (synth22v, docs/objects.md.)  False: support by area, and no such join (before
        2026-11-29).
    open_treads : bool
        Join the treads of an open-riser flight (:func:`planerel.features.open_treads.open_tread_pairs`):
        three or more *slabs* (planes at most ``OPEN_THICK`` m high along up and at most
        ``OPEN_TILT`` degrees from horizontal: a tread's top, or at range its top and front
        edge fitted as one tilted strip) whose hull tops lie one rise
        (``step_rise_min``-``step_rise_max``, or two) above each other, overlapping across the
        flight, each one's near edge at most ``step_run_max`` per rise beyond the one below
        and no more than 5 cm before it.  No two treads of such a flight touch, so each was a
        proposal of its own (riser26, docs/objects.md "Open-riser flights").  False: no such
        join (before riser26).
    channel_room_walls : bool
        Of two walls facing each other across a flight (``group_channels``), one that is a
        stairwell's room wall (:func:`planerel.features.walls.room_wall`: no top edge seen and
        at least half its top at the image border; it goes on out of view, as the walls of a
        stairwell seen from the flight's top do) does not join it, and left alone (with vertical
        pieces under ``border_wall_area`` at most) it is no proposal.  A person's rectangle around a flight in a
        stairwell leaves the walls out; a balustrade or string whose top is seen (level or
        following the steps) joins as before (walls36, docs/objects.md "A stairwell's walls
        are no flight's sides").  False: both walls join (before walls36).
    """

    support_min_area: float = 2.0
    wall_test: bool = True
    wall_tol: float = 0.10
    wall_window: float = 0.05
    floor_gap: float = 0.006
    drop_border_walls: bool = True
    border_wall_area: float = 0.3
    wall_behind: float = 0.01
    wall_floor_behind: float = 0.05
    min_points: int = 0
    split_concave: bool = True
    concave_tol: float = 10.0
    edge_band: int = 2
    edge_depth: float = 0.03
    step_overlap: float = 0.5
    min_border_area: float = 0.005
    step_chains: bool = True
    step_rise_min: float = 0.08
    step_rise_max: float = 0.30
    step_run_min: float = 0.12
    step_run_max: float = 0.60
    step_tilt: float = 12.0
    riser_tilt: float = 20.0
    riser_walls: bool = True
    split_stepped: bool = True
    raised_objects: bool = True
    coplanar_depth: float | None = 0.03
    sanity_angle: float = 50.0
    cavities: bool = True
    cavity_overlap: float = 0.5
    cut_apart_parallel: bool = True
    group_channels: bool = True
    occluded_channels: bool = True
    cavity_skip_walls: bool = True
    split_panels: bool = True
    apart_edge: int = 10
    apart_gap: float = 0.02
    touch_gap: float = 8.0
    skirt_gap: float = 0.03
    skin_height: float = 0.015
    skin_angle: float = 25.0
    skin_lifted: bool = True
    concave_band: float = 0.0
    cut_long_side: bool = True
    step_tread_axes: bool = True
    step_cut_top: bool = True
    step_cut_chain: bool = True
    step_tread_pieces: bool = True
    step_two_risers: bool = True
    riser_pieces: bool = True
    floor_tread: bool = True
    side_wall_members: int = 0
    side_wall_rise_max: float = 1.1
    side_wall_follow: float = 0.5
    occluded_pieces: bool = True
    occluded_flat: bool = True
    occluded_near: bool = True
    piece_depth: float = 0.02
    piece_gap: float = 0.25
    shared_top: bool = True
    concave_cut: float = 0.25
    ramp_tilt: float = 3.0
    ramp_rise: float = 0.02
    riser_max: float = 0.60
    stacked_boards: bool = True
    board_rise_max: float = 0.60
    board_overlap: float = 0.5
    stacked_faces: float = 0.3
    stacked_parallel: bool = True
    top_rise: float = 0.02
    top_rise_edge: float = 0.02
    riser_min: float = 0.08
    riser_floor: bool = True
    skip_missing: bool = True
    table_area: float = 0.2
    table_height: float = 0.30
    table_legs: float = 0.08
    legs_apart: float = 1.8
    open_walls: bool = True
    flight_sides: bool = True
    open_treads: bool = True
    channel_room_walls: bool = True

    @property
    def step_tilts(self) -> tuple:
        """``(tread tilt, riser tilt)`` in degrees: ``step_tilt`` and ``riser_tilt``, as
        :func:`_step_kind` takes them."""
        return (self.step_tilt, self.riser_tilt)

    def __post_init__(self) -> None:
        _check_nonneg(self, ("table_area", "table_height", "table_legs", "legs_apart", "support_min_area", "wall_tol", "wall_window", "floor_gap", "min_points", "concave_tol", "border_wall_area",
                             "wall_floor_behind", "edge_depth", "step_overlap", "min_border_area", "wall_behind",
                             "step_rise_min", "step_rise_max",
                             "step_run_min", "step_run_max", "step_tilt", "riser_tilt", "cavity_overlap", "piece_gap", "piece_depth",
                             "ramp_tilt", "ramp_rise", "concave_cut", "board_rise_max", "riser_max", "riser_min",
                             "side_wall_rise_max", "top_rise", "top_rise_edge", "side_wall_follow", "apart_gap",
                             "touch_gap", "skin_height", "skin_angle"))
        if not 0 <= self.concave_band <= 1:
            raise InputError(f"concave_band must be in 0..1, got {self.concave_band!r}")
        if not 0 <= self.board_overlap <= 1:
            raise InputError(f"board_overlap must be in 0..1, got {self.board_overlap!r}")
        if not 0 <= self.stacked_faces <= 1:
            raise InputError(f"stacked_faces must be in 0..1, got {self.stacked_faces!r}")
        if self.step_rise_min > self.step_rise_max or self.step_run_min > self.step_run_max:
            raise InputError("step_rise_min / step_run_min must not exceed step_rise_max / step_run_max, "
                             f"got {self.step_rise_min!r}-{self.step_rise_max!r} and "
                             f"{self.step_run_min!r}-{self.step_run_max!r}")
        if self.coplanar_depth is not None:
            _check_nonneg(self, ("coplanar_depth",))
        _check_nonneg(self, ("sanity_angle",))
        if self.riser_tilt > 45:
            raise InputError(f"riser_tilt must be in 0..45 degrees (off vertical), got {self.riser_tilt!r}")
        if self.sanity_angle > 90:
            raise InputError(f"sanity_angle must be in 0..90 degrees, got {self.sanity_angle!r}")
        for name in ("side_wall_members", "apart_edge"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise InputError(f"{name} must be an integer >= 0, got {v!r}")
        if isinstance(self.edge_band, bool) or not isinstance(self.edge_band, int) or not 1 <= self.edge_band <= 8:
            raise InputError(f"edge_band must be an integer number of pixels in 1..8, got {self.edge_band!r}")
        check_bools(self)


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
    return out


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

#: An open-riser tread's slab (``ProposalParams.open_treads``): at most this high along up
#: (metres; the real Kinect room's treads at 2-3 m: 0.01-0.13 with the front edge) and at most
#: this tilted from horizontal (degrees; their strips: 0-58).
OPEN_THICK = 0.15
OPEN_TILT = 60.0


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


def _regular_step(pa, pb, byl, nbrs, cos_tol, flight_riser_max: float | None = None,
                  seat_depth: float | None = None, turned: bool = False,
                  floor_low: bool = False, riser_pieces: bool = False) -> bool:
    """False when a tread and the riser above it are not one step of a regular flight: the
    tread has a riser below it (a vertical neighbour parallel to the one above, lower than
    the tread) and the two risers' heights differ by more than 30 %: a box standing on a
    box of the same width, not a staircase, whose steps rise alike.  With
    ``flight_riser_max`` (metres), a riser above higher than that (a flight's risers are not)
    is taken only as a seat's backrest: the tread at most ``seat_depth`` metres deep across
    the edge and with no vertical neighbour lower than it (a chair's seat stands on legs; a
    box's top has its sides below it, a platform or floor is deeper).  With ``turned``, a
    tread with vertical neighbours lower than it none of which is parallel or perpendicular
    (within the angle of ``cos_tol``) to the riser above is no step either: a box standing
    turned on another box (a flight's riser above is parallel to the riser below, a solid
    flight's side is perpendicular to both; tabletop22).  With ``floor_low``, the riser
    below counts no higher than the tread's height above the floor when that is lower (and
    above 0): a hull's outliers made a low box's side as high as the taller box's face over
    it (synth22r).  With ``riser_pieces`` the risers
    below are measured together (the height range of all their hulls) rather than each on its
    own: a real riser below a rounded nosing comes in pieces, and a 5 cm strip of it measured
    alone against the riser above cut a real staircase (2026-11-29)."""
    if "horizontal" not in (pa.orientation, pb.orientation):
        return True
    tread, riser = (pa, pb) if pa.orientation == "horizontal" else (pb, pa)
    if (riser.orientation != "vertical" or getattr(tread, "height", None) is None
            or getattr(riser, "height", None) is None or riser.height <= tread.height):
        return True
    up = np.asarray(tread.normal, float)
    nr = np.asarray(riser.normal, float)
    high = float(np.ptp(np.asarray(riser.hull3d, float) @ up))
    if flight_riser_max is not None and high > flight_riser_max:
        # higher than a flight's riser: only a seat's backrest, a seat deep and with no face
        # below it (a chair's seat stands on legs; a box's top has its sides below it)
        if seat_depth is not None and float(np.ptp(np.asarray(tread.hull3d, float) @ nr)) > seat_depth:
            return False
        for k in nbrs.get(tread.label, ()):
            q = byl[k]
            if (q is not riser and q.orientation == "vertical"
                    and getattr(q, "height", None) is not None and q.height < tread.height):
                return False
    if turned:
        below = [abs(float(np.asarray(byl[k].normal, float) @ nr)) for k in nbrs.get(tread.label, ())
                 if byl[k] is not riser and byl[k].orientation == "vertical"
                 and getattr(byl[k], "height", None) is not None and byl[k].height < tread.height]
        sin_tol = math.sqrt(max(0.0, 1.0 - cos_tol * cos_tol))
        if below and all(sin_tol < c < cos_tol for c in below):
            return False
    lows = []
    for k in nbrs.get(tread.label, ()):
        q = byl[k]
        if (q is riser or q.orientation != "vertical" or getattr(q, "height", None) is None
                or q.height >= tread.height
                or abs(float(np.asarray(q.normal, float) @ nr)) < cos_tol):
            continue
        h = np.asarray(q.hull3d, float) @ up
        if riser_pieces:
            lows.append(h)
            continue
        low = float(np.ptp(h))
        if floor_low and 0.0 < tread.height < low:
            low = float(tread.height)
        if abs(high - low) > 0.3 * max(high, low):
            return False
    if lows:
        # the riser below in however many pieces (a strip under a real stair's nosing apart
        # from the rest of its riser): their height range together
        h = np.concatenate(lows)
        low = float(h.max() - h.min())
        if floor_low and 0.0 < tread.height < low:
            low = float(tread.height)
        if abs(high - low) > 0.3 * max(high, low):
            return False
    return True


def _step_kind(p, tilt) -> str | None:
    """``"tread"`` for a face within ``tilt`` degrees of horizontal, ``"riser"`` within ``tilt``
    of vertical, else None (a far tread's strip measures a few degrees off horizontal).
    ``tilt`` is one angle for both or a pair ``(tread tilt, riser tilt)``
    (:attr:`ProposalParams.step_tilts`: a carpeted or raked riser leans back from its nosing)."""
    tread, riser = (tilt, tilt) if isinstance(tilt, (int, float)) else tilt
    if p.orientation == "horizontal" or p.incline <= tread:
        return "tread"
    if p.orientation == "vertical" or p.incline >= 90.0 - riser:
        return "riser"
    return None


def _anchor_offset(face, anchor, up) -> np.ndarray:
    """Horizontal offset ``(3,)`` from a face's centroid to the nearest point of another plane's
    hull (zero when the centroid lies over the hull)."""
    import shapely
    from shapely.geometry import Point, Polygon
    from shapely.ops import nearest_points

    c = np.asarray(face.centroid, float)
    H = np.asarray(anchor.hull3d, float)
    e1, e2 = _horizontal_basis(up)
    P = np.stack([H @ e1, H @ e2], 1)
    q = (float(c @ e1), float(c @ e2))
    geom = Polygon(P) if len(P) >= 3 else shapely.LineString(P) if len(P) == 2 else Point(P[0])
    if not geom.is_valid:
        geom = geom.convex_hull
    if geom.contains(Point(q)):
        return np.zeros(3)
    near = nearest_points(geom, Point(q))[0]
    return (near.x - q[0]) * e1 + (near.y - q[1]) * e2


#: a two-rise step whose face between is seen needs its other end within this fraction of a
#: rise of one rise beyond that face (``skip_missing``)
SKIP_GRID = 0.15


def _surely_deep(p, up, limit: float) -> bool:
    """True when ``p``'s hull, projected on the horizontal plane, is more than ``limit`` wide
    across every direction, known without :func:`_tread_depth_axis`' rotating calipers.

    The projection's area ``A`` over its diameter ``D`` (the largest distance between two
    of its vertices) bounds its smallest width ``w`` from below: a convex polygon lies in a
    strip ``w`` wide and at most ``D`` long, so ``A <= w D``; ``hull3d`` is the outline of a
    convex hull (a subset of its vertices when simplified), so its projection is a simple
    polygon with at most its own hull's area and the same diameter.  The extent across any
    horizontal direction, the calipers' included, is at least ``w``; the margin (relative
    ``1e-6``) covers the rounding of either computation.  In Python floats: a hull has 3-20
    vertices, and the calipers' numpy calls take 30 us warm, 150 us in the flow.  False for
    fewer than 3 vertices or no area (the calipers decide)."""
    H = p.hull3d
    m = len(H)
    if m < 3:
        return False
    (a0, a1, a2), (b0, b1, b2) = (e.tolist() for e in _horizontal_basis(up))
    xs, ys = [], []
    for x, y, z in np.asarray(H, float).tolist():
        xs.append(x * a0 + y * a1 + z * a2)
        ys.append(x * b0 + y * b1 + z * b2)
    twice = 0.0
    for i in range(m):
        twice += xs[i] * ys[i - 1] - xs[i - 1] * ys[i]
    need = limit * (1 + 1e-6)
    # the diagonal of the vertices' box first (at least D); the diameter itself only then
    diag = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    if diag > 0 and 0.5 * abs(twice) > need * diag:
        return True
    d2 = max((xs[i] - xs[j]) ** 2 + (ys[i] - ys[j]) ** 2 for i in range(m) for j in range(i))
    return d2 > 0 and 0.5 * abs(twice) > need * math.sqrt(d2)


def _some_rise(dv: float, rise, spans) -> bool:
    """Whether ``dv`` is one rise of a step over one of ``spans`` (1 or 2 faces apart): the
    rise half of :func:`step_chain_pairs`' step test, asked before the pair's run and its
    treads' step directions (``_tread_depth_axis``, 30-300 us a tread) are measured."""
    for k in spans:  # (a loop, not any() over a generator: about 1 us a pair less)
        if rise[0] <= dv / k <= rise[1]:
            return True
    return False


def flight_faces(planes, labels, params: ProposalParams | None = None) -> bool:
    """Whether the planes ``labels`` of one object hold a flight's faces in a regular row: a
    step of :func:`step_chain_pairs` (three treads or three risers or more, each one rise above
    and one run beyond the last), with the proposals' step settings ``params``.

    With ``params.open_treads``, three open-riser treads or more in a row
    (:func:`planerel.features.open_treads.open_tread_pairs`) are such a row too: seen at
    range their tops and front edges are fitted as strips 15-55 degrees off horizontal, and
    such a flight can show no horizontal plane at all (riser26).
    A flight seen from below shows its risers and no tread; a wall with the posts of a banister
    before it, or a cabinet's faces, hold no such row (hunt25: the decision's level gate,
    :func:`planerel.ilp.metrics.level_refusals`, keeps ``stairs`` for such an object).

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
    params : ProposalParams, optional
    """
    p = params or ProposalParams()
    labels = tuple(labels)
    if step_chain_pairs(planes, labels, (p.step_rise_min, p.step_rise_max),
                        (p.step_run_min, p.step_run_max), p.step_overlap or 0.5,
                        p.concave_tol, tilt=p.step_tilts, cut_long_side=p.cut_long_side,
                        skip_missing=p.skip_missing, tread_axes=p.step_tread_axes,
                        cut_top=p.step_cut_top, cut_chain=p.step_cut_chain,
                        tread_pieces=p.step_tread_pieces, two_risers=p.step_two_risers):
        return True
    # an open-riser flight's treads, fitted as strips tilted off horizontal at range
    return p.open_treads and bool(open_tread_pairs(planes, labels, (p.step_rise_min, p.step_rise_max),
                                                   p.step_run_max, OPEN_THICK, OPEN_TILT))


#: Where :func:`flight_steps` looks for steps (rise and run per step, metres): wider than a
#: staircase's, so that every level change between parallel faces of an object is found.
STEP_WINDOW_RISE = (0.05, 0.35)
STEP_WINDOW_RUN = (0.08, 0.8)
#: A staircase's step (rise, run; metres): the demo's training flights rise 0.12-0.22 m and
#: run 0.22-0.36 m (:mod:`planerel.synth.generator`, :class:`planerel.synth.world.WorldRange`),
#: widened by a third of a rise and of a run for what a sensor measures of them
#: (:func:`flight_evidence`).
STAIR_RISE = (0.08, 0.25)
STAIR_RUN = (0.15, 0.45)
#: Two steps of one flight: their rises and runs per step within this ratio (the regular row's
#: tolerance of :func:`step_chain_pairs`).
STEP_AGREE = 0.7


def flight_steps(planes, labels, params: ProposalParams | None = None, *,
                 keep_cut: bool = False) -> list:
    """Every step between parallel faces of the planes ``labels`` of one object: two treads or
    two risers :data:`STEP_WINDOW_RISE` above and :data:`STEP_WINDOW_RUN` beyond each other
    (one span, no chain asked: :func:`step_chain_pairs` with ``chain=False``), with the
    proposals' step settings ``params``.  With ``keep_cut``, treads the image border cuts
    along their length take part too (:func:`flight_fragments`).

    Returns
    -------
    list of (int, int, float, float)
        ``(lower label, higher label, rise, run)`` per step, metres.
    """
    p = params or ProposalParams()
    steps = step_chain_pairs(planes, tuple(labels), STEP_WINDOW_RISE, STEP_WINDOW_RUN,
                             p.step_overlap or 0.5, p.concave_tol, tilt=p.step_tilts, skip=False,
                             cut_long_side=p.cut_long_side, tread_axes=p.step_tread_axes,
                             chain=False, drop_cut=not keep_cut)
    return [(int(lo), int(hi), float(r), float(g)) for lo, hi, r, _d, _k, g in steps]


def flight_evidence(planes, labels, params: ProposalParams | None = None, *,
                    fragments: bool = True) -> bool:
    """Whether the planes ``labels`` of one object show a staircase's steps: a regular row of
    three faces (:func:`flight_faces`), or steps that are one flight's (pile26).

    Without a row (a flight of two steps: two treads and two risers), the object's steps
    (:func:`flight_steps`: every level change between two parallel treads or risers) must be
    one flight's: the lowest step a stair's (:data:`STAIR_RISE`, :data:`STAIR_RUN`), and
    every other step one, two or three of it, rise and run alike (within :data:`STEP_AGREE`).
    Cartons packed on a pallet at three heights (a step of 0.10 m beside one of 0.20 m whose
    run is no longer) and boxes of two heights touching (one step 0.30 m high and 0.67 m
    deep) are no flight, nor is an object with no step at all (a machine's faces, a room
    wall's posts).  Two levels one stair rise above and one run beyond each other are a step
    to this test whatever they are made of: a pile of two heights of stair-like cartons stays
    a flight.  With ``fragments`` (``decision.flight_fragments``), a flight seen in fragments
    counts too (:func:`flight_fragments`: risers stacked one on the other, treads the image
    border cuts; flight48).

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
    params : ProposalParams, optional
    fragments : bool
        Ask :func:`flight_fragments` when the steps above are not one flight's.
    """
    labels = tuple(labels)
    return (flight_faces(planes, labels, params)
            or steps_of_one_flight(flight_steps(planes, labels, params))
            or (fragments and flight_fragments(planes, labels, params)))


def steps_of_one_flight(steps) -> bool:
    """Whether ``steps`` (``(lower, higher, rise, run)`` per step, :func:`flight_steps`) are
    one flight's: at least one, the lowest (least rise) a stair's (:data:`STAIR_RISE`,
    :data:`STAIR_RUN`), and every other one, two or three of it in rise and run alike, each
    within :data:`STEP_AGREE` (:func:`flight_evidence`)."""
    if not steps:
        return False
    _lo, _hi, rise, run = min(steps, key=lambda s: (s[2], s[3]))
    if not (STAIR_RISE[0] <= rise <= STAIR_RISE[1] and STAIR_RUN[0] <= run <= STAIR_RUN[1]):
        return False

    def agrees(r: float, g: float) -> bool:
        return any(STEP_AGREE <= r / (k * rise) <= 1 / STEP_AGREE
                   and STEP_AGREE <= g / (k * run) <= 1 / STEP_AGREE for k in (1, 2, 3))

    return all(agrees(r, g) for _a, _b, r, g in steps)


#: Two risers of one flight are stacked: the higher one's foot lies within this fraction of a
#: rise of the lower one's top edge, and the higher one is at most this fraction taller than a
#: rise (:func:`stacked_riser_steps`; on the varied world's fragmented flights the foot lies
#: within 0.08 of a rise and the higher riser at most 1.07 rises high, flight48).
STACK_TOL = 0.15
#: ... and they overlap across the flight by at least this fraction of the narrower one's
#: width (a riser seen in part, cut by the image border or hidden, lies within its flight).
STACK_OVERLAP = 0.5


def stacked_riser_steps(planes, labels, params: ProposalParams | None = None) -> list:
    """Steps between two risers of the planes ``labels`` (faces within ``params.step_tilt``
    degrees of vertical, normals within ``params.concave_tol``) that stand one on the other:
    a flight's risers, however much of their width is seen.

    The varied world's flights at 160x120 come in fragments (accept45, flight48): a riser's
    width seen in part (the border, a rail, too few pixels) makes two risers' areas differ
    more than :func:`step_chain_pairs` allows (3 times), and the centroid of a riser whose top
    the image cuts lies under its middle.  What a fragment keeps is its height: a flight's
    riser is one rise high and the next one starts where it ends.  So two risers are a step
    when the higher one's foot lies within :data:`STACK_TOL` of a rise of the lower one's top
    edge, the rise (foot to foot) is a stair's (:data:`STAIR_RISE`), the higher one is no
    taller than a rise (within :data:`STACK_TOL`; it may be cut shorter), their horizontal
    offset along the lower one's normal is a stair's run (:data:`STAIR_RUN`) and they overlap
    across the flight by :data:`STACK_OVERLAP` of the narrower one.  Boxes standing on the
    floor side by side or one behind the other have their faces' feet at one level: no step;
    a carton behind a lower one shows its face from the lower one's top up, a step only when
    no taller than the lower one (a pile of two heights 0.25 and 0.55 m is none).

    Returns
    -------
    list of (int, int, float, float)
        ``(lower label, higher label, rise, run)`` per step, metres (as :func:`flight_steps`).
    """
    p = params or ProposalParams()
    up = np.asarray(planes.up, float)
    cos_tol = math.cos(math.radians(p.concave_tol))
    want = set(labels)
    risers = []
    for q in planes:
        if q.label not in want or _step_kind(q, p.step_tilts) != "riser":
            continue
        h = np.asarray(q.hull3d, float)
        if len(h) < 2:
            continue
        t = h @ up
        n = np.asarray(q.normal, float)
        nh = n - (n @ up) * up
        norm = float(np.linalg.norm(nh))
        if norm < 1e-9:
            continue
        risers.append((q, float(t.min()), float(t.max()), nh / norm, h))
    out = []
    for i, (a, a0, a1, na, ha) in enumerate(risers):
        for b, b0, b1, nb, hb in risers[i + 1:]:
            if abs(float(np.asarray(a.normal, float) @ np.asarray(b.normal, float))) < cos_tol:
                continue
            lo, l0, l1, nl, hl, hi, h0, h1, hh = ((a, a0, a1, na, ha, b, b0, b1, hb) if a0 <= b0
                                                  else (b, b0, b1, nb, hb, a, a0, a1, ha))
            rise = h0 - l0
            if not STAIR_RISE[0] <= rise <= STAIR_RISE[1]:
                continue
            if abs(h0 - l1) > STACK_TOL * rise or h1 - h0 > (1.0 + STACK_TOL) * rise:
                continue
            d = np.asarray(hi.centroid, float) - np.asarray(lo.centroid, float)
            run = abs(float(d @ nl))
            if not STAIR_RUN[0] <= run <= STAIR_RUN[1]:
                continue
            across = cross3(up, nl)
            pl, ph = hl @ across, hh @ across
            inter = min(pl.max(), ph.max()) - max(pl.min(), ph.min())
            if inter < STACK_OVERLAP * min(np.ptp(pl), np.ptp(ph)) or inter <= 0:
                continue
            out.append((int(lo.label), int(hi.label), float(rise), float(run)))
    return out


def flight_fragments(planes, labels, params: ProposalParams | None = None) -> bool:
    """Whether the planes ``labels`` of one object show a flight seen in fragments
    (flight48): its stacked risers (:func:`stacked_riser_steps`) are one flight's steps
    (:func:`steps_of_one_flight`), or its steps with the treads the image border cuts along
    their length (:func:`flight_steps` with ``keep_cut``; a flight seen from its top, the far
    treads running out of the image) are.

    The second part of :func:`flight_evidence`'s test, asked when the object's faces make no
    regular row and its whole faces' steps are not one flight's: accept45 measured 27-52 true
    160x120 flights a varied model refused so (risers whose areas differ more than 3 times,
    treads cut by the border); each list must still be one flight's as a whole, so a pile's
    unequal steps keep it out.

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
    params : ProposalParams, optional
    """
    labels = tuple(labels)
    stacked = stacked_riser_steps(planes, labels, params)
    if stacked and steps_of_one_flight(stacked):
        return True
    return steps_of_one_flight(flight_steps(planes, labels, params, keep_cut=True))


def step_offset(lo, hi, kind: str, up, tread_axis=None) -> tuple[float, np.ndarray]:
    """How far, horizontally, the higher face ``hi`` of a step lies beyond the lower ``lo``,
    and in which direction: for risers along the lower one's horizontal normal, for treads
    between their centroids, or (``tread_axis``, a function giving a tread's depth axis and
    elongation, :func:`_tread_depth_axis`) across two long treads whatever the lateral offset
    of their centroids (a tread partly hidden by a leg or the image border).

    Parameters
    ----------
    lo, hi : Plane
    kind : str
        ``"riser"`` or ``"tread"``.
    up : ndarray, shape (3,)
    tread_axis : callable, optional

    Returns
    -------
    (float, ndarray of shape (3,))
        The run (m) and the unit horizontal step direction.
    """
    d = np.asarray(hi.centroid, float) - np.asarray(lo.centroid, float)
    dh = d - (d @ up) * up
    if kind == "riser":
        nh = np.asarray(lo.normal, float) - (np.asarray(lo.normal, float) @ up) * up
        nh /= max(float(np.linalg.norm(nh)), 1e-9)
        dist = abs(float(dh @ nh))
        return dist, (nh if float(dh @ nh) >= 0 else -nh)
    dist = float(np.linalg.norm(dh))
    direction = dh / max(dist, 1e-9)
    if tread_axis is not None:
        (da, ea), (db, eb) = tread_axis(lo), tread_axis(hi)
        if min(ea, eb) >= 1.5 and abs(float(da @ db)) >= _COS_25:
            along = float(dh @ da)
            return abs(along), (da if along >= 0 else -da)
    return dist, direction


#: cos 25 degrees: two step directions (or tread axes) that agree
_COS_25 = math.cos(math.radians(25.0))


def step_chain_pairs(planes, labels=(), rise=(0.08, 0.30), run=(0.12, 0.60),
                     min_overlap: float = 0.5, angle_tol: float = 10.0,
                     max_ratio: float = 3.0, tilt=12.0, skip: bool = True,
                     min_width: float = 0.5, cut_long_side: bool = True,
                     skip_missing: bool = False, tread_axes: bool = False,
                     chain: bool = True, cut_top: bool = False, drop_cut: bool = True,
                     cut_chain: bool = False, tread_pieces: bool = False,
                     two_risers: bool = False):
    """Pairs of parallel faces that are consecutive steps of a staircase (in a chain of >= 3).

    Two treads (faces within ``tilt`` degrees of horizontal) or two risers (within ``tilt`` of
    vertical; ``tilt`` one angle or ``(tread, riser)`` angles: :attr:`ProposalParams.step_tilts`)
    with normals within ``angle_tol`` degrees are a *step* when the higher one's
    centroid lies ``rise`` above and ``run`` beyond the lower one's (horizontally; for risers
    along their normal), their extents across that direction overlap by at least
    ``min_overlap`` (interval IoU: one flight's width), their areas differ by at most
    ``max_ratio`` times and each is at most one step deep (a tread's extent along the step
    direction at most ``run[1]``, a riser's height at most ``rise[1]``): not a landing or the
    floor a flight goes down from.  With ``skip``, two faces two rises above and two runs
    beyond each other are a step too (the face between them not found: cut by a rail, too few
    pixels), counted as two.  A step counts only when one of its faces is also a face of
    another step in the same direction (unit horizontal offsets within 25 degrees) with a rise
    per step within 30 %: three faces in a regular row.  Two boxes, one behind the other, make
    one step, not a chain; a staircase seen from above (treads only) or below (risers only)
    makes many.  A tread the image border cuts along its length (the landing the camera stands
    on, seen to the bottom edge) is no member: its depth is not seen (``cut_long_side``: only
    the border on the sides of its pixel box's long side counts, :func:`_cut_lengthwise`).
    With ``skip_missing``, a two-rise step spans a *missing* face only: when one of its faces
    already makes a one-rise step (same direction) with a face lying between the two in
    height, makes none with the other end, and the other end lies more than ``SKIP_GRID``
    (15 %) of a rise off one rise beyond it, the two-rise step is dropped (a box's top 0.21 m
    high two runs before a flight's tread, the tread between at 0.33 m, rise 0.17 m; a
    flight's lowest riser, partly hidden and no step of the next, lies on the flight's
    rises; synth22r).  Two treads alone make
    a step that counts when both are at least ``min_width`` wide across the flight and 1.5
    times wider than deep, and a third horizontal plane (any: the landing, the floor) lies
    one more rise (within 30 %) above or below and comes within ``run[1]`` of them
    horizontally, on the flight's line: a short flight seen from above.  With ``cut_top``, the
    higher of those two treads may be one the border cuts along its length (a flight going
    down from the landing the camera stands on: the top tread, nearest the camera, runs out of
    the image's bottom edge; :func:`_cut_top_steps`), counted only when the lower tread is in
    no step already counted (above a row of treads the cut strip may be the landing); with
    ``chain=False`` such steps are listed too.

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
        Planes to consider (e.g. the non-support planes); empty = all.

    cut_chain : bool
        With ``chain``, a tread the border cuts along its length still extends a counted row
        by one step at either end when the step passes every test a step of whole treads
        passes and repeats the row's rise and run (:func:`_cut_chain_steps`): a flight seen
        at a yaw whose treads run out of the image's bottom edge at a slant.
    tread_pieces : bool
        Treads lying as coplanar pieces of one tread side by side
        (:func:`planerel.features.tread_pieces.tread_unions`) also take part as their
        union: a counted pair of the union names each piece (they join the flight), a step
        of ``chain=False`` its largest piece only (one step, as a whole face's).  A tread in
        two pieces, each half the flight's width, fails the overlap and area tests against
        the whole tread below it.
    two_risers : bool
        With ``chain``, two risers alone make a step that counts when both are flight-like
        and the lower one stands on a horizontal plane (:func:`_two_riser_steps`).
    chain : bool
        False: return every step found, before the chain test (a list of ``(lower, higher,
        rise per step, unit horizontal direction (3,), span, run per step)``;
        :func:`flight_step`).
    drop_cut : bool
        False: treads the image border cuts along their length take part like any other
        (:func:`flight_fragments`; no ``cut_top`` steps then).

    Returns
    -------
    set of (int, int)
        ``(lower, higher)`` label pairs of the steps that count.
    """
    want = set(labels)
    up = np.asarray(planes.up, float)
    cos_tol = math.cos(math.radians(angle_tol))
    kind = {p.label: _step_kind(p, tilt) for p in planes}
    # the border cut is asked of the candidate treads only (the same candidates)
    cut = _cut_lengthwise([p for p in planes if (not want or p.label in want)
                           and kind[p.label] == "tread"], cut_long_side,
                          getattr(planes, "labels", None)) if drop_cut else set()
    cands = [p for p in planes if (not want or p.label in want) and kind[p.label]
             and not (kind[p.label] == "tread" and p.label in cut)]
    unions: dict = {}
    if tread_pieces:
        unions = tread_unions([p for p in cands if kind[p.label] == "tread"], up, cos_tol,
                              max((p.label for p in planes), default=0) + 1)
        for k, (u, _) in unions.items():
            cands.append(u)
            kind[k] = "tread"
    steps = []  # (lower, higher, rise per step, unit horizontal direction)
    spans = (1, 2) if skip else (1,)
    axes_of: dict = {}

    def tread_axis(q):
        if q.label not in axes_of:
            axes_of[q.label] = _tread_depth_axis(q, up)
        return axes_of[q.label]

    for i, pa in enumerate(cands):
        na = np.asarray(pa.normal, float)
        for pb in cands[i + 1:]:
            if kind[pb.label] != kind[pa.label]:
                continue
            # the tests on Python floats first (each test only rejects: their order does not
            # change which pairs pass), the normals' product only for a pair that passes them
            if max(pa.area, pb.area) > max_ratio * min(pa.area, pb.area):
                continue
            lo, hi = (pa, pb) if pa.height <= pb.height else (pb, pa)
            dv = hi.height - lo.height
            if not _some_rise(dv, rise, spans):
                continue  # no span's rise: the step test below fails whatever the run
            if abs(float(na @ np.asarray(pb.normal, float))) < cos_tol:
                continue
            dist, direction = step_offset(lo, hi, kind[lo.label], up,
                                          tread_axis if tread_axes else None)
            k = next((k for k in spans if rise[0] <= dv / k <= rise[1]
                      and run[0] <= dist / k <= run[1]), None)
            if k is None:
                continue
            # each face is one step deep (treads) or high (risers): not a floor or a landing
            depth_axis = direction if kind[lo.label] == "tread" else up
            limit = run[1] if kind[lo.label] == "tread" else rise[1]
            if not _step_faces(lo, hi, up, direction, depth_axis, limit, min_overlap):
                continue
            steps.append((lo.label, hi.label, dv / k, direction, k, dist / k))
    cos_dir = math.cos(math.radians(25.0))
    if skip_missing and any(s[4] == 2 for s in steps):
        hgt = {p.label: p.height for p in cands}
        one = [s for s in steps if s[4] == 1]
        ones = {(s[0], s[1]) for s in one}

        def spans_seen(s2) -> bool:
            lo_l, hi_l, r, dirn = s2[:4]
            for s1 in one:
                if float(s1[3] @ dirn) < cos_dir:
                    continue
                for end, other, mid in ((hi_l, lo_l, s1[0]), (lo_l, hi_l, s1[1])):
                    if (s1[1] if end == hi_l else s1[0]) != end or mid in (lo_l, hi_l):
                        continue
                    if abs(hgt[mid] - (hgt[lo_l] + r)) > 0.3 * r:
                        continue  # not the face between them
                    if ((other, mid) if end == hi_l else (mid, other)) in ones:
                        continue
                    # the face between is seen: the other end lies one rise beyond it
                    step = s1[2]
                    want = hgt[mid] - step if end == hi_l else hgt[mid] + step
                    if abs(hgt[other] - want) > SKIP_GRID * step:
                        return True
            return False

        steps = [s2 for s2 in steps if s2[4] != 2 or not spans_seen(s2)]
    extra = []
    if cut_top and cut:
        tops = [p for p in planes if p.label in cut and (not want or p.label in want)]
        lows = [p for p in cands if kind[p.label] == "tread"]
        extra = _cut_top_steps(lows, tops, up, rise, run, min_overlap, max_ratio, cos_tol,
                               tread_axis)
    if not chain:
        # each union's largest piece only: one step, not one a piece (the stair_step/2 facts)
        return _spread_steps(steps + extra, unions, largest=True) if unions else steps + extra
    out = set()
    for s1 in steps:
        for s2 in steps:
            if s1 is s2 or not (s1[1] == s2[0] or s1[0] == s2[1]):
                continue
            if float(s1[3] @ s2[3]) >= cos_dir and 0.7 <= s1[2] / s2[2] <= 1 / 0.7:
                out.add((s1[0], s1[1]))
                break
    # two treads alone (a short flight seen from above: the landing, two treads, the floor):
    # the third face may be any horizontal plane one more rise up or down that comes within a
    # run of them (the landing or floor, support or cut by the border; it does not join the
    # proposal), when both treads are flight-like: wide and shallow
    byl = {p.label: p for p in planes}
    byl.update((k, u) for k, (u, _) in unions.items())
    anchors = [p for p in planes if kind[p.label] == "tread"]
    members: set = set()
    n_steps = len(steps)
    for i, (lo_l, hi_l, dv, direction, k, _run) in enumerate(steps + extra):
        lo, hi = byl[lo_l], byl[hi_l]
        if i == n_steps:
            # a cut top tread only where the lower one is in no counted step: with a row of
            # treads found, the strip the border cuts above its top may be the landing the
            # camera stands on as well as the top tread (dev_st i0001, dev_sr i0020), and
            # its seen part tells them apart by nothing
            members = {x for pr in out for x in pr}
        if i >= n_steps and lo_l in members:
            continue
        if (lo_l, hi_l) in out or k != 1 or kind[lo_l] != "tread":
            continue
        across = cross3(up, direction)
        if any(np.ptp(np.asarray(q.hull3d, float) @ across) < max(min_width, 1.5 * np.ptp(
                np.asarray(q.hull3d, float) @ direction)) for q in (lo, hi)):
            continue
        for a in anchors:
            if a.label in (lo_l, hi_l):
                continue
            face, sign = (hi, 1.0) if a.height > hi.height else (lo, -1.0)
            gap = abs(a.height - face.height)
            if not 0.7 <= gap / dv <= 1 / 0.7 or abs(float(np.asarray(a.normal) @ up)) < cos_tol:
                continue
            off = _anchor_offset(face, a, up)
            dist = float(np.linalg.norm(off))
            if dist > run[1] or (dist >= 0.5 * run[0] and float(off @ direction) * sign < cos_dir * dist):
                continue
            out.add((lo_l, hi_l))
            break
    if two_risers:
        out |= _two_riser_steps(steps, out, byl, planes, kind, up, run, min_width)
    if cut_chain and cut and out:
        lab = getattr(planes, "labels", None)
        # treads cut at a slant only: the landing the camera stands on is cut all along
        slanted = [p for p in planes if p.label in cut and (not want or p.label in want)
                   and _border_share(lab, p) < CUT_CHAIN_BORDER]
        out |= _cut_chain_steps(steps + extra, out, slanted, byl, up, run, min_overlap,
                                max_ratio, cos_tol, tread_axis if tread_axes else None)
    if unions:
        return {pr[:2] for pr in _spread_steps([(lo, hi) for lo, hi in out], unions)}
    return out


#: A two-riser step's ground: a horizontal plane level with the lower riser's foot within this
#: share of the step's rise (:func:`_two_riser_steps`)
TWO_RISER_FOOT = 0.3


def _two_riser_steps(steps, counted, by_label, planes, kind, up, run, min_width: float) -> set:
    """Steps of two risers alone that count: a flight seen level from a low camera.

    A camera 0.3-0.5 m over the floor (a tracked rescue robot, a low service robot) sees an
    ascending flight's risers and its treads edge on: no tread is a plane, and the row of
    three risers that a step needs to count may be two (a two-step flight; the upper risers
    partly hidden behind the treads' noses, too unlike in size to pair).  A step of two
    risers (``steps``' entries ``(lower, higher, rise, direction (3,), span, run)``, one span)
    that is not counted yet counts when

    - both risers are flight-like: their extent across the flight at least ``min_width`` and
      1.5 times their height (a box's face or a cabinet's door is narrower than tall);
    - no horizontal plane lies level with the lower riser's top edge within ``run[1]`` of it:
      the tread between them is not seen (two boxes of two heights seen from above show the
      lower one's top, and stay two proposals, as the issue asks of touching boxes);
    - the lower riser stands on a horizontal plane (the floor, a landing): a plane within
      ``tilt`` of level whose level lies within :data:`TWO_RISER_FOOT` of a rise of the
      riser's lowest hull point, and whose hull comes within ``run[1]`` of the riser's
      centroid horizontally, on the side the flight rises from (a box on a table before a
      wall's skirting has no ground under its face at that level).

    Two boxes, the farther one a step taller, standing a run apart on the floor and seen so
    low that the nearer one's top is no plane, are such a step too: that is the geometry of a
    two-step flight seen so.

    Returns
    -------
    set of (int, int)
        ``(lower, higher)`` label pairs.
    """
    cos_dir = math.cos(math.radians(25.0))
    out: set = set()
    grounds = [p for p in planes if kind.get(p.label) == "tread"
               or getattr(p, "orientation", None) == "horizontal"]
    if not grounds:
        return out
    for lo_l, hi_l, dv, direction, k, _run in steps:
        if k != 1 or (lo_l, hi_l) in counted or kind.get(lo_l) != "riser":
            continue
        lo, hi = by_label[lo_l], by_label[hi_l]
        across = cross3(up, direction)
        if any(np.ptp(np.asarray(q.hull3d, float) @ across) < max(
                min_width, 1.5 * np.ptp(np.asarray(q.hull3d, float) @ up)) for q in (lo, hi)):
            continue
        levels = np.asarray(lo.hull3d, float) @ up
        foot, top = float(levels.min()), float(levels.max())
        if any(abs(float(np.asarray(g.centroid, float) @ up) - top) <= TWO_RISER_FOOT * dv
               and float(np.linalg.norm(_anchor_offset(lo, g, up))) <= run[1]
               for g in grounds if g.label not in (lo_l, hi_l)):
            continue  # the tread between them is seen: a row of three decides, as before
        for g in grounds:
            if g.label in (lo_l, hi_l):
                continue
            if abs(float(np.asarray(g.centroid, float) @ up) - foot) > TWO_RISER_FOOT * dv:
                continue
            off = _anchor_offset(lo, g, up)
            dist = float(np.linalg.norm(off))
            # within a run, and before the riser (against the flight's direction)
            if dist > run[1] or (dist >= 0.5 * run[0] and -float(off @ direction) < cos_dir * dist):
                continue
            out.add((lo_l, hi_l))
            break
    return out


def _spread_steps(steps, unions, largest: bool = False) -> list:
    """``steps`` (tuples beginning ``(lower, higher)``) with each union of tread pieces
    (``unions``, :func:`~planerel.features.tread_pieces.tread_unions`) replaced by its pieces:
    one tuple a piece (two unions: a tuple a pair of pieces), the rest of the tuple kept; with
    ``largest``, by its largest piece only (a step named once, as a whole face's would be)."""
    out = []
    keep = slice(0, 1) if largest else slice(None)
    for s in steps:
        los = unions[s[0]][1][keep] if s[0] in unions else (s[0],)
        his = unions[s[1]][1][keep] if s[1] in unions else (s[1],)
        out.extend((lo, hi) + tuple(s[2:]) for lo in los for hi in his)
    return out


#: A cut tread's step repeats its row's: rise within this share of the row's rise per step,
#: run within :data:`CUT_CHAIN_RUN` of its run (:func:`_cut_chain_steps`)
CUT_CHAIN_RISE = 0.15
CUT_CHAIN_RUN = 0.2
#: ... and the border holds under this share of the long side of the cut tread's pixel box: a
#: tread cut at a slant shows an end or part of its near edge (0.55 in dev_st's flights seen
#: at a yaw), the landing the camera stands on runs out of the image all along (0.94-0.97)
CUT_CHAIN_BORDER = 0.75


def _cut_chain_steps(steps, counted, cut, by_label, up, run, min_overlap: float,
                     max_ratio: float, cos_tol: float, tread_axis) -> set:
    """Steps from a counted row's end tread to a tread the image border cuts along its length
    (``cut``), one step further along the row.

    The border cuts a tread "along its length" when its pixels on the border's rows (or
    columns) reach half its pixel box's long side; a flight seen at a yaw has its treads
    running out of the image's bottom edge at a slant, so whole treads of it are cut so.  Such
    a tread still extends a row of steps already counted (``counted``, ``(lower, higher)``
    pairs of ``steps``' entries ``(lower, higher, rise, direction (3,), span, run)``) when the
    step between it and the row's end tread passes the tests a step of two whole treads passes
    (normals within ``cos_tol``, areas within ``max_ratio``, each at most ``run[1]`` deep,
    extents across overlapping by ``min_overlap``) and repeats the row: its rise within
    :data:`CUT_CHAIN_RISE` of the row's step's rise, its run within :data:`CUT_CHAIN_RUN` of
    that step's run, its direction within 25 degrees.  The caller passes only treads cut at
    a slant (:data:`CUT_CHAIN_BORDER`): the landing the camera stands on is a step's rise
    and, by chance, a run away too, but the border cuts it all along.  Repeated while a tread
    joins (a row runs on through several cut treads).

    Returns
    -------
    set of (int, int)
        ``(lower, higher)`` label pairs.
    """
    cos_dir = math.cos(math.radians(25.0))
    rows = [s for s in steps if (s[0], s[1]) in counted and s[4] == 1]
    members = {x for pr in counted for x in pr}
    left = [c for c in cut if c.label not in members]

    def extends(c, row):
        """The step ``(lower, higher)`` from ``row``'s lower or higher end to the cut tread
        ``c`` that repeats the row and passes the step tests, or None."""
        lo_l, hi_l, dv, direction, _k, dist = row
        for end, sign in ((by_label[hi_l], 1.0), (by_label[lo_l], -1.0)):
            if abs(sign * (c.height - end.height) - dv) > CUT_CHAIN_RISE * dv \
                    or max(c.area, end.area) > max_ratio * min(c.area, end.area) \
                    or abs(float(np.asarray(c.normal, float) @ np.asarray(end.normal, float))) \
                    < cos_tol:
                continue
            lo, hi = (end, c) if sign > 0 else (c, end)
            d2, dir2 = step_offset(lo, hi, "tread", up, tread_axis)
            if (run[0] <= d2 <= run[1] and abs(d2 - dist) <= CUT_CHAIN_RUN * dist
                    and float(dir2 @ direction) >= cos_dir
                    and _step_faces(lo, hi, up, dir2, dir2, run[1], min_overlap)):
                return lo, hi
        return None

    out: set = set()
    grown = True
    while grown and left:
        grown = False
        for c in list(left):
            for row in rows:
                step = extends(c, row)
                if step is not None:
                    lo, hi = step
                    out.add((lo.label, hi.label))
                    rows.append((lo.label, hi.label, row[2], row[3], 1, row[5]))
                    left.remove(c)
                    grown = True
                    break
    return out


def _step_faces(lo, hi, up, direction, depth_axis, limit: float, min_overlap: float) -> bool:
    """The last tests of a step between the faces ``lo`` and ``hi``: each at most ``limit``
    deep along ``depth_axis`` (one step deep or high: not a floor or a landing), and their
    extents across ``direction`` overlapping by at least ``min_overlap`` (interval IoU)."""
    if any(np.ptp(np.asarray(q.hull3d, float) @ depth_axis) > limit for q in (lo, hi)):
        return False
    return _across_overlap(lo, hi, up, direction) >= min_overlap


#: Metres: how far the plan gap between a cut top tread's far edge and the lower tread's near
#: edge may lie off the band the top tread's nosing hides (:func:`_cut_top_steps`)
CUT_TOP_SLACK = 0.05


def _cut_top_steps(lows, tops, up, rise, run, min_overlap: float, max_ratio: float,
                   cos_tol: float, tread_axis) -> list:
    """One-rise steps from a tread the image border cuts along its length (``tops``: the top
    tread of a flight going down from the camera's landing, its near part out of the image) to
    a whole tread (``lows``) one rise lower and one run *farther from the camera*, its riser
    hidden: the top tread's far edge (the nosing) occludes the lower tread's back.

    A pair counts when both treads are long (1.5 times longer than deep) with step directions
    within 25 degrees (the run is measured across them, between their centroids, within
    ``run``: the cut tread's centroid lies nearer its nosing), their extents across the flight
    overlap by ``min_overlap`` (interval IoU), each is at most ``run[1]`` deep as seen, the cut
    tread's seen area is at most ``max_ratio`` times the whole one's (a landing's seen piece is
    larger; no lower bound: the border leaves a strip of the top tread), and the plan gap from
    the top tread's far edge to the lower tread's near edge lies within ``CUT_TOP_SLACK`` of
    the band the nosing hides from the camera (rise times the nosing's distance from the camera
    along the flight over its depth under the camera; the camera at the origin): the two are
    seen edge to edge, no
    floor between them.  The caller asks of these pairs what it asks of two treads alone (wide,
    shallow, a third level one more rise up or down).

    Returns
    -------
    list of tuple
        ``(lower, higher, rise, unit horizontal direction (3,), 1, run)`` as
        :func:`step_chain_pairs` lists its steps (``chain=False``).
    """
    out = []
    cos_dir = math.cos(math.radians(25.0))
    for hi in tops:
        nh = np.asarray(hi.normal, float)
        ch = np.asarray(hi.centroid, float)
        for lo in lows:
            dv = hi.height - lo.height
            if not rise[0] <= dv <= rise[1] or hi.area > max_ratio * lo.area:
                continue
            if abs(float(nh @ np.asarray(lo.normal, float))) < cos_tol:
                continue
            (da, ea), (db, eb) = tread_axis(lo), tread_axis(hi)
            if min(ea, eb) < 1.5 or abs(float(da @ db)) < cos_dir:
                continue
            cl = np.asarray(lo.centroid, float)
            d = ch - cl
            dh = d - (d @ up) * up
            along = float(dh @ da)
            direction = da if along >= 0 else -da  # from the lower tread to the top one
            dist = abs(along)
            if not run[0] <= dist <= run[1]:
                continue
            # the camera (at the origin) stands on the top tread's side: the flight goes down
            # away from it, the lower tread beyond the top one
            if float(ch @ direction) >= 0.0:
                continue
            if any(np.ptp(np.asarray(q.hull3d, float) @ direction) > run[1] for q in (lo, hi)):
                continue
            if _across_overlap(lo, hi, up, direction) < min_overlap:
                continue
            # edge to edge: the plan gap is the band the top tread's nosing hides
            H = np.asarray(hi.hull3d, float)
            t = H @ direction
            nose = H[int(np.argmin(t))]
            below = -float(nose @ up)  # the nosing's depth under the camera
            if below <= 0:
                continue  # the camera is not above the top tread: not seen from the landing
            # the sight line over the nosing drops one rise over this much of the flight
            band = dv * -float(nose @ direction) / below
            gap = float(t.min()) - float((np.asarray(lo.hull3d, float) @ direction).max())
            if abs(gap - band) > CUT_TOP_SLACK:
                continue
            out.append((lo.label, hi.label, dv, direction, 1, dist))
    return out


def _across_overlap(lo, hi, up, direction) -> float:
    """Interval IoU of planes ``lo`` and ``hi`` across the horizontal ``direction`` (their
    hulls' extents along ``up x direction``: one flight's width); -1 when the union is empty."""
    across = cross3(up, direction)
    a0, a1 = _extent(lo, across)
    b0, b1 = _extent(hi, across)
    union = max(a1, b1) - min(a0, b0)
    return (min(a1, b1) - max(a0, b0)) / union if union > 0 else -1.0


def _step_like(pa, pb, min_overlap: float, up=None, riser_max: float | None = None,
               riser_min: float = 0.0) -> bool:
    """A horizontal or inclined plane and a vertical one meeting as tread and riser (or a
    slope and the face at its end): their extents along the shared edge line overlap by at
    least ``min_overlap`` (IoU of the two intervals), and (with ``up`` and ``riser_max``) the
    vertical one is at most ``riser_max`` high or 1.5 times the other's height range: a wall
    seen behind a far tread is no riser, a ramp's end face is as high as its slope.  With
    ``up`` and ``riser_min`` > 0, a vertical plane over a horizontal one lower than
    ``riser_min`` is no riser (a box's face rising a few centimetres over a lower box)."""
    ors = sorted((pa.orientation, pb.orientation))
    if ors not in (["horizontal", "vertical"], ["inclined", "vertical"]):
        return False
    if up is not None and (riser_max is not None or riser_min > 0):
        vert, other = (pa, pb) if pa.orientation == "vertical" else (pb, pa)
        u = np.asarray(up, float)
        high = float(np.ptp(np.asarray(vert.hull3d, float) @ u))  # the riser's height
        if riser_min > 0 and other.orientation == "horizontal" and high < riser_min:
            return False
        if riser_max is not None and high > max(
                riser_max, 1.5 * float(np.ptp(np.asarray(other.hull3d, float) @ u))):
            return False
    return edge_overlap(pa, pb) >= min_overlap


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

        def border_wall(c) -> bool:
            return (all(byl[x].orientation == "vertical" for x in c)
                    and any(byl[x].touches_border for x in c)
                    and max(byl[x].area for x in c) >= params.border_wall_area
                    and (not look or seen_behind(lab, cloud.xyz, c) <= params.wall_behind)
                    and not floor_behind(c))

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
