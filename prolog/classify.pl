/*  planerel: classify objects with learned rules and explain the answer.

    A model file (rules.pl) holds learned clauses whose head is either
    class(Obj, Class) (one multi-class task) or Class(Obj) (one task per
    class), plus optional statistics facts

        planerel_rule_stats(Index, Class, TruePositives, FalsePositives).

    Index counts the model's clauses from 1 in file order.  planerel_load_model/1
    records every clause with its variable names, so that planerel_explain/5
    can say which planes a rule bound; consult the model file as well to have
    the rules and their statistics as ordinary Prolog.

    Written for planerel.
*/

:- dynamic planerel_rule/6.          % Index, Class, Obj, Head, Body, VarNames
:- dynamic planerel_rule_stats/4.    % Index, Class, TP, FP (defined by the model file)
:- multifile planerel_rule_stats/4.

%   planerel_load_model(+File)
%   Forget any earlier model, then read File's clauses with their variable
%   names.  Syntax errors raise an exception naming file and line.
planerel_load_model(File) :-
    retractall(planerel_rule(_, _, _, _, _, _)),
    setup_call_cleanup(
        open(File, read, In),
        planerel_read_model(In, 1),
        close(In)).

planerel_read_model(In, I) :-
    read_term(In, Term, [variable_names(Names), syntax_errors(error)]),
    (   Term == end_of_file
    ->  true
    ;   planerel_add_model_term(Term, Names, I, I1),
        planerel_read_model(In, I1)
    ).

planerel_add_model_term(planerel_rule_stats(_, _, _, _), _, I, I) :- !.
planerel_add_model_term((:- _), _, I, I) :- !.
planerel_add_model_term((Head :- Body), Names, I, I1) :- !,
    planerel_head_class(Head, Obj, Class),
    assertz(planerel_rule(I, Class, Obj, Head, Body, Names)),
    I1 is I + 1.
planerel_add_model_term(Head, Names, I, I1) :-
    planerel_head_class(Head, Obj, Class),
    assertz(planerel_rule(I, Class, Obj, Head, true, Names)),
    I1 is I + 1.

planerel_head_class(class(Obj, Class), Obj, Class) :- atom(Class), !.
planerel_head_class(Head, Obj, Class) :-
    compound(Head),
    Head =.. [Class, Obj], !.
planerel_head_class(Head, _, _) :-
    throw(error(domain_error(planerel_rule_head, Head), _)).

%   planerel_explain(+Obj, -Class, -Index, -Bindings, -Text)
%   Some rule of the model proves that Obj is a Class.  Bindings is the list
%   of Name-Value pairs of the rule's variables in the first proof (Values
%   written as atoms), Text the clause as written, with its variable names.
planerel_explain(Obj, Class, Index, Bindings, Text) :-
    planerel_rule(Index, Class, Obj0, _, Body0, Names0),
    copy_term(t(Obj0, Body0, Names0), t(Obj, Body, Names)),
    planerel_rule_text(Index, Text),
    catch(once(call(Body)), E, (print_message(warning, E), fail)),
    findall(N-VA,
            ( member(N=V, Names), ground(V), format(atom(VA), '~w', [V]) ),
            Bindings).

planerel_rule_text(Index, Text) :-
    planerel_rule(Index, _, _, Head, Body, Names),
    copy_term(t(Head, Body, Names), t(H, B, Ns)),
    maplist([N=V]>>(V = '$VAR'(N)), Ns),
    (   B == true
    ->  format(atom(Text), '~W.', [H, [quoted(true), numbervars(true)]])
    ;   format(atom(Text), '~W :- ~W.', [H, [quoted(true), numbervars(true)],
                                         B, [quoted(true), numbervars(true)]])
    ).

%   planerel_classes(-Classes): the classes the model has rules for.
planerel_classes(Classes) :-
    findall(C, planerel_rule(_, C, _, _, _, _), Cs),
    sort(Cs, Classes).

%   planerel_explain_text(+Obj, -Class, -Index, -Bindings, -Text)
%   As planerel_explain/5, with Bindings as one atom of "Name\tValue" lines
%   (for callers that read answers as text, such as pyswip).
planerel_explain_text(Obj, Class, Index, BindingsText, Text) :-
    planerel_explain(Obj, Class, Index, Bindings, Text),
    findall(Line, ( member(N-V, Bindings), format(atom(Line), '~w\t~w', [N, V]) ), Lines),
    atomic_list_concat(Lines, '\n', BindingsText).
