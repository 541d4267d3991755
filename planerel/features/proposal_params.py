"""The settings of the object proposals (:class:`ProposalParams`, ``--param proposals.NAME``).

Their own module because both :mod:`planerel.features.proposals` and
:mod:`planerel.features.step_chains` (the flight tests) build them, and the proposals import
the step chains.  Moved out of :mod:`planerel.features.relations` (split95), which still gives
``ProposalParams``.
"""

from __future__ import annotations

from dataclasses import dataclass

from planerel.errors import InputError, check_bools
from planerel.features.relations import _check_nonneg

__all__ = ["ProposalParams"]


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
    wedge_side_max : float
        Degrees (0 = off): a vertical plane whose top edge is seen straight over half a metre
        or more (in at least half its bins), sloping at most this much, with the face lying
        under it (the test of ``top_slope/2``, :func:`planerel.features.proposals.wedge_sides`)
        is a wedge's side, not a room wall: no support at ``support_min_area`` or more, and no
        border wall (``drop_border_walls``), so it can be a proposal (wedge96: a ramp seen
        from its side by a camera lower than its top shows only that triangle; docs/objects.md
        "A ramp seen only from its side").  Ramps slope 4-20 degrees; 25.
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
    wedge_side_max: float = 25.0
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
        _check_nonneg(self, ("sanity_angle", "wedge_side_max"))
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
