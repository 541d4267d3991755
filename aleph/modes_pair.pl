/*  planerel task for the product part's extension (pair41): modes_relational.pl and
    face_pair/2 (two upright walls of one solid at an outside corner of at least 85 degrees,
    tops level and bottoms level, walls as narrow as 2 cm: a narrow box seen level with the
    table, no top and no ground in view).  examples/demo.py learn_shipped gives it to the
    extension stage only, so the base stage's rules are learned from modes_relational.pl as
    before.

    Every line of aleph/modes_relational.pl, in its order (its parts and its own lines, the
    comments on them there), and face_pair/2 right after the relations of part 1, before
    stair_step/2, where it has been since pair41: the bottom clause's order, and so the
    extension's rules, stay as they were learned (tests/test_facing.py keeps the file so).
*/

:- planerel_include('part1_relations.pl').
:- modeb(*, face_pair(+plane, -plane)).
:- modeb(*, stair_step(+plane, -plane)).
:- planerel_include('part2_measures.pl').
:- modeb(1, tall_face(+plane)).
:- modeb(1, lying(+plane)).
:- planerel_include('part3_objects.pl').
:- modeb(1, gteq(+incline, #incline)).
:- modeb(1, lteq(+incline, #incline)).
:- planerel_include('part4_thresholds.pl').
