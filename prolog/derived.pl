/*  planerel: relations derived from the scene facts (see docs/predicates.md).

    Load after (or together with) a facts file written by `planerel describe`
    or the background of an exported Aleph task.
*/

%   horizontal(?P), vertical(?P), inclined(?P): orientation class of plane P.
horizontal(P) :- orientation(P, horizontal).
vertical(P)   :- orientation(P, vertical).
inclined(P)   :- orientation(P, inclined).

%   object_plane(?S, ?O, ?P): plane P belongs to object O of scene S.
object_plane(S, O, P) :- object(S, O), has_plane(O, P).

%   step_up(?P, ?Q): P and Q are horizontal planes, Q lies above P (above/2)
%   and a vertical plane R (a riser) is adjacent to both, with its centroid
%   between their heights and no other horizontal plane adjacent to R in
%   between: one step of a staircase.  May succeed once per such R.
step_up(P, Q) :-
    horizontal(P),
    adjacent(P, R), vertical(R),
    adjacent(R, Q), Q \== P,
    horizontal(Q),
    above(Q, P),
    height(P, HP), height(Q, HQ), height(R, HR),
    HP < HR, HR < HQ,
    \+ ( adjacent(R, M), M \== P, M \== Q, horizontal(M),
         height(M, HM), HP < HM, HM < HQ ).
