% A numeric-threshold task, written for planerel's tests: a parcel is heavy
% when its weight is at least a threshold that must be learned from the data.
% gteq/2 and lteq/2 are evaluated lazily (Aleph's protocol): during the search
% they are called with [PosValues, NegValues] in place of their first
% argument and return a cut-off; otherwise they are ordinary comparisons.

:- set(i, 2).
:- set(clauselength, 3).
:- set(test_pos, 'threshold_test.f').
:- set(test_neg, 'threshold_test.n').

:- modeh(1, heavy(+parcel)).
:- modeb(1, weight(+parcel, -kg)).
:- modeb(1, colour(+parcel, #colour)).
:- modeb(1, gteq(+kg, #kg)).
:- modeb(1, lteq(+kg, #kg)).

:- determination(heavy/1, weight/2).
:- determination(heavy/1, colour/2).
:- determination(heavy/1, gteq/2).
:- determination(heavy/1, lteq/2).

:- lazy_evaluate(gteq/2).
:- lazy_evaluate(lteq/2).

% Lazy form: the cut-off halfway between the least positive value and the
% largest negative value below it.
gteq([Pos, Neg], T) :- !,
    min_list(Pos, MinP),
    include(>(MinP), Neg, Below),
    (   Below == []
    ->  T = MinP
    ;   max_list(Below, MaxN),
        T is (MinP + MaxN) / 2
    ).
gteq(X, T) :- number(X), number(T), X >= T.

lteq([Pos, Neg], T) :- !,
    max_list(Pos, MaxP),
    include(<(MaxP), Neg, Above),
    (   Above == []
    ->  T = MaxP
    ;   min_list(Above, MinN),
        T is (MaxP + MinN) / 2
    ).
lteq(X, T) :- number(X), number(T), X =< T.

parcel(p1). parcel(p2). parcel(p3). parcel(p4). parcel(p5). parcel(p6).
parcel(p7). parcel(p8). parcel(p9). parcel(p10). parcel(p11). parcel(p12).
parcel(p13). parcel(p14). parcel(p15). parcel(p16).
parcel(t1). parcel(t2). parcel(t3). parcel(t4). parcel(t5). parcel(t6).

weight(p1, 5.0).  colour(p1, red).
weight(p2, 5.5).  colour(p2, blue).
weight(p3, 6.25). colour(p3, red).
weight(p4, 7.0).  colour(p4, green).
weight(p5, 8.5).  colour(p5, blue).
weight(p6, 9.25). colour(p6, red).
weight(p7, 5.75). colour(p7, green).
weight(p8, 6.5).  colour(p8, blue).
weight(p9, 1.25). colour(p9, red).
weight(p10, 2.5). colour(p10, blue).
weight(p11, 3.25). colour(p11, green).
weight(p12, 4.0). colour(p12, red).
weight(p13, 0.75). colour(p13, blue).
weight(p14, 3.75). colour(p14, green).
weight(p15, 2.25). colour(p15, red).
weight(p16, 1.75). colour(p16, blue).

% held-out parcels (threshold_test.f / .n)
weight(t1, 5.25). colour(t1, green).
weight(t2, 7.75). colour(t2, red).
weight(t3, 4.75). colour(t3, blue).
weight(t4, 4.25). colour(t4, red).
weight(t5, 1.0).  colour(t5, green).
weight(t6, 3.0).  colour(t6, blue).
