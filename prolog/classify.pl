/*  planerel: classify objects with learned rules and explain the answer.

    A model file (rules.pl) holds learned clauses whose head is either
    class(Obj, Class) (one multi-class task) or Class(Obj) (one task per
    class), plus optional statistics facts

        planerel_rule_stats(Index, Class, TruePositives, FalsePositives).

    Index counts the model's clauses from 1 in file order.

    A model is DATA, never code: planerel_load_model/4 reads the file with
    read_term/3 (nothing in it is executed), refuses directives (except the
    three harmless declarations planerel itself writes, which are skipped),
    refuses heads that are not a class, class names that are built-in or
    library predicates or planerel's vocabulary, and bodies that call anything
    but the vocabulary, control constructs and a short list of safe built-ins
    (comparisons, arithmetic, type tests), each also checked with
    library(sandbox).  The clauses are kept as terms in the model's own
    module, so any number of models coexist in one process: each is named by
    the module the caller chooses and answers with its own rules.

    A model may come with a background file of the user's own
    (planerel_load_model/5, planerel_load_background/5): plain clauses over
    the same vocabulary and safe built-ins, read as data and checked the
    same way, then asserted into the model's module, where its rule bodies
    run (that module sees the scene facts and support predicates of user).

    Written for planerel.
*/

:- use_module(library(sandbox), [safe_goal/1]).

:- dynamic planerel_rule_stats/4.    % kept so that consulting an old model file still works
:- multifile planerel_rule_stats/4.
:- dynamic planerel_rule_cofire/4.
:- multifile planerel_rule_cofire/4.

%   planerel_load_model(+Model, +File, +Vocabulary, -Status)
%   Forget Model's earlier rules, then read File's clauses as data into
%   module Model: Model:planerel_rule(Index, Class, Obj, Head, Body, VarNames)
%   Model:planerel_stats(Index, Class, TP, FP) and
%   Model:planerel_cofire(I, J, Class, N).  Vocabulary is a list of
%   Name/Arity a rule body may call.  Status is ok, or error(Line, Message)
%   for the first clause that is refused (the model is then left empty).
planerel_load_model(Model, File, Vocabulary, Status) :-
    planerel_load_model(Model, File, none, Vocabulary, Status).

%   planerel_load_model(+Model, +File, +Background, +Vocabulary, -Status)
%   As planerel_load_model/4, after the clauses of Background (a file, or
%   none) are read into Model by planerel_load_background/5: a rule body may
%   then call the predicates it defines too.  Status is ok, error(Line,
%   Message) for File, or background_error(Line, Message) for Background
%   (the model is then left empty).
planerel_load_model(Model, File, Background, Vocabulary, Status) :-
    must_be(atom, Model),
    planerel_unload_model(Model),
    (   Background == none
    ->  Defined = [], BgStatus = ok
    ;   planerel_load_background(Model, Background, Vocabulary, Defined, BgStatus)
    ),
    (   BgStatus = error(BgLine, BgMsg)
    ->  Status = background_error(BgLine, BgMsg)
    ;   append(Vocabulary, Defined, Vocabulary1),
        catch(setup_call_cleanup(
                  open(File, read, In),
                  planerel_read_model(In, Model, Vocabulary1, 1),
                  close(In)),
              E,
              planerel_load_error(E, Status0)),
        (   var(Status0)
        ->  Status = ok
        ;   planerel_unload_model(Model),
            Status = Status0
        )
    ).

planerel_load_error(planerel_refused(Line, Msg), error(Line, Msg)) :- !.
planerel_load_error(error(syntax_error(What), Ctx), error(Line, Msg)) :- !,
    (   Ctx = stream(_, Line, _, _) -> true
    ;   Ctx = file(_, Line, _, _) -> true
    ;   Line = 0
    ),
    format(atom(Msg), 'syntax error: ~w', [What]).
planerel_load_error(E, error(0, Msg)) :-
    catch(( '$messages':translate_message(E, Lines, []),
            with_output_to(string(S), print_message_lines(current_output, '', Lines)),
            normalize_space(atom(Msg), S) ), _,
          format(atom(Msg), '~q', [E])).

%   planerel_unload_model(+Model): forget Model's rules, statistics and
%   background clauses.
planerel_unload_model(Model) :-
    retractall(Model:planerel_rule(_, _, _, _, _, _)),
    retractall(Model:planerel_stats(_, _, _, _)),
    retractall(Model:planerel_cofire(_, _, _, _)),
    dynamic(Model:planerel_bg_pred/2),       % (so that retract/1 fails, not raises, without one)
    forall(retract(Model:planerel_bg_pred(N, A)),
           ( functor(H, N, A), retractall(Model:H) )).

