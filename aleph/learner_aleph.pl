/*  Driver that runs the real Aleph for planerel.ilp.learn (engine "aleph").

    Usage:
        swipl learner_aleph.pl -- classic /path/to/aleph_orig.pl STEM RULES [NAME=VALUE ...]
        swipl learner_aleph.pl -- module  /path/to/aleph.pl      STEM RULES [NAME=VALUE ...]
        swipl learner_aleph.pl -- module  library                STEM RULES [NAME=VALUE ...]

    classic  a single-file Aleph that defines everything in module user
             (Aleph 5 and its SWI-Prolog port aleph_orig.pl): read_all/1,
             set/2, induce/0 are called in user.
    module   the SWI-Prolog pack's module file (module aleph, from a path or
             as library(aleph)): the problem's data live in user, Aleph's
             predicates take that module as an extra argument (set/3,
             read_all(user:Stem), induce(user:Program)); STEM.b's directives
             set/2 and determination/2, which the module does not export, are
             defined in user as calls to it.

    This file is the module planerel_aleph_driver, so nothing it defines
    meets a predicate of Aleph or of the problem in user.  After induce the
    theory is taken from Aleph's own store (the clauses write_rules/1 would
    print), not from printed text, so Aleph's portray_literals setting
    (English output) changes nothing.  The theory is written to RULES,
    asserted into the module planerel_theory (which sees user's background)
    and scored on the examples here, so that both engines report the same
    machine-readable summary (@@ lines).
    Written for planerel; contains nothing of Aleph's source.
*/

:- module(planerel_aleph_driver, []).

:- initialization(main, main).

:- dynamic theory_rule/1.

main :-
    current_prolog_flag(argv, Argv),
    (   catch(run(Argv), E, report_error(E))
    ->  halt(0)
    ;   format(user_error, "error: the Aleph driver failed (see Aleph's output above)~n", []),
        halt(3)
    ).

run([Kind, Path, Stem, Rules|Sets]) :-
    memberchk(Kind, [classic, module]), !,
    load_aleph(Kind, Path),
    read_problem(Kind, Stem),
    forall(member(S, Sets), apply_setting(Kind, S)),
    learn(Kind),
    collect_theory(Kind),
    write_theory(Rules),
    summary(Kind, Stem).
run(_) :-
    throw(planerel_input_error("usage: swipl learner_aleph.pl -- classic|module PATH STEM RULES [NAME=VALUE ...]")).

%   load_aleph(+Kind, +Path)
load_aleph(_, Path) :-
    Path \== library,
    \+ exists_file(Path), !,
    format(string(S), "PLANEREL_ALEPH=~w: file not found", [Path]),
    throw(planerel_input_error(S)).
load_aleph(classic, Path) :-
    user:consult(Path).
load_aleph(module, library) :- !,
    user:use_module(library(aleph)).
load_aleph(module, Path) :-
    user:use_module(Path).

%   read_problem(+Kind, +Stem): STEM.b, STEM.f, STEM.n into user.
read_problem(classic, Stem) :-
    user:read_all(Stem).
read_problem(module, Stem) :-
    (   current_predicate(user:set/2) -> true
    ;   user:assertz((set(N, V) :- aleph:set(N, V, user)))
    ),
    (   current_predicate(user:determination/2) -> true
    ;   user:assertz((determination(P, Q) :- aleph:determination(P, Q, user)))
    ),
    aleph:read_all(user:Stem).

aleph_set(classic, Name, Value) :- user:set(Name, Value).
aleph_set(module, Name, Value)  :- aleph:set(Name, Value, user).

aleph_setting(classic, Name, Value) :- user:setting(Name, Value).
aleph_setting(module, Name, Value)  :- aleph:setting(Name, Value, user).

apply_setting(Kind, Text) :-
    (   sub_atom(Text, B, _, A, '=')
    ->  sub_atom(Text, 0, B, _, Name),
        sub_atom(Text, _, A, 0, VText),
        (   memberchk(Name, [test_pos, test_neg])
        ->  Value = VText
        ;   catch(term_string(T, VText), _, fail), atomic(T)
        ->  Value = T
        ;   Value = VText
        ),
        aleph_set(Kind, Name, Value)
    ;   format(string(S), "--set ~w: expected NAME=VALUE", [Text]),
        throw(planerel_input_error(S))
    ).

