/*  Part 3 of 4 of planerel's task files (not a task of its own; aleph/part1_relations.pl says
    how the parts are put together): the sizes of a plane seen whole, the measures of the
    object, and the thresholds on the pair measures.
*/

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

% lazily evaluated thresholds, one pair per measure (those on incline/2 follow in the task
% that has them, then part 4)
:- modeb(1, gteq(+angle, #angle)).
:- modeb(1, lteq(+angle, #angle)).
:- modeb(1, gteq(+gap, #gap)).
:- modeb(1, lteq(+gap, #gap)).
:- modeb(1, gteq(+rise, #rise)).
:- modeb(1, lteq(+rise, #rise)).