planerel_read_model(In, Model, Vocabulary, I) :-
    read_term(In, Term, [variable_names(Names), syntax_errors(error),
                         term_position(Pos), quasi_quotations(QQ)]),
    stream_position_data(line_count, Pos, Line),
    (   Term == end_of_file
    ->  true
    ;   (   QQ == []
        ->  true
        ;   planerel_refuse(Line, 'a quasi-quotation has no place in a model')
        ),
        planerel_add_model_term(Term, Names, Model, Vocabulary, Line, I, I1),
        planerel_read_model(In, Model, Vocabulary, I1)
    ).

planerel_refuse(Line, Format-Args) :- !,
    format(atom(Msg), Format, Args),
    throw(planerel_refused(Line, Msg)).
planerel_refuse(Line, Msg) :-
    throw(planerel_refused(Line, Msg)).

% the declarations older planerel versions wrote at the top of every model
planerel_harmless_directive(dynamic(planerel_rule_stats/4)).
planerel_harmless_directive(multifile(planerel_rule_stats/4)).
planerel_harmless_directive(dynamic(planerel_rule_cofire/4)).
planerel_harmless_directive(multifile(planerel_rule_cofire/4)).
planerel_harmless_directive(style_check(-singleton)).

planerel_add_model_term(Var, _, _, _, Line, _, _) :-
    var(Var), !,
    planerel_refuse(Line, 'a clause may not be a variable').
planerel_add_model_term((:- D), _, _, _, Line, I, I) :- !,
    (   ground(D), planerel_harmless_directive(D)
    ->  true
    ;   planerel_refuse(Line, 'directive ~W refused: a model is data (rules, planerel_rule_stats/4 and planerel_rule_cofire/4 facts), nothing in it is run'-
                        [(:- D), [quoted(true), max_depth(6)]])
    ).
planerel_add_model_term((?- D), N, M, V, Line, I, I1) :- !,
    planerel_add_model_term((:- D), N, M, V, Line, I, I1).
planerel_add_model_term(planerel_rule_stats(Ix, C, TP, FP), _, Model, _, Line, I, I) :- !,
    (   integer(Ix), atom(C), integer(TP), integer(FP)
    ->  assertz(Model:planerel_stats(Ix, C, TP, FP))
    ;   planerel_refuse(Line, 'planerel_rule_stats/4 needs an integer index, a class name and two integer counts')
    ).
planerel_add_model_term(planerel_rule_cofire(Ix, Jx, C, N), _, Model, _, Line, I, I) :- !,
    (   integer(Ix), integer(Jx), atom(C), integer(N)
    ->  assertz(Model:planerel_cofire(Ix, Jx, C, N))
    ;   planerel_refuse(Line, 'planerel_rule_cofire/4 needs two integer rule indices, a class name and an integer count')
    ).
planerel_add_model_term((Head :- Body), Names, Model, Vocabulary, Line, I, I1) :- !,
    planerel_head_class(Head, Obj, Class, Line),
    planerel_check_body(Body, Vocabulary, Line),
    assertz(Model:planerel_rule(I, Class, Obj, Head, Body, Names)),
    I1 is I + 1.
planerel_add_model_term(Head, Names, Model, _, Line, I, I1) :-
    planerel_head_class(Head, Obj, Class, Line),
    assertz(Model:planerel_rule(I, Class, Obj, Head, true, Names)),
    I1 is I + 1.

planerel_head_class(class(Obj, Class), Obj, Class, Line) :- !,
    (   atom(Class)
    ->  planerel_check_class(Class, Line)
    ;   planerel_refuse(Line, 'the class of a class(Obj, Class) head must be a name')
    ).
planerel_head_class(Head, Obj, Class, Line) :-
    compound(Head),
    compound_name_arguments(Head, Class, [Obj]), !,
    planerel_check_class(Class, Line).
planerel_head_class(Head, _, _, Line) :-
    planerel_refuse(Line, 'the head ~W is not a class: expected Class(Obj) or class(Obj, Class)'-
                    [Head, [quoted(true), max_depth(6)]]).

%   planerel_reserved_class(+Name): Name/1 is a built-in or library predicate
%   or part of planerel's support code, so it may not name a class.
planerel_reserved_class(Name) :-
    functor(H, Name, 1),
    planerel_reserved_head(H).

