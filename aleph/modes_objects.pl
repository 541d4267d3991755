/*  planerel task with the hand-written stairs detector step_up/2: optional.

    The default task is aleph/modes_relational.pl (pairwise relations and
    plane size as body modes, no detector).  This file keeps the older
    vocabulary for comparison: `planerel export-aleph DS OUT --task
    modes_objects.pl`.

    Read by `planerel export-aleph`, which writes it into STEM.b after the
    target's mode head (modeh(1, Class(+obj)), or modeh(1, class(+obj, #cls))
    for a multi-class task) and adds one determination from the target to
    every predicate declared below with modeb.

    Types: obj (an object), plane, orient (horizontal / vertical /
    inclined), and one type per numeric attribute (nplanes, nhorizontal,
    nvertical, ninclined, incline, height), so that Aleph never joins equal
    numbers of different attributes.  Thresholds come from lteq/2 and gteq/2,
    evaluated lazily over the values of the covered examples.

    Bottom clauses stay near 100 literals for a 12-plane staircase: one
    literal per object count, has_plane for each plane, and per plane its
    orientation, incline, height and their comparisons; step_up/2 (a derived
    relation, see prolog/derived.pl) links the treads of a staircase.
*/

:- set(search, heuristic).
:- set(evalfn, laplace).
:- set(clauselength, 7).
:- set(i, 3).
:- set(nodes, 3000).
:- set(minpos, 2).
:- set(noise, 0).

:- modeb(*, has_plane(+obj, -plane)).
:- modeb(1, orientation(+plane, #orient)).
:- modeb(*, step_up(+plane, -plane)).
:- modeb(1, incline(+plane, -incline)).
:- modeb(1, height(+plane, -height)).
:- modeb(1, nhorizontal(+obj, -nhorizontal)).
:- modeb(1, nvertical(+obj, -nvertical)).
:- modeb(1, ninclined(+obj, -ninclined)).
:- modeb(1, gteq(+incline, #incline)).
:- modeb(1, lteq(+incline, #incline)).
:- modeb(1, gteq(+height, #height)).
:- modeb(1, lteq(+height, #height)).
:- modeb(1, gteq(+nhorizontal, #nhorizontal)).
:- modeb(1, lteq(+nhorizontal, #nhorizontal)).
:- modeb(1, gteq(+nvertical, #nvertical)).
:- modeb(1, lteq(+nvertical, #nvertical)).
:- modeb(1, gteq(+ninclined, #ninclined)).
:- modeb(1, lteq(+ninclined, #ninclined)).

:- lazy_evaluate(lteq/2).
:- lazy_evaluate(gteq/2).
