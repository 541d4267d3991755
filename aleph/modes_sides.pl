/*  planerel task for the extension with the training world's side-view part (ramp77):
    aleph/modes_pair.pl and top_slope/2 (the slope from level of an upright face's top edge
    where the camera sees it straight over 0.5 m or more, on a face that lies under that edge:
    a ramp's side face seen from lower than its top rises with the slope, a flight's closed
    side rises at its pitch; ramp78).  examples/demo.py learn_shipped gives it to its third
    stage, ramp clauses only, when the world has a side-view part (--side-views N, 30 by
    default since ramp78), so the base stage's rules and the product extension's are
    learned as before.

    Every line of aleph/modes_pair.pl in its order, top_slope/2 right after lying/1 and its
    thresholds last (tests/test_task_include.py keeps the file so).
*/

:- planerel_include('part1_relations.pl').
:- modeb(*, face_pair(+plane, -plane)).
:- modeb(*, stair_step(+plane, -plane)).
:- planerel_include('part2_measures.pl').
:- modeb(1, tall_face(+plane)).
:- modeb(1, lying(+plane)).
% the slope from level of an upright face's top edge seen straight over 0.5 m or more (ramp77)
:- modeb(1, top_slope(+plane, -topslope)).
:- planerel_include('part3_objects.pl').
:- modeb(1, gteq(+incline, #incline)).
:- modeb(1, lteq(+incline, #incline)).
:- planerel_include('part4_thresholds.pl').
:- modeb(1, gteq(+topslope, #topslope)).
:- modeb(1, lteq(+topslope, #topslope)).
