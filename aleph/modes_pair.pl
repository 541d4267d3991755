/*  planerel task for the product part's extension (pair41): modes_relational.pl and
    face_pair/2 (two upright walls of one solid at an outside corner of at least 85 degrees,
    tops level and bottoms level, walls as narrow as 2 cm: a narrow box seen level with the
    table, no top and no ground in view).  examples/demo.py learn_shipped gives it to the
    extension stage only, so the base stage's rules are learned from modes_relational.pl as
    before.  The rest of this file is modes_relational.pl's.
*/

/*  planerel task: the class of an object (box / stairs / ramp) from its planes
    and the relations between them.

    Read by `planerel export-aleph`, which writes it into STEM.b after the
    target's mode head (modeh(1, Class(+obj)), or modeh(1, class(+obj, #cls))
    for a multi-class task) and adds one determination from the target to
    every predicate declared below with modeb.

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
*/

:- set(search, heuristic).
:- set(evalfn, laplace).
:- set(clauselength, 6).
:- set(i, 3).
:- set(nodes, 3000).
:- set(minpos, 2).
:- set(noise, 0).

% planes and their pairwise relations
:- modeb(*, has_plane(+obj, -plane)).
:- modeb(1, orientation(+plane, #orient)).
:- modeb(*, adjacent(+plane, -plane)).
:- modeb(*, parallel(+plane, -plane)).
:- modeb(*, perpendicular(+plane, -plane)).
:- modeb(*, above(+plane, -plane)).
:- modeb(*, skirt(+plane, -plane)).
:- modeb(*, corner(+plane, -plane)).
:- modeb(*, face_pair(+plane, -plane)).
:- modeb(*, stair_step(+plane, -plane)).
:- modeb(1, angle(+plane, +plane, -angle)).
:- modeb(1, gap(+plane, +plane, -gap)).
:- modeb(1, rise(+plane, +plane, -rise)).

% plane attributes: orientation, height and size
:- modeb(1, incline(+plane, -incline)).
:- modeb(1, slope(+plane, -slope)).
:- modeb(1, height(+plane, -height)).
:- modeb(1, area(+plane, -area)).
:- modeb(1, plane_length(+plane, -plength)).
:- modeb(1, plane_width(+plane, -pwidth)).
% a vertical rectangle standing on the ground, its top at or above the sensor's eye level or
% out of view: a box seen so shows no top (a tall box, a box seen face-on); a chair's back
% stands on nothing, a ramp's back or a laptop's lid is seen from above (face24)
:- modeb(1, tall_face(+plane)).
% a level or tilted plane at most 0.6 m long lying 1.5-12 cm over a larger horizontal plane
% beside it: the top of a book or a flat box lying on a table, its sides edge-on or hidden;
% a table's top, a seat, a landing stand higher, a floor's far piece is level (top25)
:- modeb(1, lying(+plane)).
% a plane seen whole (not cut by the image border, not partly hidden): its sizes are sizes;
% plane_length / plane_width measure the part in view, a lower bound when it is cut, so they
% take only gteq ("at least this long") and an upper bound is on seen_length / seen_width
:- modeb(1, seen_length(+plane, -slength)).
:- modeb(1, seen_width(+plane, -swidth)).

% object measures: the number of horizontal planes as a constant ("exactly one
% horizontal plane" is one literal), the oblique share with a threshold
:- modeb(1, nhorizontal(+obj, #nhorizontal)).
:- modeb(1, oblique_share(+obj, -oblique)).

% how much of the object flat planes explain (planerel.curved): round objects are curved
:- modeb(1, planar_fraction(+obj, -pfrac)).
:- modeb(1, curved(+obj)).

% lazily evaluated thresholds, one pair per measure
:- modeb(1, gteq(+angle, #angle)).
:- modeb(1, lteq(+angle, #angle)).
:- modeb(1, gteq(+gap, #gap)).
:- modeb(1, lteq(+gap, #gap)).
:- modeb(1, gteq(+rise, #rise)).
:- modeb(1, lteq(+rise, #rise)).
:- modeb(1, gteq(+incline, #incline)).
:- modeb(1, lteq(+incline, #incline)).
:- modeb(1, gteq(+slope, #slope)).
:- modeb(1, lteq(+slope, #slope)).
:- modeb(1, gteq(+height, #height)).
:- modeb(1, lteq(+height, #height)).
:- modeb(1, gteq(+area, #area)).
:- modeb(1, lteq(+area, #area)).
:- modeb(1, gteq(+plength, #plength)).
:- modeb(1, gteq(+pwidth, #pwidth)).
:- modeb(1, lteq(+slength, #slength)).
:- modeb(1, lteq(+swidth, #swidth)).
:- modeb(1, gteq(+pfrac, #pfrac)).
:- modeb(1, lteq(+pfrac, #pfrac)).
:- modeb(1, gteq(+oblique, #oblique)).
:- modeb(1, lteq(+oblique, #oblique)).

:- lazy_evaluate(lteq/2).
:- lazy_evaluate(gteq/2).
