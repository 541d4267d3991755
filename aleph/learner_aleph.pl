/*  Driver that runs the real Aleph for planerel.learn (engine "aleph").

    Usage:
        swipl learner_aleph.pl -- file  /path/to/aleph.pl STEM RULES [NAME=VALUE ...]
        swipl learner_aleph.pl -- pack  -                 STEM RULES [NAME=VALUE ...]

    "file" consults a classic single-file Aleph (everything in module user);
    "pack" loads the SWI-Prolog pack library(aleph), whose module does not
    export set/2, read_all/1 or induce/0, so they are called module-qualified.
    After induce the theory is written with Aleph's write_rules/1, read back
    into the module planerel_theory, and scored on the examples by this file
    (Aleph's own printed confusion matrix is left as it is), so that both
    engines report the same machine-readable summary (@@ lines).
    Written for planerel; contains nothing of Aleph's source.
*/

:- initialization(planerel_aleph_main, main).

planerel_aleph_main :-
    current_prolog_flag(argv, Argv),
    catch(aleph_main(Argv), E, aleph_error(E)),
    halt(0).

aleph_main([Kind, Path, Stem, Rules|Sets]) :- !,
    load_aleph(Kind, Path, M),
    M:read_all(Stem),
    forall(member(S, Sets), apply_setting(M, S)),
    M:induce,
    M:write_rules(Rules),
    load_theory(Rules),
    summary(M, Stem).
aleph_main(_) :-
    throw(planerel_input_error("usage: swipl learner_aleph.pl -- file|pack PATH STEM RULES [NAME=VALUE ...]")).

load_aleph(file, Path, user) :- !,
    (   exists_file(Path)
    ->  user:consult(Path)
    ;   format(string(S), "PLANEREL_ALEPH=~w: file not found", [Path]),
        throw(planerel_input_error(S))
    ).
load_aleph(pack, _, aleph) :-
    user:use_module(library(aleph)),
    (   catch(aleph:aleph, _, true) -> true ; true ).

apply_setting(M, Text) :-
    (   sub_atom(Text, B, _, A, '=')
    ->  sub_atom(Text, 0, B, _, Name),
        sub_atom(Text, _, A, 0, VText),
        (   memberchk(Name, [test_pos, test_neg])
        ->  Value = VText
        ;   catch(term_string(T, VText), _, fail), atomic(T)
        ->  Value = T
        ;   Value = VText
        ),
        M:set(Name, Value)
    ;   format(string(S), "--set ~w: expected NAME=VALUE", [Text]),
        throw(planerel_input_error(S))
    ).

:- dynamic planerel_theory:'$planerel_none'/0.
:- dynamic planerel_rule/1.

load_theory(File) :-
    setup_call_cleanup(open(File, read, S),
                       read_rules(S),
                       close(S)).

read_rules(S) :-
    read_term(S, T, []),
    (   T == end_of_file
    ->  true
    ;   (   T = (:- _)
        ->  true
        ;   assertz(planerel_theory:T),
            assertz(planerel_rule(T))
        ),
        read_rules(S)
    ).

%   An example is covered when the theory proves it (depth-limited, so a
%   left-recursive theory cannot loop).  Background predicates are found in
%   user (and in aleph for the pack).
covered(E) :-
    catch(call_with_depth_limit(planerel_theory:E, 10000, R), _, fail),
    R \== depth_exceeded,
    !.

examples(File, Es) :-
    (   exists_file(File)
    ->  setup_call_cleanup(open(File, read, S), read_examples(S, Es), close(S))
    ;   Es = []
    ).

read_examples(S, Es) :-
    read_term(S, T, []),
    (   T == end_of_file
    ->  Es = []
    ;   T = (:- _)
    ->  read_examples(S, Es)
    ;   Es = [T|Es1],
        read_examples(S, Es1)
    ).

confusion(PosFile, NegFile, TP, FN, FP, TN) :-
    examples(PosFile, Ps),
    examples(NegFile, Ns),
    prepare(Ps), prepare(Ns),
    aggregate_all(count, (member(E, Ps), covered(E)), TP),
    length(Ps, NP), FN is NP - TP,
    aggregate_all(count, (member(E, Ns), covered(E)), FP),
    length(Ns, NN), TN is NN - FP.

prepare(Es) :-
    forall(( member(E, Es), functor(E, F, A) ),
           (   current_predicate(planerel_theory:F/A)
           ->  true
           ;   dynamic(planerel_theory:F/A)
           )),
    (   current_module(aleph)
    ->  add_import_module(planerel_theory, aleph, end)
    ;   true
    ).

summary(M, Stem) :-
    format("@@begin~n@@engine aleph~n", []),
    forall(planerel_rule(R),
           (   (   R = (H :- B) -> rule_text(H, B, T) ; rule_text(R, true, T) ),
               format("@@rule ~s~n", [T])
           )),
    atom_concat(Stem, '.f', F), atom_concat(Stem, '.n', N),
    confusion(F, N, TP, FN, FP, TN),
    format("@@train ~w ~w ~w ~w~n", [TP, FN, FP, TN]),
    (   test_file(M, test_pos, TPF) -> true ; TPF = none ),
    (   test_file(M, test_neg, TNF) -> true ; TNF = none ),
    (   ( TPF \== none ; TNF \== none )
    ->  confusion(TPF, TNF, A, B1, C, D),
        format("@@test ~w ~w ~w ~w~n", [A, B1, C, D])
    ;   true
    ),
    format("@@end~n", []).

test_file(M, Name, File) :-
    catch(M:setting(Name, File0), _, fail),
    atom(File0), File0 \== '', File0 \== none, File0 \== false,
    File = File0.

rule_text(H, B, Text) :-
    copy_term(H-B, H1-B1),
    numbervars(H1-B1, 0, _),
    Opts = [quoted(true), numbervars(true), spacing(standard)],
    (   B1 == true
    ->  format(string(Text), "~W.", [H1, Opts])
    ;   conj_list(B1, Ls),
        maplist([L, LT]>>format(string(LT), "~W", [L, Opts]), Ls, LTs),
        atomic_list_concat(LTs, ', ', BT),
        format(string(Text), "~W :- ~w.", [H1, Opts, BT])
    ).

conj_list((A, B), [A|Ls]) :- !, conj_list(B, Ls).
conj_list(A, [A]).

aleph_error(planerel_input_error(Text)) :- !,
    format(user_error, "error: ~s~n", [Text]),
    halt(2).
aleph_error(E) :-
    (   catch(message_to_codes(E, _, Codes), _, fail)
    ->  string_codes(T, Codes)
    ;   format(string(T), "~q", [E])
    ),
    format(user_error, "error: ~s~n", [T]),
    halt(3).
