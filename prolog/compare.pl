/*  planerel: numeric comparisons for learned thresholds.

    lteq(X, T)  holds when the number X is at most the threshold T.
    gteq(X, T)  holds when the number X is at least the threshold T.

    They are called in three ways:

    1. Ordinary test: X and T are numbers.
    2. Saturation (building a bottom clause): X is a number and T is unbound;
       T is bound to X itself, so the bottom clause holds the seed's value.
    3. Lazy evaluation (Aleph's lazy_evaluate/1 protocol): X is the list
       [PosValues, NegValues] of the values the input argument takes on the
       positive and the negative examples covered so far, and T is unbound.
       T is bound to the cut-off that separates the two lists best: the one
       that maximises (positives kept - negatives kept), then keeps fewest
       negatives.  The cut-off is the shortest decimal strictly between the last
       value kept and the next value, or the value itself when every value
       is an integer (counts), so learned rules read "gteq(N, 2)".
       An element ex(Values) of either list is one example's values (planerel's
       learner with set(lazy_examples, true)): it counts as one example, by
       its smallest value for lteq and its largest for gteq (the example is
       covered when some answer passes the threshold).
       With planerel's learner and set(lazy_band, true), gteq offers a
       second cut-off: the lower edge of a band.  A band on a measure
       (gteq then lteq: the bottom clause holds gteq first) has its lower
       edge chosen alone, on each example's largest value, before the upper
       edge exists, and the upper edge is then chosen above it; the pair is
       not the best band.  One step of coordinate ascent gives a better
       lower edge: the upper edge the first cut-off would get (lteq on the
       values at or above it), then the best lower edge for the values at
       or below that (each example by its largest value there).  When it
       differs from the first cut-off, gteq has two solutions, the first
       cut-off and this one (the learner makes a refinement for each).
       With planerel's learner and set(cutoff_slack, K) (a number >= 0;
       default off: the cut-off above), the best cut-off is then moved
       outwards to the loosest positive value whose cut-off scores within K
       standard deviations of the best: the examples it adds (dP
       positives, dN negatives: the score falls by dN - dP) satisfy
       dN - dP =< K * sqrt(dP + dN) (the "one standard error" rule for
       K = 1).  K = 0 keeps the score and breaks a tie towards the looser
       cut-off (more positives kept) instead of the tighter one.  A cut-off
       placed where the training examples barely prefer it (a rise band's
       edge among a few negatives) is then not placed inside the positives'
       range (docs/learner.md, "cutoff_slack").

    Written for planerel; no code is taken from Aleph.
*/

lteq([Pos, Neg], T) :- !,
    planerel_cutoff(le, Pos, Neg, T).
lteq(X, T) :-
    number(X),
    (   var(T)
    ->  T = X
    ;   number(T),
        X =< T
    ).

gteq([Pos, Neg], T) :- !,
    planerel_cutoff(ge, Pos, Neg, T1),
    (   planerel_band_on,
        planerel_band_lower(T1, Pos, Neg, T2),
        T2 =\= T1
    ->  ( T = T1 ; T = T2 )
    ;   T = T1
    ).
gteq(X, T) :-
    number(X),
    (   var(T)
    ->  T = X
    ;   number(T),
        X >= T
    ).

%   planerel_cutoff(+Dir, +Pos, +Neg, -T)
%   Dir = le: examples kept are those =< T; Dir = ge: those >= T.
planerel_cutoff(Dir, Pos00, Neg00, T) :-
    planerel_per_example(Pos00, Dir, Pos0),
    planerel_per_example(Neg00, Dir, Neg0),
    planerel_numbers(Pos0, Pos),
    planerel_numbers(Neg0, Neg),
    Pos \== [],
    msort(Pos, PosSorted),
    msort(Neg, NegSorted),
    planerel_dedup(PosSorted, PosValues), % distinct values, ascending (sort/2)
    planerel_best(Dir, PosValues, PosSorted, NegSorted, Best0),
    planerel_loosen(Dir, Best0, PosValues, PosSorted, NegSorted, Best),
    planerel_neighbour(Dir, Best, PosSorted, NegSorted, Next),
    planerel_between(Dir, Best, Next, PosSorted, NegSorted, T).

% planerel_per_example(+List, +Dir, -Values): ex(Vs) -> the value of Vs that
% decides whether the example passes (le: the smallest, ge: the largest);
% anything else as it is
planerel_per_example([], _, []).
planerel_per_example([X|Xs], Dir, [Y|Ys]) :-
    (   nonvar(X), X = ex(Vs0)
    ->  planerel_numbers(Vs0, Vs),
        (   Vs == []
        ->  Y = none
        ;   Dir == le
        ->  min_list(Vs, Y)
        ;   max_list(Vs, Y)
        )
    ;   Y = X
    ),
    planerel_per_example(Xs, Dir, Ys).

% the numbers of a list, in order (include(number, ...) without a call per element)
planerel_numbers([], []).
planerel_numbers([X|Xs], L) :-
    (   number(X)
    ->  L = [X|L1]
    ;   L = L1
    ),
    planerel_numbers(Xs, L1).