%   planerel_reserved_head(+Head): Head's predicate is a built-in or library
%   predicate or part of planerel's support code.
planerel_reserved_head(H) :-
    functor(H, Name, _),
    (   predicate_property(system:H, defined)
    ;   predicate_property(user:H, defined)
    ;   '$autoload':library_index(H, _, _)
    ;   sub_atom(Name, 0, _, _, planerel_)
    ), !.

planerel_check_class(Class, Line) :-
    (   planerel_reserved_class(Class)
    ->  planerel_refuse(Line, 'the class name ~q is a built-in, library or planerel predicate; choose another name'-[Class])
    ;   true
    ).

%   planerel_check_body(+Body, +Vocabulary, +Line)
planerel_check_body(Body, Vocabulary, Line) :-
    planerel_check_body(Body, Vocabulary, 'planerel\'s vocabulary', Line).

%   planerel_check_body(+Body, +Vocabulary, +Known, +Line): Known says what
%   Vocabulary is, in the message that refuses a call outside it.
planerel_check_body(G, _, _, Line) :-
    var(G), !,
    planerel_refuse(Line, 'a rule body may not call a variable').
planerel_check_body((A, B), V, K, L) :- !, planerel_check_body(A, V, K, L), planerel_check_body(B, V, K, L).
planerel_check_body((A ; B), V, K, L) :- !, planerel_check_body(A, V, K, L), planerel_check_body(B, V, K, L).
planerel_check_body((A -> B), V, K, L) :- !, planerel_check_body(A, V, K, L), planerel_check_body(B, V, K, L).
planerel_check_body(\+ A, V, K, L) :- !, planerel_check_body(A, V, K, L).
planerel_check_body(true, _, _, _) :- !.
planerel_check_body(G, V, Known, Line) :-
    (   callable(G) -> true
    ;   planerel_refuse(Line, 'the body goal ~q is not callable'-[G])
    ),
    functor(G, N, A),
    (   memberchk(N/A, V)
    ->  true
    ;   planerel_safe_builtin(N/A),
        catch(safe_goal(G), _, fail)
    ->  true
    ;   planerel_refuse(Line, 'the rule calls ~q, which is neither ~w nor a safe built-in'-[N/A, Known])
    ).

