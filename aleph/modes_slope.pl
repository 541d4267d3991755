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
    with it.  tests/test_slope.py keeps it so.  Written as the four parts every task
    shares (aleph/part1_relations.pl says how) and the thresholds on incline/2.
*/

:- planerel_include('part1_relations.pl').
:- planerel_include('part2_measures.pl').
:- planerel_include('part3_objects.pl').
:- modeb(1, gteq(+incline, #incline)).
:- modeb(1, lteq(+incline, #incline)).
:- planerel_include('part4_thresholds.pl').