% planerel_dedup(+Sorted, -Set): the msort/2-ed list without repeats (== ), as sort/2
planerel_dedup([], []).
planerel_dedup([X|Xs], [X|Ys]) :-
    planerel_dedup_(Xs, X, Ys).

planerel_dedup_([], _, []).
planerel_dedup_([X|Xs], P, Ys) :-
    (   X == P
    ->  planerel_dedup_(Xs, P, Ys)
    ;   Ys = [X|Ys1],
        planerel_dedup_(Xs, X, Ys1)
    ).

% planerel_skip_le(+Sorted, +V, +K0, -Rest, -K): skip the leading X =< V of the
% ascending list Sorted, counting them from K0 (planerel_skip_lt/5: X < V)
planerel_skip_le([X|Xs], V, K0, S, K) :-
    X =< V, !,
    K1 is K0 + 1,
    planerel_skip_le(Xs, V, K1, S, K).
planerel_skip_le(S, _, K, S, K).

planerel_skip_lt([X|Xs], V, K0, S, K) :-
    X < V, !,
    K1 is K0 + 1,
    planerel_skip_lt(Xs, V, K1, S, K).
planerel_skip_lt(S, _, K, S, K).

% planerel_best(+Dir, +Values, +PosSorted, +NegSorted, -Best): the value V of
% the ascending Values whose Score-NegKept-V is the largest in the standard
% order (Score = positives kept - negatives kept, NegKept = - negatives kept;
% le: kept =< V, ge: kept >= V), the counts made in one sweep over both
% sorted lists (each value's counts and the largest term, in one pass)
planerel_best(le, [V|Vs], PS0, NS0, Best) :-
    planerel_skip_le(PS0, V, 0, PS, P),
    planerel_skip_le(NS0, V, 0, NS, N),
    Score is P - N, NegKept is -N,
    planerel_best_le(Vs, PS, P, NS, N, Score-NegKept-V, Best).
planerel_best(ge, Vs, PS, NS, Best) :-
    length(PS, NP),
    length(NS, NN),
    planerel_best_ge(Vs, PS, 0, NS, 0, NP, NN, none, Best).

planerel_best_le([], _, _, _, _, _-_-Best, Best).
planerel_best_le([V|Vs], PS0, P0, NS0, N0, B0, Best) :-
    planerel_skip_le(PS0, V, P0, PS, P),
    planerel_skip_le(NS0, V, N0, NS, N),
    Score is P - N, NegKept is -N,
    C = Score-NegKept-V,
    ( C @> B0 -> B1 = C ; B1 = B0 ),
    planerel_best_le(Vs, PS, P, NS, N, B1, Best).

planerel_best_ge([], _, _, _, _, _, _, _-_-Best, Best).
planerel_best_ge([V|Vs], PS0, BP0, NS0, BN0, NP, NN, B0, Best) :-
    planerel_skip_lt(PS0, V, BP0, PS, BP),
    planerel_skip_lt(NS0, V, BN0, NS, BN),
    N is NN - BN,
    Score is NP - BP - N, NegKept is -N,
    C = Score-NegKept-V,
    ( B0 == none -> B1 = C ; C @> B0 -> B1 = C ; B1 = B0 ),
    planerel_best_ge(Vs, PS, BP, NS, BN, NP, NN, B1, Best).

% planerel_band_on: planerel's learner's setting lazy_band is true (fails under
% any other learner)
planerel_band_on :-
    catch(planerel_learner:setting(lazy_band, true), _, fail).

% planerel_band_lower(+T1, +Pos, +Neg, -T): the lower edge of a band whose upper
% edge is the le cut-off of the values at or above T1 (the comment at the top)
planerel_band_lower(T1, Pos, Neg, T) :-
    planerel_keep(ge, T1, Pos, PosA),
    planerel_keep(ge, T1, Neg, NegA),
    planerel_cutoff(le, PosA, NegA, U),
    planerel_keep(le, U, Pos, PosB),
    planerel_keep(le, U, Neg, NegB),
    planerel_cutoff(ge, PosB, NegB, T).

% planerel_keep(+Dir, +T, +List, -Kept): each example's values =< T (le) or >=
% T (ge), as ex(Values); an example with none is left out (a number is an
% example of one value)
planerel_keep(_, _, [], []).
planerel_keep(Dir, T, [X|Xs], Kept) :-
    (   nonvar(X), X = ex(Vs0)
    ->  planerel_numbers(Vs0, Vs)
    ;   number(X)
    ->  Vs = [X]
    ;   Vs = []
    ),
    planerel_keep_values(Dir, T, Vs, Ks),
    (   Ks == []
    ->  Kept = Kept1
    ;   Kept = [ex(Ks)|Kept1]
    ),
    planerel_keep(Dir, T, Xs, Kept1).

planerel_keep_values(_, _, [], []).
planerel_keep_values(Dir, T, [V|Vs], Ks) :-
    (   ( Dir == le -> V =< T ; V >= T )
    ->  Ks = [V|Ks1]
    ;   Ks = Ks1
    ),
    planerel_keep_values(Dir, T, Vs, Ks1).

% planerel_slack(-K): planerel's learner's setting cutoff_slack, when it is a
% number (fails when it is off, and under any other learner)
planerel_slack(K) :-
    catch(planerel_learner:setting(cutoff_slack, K), _, fail),
    number(K).

% planerel_loosen(+Dir, +Best0, +Values, +PosSorted, +NegSorted, -Best): the
% loosest positive value whose cut-off scores within K standard deviations of
% Best0's (the comment at the top); Best0 itself without cutoff_slack.  ge is le on the negated values.
planerel_loosen(Dir, Best0, PV, PS, NS, Best) :-
    (   planerel_slack(K)
    ->  (   Dir == le
        ->  planerel_loosen_le(Best0, PV, PS, NS, K, Best)
        ;   planerel_negated(PV, PVn),
            planerel_negated(PS, PSn),
            planerel_negated(NS, NSn),
            B0n is -Best0,
            planerel_loosen_le(B0n, PVn, PSn, NSn, K, Bn),
            Best is -Bn
        )
    ;   Best = Best0
    ).

% the negated values of an ascending list, ascending
planerel_negated(L, N) :-
    planerel_negated_(L, [], N).
planerel_negated_([], Acc, Acc).
planerel_negated_([X|Xs], Acc, N) :-
    Y is -X,
    planerel_negated_(Xs, [Y|Acc], N).

planerel_loosen_le(B0, PV, PS0, NS0, K, Best) :-
    planerel_skip_le(PS0, B0, 0, PS, P0),
    planerel_skip_le(NS0, B0, 0, NS, N0),
    planerel_after(PV, B0, Cands),
    planerel_loosen_walk(Cands, PS, P0, NS, N0, P0, N0, K, B0, Best).

% the values of an ascending list above V
planerel_after([], _, []).
planerel_after([X|Xs], V, L) :-
    (   X > V
    ->  L = [X|Xs]
    ;   planerel_after(Xs, V, L)
    ).

planerel_loosen_walk([], _, _, _, _, _, _, _, Best, Best).
planerel_loosen_walk([V|Vs], PS0, P1, NS0, N1, P0, N0, K, Acc, Best) :-
    planerel_skip_le(PS0, V, P1, PS, P),
    planerel_skip_le(NS0, V, N1, NS, N),
    DP is P - P0,
    DN is N - N0,
    (   DN - DP =< K * sqrt(DP + DN)
    ->  Acc1 = V
    ;   Acc1 = Acc
    ),
    planerel_loosen_walk(Vs, PS, P, NS, N, P0, N0, K, Acc1, Best).

% the next value beyond Best in the direction that is cut off (none: Best
% itself): of all the values (both sorted lists), the first above Best (le) or
% the last below it (ge) in the standard order, as in their sort/2-ed union
planerel_neighbour(le, Best, PS, NS, Next) :-
    (   planerel_first_above(PS, Best, X1)
    ->  (   planerel_first_above(NS, Best, X2)
        ->  ( X2 @< X1 -> Next = X2 ; Next = X1 )
        ;   Next = X1
        )
    ;   planerel_first_above(NS, Best, X2)
    ->  Next = X2
    ;   Next = Best
    ).
planerel_neighbour(ge, Best, PS, NS, Next) :-
    planerel_last_below(PS, Best, none, X1),
    planerel_last_below(NS, Best, none, X2),
    (   X1 == none
    ->  ( X2 == none -> Next = Best ; Next = X2 )
    ;   X2 == none
    ->  Next = X1
    ;   ( X2 @> X1 -> Next = X2 ; Next = X1 )
    ).

planerel_first_above([X|Xs], Best, Y) :-
    (   X > Best
    ->  Y = X
    ;   planerel_first_above(Xs, Best, Y)
    ).

% the last X < Best of an ascending list (Acc when none)
planerel_last_below([], _, Acc, Acc).
planerel_last_below([X|Xs], Best, Acc, Y) :-
    (   X < Best
    ->  planerel_last_below(Xs, Best, X, Y)
    ;   Y = Acc                          % ascending: no later X is below
    ).

planerel_between(_, Best, _, PS, NS, Best) :-
    planerel_all_integers(PS),
    planerel_all_integers(NS), !.
planerel_between(_, Best, Best, _, _, Best) :- !.
planerel_between(Dir, Best, Next, _, _, T) :-
    Mid is (Best + Next) / 2,
    (   between(0, 6, D),
        Scale is 10.0 ** D,
        T0 is round(Mid * Scale) / Scale,
        planerel_inside(Dir, Best, Next, T0)
    ->  T = T0
    ;   T is float(Mid)
    ).

planerel_all_integers([]).
planerel_all_integers([X|Xs]) :- integer(X), planerel_all_integers(Xs).

planerel_inside(le, Best, Next, T) :- T > Best, T < Next.
planerel_inside(ge, Best, Next, T) :- T < Best, T > Next.