%   planerel_load_background(+Model, +File, +Vocabulary, -Defined, -Status)
%   Read File, a background file of the user's own, as data and check every
%   clause before any is kept: no directive, a head that is neither in
%   Vocabulary (planerel's predicates are not redefined) nor a built-in,
%   library or planerel predicate, and a body that calls only Vocabulary, the
%   safe built-ins a rule may call (planerel_check_body/3) and the predicates
%   File defines (recursion is allowed).  The clauses are then asserted into
%   module Model.  Defined is the sorted list of Name/Arity File defines;
%   Status is ok or error(Line, Message) for the first clause refused.
planerel_load_background(Model, File, Vocabulary, Defined, Status) :-
    must_be(atom, Model),
    catch(( setup_call_cleanup(open(File, read, In),
                               planerel_read_background(In, Clauses),
                               close(In)),
            planerel_check_background(Clauses, Vocabulary, Defined0) ),
          E,
          planerel_load_error(E, Status0)),
    (   var(Status0)
    ->  forall(member(c(C, _), Clauses), assertz(Model:C)),
        forall(member(N/A, Defined0), assertz(Model:planerel_bg_pred(N, A))),
        Defined = Defined0,
        Status = ok
    ;   Defined = [],
        Status = Status0
    ).

planerel_read_background(In, Clauses) :-
    read_term(In, Term, [syntax_errors(error), term_position(Pos), quasi_quotations(QQ)]),
    stream_position_data(line_count, Pos, Line),
    (   Term == end_of_file
    ->  Clauses = []
    ;   (   QQ == []
        ->  true
        ;   planerel_refuse(Line, 'a quasi-quotation has no place in a background file')
        ),
        planerel_background_term(Term, Line),
        Clauses = [c(Term, Line)|Rest],
        planerel_read_background(In, Rest)
    ).

planerel_background_term(T, Line) :-
    var(T), !,
    planerel_refuse(Line, 'a clause may not be a variable').
planerel_background_term(T, Line) :-
    ( T = (:- _) ; T = (?- _) ), !,
    planerel_refuse(Line, 'directive ~W refused: a background file holds clauses only (facts and rules), nothing in it is run'-
                    [T, [quoted(true), max_depth(6)]]).
planerel_background_term((_ --> _), Line) :- !,
    planerel_refuse(Line, 'a grammar rule (-->) has no place in a background file: write it as clauses').
planerel_background_term(_, _).

planerel_check_background(Clauses, Vocabulary, Defined) :-
    findall(N/A, ( member(c(C, Line), Clauses),
                   planerel_clause_head(C, H),
                   planerel_check_head(H, Vocabulary, Line),
                   functor(H, N, A) ),
            Ps),
    sort(Ps, Defined),
    append(Vocabulary, Defined, Callable),
    forall(member(c((_ :- B), Line), Clauses),
           planerel_check_body(B, Callable, 'planerel\'s vocabulary nor a predicate this file defines', Line)).

planerel_clause_head((H :- _), H) :- !.
planerel_clause_head(H, H).

planerel_check_head(H, _, Line) :-
    ( \+ callable(H) ; H = _:_ ), !,
    planerel_refuse(Line, 'the head ~q is not a predicate of this file (a name, or a name with arguments)'-[H]).
planerel_check_head(H, Vocabulary, Line) :-
    functor(H, N, A),
    (   memberchk(N/A, Vocabulary)
    ->  planerel_refuse(Line, 'the clause redefines ~q, which is planerel\'s vocabulary (docs/predicates.md); a background file defines predicates of its own'-[N/A])
    ;   planerel_reserved_head(H)
    ->  planerel_refuse(Line, 'the clause defines ~q, a built-in, library or planerel predicate; choose another name'-[N/A])
    ;   true
    ).

%   planerel_background_main(+File, +Data)
%   planerel's check of a background file before learning
%   (planerel.ilp.background), in its own swipl: Data holds the vocabulary.
%   Prints "@@defined Name Arity" for every predicate File defines, or
%   "error: Line: Message" and halts 2.
planerel_background_main(File, Data) :-
    setup_call_cleanup(open(Data, read, In), read_term(In, Vocabulary, []), close(In)),
    planerel_load_background(planerel_background, File, Vocabulary, Defined, Status),
    (   Status = error(Line, Msg)
    ->  format(user_error, 'error: ~w: ~w~n', [Line, Msg]),
        halt(2)
    ;   forall(member(N/A, Defined), format("@@defined ~q ~q~n", [N, A]))
    ).

% comparisons, arithmetic, unification and type tests: all a learned rule needs
planerel_safe_builtin(Op/2) :- memberchk(Op, [<, >, =<, >=, =:=, =\=, is, =, \=, ==, \==,
                                              @<, @>, @=<, @>=]).
planerel_safe_builtin(T/1) :- memberchk(T, [number, integer, float, atom, atomic, var,
                                             nonvar, ground, is_list, callable]).
planerel_safe_builtin(fail/0).
planerel_safe_builtin(false/0).

%   planerel_explain(+Model, +Obj, -Class, -Index, -Bindings, -Text)
%   Some rule of Model proves that Obj is a Class.  Bindings is the list of
%   Name-Value pairs of the rule's variables in the first proof (Values
%   written as atoms), Text the clause as written, with its variable names.
planerel_explain(Model, Obj, Class, Index, Bindings, Text) :-
    Model:planerel_rule(Index, Class, Obj0, _, Body0, Names0),
    copy_term(t(Obj0, Body0, Names0), t(Obj, Body, Names)),
    planerel_rule_text(Model, Index, Text),
    catch(once(planerel_prove(Model, Body)), E, (print_message(warning, E), fail)),
    findall(N-VA,
            ( member(N=V, Names), ground(V), format(atom(VA), '~w', [V]) ),
            Bindings).

%   planerel_prove(+Model, +Body): prove a rule body of Model in Model's
%   module.  The predicates of a background file of the user's own may
%   recurse, so a model with one proves each body within
%   planerel_inference_limit/1 inferences: a proof that does not end is a
%   warning and no proof, never a classify that hangs.
planerel_prove(Model, Body) :-
    (   catch(Model:planerel_bg_pred(_, _), _, fail)
    ->  planerel_inference_limit(Limit),
        call_with_inference_limit(Model:Body, Limit, Result),
        (   Result == inference_limit_exceeded
        ->  print_message(warning, format("planerel: a proof of ~q was stopped after ~D inferences (does a background predicate of the model never end?)", [Model, Limit])),
            fail
        ;   true
        )
    ;   Model:Body
    ).

planerel_inference_limit(10000000).