%   induce fails in the module file when no positive example is left to cover
%   (and in either when a problem has none): the theory is then empty.
%   Float division by zero gives infinity and 0/0 NaN rather than an error:
%   Aleph's clause-length check (maxlength_neg_ok/4) computes P/(P+N) for a
%   clause covering no example at all, and with minacc set that 0/0 stopped
%   the whole run (make demo's box task, samplesize 8).  NaN < MinAcc is
%   false, so such a clause is judged by its negatives alone, as a clause
%   covering nothing can be; a run that divides by no zero is unchanged.
learn(Kind) :-
    set_prolog_flag(float_zero_div, infinity),
    set_prolog_flag(float_undefined, nan),
    induce(Kind).

induce(classic) :- ( user:induce -> true ; true ).
induce(module)  :- ( aleph:induce(user:_) -> true ; true ).

%   collect_theory(+Kind): the clauses of the theory, in the order Aleph
%   found them, from the store Aleph's write_rules/1 prints from
%   ('$aleph_global'(rules, rules(Ids)), newest first, and
%   '$aleph_global'(theory, theory(Id, _, Clause, _, _))).
%   A classic-style file without that store (an Aleph-compatible learner)
%   is asked for its rules with write_rules/1, and the file is read back.
collect_theory(Kind) :-
    retractall(theory_rule(_)),
    (   current_predicate(user:'$aleph_global'/2)
    ->  (   user:'$aleph_global'(rules, rules(Ids0))
        ->  reverse(Ids0, Ids)
        ;   Ids = []
        ),
        forall(( member(Id, Ids),
                 user:'$aleph_global'(theory, theory(Id, _, Clause, _, _)) ),
               add_rule(Clause))
    ;   Kind == classic
    ->  tmp_file(rules, File),
        user:write_rules(File),
        setup_call_cleanup(open(File, read, S), read_rules(S), close(S)),
        delete_file(File)
    ;   true
    ),
    forall(theory_rule(C), assertz(planerel_theory:C)).

add_rule((H :- true)) :- !, assertz(theory_rule(H)).
add_rule(C) :- assertz(theory_rule(C)).

read_rules(S) :-
    read_term(S, T, []),
    (   T == end_of_file
    ->  true
    ;   (   T = (:- _) -> true ; add_rule(T) ),
        read_rules(S)
    ).

write_theory(File) :-
    setup_call_cleanup(open(File, write, S),
                       forall(theory_rule(C), portray_clause(S, C)),
                       close(S)).

%   An example is covered when the theory proves it (depth-limited, so a
%   left-recursive theory cannot loop).  planerel_theory imports from user,
%   where the background is.
covered(E) :-
    catch(call_with_depth_limit(planerel_theory:E, 10000, R), _, fail),
    R \== depth_exceeded,
    !.

example_file(File, Es) :-
    (   exists_file(File)
    ->  setup_call_cleanup(open(File, read, S), example_terms(S, Es), close(S))
    ;   Es = []
    ).

example_terms(S, Es) :-
    read_term(S, T, []),
    (   T == end_of_file
    ->  Es = []
    ;   T = (:- _)
    ->  example_terms(S, Es)
    ;   Es = [T|Es1],
        example_terms(S, Es1)
    ).

confusion(PosFile, NegFile, TP, FN, FP, TN) :-
    example_file(PosFile, Ps),
    example_file(NegFile, Ns),
    declare_targets(Ps), declare_targets(Ns),
    aggregate_all(count, (member(E, Ps), covered(E)), TP),
    length(Ps, NP), FN is NP - TP,
    aggregate_all(count, (member(E, Ns), covered(E)), FP),
    length(Ns, NN), TN is NN - FP.

%   A target with no learned clause fails instead of raising.
declare_targets(Es) :-
    forall(( member(E, Es), functor(E, F, A) ),
           (   current_predicate(planerel_theory:F/A)
           ->  true
           ;   dynamic(planerel_theory:F/A)
           )).

summary(Kind, Stem) :-
    format("@@begin~n@@engine aleph~n", []),
    forall(theory_rule(R),
           (   (   R = (H :- B) -> rule_text(H, B, T) ; rule_text(R, true, T) ),
               format("@@rule ~s~n", [T])
           )),
    atom_concat(Stem, '.f', F), atom_concat(Stem, '.n', N),
    confusion(F, N, TP, FN, FP, TN),
    format("@@train ~w ~w ~w ~w~n", [TP, FN, FP, TN]),
    (   test_file(Kind, test_pos, TPF) -> true ; TPF = none ),
    (   test_file(Kind, test_neg, TNF) -> true ; TNF = none ),
    (   ( TPF \== none ; TNF \== none )
    ->  confusion(TPF, TNF, A, B1, C, D),
        format("@@test ~w ~w ~w ~w~n", [A, B1, C, D])
    ;   true
    ),
    format("@@end~n", []).

test_file(Kind, Name, File) :-
    catch(aleph_setting(Kind, Name, File0), _, fail),
    atom(File0), File0 \== '', File0 \== none, File0 \== false,
    File = File0.

rule_text(H, B, Text) :-
    copy_term(H-B, H1-B1),
    numbervars(H1-B1, 0, _),
    Opts = [quoted(true), numbervars(true), spacing(standard)],
    (   B1 == true
    ->  format(string(Text), "~W.", [H1, Opts])
    ;   conj_list(B1, Ls),
        maplist(literal_text(Opts), Ls, LTs),
        atomic_list_concat(LTs, ', ', BT),
        format(string(Text), "~W :- ~w.", [H1, Opts, BT])
    ).

literal_text(Opts, L, T) :- format(string(T), "~W", [L, Opts]).

conj_list((A, B), [A|Ls]) :- !, conj_list(B, Ls).
conj_list(A, [A]).

report_error(planerel_input_error(Text)) :- !,
    format(user_error, "error: ~s~n", [Text]),
    halt(2).
report_error(E) :-
    (   catch(message_to_codes(E, _, Codes), _, fail)
    ->  string_codes(T, Codes)
    ;   format(string(T), "~q", [E])
    ),
    format(user_error, "error: ~s~n", [T]),
    halt(3).
