/*  Part 4 of 4 of planerel's task files (not a task of its own; aleph/part1_relations.pl says
    how the parts are put together): the thresholds on the other measures, and their lazy
    evaluation.
*/

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
