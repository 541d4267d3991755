/*  Part 2 of 4 of planerel's task files (not a task of its own; aleph/part1_relations.pl says
    how the parts are put together): the measures of a pair of planes and the attributes of a
    plane that every task has.
*/

% the measures of two planes already in the clause (+plane, +plane: they never introduce one)
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
