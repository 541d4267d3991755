/*  planerel task: slope/2 with the default task of before face24, top25 and lead28.

    Optional: `--task modes_slope.pl` (planerel export-aleph,
    benchmarks/eval_heldout.py): modeb(1, slope(+plane, -slope)) with gteq
    and lteq on it.  slope/2 is the incline of an inclined plane only (no fact
    for horizontal or vertical planes), so "an inclined plane at most 20
    degrees steep" is one literal and its threshold, and a clause of
    clauselength 6 can bound the plane's size too: what the varied world's
    ramps seen close and cut by the view need (docs/results.md, conf16).
    Since lead28 the default task has slope/2 too, with the demo's training
    world's panel part (steep panels and sofas as negatives: the ramp rule
    learns "at most 28 degrees"); before, without them, the demo learned
    ramp(A) :- has_plane(A,B), adjacent(B,C), slope(C,D), which called
    parts of the real Kinect frames and an mOSD box ramp.  This task stays
    for the measurements of docs/results.md (conf16): the default task
    without tall_face/1, lying/1 and stair_step/2, which were not measured
    with it.  tests/test_slope.py keeps it so.
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
:- modeb(1, angle(+plane, +plane, -angle)).
:- modeb(1, gap(+plane, +plane, -gap)).
:- modeb(1, rise(+plane, +plane, -rise)).

% plane attributes: orientation, height and size
:- modeb(1, incline(+plane, -incline)).
% the incline of an inclined plane only: "an inclined plane at most 20 degrees steep" is one
% literal and its threshold, so a clause can bound it and the plane's size too (a ramp seen
% close, cut by the view: its size in view is small, its slope gentle)
:- modeb(1, slope(+plane, -slope)).
:- modeb(1, height(+plane, -height)).
:- modeb(1, area(+plane, -area)).
:- modeb(1, plane_length(+plane, -plength)).
:- modeb(1, plane_width(+plane, -pwidth)).
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