planerel_rule_text(Model, Index, Text) :-
    Model:planerel_rule(Index, _, _, Head, Body, Names),
    copy_term(t(Head, Body, Names), t(H, B, Ns)),
    maplist([N=V]>>(V = '$VAR'(N)), Ns),
    (   B == true
    ->  format(atom(Text), '~W.', [H, [quoted(true), numbervars(true)]])
    ;   format(atom(Text), '~W :- ~W.', [H, [quoted(true), numbervars(true)],
                                         B, [quoted(true), numbervars(true)]])
    ).

%   planerel_proof_scale(+Model, +Obj, +Index, -Scale)
%   How large the planes are that rule Index of Model proves Obj with: the
%   largest, over the rule's first 1000 proofs, of the smallest area (area/2,
%   m^2) among the planes the proof binds.  A proof made only of slivers has
%   a small scale even when the object is large; a flight of real treads a
%   large one.  Scale is `none` when no proof binds a plane with an area.
planerel_proof_scale(Model, Obj, Index, Scale) :-
    Model:planerel_rule(Index, _, Obj0, _, Body0, Names0),
    copy_term(t(Obj0, Body0, Names0), t(Obj, Body, Names)),
    (   aggregate_all(max(S),
                      limit(1000, ( catch(planerel_prove(Model, Body), _, fail),
                                    planerel_smallest_plane(Names, S) )),
                      Max)
    ->  Scale = Max
    ;   Scale = none
    ).

planerel_smallest_plane(Names, Smallest) :-
    findall(A, ( member(_=V, Names), atom(V),
                 catch(user:area(V, A), _, fail), number(A) ), Areas),
    Areas \== [],
    min_list(Areas, Smallest).

%   planerel_classes(+Model, -Classes): the classes Model has rules for.
planerel_classes(Model, Classes) :-
    findall(C, Model:planerel_rule(_, C, _, _, _, _), Cs),
    sort(Cs, Classes).

%   planerel_explain_text(+Model, +Obj, -Class, -Index, -Bindings, -Text)
%   As planerel_explain/6, with Bindings as one atom of "Name\tValue" lines
%   (for callers that read answers as text, such as pyswip).
planerel_explain_text(Model, Obj, Class, Index, BindingsText, Text) :-
    planerel_explain(Model, Obj, Class, Index, Bindings, Text),
    findall(Line, ( member(N-V, Bindings), format(atom(Line), '~w\t~w', [N, V]) ), Lines),
    atomic_list_concat(Lines, '\n', BindingsText).

%   planerel_predict_main(+Facts, +Rules, +Data)
%   The rule query of planerel's learner (pipeline.prolog_predict), run in its
%   own swipl: load the scene facts, read the model as data, then for every
%   object of the list in Data print "@@object O" and one "@@fired C I B T"
%   line per rule that proves a class.  Data holds two terms: the object
%   list and the vocabulary.  Paths come as data (argv), never pasted into
%   a goal.  A refused model prints "error: File:Line: Message" and halts 2.
planerel_predict_main(Facts, Rules, Data) :-
    planerel_predict_main(Facts, Rules, Data, []).

%   planerel_predict_main(+Facts, +Rules, +Data, +Background)
%   As planerel_predict_main/3 with the model's background file: Background
%   is [] or [File] (planerel_load_model/5).
planerel_predict_main(Facts, Rules, Data, Background) :-
    load_files(Facts, [silent(true)]),
    setup_call_cleanup(open(Data, read, In),
                       ( read_term(In, Objs, []), read_term(In, Vocabulary, []) ),
                       close(In)),
    (   Background = [Bg] -> true ; Bg = none ),
    planerel_load_model(planerel_predict, Rules, Bg, Vocabulary, Status),
    (   Status = error(Line, Msg)
    ->  format(user_error, 'error: ~w:~w: ~w~n', [Rules, Line, Msg]),
        halt(2)
    ;   Status = background_error(Line, Msg)
    ->  format(user_error, 'error: ~w:~w: ~w~n', [Bg, Line, Msg]),
        halt(2)
    ;   forall(member(O, Objs), planerel_report(O))
    ).

planerel_report(O) :-
    format("@@object ~q~n", [O]),
    forall(planerel_explain(planerel_predict, O, C, I, B, T),
           ( planerel_proof_scale(planerel_predict, O, I, S),
             format("@@fired ~q ~q ~q ~q~n@@scale ~q~n", [C, I, B, T, S]) )).
