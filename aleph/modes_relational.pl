/*  planerel task: the class of an object (box / stairs / ramp) from its planes
    and the relations between them.

    Read by `planerel export-aleph`, which writes it into STEM.b after the
    target's mode head (modeh(1, Class(+obj)), or modeh(1, class(+obj, #cls))
    for a multi-class task) and adds one determination from the target to
    every predicate declared below with modeb (in this file and its parts).

    Vocabulary (docs/predicates.md): the planes of an object (has_plane), per
    plane its orientation, incline, height and size (area, plane_length,
    plane_width), whether it is a tall face (tall_face: a vertical
    rectangle standing on the ground with its top out of sight, as a box
    seen as one face) and whether it lies on a larger plane as a flat
    thing's top (lying: a book on a table, its sides edge-on), per
    ordered pair of planes the relations adjacent,
    parallel, perpendicular, above, skirt (a vertical face hanging below a
    horizontal plane as a box's side below its top), corner (two vertical
    walls of one solid: right angle, level tops, neither a post), and the
    measures angle, gap and rise,
    and per object its number of horizontal planes and its oblique share
    (the share of its area in planes meeting a larger plane of it at an
    oblique angle: facets of a curved surface, a tilted lid on its base).
    The counts of vertical and inclined planes are facts but not modes
    here: "one inclined plane" fired on any tilted fragment and laptop
    lid, and a rule on them binds no plane; rules about inclined or
    vertical planes name the plane (orientation/2) and its size.
    Thresholds on every measure come from lteq/2 and gteq/2, evaluated
    lazily over the values of the covered examples, so the bottom clause
    holds one comparison per value and the search picks the cut-off.

    Types: obj, plane, orient, and one type per measure (incline, height,
    area, plength, pwidth, angle, gap, rise, nhorizontal, oblique, pfrac),
    so that Aleph never joins or compares equal numbers of
    different measures.  The pair measures take two planes already in the
    clause (+plane, +plane): they describe pairs, they never introduce one.

    No hand-written detector: step_up/2 stays in prolog/derived.pl as
    background and is a mode only in aleph/modes_objects.pl.

    Written as the four parts every task shares (aleph/part1_relations.pl ..
    part4_thresholds.pl, taken with planerel_include, which planerel expands
    when it reads the task) and this task's own lines between them, each where
    the bottom clause has always had it: stair_step/2 after the relations,
    tall_face/1 and lying/1 after the plane attributes, the thresholds on
    incline/2 after those on the pair measures.  The task written out line by
    line is the modes section of any STEM.b that planerel export-aleph writes
    with it (docs/learner.md "A task that extends another").
*/

:- planerel_include('part1_relations.pl').
% two treads or two risers one stair step apart (lead28)
:- modeb(*, stair_step(+plane, -plane)).
:- planerel_include('part2_measures.pl').
% a vertical rectangle standing on the ground, its top at or above the sensor's eye level or
% out of view: a box seen so shows no top (a tall box, a box seen face-on); a chair's back
% stands on nothing, a ramp's back or a laptop's lid is seen from above (face24)
:- modeb(1, tall_face(+plane)).
% a level or tilted plane at most 0.6 m long lying 1.5-12 cm over a larger horizontal plane
% beside it: the top of a book or a flat box lying on a table, its sides edge-on or hidden;
% a table's top, a seat, a landing stand higher, a floor's far piece is level (top25)
:- modeb(1, lying(+plane)).
:- planerel_include('part3_objects.pl').
:- modeb(1, gteq(+incline, #incline)).
:- modeb(1, lteq(+incline, #incline)).
:- planerel_include('part4_thresholds.pl').
