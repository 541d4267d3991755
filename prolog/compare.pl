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
    planerel_cutoff(ge, Pos, Neg, T).
gteq(X, T) :-
    number(X),
    (   var(T)
    ->  T = X
    ;   number(T),
        X >= T
    ).

%   planerel_cutoff(+Dir, +Pos, +Neg, -T)
%   Dir = le: examples kept are those =< T; Dir = ge: those >= T.
planerel_cutoff(Dir, Pos0, Neg0, T) :-
    include(number, Pos0, Pos),
    include(number, Neg0, Neg),
    Pos \== [],
    append(Pos, Neg, All0),
    sort(All0, All),                      % distinct values, ascending
    sort(Pos, PosValues),
    msort(Pos, PosSorted),
    msort(Neg, NegSorted),
    planerel_counts(Dir, PosValues, PosSorted, PCounts),
    planerel_counts(Dir, PosValues, NegSorted, NCounts),
    planerel_scored(PosValues, PCounts, NCounts, Scored),
    max_member(_-_-Best, Scored),
    planerel_neighbour(Dir, Best, All, Next),
    planerel_between(Dir, Best, Next, All, T).

%   planerel_counts(+Dir, +Values, +Sorted, -Counts): for each of the
%   ascending Values, how many of the ascending list Sorted are kept
%   (le: =< V; ge: >= V), in one sweep.
planerel_counts(le, Vs, Sorted, Counts) :-
    planerel_sweep_le(Vs, Sorted, 0, Counts).
planerel_counts(ge, Vs, Sorted, Counts) :-
    length(Sorted, N),
    planerel_sweep_lt(Vs, Sorted, 0, Below),
    planerel_rest(Below, N, Counts).

% the sweep with =< (le) and < (ge), without a call/3 per value
planerel_sweep_le([], _, _, []).
planerel_sweep_le([V|Vs], S0, K0, [K|Ks]) :-
    planerel_skip_le(S0, V, K0, S, K),
    planerel_sweep_le(Vs, S, K, Ks).

planerel_skip_le([X|Xs], V, K0, S, K) :-
    X =< V, !,
    K1 is K0 + 1,
    planerel_skip_le(Xs, V, K1, S, K).
planerel_skip_le(S, _, K, S, K).

planerel_sweep_lt([], _, _, []).
planerel_sweep_lt([V|Vs], S0, K0, [K|Ks]) :-
    planerel_skip_lt(S0, V, K0, S, K),
    planerel_sweep_lt(Vs, S, K, Ks).

planerel_skip_lt([X|Xs], V, K0, S, K) :-
    X < V, !,
    K1 is K0 + 1,
    planerel_skip_lt(Xs, V, K1, S, K).
planerel_skip_lt(S, _, K, S, K).

% planerel_rest(+Below, +N, -Counts): N - B for each B (a plain loop: a lambda
% would be copied once per value)
planerel_rest([], _, []).
planerel_rest([B|Bs], N, [C|Cs]) :-
    C is N - B,
    planerel_rest(Bs, N, Cs).

planerel_scored([], [], [], []).
planerel_scored([V|Vs], [P|Ps], [N|Ns], [Score-NegKept-V|T]) :-
    Score is P - N,
    NegKept is -N,
    planerel_scored(Vs, Ps, Ns, T).

% the next value beyond Best in the direction that is cut off (none: Best itself)
planerel_neighbour(le, Best, All, Next) :-
    (   member(X, All), X > Best -> Next = X ; Next = Best ).
planerel_neighbour(ge, Best, All, Next) :-
    reverse(All, Desc),
    (   member(X, Desc), X < Best -> Next = X ; Next = Best ).

planerel_between(_, Best, _, All, Best) :-
    forall(member(X, All), integer(X)), !.
planerel_between(_, Best, Best, _, Best) :- !.
planerel_between(Dir, Best, Next, _, T) :-
    Mid is (Best + Next) / 2,
    (   between(0, 6, D),
        Scale is 10.0 ** D,
        T0 is round(Mid * Scale) / Scale,
        planerel_inside(Dir, Best, Next, T0)
    ->  T = T0
    ;   T is float(Mid)
    ).

planerel_inside(le, Best, Next, T) :- T > Best, T < Next.
planerel_inside(ge, Best, Next, T) :- T < Best, T > Next.
