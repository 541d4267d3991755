/*  Part 1 of 4 of planerel's task files (not a task of its own): the settings, the planes of
    an object and the pairwise relations that every task has.

    A task file takes the four parts in order with `:- planerel_include('part1_relations.pl').`
    and so on (planerel expands the directive where it stands when it reads the task; it is
    never written into STEM.b), its own lines between them: after this part its further pair
    relations (stair_step/2, face_pair/2, facing/2, over/2), after part 2 its further plane
    attributes (tall_face/1, lying/1), after part 3 the thresholds on incline/2.  The order of
    the modeb lines is the order of the bottom clause's literals, and so decides the search:
    the parts are cut where the tasks differ, so each task's lines stand where they always
    stood (aleph/modes_relational.pl; docs/learner.md "A task that extends another").
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
