/*  planerel's own Aleph-compatible ILP learner.

    Written for planerel from the published descriptions of Progol and Aleph
    (Muggleton 1995, "Inverse entailment and Progol"; Srinivasan, "The Aleph
    Manual").  No line of Aleph's source is used.

    Input language: Aleph's.  read_all(Stem) reads Stem.b (background,
    :- set/2, :- modeh/2, :- modeb/2, :- mode/2, :- determination/2,
    :- lazy_evaluate/1), Stem.f (positive examples) and Stem.n (negative
    examples); induce/0 learns a theory by greedy cover; write_rules/1 writes it.

    Algorithm (see docs/learner.md):
      repeat
        seed      := first positive not yet covered (samplesize K >= 2: K
                     seeds spread over them, each searched as below, the
                     best clause of the K kept)
        bottom    := saturation of seed (modes, recall, variable depth i, types)
        search    := bf | df | heuristic over clauses made of bottom literals
                     (head-connected, inputs bound, at most clauselength
                     literals), scored by coverage | laplace | accuracy |
                     compression, bounded by nodes
        add the best clause meeting minpos, minacc and noise and remove
        the positives it covers; when there is none, remove the seed (as
        Aleph, the seed itself becomes a rule only when minpos =< 1), and
        set aside without a search every later seed whose bottom clause
        is a variant of this one (skip_same_bottom, planerel's own)
      until no positive is left.

    Efficiency: examples are indexed by id; a refinement is tested only on the
    examples its parent covered; refinements add bottom literals in index
    order, so no clause is generated twice; clauses covering fewer than
    minpos positives are pruned, and so are nodes whose best possible
    refinement cannot beat the best clause found so far.
*/

:- module(planerel_learner,
          [ read_all/1,
            induce/0,
            write_rules/1,
            set/2,
            setting/2,
            modeh/2,
            modeb/2,
            mode/2,
            determination/2,
            lazy_evaluate/1,
            show_theory/0,
            planerel_main/0,
            planerel_score_main/0
          ]).

%   Compiled in optimised mode (as `swipl -O`; the flag is scoped to this
%   file): arithmetic becomes virtual-machine instructions instead of calls.
%   The background file is loaded the same way (load_background/1).  The
%   search is the same; docs/learner.md has the times.
:- set_prolog_flag(optimise, true).

:- op(500, fy, #).              % the constant marker of mode declarations
:- op(500, fy, user:(#)).        % ... and for the files read into user

:- use_module(library(lists)).
:- use_module(library(apply)).
:- use_module(library(heaps)).
:- use_module(library(ordsets)).
:- use_module(library(readutil)).

:- dynamic
    setting_value/3,        % Name, Value, Where
    mode_decl/5,            % h|b, Recall, Template, Where, Seq
    det_decl/3,             % Target N/A, Body N/A, Where
    lazy_decl/2,            % N/A, Where
    bg_pred/1,              % N/A defined by the background files
    bg_file/1,              % absolute path of the loaded background file
    bg_loading/1,           % the background file being loaded
    bg_problem/1,           % the first error met while loading it
    constraint_decl/2,      % Body, Where: an integrity constraint false :- Body
    pos_ex/2, neg_ex/2,     % Id, Atom  (training examples)
    tpos_ex/2, tneg_ex/2,   % Id, Atom  (test examples)
    theory_clause/5,        % No, Head, BodyList, PosCover, NegCover
    warned/1,
    rec_target/1,           % N/A: target that appears in its own determinations
    sat_var/3,              % Value, Type, VarId          (saturation scratch)
    sat_avail/4,            % Type, VarId, Value, Depth
    sat_lit/5,              % Idx, Literal, InIds, OutIds, Lazy
    sat_seen/1,             % Literal
    sat_done/2,             % ModeSeq, InIds
    lazy_cache/2,           % variant hash of a lazy call, its constants
    lazy_clause_cache/4,    % variant hash of a clause and lazy literal, how many pos and neg it covers, the constants
    cov_cache/3,            % variant hash of a clause, its positives and negatives as bit sets
    cov_inconsistent/1,     % variant hash of a clause that covers more than noise negatives
    nv_hash/3,              % run-wide key of a variable's values, number of covered negatives, hash of their values
    cache_record/1,         % reference of a record of the answer and value caches (big_cache/2)
    hopeless_bottom/1,      % variant hash of a bottom clause whose search found no clause
    looked_ahead/2,         % Seq of a node of the current search, the lazy literals lazy_lookahead made for it
    loaded_stem/1.

:- dynamic planerel_ext:'$planerel_none'/0.
:- dynamic user:hypothesis/3.     % the clause under test, for integrity constraints

                 /*******************************
                 *     ERRORS AND WARNINGS      *
                 *******************************/

%   Errors a user can cause are thrown as planerel_input_error(Text); the
%   driver prints them as one line and exits with status 2.

input_error(Fmt, Args) :-
    format(string(S), Fmt, Args),
    throw(planerel_input_error(S)).

warn(Fmt, Args) :-
    format(string(S), Fmt, Args),
    format(user_error, "warning: ~s~n", [S]).

warn_once(Key, Fmt, Args) :-
    (   warned(Key)
    ->  true
    ;   assertz(warned(Key)),
        warn(Fmt, Args)
    ).

where_text(File:Line, Text) :- !, format(string(Text), "~w:~w", [File, Line]).
where_text(Other, Text) :- format(string(Text), "~w", [Other]).

                 /*******************************
                 *           SETTINGS           *
                 *******************************/

%   setting_spec(Name, Default, Type): the settings this learner implements,
%   with Aleph's names and defaults.

setting_spec(clauselength, 4,        int(1)).
setting_spec(i,            2,        int(1)).
setting_spec(nodes,        5000,     int(1)).
setting_spec(minpos,       1,        int(1)).
setting_spec(minacc,       0.0,      fraction).
setting_spec(noise,        0,        int(0)).
setting_spec(search,       bf,       oneof([bf, df, heuristic])).
setting_spec(evalfn,       coverage, oneof([coverage, laplace, accuracy, compression])).
setting_spec(depth,        10,       int(1)).
setting_spec(verbosity,    1,        int(0)).
setting_spec(test_pos,     none,     file).
setting_spec(test_neg,     none,     file).
setting_spec(recursion,    false,    oneof([true, false])).
setting_spec(openlist,     inf,      int_or_inf(1)).
setting_spec(explore,      false,    oneof([true, false])).
setting_spec(searchtime,   inf,      pos_or_inf).
setting_spec(caching,      true,     oneof([true, false])).
setting_spec(cache_clauselength, inf, int_or_inf(1)).
setting_spec(skip_same_bottom, true, oneof([true, false])).   % planerel's own (see cover_loop/1)
setting_spec(samplesize,   0,        int(0)).                   % seeds per clause (see sample_seeds/2)
setting_spec(lazy_examples, false,   oneof([true, false])).     % planerel's own (see ex_values_on/3)
setting_spec(lazy_lookahead, false,  oneof([true, false])).     % planerel's own (see lookahead/6)
setting_spec(cutoff_slack, off,      num_or_off).               % planerel's own (prolog/compare.pl)
setting_spec(lazy_band,    false,    oneof([true, false])).     % planerel's own (prolog/compare.pl)

%   Values Aleph accepts for search/evalfn that this learner does not implement.
aleph_other_value(search, [ar, ibs, ic, id, ils, rls, scs, false]).
aleph_other_value(evalfn, [auto_m, mestimate, pbayes, posonly, sd, wracc,
                           entropy, gini, user]).

%   Settings of Aleph that this learner does not implement: warned about once.
aleph_setting(Name) :-
    memberchk(Name,
              [ abduce, best, check_good, check_redundant,
                check_useless, classes, clauselength_distribution, clauses,
                condition, confidence, construct_bottom, dependent, discretise,
                good, goodfile, gsamplesize, interactive, language,
                lazy_negs, lazy_on_contradiction, lazy_on_cost, lookahead, m,
                max_abducibles, max_features, mingain, minposfrac, minscore,
                mode_overlap_threshold, moves, newvars, nreduce_bottom,
                optimise_clauses, permute_bottom, prior, prune_tree,
                portray_examples, portray_hypothesis, portray_literals,
                portray_search, print, proof_strategy, prooftime, prune_defs,
                record, recordfile, refine, refineop, resample, rls_type, rulefile,
                samplenum, scs_percentile, scs_prob, scs_sample,
                searchstrat, skolemvars, splitvars, stage,
                store_bottom, subsample, subsamplesize, temperature, threads,
                train_pos, train_neg, tree_type, tries, typeoverlap,
                uniform_sample, updateback, version, walk, minprec, date,
                experiment
              ]).

%!  set(+Name, +Value) is det.
%
%   Aleph's set/2, with validation: an unknown name or an illegal value is
%   an error.
set(Name, Value) :-
    set_setting(Name, Value, 'set/2').

%!  setting(?Name, ?Value) is nondet.
%
%   The value in effect (the default when it was not set).
setting(Name, Value) :-
    setting_spec(Name, Default, _),
    (   setting_value(Name, V, _)
    ->  Value = V
    ;   Value = Default
    ).

set_setting(verbose, Value, Where) :- !,       % Aleph's other name of verbosity
    set_setting(verbosity, Value, Where).
set_setting(evalfn, posonly, Where) :- !,
    where_text(Where, W),
    input_error("~s: evalfn(posonly) (learning from positive examples only, scored against randomly generated examples) is not implemented by planerel's learner: give negative examples in STEM.n, or use the real Aleph (--engine aleph)",
                [W]).
set_setting(Name, Value, Where) :-
    where_text(Where, W),
    (   atom(Name)
    ->  true
    ;   input_error("~s: set/2 needs a setting name, got ~q", [W, Name])
    ),
    (   setting_spec(Name, Default, Type)
    ->  (   check_value(Type, Value, V1)
        ->  retractall(setting_value(Name, _, _)),
            assertz(setting_value(Name, V1, Where))
        ;   Type = oneof(_),
            aleph_other_value(Name, Others),
            memberchk(Value, Others)
        ->  warn_once(value(Name, Value),
                      "~s: ~w(~w) is an Aleph setting value that planerel's learner does not implement; using ~w(~w)",
                      [W, Name, Value, Name, Default])
        ;   type_text(Type, Expected),
            input_error("~s: illegal value ~q for setting ~w (expected ~s)",
                        [W, Value, Name, Expected])
        )
    ;   aleph_setting(Name)
    ->  warn_once(setting(Name),
                  "~s: the Aleph setting ~w is not implemented by planerel's learner; ignored (value ~q)",
                  [W, Name, Value])
    ;   input_error("~s: unknown setting ~q (value ~q): Aleph has no setting of this name",
                    [W, Name, Value])
    ).

check_value(int(Min), V, V) :- integer(V), V >= Min.
check_value(fraction, V, F) :- number(V), V >= 0, V =< 1, F is float(V).
check_value(oneof(L), V, V) :- atom(V), memberchk(V, L).
check_value(file, V, A) :- ( atom(V) ; string(V) ), V \== '', atom_string(A, V).
check_value(int_or_inf(_), inf, inf) :- !.
check_value(int_or_inf(Min), V, V) :- integer(V), V >= Min.
check_value(pos_or_inf, inf, inf) :- !.
check_value(pos_or_inf, V, F) :- number(V), V > 0, F is float(V).
check_value(num_or_off, off, off) :- !.
check_value(num_or_off, V, F) :- number(V), V >= 0, F is float(V).

type_text(int(Min), T) :- format(string(T), "an integer >= ~w", [Min]).
type_text(fraction, "a number between 0 and 1").
type_text(oneof(L), T) :- atomic_list_concat(L, ', ', A), format(string(T), "one of ~w", [A]).
type_text(file, "a file name").
type_text(int_or_inf(Min), T) :- format(string(T), "an integer >= ~w or inf", [Min]).
type_text(pos_or_inf, "a positive number of seconds or inf").
type_text(num_or_off, "a number >= 0 or off").

                 /*******************************
                 *         DECLARATIONS         *
                 *******************************/

modeh(Recall, Template) :- add_mode(h, Recall, Template, 'modeh/2').
modeb(Recall, Template) :- add_mode(b, Recall, Template, 'modeb/2').
mode(Recall, Template) :-
    add_mode(h, Recall, Template, 'mode/2'),
    add_mode(b, Recall, Template, 'mode/2').
determination(Target, Body) :- add_det(Target, Body, 'determination/2').
lazy_evaluate(Spec) :- add_lazy(Spec, 'lazy_evaluate/1').

add_mode(Kind, Recall, Template, Where) :-
    where_text(Where, W),
    (   ( Recall == '*' ; integer(Recall), Recall >= 1 )
    ->  true
    ;   input_error("~s: illegal recall ~q in a mode declaration (expected a positive integer or *)",
                    [W, Recall])
    ),
    (   callable(Template)
    ->  true
    ;   input_error("~s: a mode declaration needs an atom like p(+type,-type,#type), got ~q",
                    [W, Template])
    ),
    Template =.. [_|Args],
    forall(member(A, Args), check_mode_arg(A, W, Template)),
    (   mode_skeleton(Template, _, Phs0), Phs0 == []
    ->  warn("~s: mode ~q has no +type, -type or #type argument", [W, Template])
    ;   true
    ),
    flag(planerel_mode_seq, Seq, Seq + 1),
    assertz(mode_decl(Kind, Recall, Template, Where, Seq)).

check_mode_arg(A, W, T) :-
    (   var(A)
    ->  input_error("~s: mode ~q has a variable argument; write +type, -type or #type", [W, T])
    ;   A = +Ty -> check_type_name(Ty, W, T)
    ;   A = -Ty -> check_type_name(Ty, W, T)
    ;   A = #Ty -> check_type_name(Ty, W, T)
    ;   atomic(A) -> true
    ;   A =.. [_|As],                    % structured: not(p(+t)), [-t|-list], ...
        forall(member(B, As), check_mode_arg(B, W, T))
    ).

%!  mode_skeleton(+Template, -Skel, -Phs) is det.
%
%   Skel is Template with every +Type, -Type and #Type (at any depth, e.g.
%   in not(p(+t)) or (+list)=[-any|-list]) replaced by a fresh variable;
%   Phs lists them left to right as ph(Kind, Type, Var), Kind in, out or
%   const.
mode_skeleton(T, Skel, Phs) :-
    mode_skeleton(T, Skel, Phs, []).

mode_skeleton(T, V, [ph(K, Ty, V)|Ps], Ps) :-
    compound(T), placeholder(T, K, Ty), !.
mode_skeleton(T, T, Ps, Ps) :-
    \+ compound(T), !.
mode_skeleton(T, S, Ps0, Ps) :-
    T =.. [F|As],
    foldl(skel_arg, As, Ss, Ps0, Ps),
    S =.. [F|Ss].

skel_arg(A, S, Ps0, Ps) :- mode_skeleton(A, S, Ps0, Ps).

placeholder(+Ty, in, Ty).
placeholder(-Ty, out, Ty).
placeholder(#Ty, const, Ty).

check_type_name(Ty, W, T) :-
    (   atom(Ty)
    ->  true
    ;   input_error("~s: mode ~q: the type ~q must be an atom (a type name)", [W, T, Ty])
    ).

add_det(Target, Body, Where) :-
    where_text(Where, W),
    (   pred_spec(Target), pred_spec(Body)
    ->  (   det_decl(Target, Body, _)
        ->  true
        ;   assertz(det_decl(Target, Body, Where))
        )
    ;   input_error("~s: determination(~q, ~q) needs Name/Arity for both arguments",
                    [W, Target, Body])
    ).

add_lazy(Spec, Where) :-
    (   pred_spec(Spec)
    ->  assertz(lazy_decl(Spec, Where))
    ;   where_text(Where, W),
        input_error("~s: lazy_evaluate(~q) needs Name/Arity", [W, Spec])
    ).

pred_spec(N/A) :- atom(N), integer(A), A >= 0.

                 /*******************************
                 *            READING           *
                 *******************************/

%!  read_all(+Stem) is det.
%
%   Read Stem.b, Stem.f and Stem.n (a missing Stem.n means no negatives).
%   Errors name the file and line.
read_all(Stem0) :-
    (   atom(Stem0) ; string(Stem0) ),
    !,
    atom_string(Stem, Stem0),
    reset_all,
    atom_concat(Stem, '.b', BFile),
    atom_concat(Stem, '.f', FFile),
    atom_concat(Stem, '.n', NFile),
    load_background(BFile),
    read_source(FFile, pos),
    (   exists_file(NFile)
    ->  read_source(NFile, neg)
    ;   warn("~w: not found; learning with no negative examples", [NFile])
    ),
    check_declarations,
    assertz(loaded_stem(Stem)).
read_all(Stem) :-
    input_error("read_all/1 needs a file stem (an atom), got ~q", [Stem]).

reset_all :-
    forall(retract(bg_file(F)), catch(unload_file(F), _, true)),
    forall(retract(bg_pred(N/A)), ( functor(H, N, A), catch(retractall(user:H), _, true) )),
    retractall(constraint_decl(_, _)),
    retractall(setting_value(_, _, _)),
    retractall(mode_decl(_, _, _, _, _)),
    retractall(det_decl(_, _, _)),
    retractall(lazy_decl(_, _)),
    retractall(bg_pred(_)),
    retractall(pos_ex(_, _)),
    retractall(neg_ex(_, _)),
    retractall(tpos_ex(_, _)),
    retractall(tneg_ex(_, _)),
    retractall(theory_clause(_, _, _, _, _)),
    retractall(warned(_)),
    retractall(rec_target(_)),
    retractall(loaded_stem(_)),
    flag(planerel_mode_seq, _, 0),
    forall(member(S, [pos, neg, test_pos, test_neg]), (atom_concat(planerel_id_, S, F), flag(F, _, 0))).

%   The background file is compiled into module user with load_files/2, so
%   it may use everything a Prolog source file may (conditional compilation
%   :- if/elif/else/endif, arithmetic_function/1, use_module, term
%   expansion, ...) and its predicates are compiled with SWI-Prolog's
%   indexing.  While it loads, user:term_expansion/2 takes Aleph's directives
%   (set/2, modeh/2, modeb/2, mode/2, determination/2, lazy_evaluate/1, ...)
%   and constraints (false :- Body) out of the file, and user:message_hook/3
%   turns the first error (syntax error, failing or raising directive) into
%   planerel_input_error with file and line.

load_background(File) :-
    (   exists_file(File)
    ->  true
    ;   input_error("~w: file not found", [File])
    ),
    absolute_file_name(File, Abs),
    retractall(bg_problem(_)),
    setup_call_cleanup(
        assertz(bg_loading(Abs)),
        catch(load_files(user:Abs, [silent(true), if(true), optimise(true)]), E, bg_exception(E)),
        retractall(bg_loading(_))),
    assertz(bg_file(Abs)),
    forall(( source_file(user:H, Abs), functor(H, N, A) ),
           ( bg_pred(N/A) -> true ; assertz(bg_pred(N/A)) )),
    (   bg_problem(Text)
    ->  retractall(bg_problem(_)),
        throw(planerel_input_error(Text))
    ;   true
    ).

bg_exception(planerel_input_error(T)) :- !, note_bg_problem(T).
bg_exception(E) :- message_to_codes_text(E, T), note_bg_problem(T).

note_bg_problem(Text) :-
    (   bg_problem(_) -> true ; assertz(bg_problem(Text)) ).

bg_where(File:Line) :-
    (   prolog_load_context(term_position, Pos),
        stream_position_data(line_count, Pos, Line),
        prolog_load_context(file, File)
    ->  true
    ;   source_location(File, Line)
    ->  true
    ;   bg_loading(File), Line = '?'
    ).

:- multifile user:term_expansion/2, user:message_hook/3.

%   One clause per term shape, so that the many facts of a background file
%   are not looked at (first-argument indexing).
user:term_expansion((:- D), Out) :-
    bg_loading(_),
    bg_expand((:- D), Out).
user:term_expansion((false :- B), Out) :-
    bg_loading(_),
    bg_expand((false :- B), Out).
user:term_expansion(false, Out) :-
    bg_loading(_),
    bg_expand(false, Out).

bg_expand((:- D), []) :-
    nonvar(D),
    aleph_directive(D), !,
    bg_where(Where),
    catch(directive(D, Where, none), E, bg_exception(E)).
bg_expand((false :- Body), []) :- !,
    bg_where(Where),
    assertz(constraint_decl(Body, Where)).
bg_expand(false, []) :- !,
    bg_where(Where),
    assertz(constraint_decl(true, Where)).

%   Directives this learner handles itself (the rest run as in any source file).
aleph_directive(D) :-
    functor(D, F, A),
    (   memberchk(F/A, [ set/2, aleph_set/2, modeh/2, modeb/2, mode/2, determination/2,
                         lazy_evaluate/1, aleph/0, abducible/1 ])
    ->  true
    ;   D == use_module(library(aleph))
    ->  true
    ;   aleph_declaration(D)
    ).

user:message_hook(Msg, Kind, _) :-
    bg_loading(_),
    memberchk(Kind, [error, warning]),
    bg_message(Kind, Msg).

bg_message(error, error(syntax_error(What), Ctx)) :- !,
    (   Ctx = file(File, Line, _, _) -> true ; bg_where(File:Line) ),
    format(string(T), "~w:~w: syntax error: ~w", [File, Line, What]),
    note_bg_problem(T).
bg_message(error, E) :- !,
    bg_where(Where), where_text(Where, W),
    message_to_codes_text(E, M),
    format(string(T), "~s: ~s", [W, M]),
    note_bg_problem(T).
bg_message(warning, goal_failed(directive, _:G)) :- !,
    bg_where(Where), where_text(Where, W),
    format(string(T), "~s: the directive ~q failed", [W, G]),
    note_bg_problem(T).
bg_message(warning, _).           % singletons, discontiguous clauses, ...: silent

read_source(File, Kind) :-
    (   exists_file(File)
    ->  true
    ;   input_error("~w: file not found", [File])
    ),
    file_directory_name(File, Dir),
    setup_call_cleanup(open(File, read, S, [encoding(utf8)]),
                       read_terms(S, File, Dir, Kind),
                       close(S)).

read_terms(S, File, Dir, Kind) :-
    catch(read_term(S, T, [term_position(Pos), syntax_errors(error), module(user)]),
          E, read_error(E, File)),
    (   T == end_of_file
    ->  true
    ;   stream_position_data(line_count, Pos, Line),
        handle_term(Kind, T, File:Line, Dir),
        read_terms(S, File, Dir, Kind)
    ).

read_error(error(syntax_error(What), Ctx), File) :- !,
    (   ( Ctx = file(_, Line, _, _) ; Ctx = stream(_, Line, _, _) )
    ->  true
    ;   Line = '?'
    ),
    input_error("~w:~w: syntax error: ~w", [File, Line, What]).
read_error(E, File) :-
    message_to_codes_text(E, Text),
    input_error("~w: cannot read: ~s", [File, Text]).

message_to_codes_text(E, Text) :-
    (   catch(message_to_codes(E, _, Codes), _, fail)
    ->  string_codes(Text, Codes)
    ;   format(string(Text), "~q", [E])
    ).

handle_term(_, (:- D), Where, Dir) :- !, directive(D, Where, Dir).
handle_term(_, (?- D), Where, Dir) :- !, directive(D, Where, Dir).
handle_term(background, Clause, Where, _) :- !, add_background(Clause, Where).
handle_term(Set, Atom, Where, _) :-
    (   callable(Atom), Atom \= (_ :- _), Atom \= (_ , _)
    ->  true
    ;   where_text(Where, W),
        input_error("~s: an example must be an atom like p(a,b), got ~q", [W, Atom])
    ),
    atom_concat(planerel_id_, Set, Flag),
    flag(Flag, Id0, Id0 + 1),
    Id is Id0 + 1,
    example_fact(Set, Id, Atom, Fact),
    assertz(Fact).

example_fact(pos, Id, A, pos_ex(Id, A)).
example_fact(neg, Id, A, neg_ex(Id, A)).
example_fact(test_pos, Id, A, tpos_ex(Id, A)).
example_fact(test_neg, Id, A, tneg_ex(Id, A)).

add_background(Clause, Where) :-
    (   Clause = (H :- _) -> true ; H = Clause ),
    where_text(Where, W),
    (   callable(H), H \= _:_
    ->  true
    ;   input_error("~s: not a clause: ~q", [W, Clause])
    ),
    functor(H, N, A),
    catch(assertz(user:Clause), E,
          ( message_to_codes_text(E, T),
            input_error("~s: cannot add the clause for ~w/~w: ~s", [W, N, A, T]) )),
    (   bg_pred(N/A) -> true ; assertz(bg_pred(N/A)) ).

directive(D, Where, _) :- var(D), !,
    where_text(Where, W),
    input_error("~s: a directive must not be a variable", [W]).
directive(set(N, V), Where, _) :- !, set_setting(N, V, Where).
directive(aleph_set(N, V), Where, _) :- !, set_setting(N, V, Where).
directive(abducible(S), Where, _) :- !,
    where_text(Where, W),
    warn_once(abducible,
              "~s: abducible(~q): abduction is not implemented by planerel's learner; ~q is treated as ordinary background (the real Aleph, --engine aleph, implements it)",
              [W, S, S]).
directive(modeh(R, T), Where, _) :- !, add_mode(h, R, T, Where).
directive(modeb(R, T), Where, _) :- !, add_mode(b, R, T, Where).
directive(mode(R, T), Where, _) :- !, add_mode(h, R, T, Where), add_mode(b, R, T, Where).
directive(determination(T, B), Where, _) :- !, add_det(T, B, Where).
directive(lazy_evaluate(S), Where, _) :- !, add_lazy(S, Where).
directive(aleph, _, _) :- !.
directive(use_module(library(aleph)), _, _) :- !.
directive(D, Where, _) :-
    aleph_declaration(D), !,
    functor(D, F, A),
    where_text(Where, W),
    warn_once(decl(F/A), "~s: the Aleph declaration ~w/~w is not implemented by planerel's learner; ignored",
              [W, F, A]).
directive(D, Where, Dir) :-
    where_text(Where, W),
    working_directory(Old, Dir),
    catch(( user:D -> R = true ; R = false ), E, R = error(E)),
    working_directory(_, Old),
    (   R == true
    ->  true
    ;   R == false
    ->  input_error("~s: the directive ~q failed", [W, D])
    ;   R = error(E1),
        message_to_codes_text(E1, T),
        input_error("~s: the directive ~q raised an error: ~s", [W, D, T])
    ).

aleph_declaration(D) :-
    functor(D, F, A),
    memberchk(F/A, [ commutative/1, symmetric/1, reflexive/1, transitive/1,
                     positive_only/1, model/1, example_saturated/1,
                     aleph_set/2, redundant/2, cost/3, sat/1, man/1 ]).

check_declarations :-
    forall(det_decl(T, B, Where), check_determination(T, B, Where)).

check_determination(Target, N/A, Where) :-
    where_text(Where, W),
    (   has_modeb(N/A) -> HasMode = true ; HasMode = false ),
    (   known_pred(N/A) ; N/A == Target ; lazy_decl(N/A, _) -> Known = true ; Known = false ),
    (   HasMode == false, Known == false
    ->  input_error("~s: determination(~q, ~q): ~w/~w is an unknown predicate (no mode declaration and no definition)",
                    [W, Target, N/A, N, A])
    ;   HasMode == false
    ->  warn_once(nomode(N/A), "~s: ~w/~w has no modeb declaration, so determination(~q, ~q) is never used",
                  [W, N, A, Target, N/A])
    ;   Known == false
    ->  warn_once(undef(N/A), "~s: ~w/~w has a mode declaration but no definition; its literals never hold",
                  [W, N, A])
    ;   true
    ).

has_modeb(N/A) :-
    mode_decl(b, _, T, _, _),
    functor(T, N, A), !.

known_pred(N/A) :-
    (   bg_pred(N/A)
    ->  true
    ;   functor(H, N, A),
        catch(predicate_property(user:H, visible), _, fail)
    ).

                 /*******************************
                 *          SATURATION          *
                 *******************************/

%   The bottom clause is built with the ground placeholders '$v'(Id) for
%   variables (Id = the (value, type) pair's number) and '$lz' for the
%   constants of lazily evaluated literals, then turned into one term with
%   shared Prolog variables:
%       bottom(Head, HeadInIds, HeadOutIds, Lits, NLits)
%   Lits is lits(bl(Idx, Literal, InIds, OutIds, Lazy), ...).

saturate(Seed, bottom(Head, HIn, HOut, LitsT, NB), VT) :-
    clear_sat,
    functor(Seed, F, A),
    (   head_template(F/A, Seed, Tmpl)
    ->  true
    ;   input_error("no modeh declaration matches the example ~q", [Seed])
    ),
    mode_skeleton(Tmpl, Skel1, Phs1),
    Skel1 = Seed,                             % Phs1 now hold the seed's values
    mode_skeleton(Tmpl, HeadG, Phs2),
    head_args(Phs1, Phs2, HIn0, HOut0),
    sort(HIn0, HIn),
    sort(HOut0, HOut),
    setting(i, I),
    body_modes(F/A, Modes),
    forall(between(1, I, D), layer(D, Modes, F/A, HeadG)),
    findall(bl(Idx, L, In, Out, Lz), sat_lit(Idx, L, In, Out, Lz), BLs0),
    flag(planerel_var_id, NV, NV),
    length(Vs, NV),
    VT =.. [vs|Vs],
    devar(HeadG, VT, Head),
    maplist(devar_bl(VT), BLs0, BLs),
    LitsT =.. [lits|BLs],
    length(BLs, NB),
    clear_sat.

clear_sat :-
    retractall(sat_var(_, _, _)),
    retractall(sat_avail(_, _, _, _)),
    retractall(sat_lit(_, _, _, _, _)),
    retractall(sat_seen(_)),
    retractall(sat_done(_, _)),
    flag(planerel_var_id, _, 0),
    flag(planerel_lit_id, _, 0).

head_template(F/A, Seed, Tmpl) :-
    mode_decl(h, _, Tmpl, _, _),
    functor(Tmpl, F, A),
    mode_skeleton(Tmpl, Skel, Phs),
    subsumes_term(Skel, Seed),
    \+ \+ ( Skel = Seed, forall(member(ph(_, _, V), Phs), ground(V)) ), !.

head_args([], [], [], []).
head_args([ph(K, T, V)|Ps], [ph(_, _, H)|Hs], In, Out) :-
    (   K == in
    ->  var_id(V, T, Id, _), add_avail(T, Id, V, 0),
        H = '$v'(Id), In = [Id|In1], Out = Out1
    ;   K == out
    ->  var_id(V, T, Id, _),
        H = '$v'(Id), In = In1, Out = [Id|Out1]
    ;   H = V, In = In1, Out = Out1
    ),
    head_args(Ps, Hs, In1, Out1).

var_id(V, T, Id, New) :-
    (   sat_var(V, T, Id0)
    ->  Id = Id0, New = false
    ;   flag(planerel_var_id, Id, Id + 1),
        assertz(sat_var(V, T, Id)),
        New = true
    ).

add_avail(T, Id, V, D) :-
    (   sat_avail(T, Id, _, _)
    ->  true
    ;   assertz(sat_avail(T, Id, V, D))
    ).

%   body_modes(+Target, -Modes): m(Recall, Template, Lazy, Seq, Rec) for the
%   modeb declarations of the predicates the target's determinations name,
%   in determination order then declaration order.
body_modes(Target, Modes) :-
    findall(B, det_decl(Target, B, _), Bs0),
    list_to_set(Bs0, Bs),
    (   memberchk(Target, Bs)
    ->  ( rec_target(Target) -> true ; assertz(rec_target(Target)) )
    ;   true
    ),
    findall(m(R, T, Lazy, Seq, Rec),
            ( member(N/A, Bs),
              mode_decl(b, R, T, _, Seq),
              functor(T, N, A),
              ( lazy_decl(N/A, _) -> Lazy = lazy ; Lazy = none ),
              ( N/A == Target -> Rec = rec ; Rec = norec )
            ),
            Modes).

layer(D, Modes, Target, HeadG) :-
    D0 is D - 1,
    forall(member(M, Modes), mode_layer(M, D0, D, Target, HeadG)).

mode_layer(m(R, Tmpl, Lazy, Seq, Rec), D0, D, _Target, HeadG) :-
    mode_skeleton(Tmpl, Skel, Phs),
    findall(Ch, input_choice(Phs, D0, Ch), Choices),
    forall(member(Ch, Choices),
           call_mode(Ch, Skel-Phs, R, Lazy, Seq, Rec, D, HeadG)).

input_choice([], _, []).
input_choice([ph(K, T, _)|Ps], D0, [C|Cs]) :-
    (   K == in
    ->  sat_avail(T, Id, V, Dep), Dep =< D0, C = in(Id, V)
    ;   K == out
    ->  C = out(T)
    ;   C = const(T)
    ),
    input_choice(Ps, D0, Cs).

call_mode(Ch, SP, R, Lazy, Seq, Rec, D, HeadG) :-
    findall(Id, member(in(Id, _), Ch), InIds),
    (   sat_done(Seq, InIds)
    ->  true
    ;   assertz(sat_done(Seq, InIds)),
        sort(InIds, InSet),
        (   Lazy == lazy, \+ memberchk(out(_), Ch), flat_skeleton(SP)
        ->  lazy_literal(Ch, SP, InSet)
        ;   copy_term(SP, Call-CPhs),
            maplist(call_arg, Ch, CPhs, Vals),
            solutions(Rec, R, Call, Vals, Sols),
            forall(member(Vals1, Sols), add_solution(Ch, Vals1, SP, InSet, D, HeadG))
        )
    ).

%   call_arg(+Choice, +Placeholder, -Value): bind an input, leave the rest open.
call_arg(in(_, V), ph(_, _, V), V).
call_arg(out(_), ph(_, _, V), V).
call_arg(const(_), ph(_, _, V), V).

%   A lazily evaluated literal needs its placeholders as plain arguments.
flat_skeleton(Skel-Phs) :-
    Skel =.. [_|Args],
    forall(member(ph(_, _, V), Phs), ( member(A, Args), A == V )).

solutions(Rec, R, Call, Vals, Sols) :-
    (   Rec == rec
    ->  G = planerel_ext:Call
    ;   G = user:Call
    ),
    functor(Call, N, A),
    Safe = catch(G, E, (saturation_error(N/A, E), fail)),
    (   R == '*'
    ->  findall(Vals, Safe, Sols)
    ;   findall(Vals, limit(R, Safe), Sols)
    ).

saturation_error(PI, E) :-
    message_to_codes_text(E, T),
    warn_once(sat_error(PI), "calling ~w during saturation raised an error (treated as failure): ~s", [PI, T]).

lazy_literal(Ch, SP, InSet) :-
    copy_term(SP, Lit-LPhs),
    maplist(lazy_arg, Ch, LPhs),
    Lit =.. [_|Args],
    findall(I, ( nth1(I, Args, A), A = '$v'(_) ), InPos),
    findall(I, ( nth1(I, Args, A), A == '$lz' ), CPos),
    record_literal(Lit, InSet, [], lazy(InPos, CPos)).

lazy_arg(in(Id, _), ph(_, _, '$v'(Id))).
lazy_arg(const(_), ph(_, _, '$lz')).

add_solution(Ch, Vals, SP, InSet, D, HeadG) :-
    copy_term(SP, Lit-LPhs),
    (   maplist(solution_arg(D), Ch, Vals, LPhs, Outs0)
    ->  (   Lit == HeadG
        ->  true
        ;   exclude(==(none), Outs0, Outs1),
            sort(Outs1, Outs),
            record_literal(Lit, InSet, Outs, none)
        )
    ;   true
    ).

solution_arg(_, in(Id, _), _, ph(_, _, '$v'(Id)), none).
solution_arg(D, out(T), V, ph(_, _, '$v'(Id)), Id) :-
    ground(V),
    var_id(V, T, Id, _),
    add_avail(T, Id, V, D).
solution_arg(_, const(_), V, ph(_, _, V), none) :- ground(V).

record_literal(Lit, InSet, Outs, Lazy) :-
    (   sat_seen(Lit)
    ->  true
    ;   assertz(sat_seen(Lit)),
        flag(planerel_lit_id, I0, I0 + 1),
        I is I0 + 1,
        assertz(sat_lit(I, Lit, InSet, Outs, Lazy))
    ).

devar_bl(VT, bl(I, L0, In, Out, Lz), bl(I, L, In, Out, Lz)) :- devar(L0, VT, L).

devar(T, _, T) :- var(T), !.
devar('$v'(K), VT, V) :- integer(K), !, K1 is K + 1, arg(K1, VT, V).
devar('$lz', _, _) :- !.
devar(T, _, T) :- atomic(T), !.
devar(T, VT, T2) :-
    T =.. [F|As],
    maplist(devar_(VT), As, As2),
    T2 =.. [F|As2].
devar_(VT, A, B) :- devar(A, VT, B).

                 /*******************************
                 *            PROVING           *
                 *******************************/

%   During the search a recursive literal (the target in its own body) is
%   proved from the positive examples (asserted in module planerel_ext);
%   everything else is proved by the background in module user.

prove_body([]).
prove_body([L|Ls]) :-
    call_lit(L),
    prove_body(Ls).

call_lit('$rec'(L)) :- !, planerel_ext:L.
call_lit(L) :- user:L.

%   lit_goal(+Lit, -Goal): the goal call_lit(Lit) calls, made once for the
%   loops that test one literal on many answers (call(Goal) there instead
%   of call_lit(Lit) each time: one predicate call less per answer).
lit_goal('$rec'(L), G) :- !, G = planerel_ext:L.
lit_goal(L, user:L).

covers(Head, Body, Ex) :-
    catch(\+ \+ ( Head = Ex, prove_body(Body) ), E, (coverage_error(E), fail)).

coverage_error(E) :-
    message_to_codes_text(E, T),
    warn_once(coverage_error(T), "an error while testing coverage (treated as not covered): ~s", [T]).

setup_extensional :-
    forall(( current_predicate(planerel_ext:N0/A0), functor(H0, N0, A0) ),
           retractall(planerel_ext:H0)),
    forall(( rec_target(N/A), functor(H, N, A) ),
           ( dynamic(planerel_ext:N/A),
             forall(pos_ex(_, H), assertz(planerel_ext:H)) )).

mark_recursive(Target, bl(I, L, In, Out, Lz), bl(I, L1, In, Out, Lz)) :-
    (   functor(L, N, A), N/A == Target
    ->  L1 = '$rec'(L)
    ;   L1 = L
    ).

                 /*******************************
                 *            SEARCH            *
                 *******************************/

%   A node is nd(Body, Last-PX, Bound, Len, PosCov, NegCov, P, N, Score, Seq):
%   Body the literals (in order), Last the index of the last bottom literal
%   added, PX its parent's answers (px(BV, PosAnswers, NegAnswers), none for
%   the root; see node_answers/3), Bound the ordset of bound variable ids, Len the number of
%   literals including the head, PosCov/NegCov the ids of the examples it
%   covers.

score(coverage, P, N, _, S) :- S is P - N.
score(laplace, P, N, _, S) :- S is (P + 1) / (P + N + 2).
score(accuracy, P, N, _, S) :- ( P + N =:= 0 -> S = 0.0 ; S is P / (P + N) ).
score(compression, P, N, L, S) :- S is P - N - L + 1.

%   The best score any refinement (one literal longer or more) can reach.
bound(coverage, P, _, B) :- B = P.
bound(laplace, P, _, B) :- B is (P + 1) / (P + 2).
bound(accuracy, P, _, B) :- ( P > 0 -> B = 1.0 ; B = 0.0 ).
bound(compression, P, L, B) :- B is P - L.

search_clause(Bottom, PosIds, NegIds, Ctx, Best) :-
    setting(searchtime, ST),
    (   ST == inf
    ->  nb_setval(planerel_search_deadline, inf)
    ;   statistics(cputime, T0),
        Deadline is T0 + ST,
        nb_setval(planerel_search_deadline, Deadline)
    ),
    Bottom = bottom(Head, HIn, _HOut, _LitsT, _NB),
    live_table(Bottom, LiveT),
    nb_setval(planerel_live, LiveT),
    Ctx = ctx(_, _, _, _, _, _, _, _, VT),
    functor(VT, _, NVars),
    consumer_table(Bottom, NVars, CT),
    nb_setval(planerel_consumers, CT),
    retractall(looked_ahead(_, _)),
    (   setting(lazy_lookahead, true)
    ->  lazy_table(Bottom, CT, LT),
        nb_setval(planerel_lazy_next, LT)
    ;   nb_setval(planerel_lazy_next, none)
    ),
    Ctx = ctx(_, _, Evalfn, _, _, _, _, _, _),
    include(covers_id(pos, Head, []), PosIds, PC),
    include(covers_id(neg, Head, []), NegIds, NC),
    length(PC, P), length(NC, N),
    score(Evalfn, P, N, 1, S),
    count_node,
    length(PosIds, NPos),
    nb_setval(planerel_search_npos, NPos),
    Root = nd([], 0-none, HIn, 1, PC, NC, P, N, S, 0),
    consider(Root, Ctx, none, Best0),
    Ctx = ctx(Search, _, _, _, _, _, _, _, _),
    open_empty(Search, O0),
    (   expandable(Root, Ctx, Best0)
    ->  open_push(Search, [Root], O0, O1)
    ;   O1 = O0
    ),
    search_loop(O1, Ctx, Best0, Best).

covers_id(pos, Head, Body, Id) :- pos_ex(Id, E), covers(Head, Body, E).
covers_id(neg, Head, Body, Id) :- neg_ex(Id, E), covers(Head, Body, E).

count_node :-
    flag(planerel_nodes, N, N + 1),
    flag(planerel_search_nodes, M, M + 1).

budget_left(Ctx) :-
    Ctx = ctx(_, _, _, _, MaxNodes, _, _, _, _),
    flag(planerel_search_nodes, M, M),
    M < MaxNodes,
    (   nb_current(planerel_search_deadline, Deadline), Deadline \== inf
    ->  statistics(cputime, Now),
        Now < Deadline
    ;   true
    ).

search_loop(Open, Ctx, Best0, Best) :-
    Ctx = ctx(Search, _, _, _, _, _, _, _, _),
    (   budget_left(Ctx),
        open_pop(Search, Open, Node, Open1),
        \+ no_better_left(Search, Node, Best0)
    ->  (   expandable(Node, Ctx, Best0)
        ->  refine(Node, Ctx, Best0, Best2, Children),
            include(expandable_child(Ctx), Children, Keep0),
            lookahead(Keep0, Ctx, Best2, Best1, Keep, []),
            open_push(Search, Keep, Open1, Open3),
            setting(openlist, Beam),
            open_limit(Beam, Search, Open3, Open2)
        ;   Best1 = Best0, Open2 = Open1
        ),
        search_loop(Open2, Ctx, Best1, Best)
    ;   Best = Best0
    ).

expandable_child(Ctx, Node) :- expandable(Node, Ctx, none).

%   lookahead(+Children, +Ctx, +Best0, -Best, -Open, ?Tail) (planerel's own,
%   set(lazy_lookahead, true); otherwise Open is Children): a literal whose
%   outputs only lazily evaluated literals take as input (a measure:
%   rise(B,C,D), height(B,H)) changes no coverage by itself, and a first
%   threshold on a measure often not enough (a band needs gteq and lteq), so
%   in a best-first search such a node, scored as its parent, waits behind
%   every better-scored node and its thresholds are never evaluated.  With
%   the lookahead, a child whose last literal is a measure or a lazily
%   evaluated literal is refined at once by the lazily evaluated literals on
%   the same values (those after it in the bottom clause, lazy_table/3): its
%   thresholds (and theirs, up to clauselength) are evaluated, counted as
%   nodes and considered as clauses when the child is made, and go to the
%   open list with their own scores.  The child keeps its place in the open
%   list; when it is refined later those literals are left out
%   (looked_ahead/2), so no clause is made twice.
lookahead(Cs, Ctx, Best0, Best, Open, Tail) :-
    nb_getval(planerel_lazy_next, LT),
    (   LT == none
    ->  Best = Best0,
        append(Cs, Tail, Open)
    ;   lookahead_(Cs, LT, Ctx, Best0, Best, Open, Tail)
    ).

lookahead_([], _, _, Best, Best, T, T).
lookahead_([C|Cs], LT, Ctx, Best0, Best, [C|Open], Tail) :-
    C = nd(_, J-_, Bound, _, _, _, _, _, _, Seq),
    (   J > 0,
        arg(J, LT, Js0),
        Js0 \== [],
        include(inputs_bound(Ctx, Bound), Js0, Js),
        Js \== [],
        budget_left(Ctx)
    ->  assertz(looked_ahead(Seq, Js)),
        node_answers(C, Ctx, X),
        refine_from(Js, C, X, Ctx, Best0, Best1, GCs0),
        include(expandable_child(Ctx), GCs0, GCs),
        lookahead_(GCs, LT, Ctx, Best1, Best2, Open, Open1)
    ;   Best2 = Best0,
        Open1 = Open
    ),
    lookahead_(Cs, LT, Ctx, Best2, Best, Open1, Tail).

inputs_bound(Ctx, Bound, J) :-
    Ctx = ctx(_, _, _, bottom(_, _, _, LitsT, _), _, _, _, _, _),
    arg(J, LitsT, bl(_, _, In, _, _)),
    ord_subset(In, Bound).

%   lazy_table(+Bottom, +CT, -LT): arg J of LT is the ordset of the lazily
%   evaluated bottom literals after J that take as input a value bottom
%   literal J makes (J a measure: not lazily evaluated, with outputs, each
%   taken as input only by lazily evaluated literals) or takes (J lazily
%   evaluated), [] for any other literal.
lazy_table(bottom(_, _, _, LitsT, NB), CT, LT) :-
    findall(Js, ( between(1, NB, J), lazy_next(J, LitsT, CT, Js) ), All),
    LT =.. [lazy_next|All].

lazy_next(J, LitsT, CT, Js) :-
    arg(J, LitsT, bl(_, _, In, Out, Kind)),
    (   Kind = lazy(_, _)
    ->  lazy_consumers_after(In, J, LitsT, CT, Js)
    ;   Out \== [],
        forall(( member(V, Out), K is V + 2, arg(K, CT, Cons), member(J1, Cons) ),
               arg(J1, LitsT, bl(_, _, _, _, lazy(_, _)))),
        lazy_consumers_after(Out, J, LitsT, CT, Js0),
        Js0 \== []
    ->  Js = Js0
    ;   Js = []
    ).

lazy_consumers_after(Vars, J, LitsT, CT, Js) :-
    findall(J1, ( member(V, Vars), K is V + 2, arg(K, CT, Cons), member(J1, Cons),
                  J1 > J, arg(J1, LitsT, bl(_, _, _, _, lazy(_, _))) ),
            Js0),
    sort(Js0, Js).

%   no_better_left(+Search, +Node, +Best): without explore(true) a search
%   stops, as Aleph's does, once its best acceptable clause covers every
%   positive example still to cover (no clause can cover more); with
%   explore(true) it goes on while a refinement could still score better
%   (fewer negatives), which matters only when noise or minacc allow
%   negatives (with noise 0 such a clause already has the best score).
no_better_left(_, _, best(_, _, nd(_, _, _, _, _, _, P, _, _, _))) :-
    setting(explore, false),
    nb_getval(planerel_search_npos, NP),
    P >= NP.

%   A node is worth refining if it can still be lengthened, covers at least
%   minpos positives, is not yet acceptable (more than noise negatives, or
%   precision below minacc: as in Aleph, an acceptable clause is not
%   specialised further; with explore(true), not yet consistent), and its
%   best refinement could beat the best clause so far.
expandable(nd(_, _, Bound, Len, _, _, P, N, _, _), Ctx, Best) :-
    Ctx = ctx(_, CL, Evalfn, bottom(_, _, HOut, _, _), _, MinPos, MinAcc, Noise, _),
    Len < CL,
    P >= MinPos,
    (   ( N > Noise ; P / (P + N) < MinAcc ; N > 0, setting(explore, true) )
    ->  true                              % not acceptable yet (explore: not consistent)
    ;   \+ ord_subset(HOut, Bound)        % acceptable, but head outputs still unbound
    ),
    (   Best = best(BS, _, _)
    ->  bound(Evalfn, P, Len, B),
        B > BS
    ;   true
    ).

%   Refining a node: its clause is proved once on each example it covers,
%   keeping every answer (the distinct values of its bound variables and
%   the head's variables, up to tuple_cap/1 per example); a refinement adds
%   one literal, so it covers an example iff the literal holds for one of
%   those answers (the first that does ends the test).  Past the cap an
%   example is tested by proving the whole refined clause.  The values a
%   lazily evaluated literal collects are the answers projected on its
%   input variables (cached per variable set).

refine(Node, Ctx, Best0, Best, Children) :-
    Node = nd(_, Last-_, Bound, _, _, _, _, _, _, Seq),
    node_answers(Node, Ctx, X),
    candidate_literals(Last, Bound, Js1),
    (   looked_ahead(Seq, Done)           % lazy_lookahead: made already
    ->  ord_subtract(Js1, Done, Js)
    ;   Js = Js1
    ),
    refine_from(Js, Node, X, Ctx, Best0, Best, Children).

%   refine_from(+Js, ...): the refinements by the bottom literals Js (in
%   ascending order), those whose inputs are all bound.
refine_from([], _, _, _, Best, Best, []).
refine_from([J|Js], Node, X, Ctx, Best0, Best, Children) :-
    Ctx = ctx(_, _, _, bottom(_, _, _, LitsT, _), _, _, _, _, _),
    arg(J, LitsT, BL),
    BL = bl(_, _, In, _, _),
    Node = nd(_, _, Bound, _, _, _, _, _, _, _),
    (   \+ ord_subset(In, Bound)         % inputs not bound: no refinement
    ->  refine_from(Js, Node, X, Ctx, Best0, Best, Children)
    ;   \+ budget_left(Ctx)             % (checked only here: nothing else counts)
    ->  Best = Best0, Children = []
    ;   children_of(BL, Node, X, Ctx, Best0, Best1, Children, Rest),
        refine_from(Js, Node, X, Ctx, Best1, Best, Rest)
    ).

%   candidate_literals(+Last, +Bound, -Js): the bottom literals after Last
%   that may have all their inputs bound, in ascending order: those without
%   inputs and those with an input among the bound variables Bound (from the
%   table of consumers made once per search, consumer_table/2), a superset
%   of the literals a node can be refined by and usually a small part of a
%   large bottom clause (a stairs object's has ~1 000 literals, a node binds
%   a few of its variables).  refine_from/7 tests each one's inputs as a scan
%   of every literal after Last did, in the same order, so the refinements
%   are the same.
candidate_literals(Last, Bound, Js) :-
    nb_getval(planerel_consumers, CT),
    arg(1, CT, Free),
    consumer_lists(Bound, CT, Lists),
    ord_union([Free|Lists], Js0),
    drop_upto(Js0, Last, Js).

consumer_lists([], _, []).
consumer_lists([V|Vs], CT, [L|Ls]) :-
    K is V + 2,
    arg(K, CT, L),
    consumer_lists(Vs, CT, Ls).

drop_upto([J|Js], Last, Rest) :-
    J =< Last, !,
    drop_upto(Js, Last, Rest).
drop_upto(Js, _, Js).

%   consumer_table(+Bottom, +NVars, -CT): arg 1 of CT is the ordset of the
%   bottom literals without inputs, arg Id + 2 the ordset of those with the
%   variable Id among their inputs.
consumer_table(bottom(_, _, _, LitsT, NB), NVars, CT) :-
    findall(V-J, ( between(1, NB, J), arg(J, LitsT, bl(_, _, In, _, _)),
                   ( In == [] -> V = free ; member(V, In) ) ),
            Pairs0),
    msort(Pairs0, Pairs),
    N1 is NVars + 1,
    functor(CT, consumers, N1),
    fill_consumers(Pairs, CT),
    term_variables(CT, Empty),            % variables no literal takes as input
    maplist(=([]), Empty).

fill_consumers([], _).
fill_consumers([V-J|Ps], CT) :-
    take_key(Ps, V, Js, Rest),
    ( V == free -> K = 1 ; K is V + 2 ),
    arg(K, CT, [J|Js]),
    fill_consumers(Rest, CT).

take_key([V0-J|Ps], V, [J|Js], Rest) :-
    V0 == V, !,
    take_key(Ps, V, Js, Rest).
take_key(Ps, _, [], Ps).

%   node_answers(+Node, +Ctx, -X): X = x(BV, BIds, VT, AH, PC, NC, cache(Assoc)),
%   where AH holds the node's answers (force_answers/3), computed only when
%   something needs them: a refinement whose coverage is not in the cache,
%   or a lazily evaluated literal whose constants are not (with caching on,
%   most refinements of the short clauses every search starts with are).
%   A node's answers come from its parent's: the node adds one literal, and
%   every variable of the parent's body is among the parent's answer
%   variables, so the node's answers on an example are the parent's answers
%   extended by the solutions of that literal (one literal call per parent
%   answer instead of a proof of the whole body; the parent's answer holder
%   stays referenced by its children in the open list).  An example past the
%   cap on either side is proved in full, as before.
node_answers(Node, Ctx, x(BV, BIds, VT, AH, PC, NC, cache(A))) :-
    Node = nd(Body, Last-PX, Bound, Len, PC, NC, _, _, _, _),
    Ctx = ctx(_, _, _, bottom(Head, _, HOut, _, _), _, _, _, _, VT),
    ord_union(Bound, HOut, BIds0),
    live_ids(Last, Live),
    ord_intersection(BIds0, Live, BIds),
    vars_of(BIds, VT, BV),
    (   PX = px(_, PAH)
    ->  arg(2, PAH, PChain)
    ;   PChain = []
    ),
    AH = ah(todo(Head, Body, BV, Len, PX, PC, NC), [BV|PChain]),
    empty_assoc(A).

%   live_ids(+Last, -Live): the variable ids of the bottom literals
%   after Last (their inputs and outputs), the only variables a refinement
%   of a node whose last literal is Last can use (live_table/2, made once
%   per search).
live_ids(Last, Live) :-
    nb_getval(planerel_live, LiveT),
    K is Last + 1,
    arg(K, LiveT, Live).

%   live_table(+Bottom, -LiveT): arg K of LiveT is the ordset of the
%   variable ids of the bottom literals K.. NB (inputs and outputs).
live_table(bottom(_, _, _, LitsT, NB), LiveT) :-
    NB1 is NB + 1,
    functor(LiveT, live, NB1),
    suffix_live(NB, LitsT, [], LiveT).

suffix_live(0, _, Acc, LiveT) :- !,
    arg(1, LiveT, Acc).
suffix_live(J, LitsT, Acc, LiveT) :-
    J1 is J + 1,
    arg(J1, LiveT, Acc),
    arg(J, LitsT, bl(_, _, In, Out, _)),
    ord_union(In, Out, IO),
    ord_union(Acc, IO, Acc1),
    J0 is J - 1,
    suffix_live(J0, LitsT, Acc1, LiveT).

%   force_answers(+AH, -PT, -NT): the answers of the holder's node on its
%   covered positives and negatives (Id-Tuples, or Id-full past the cap),
%   computed on first use and kept in the holder.  Called only where
%   nothing backtracks over it (setarg/3 is undone on backtracking; the
%   answers would then only be computed again).
force_answers(AH, PT, NT) :-
    arg(1, AH, State),
    (   State = done(PT, NT)
    ->  true
    ;   State = todo(Head, Body, BV, Len, PX, PC, NC),
        (   answers_cache_key(Head, Body, AH, Len, Key)
        ->  (   big_cache(Key, ans(PT0, NT0)),
                answers_on(PC, PT0, PT),
                answers_on(NC, NT0, NT)
            ->  flag(planerel_ans_reused, AR, AR + 1)
            ;   all_answers(PX, Head, Body, BV, PC, NC, PT, NT),
                add_big_cache(Key, ans(PT, NT))
            )
        ;   all_answers(PX, Head, Body, BV, PC, NC, PT, NT)
        ),
        setarg(1, AH, done(PT, NT))
    ).

all_answers(px(PBV, PAH), Head, Body, BV, PC, NC, PT, NT) :-
    last(Body, Lit), !,
    force_answers(PAH, PPT, PNT),
    answers_on(PC, PPT, PA),
    answers_on(NC, PNT, NA),
    side_child_answers(pos, Head, Body, BV, PBV, Lit, PA, PT),
    side_child_answers(neg, Head, Body, BV, PBV, Lit, NA, NT).
all_answers(_, Head, Body, BV, PC, NC, PT, NT) :-
    maplist(ex_answers(pos, Head, Body, BV), PC, PT),
    maplist(ex_answers(neg, Head, Body, BV), NC, NT).

%   side_child_answers(+Set, +Head, +Body, +BV, +PBV, +Lit, +ParentAnswers, -Answers):
%   child_answers/8 for every example of one side with one findall/3 over
%   all of them (Id-Tuple pairs, in example order), the pairs then cut into
%   each example's list: the same answers, with one findall/3 per side
%   instead of one per example.  Should a literal raise, the side is done
%   again one example at a time (child_answers/8), where the error means "no
%   answer" for that example alone.
side_child_answers(Set, Head, Body, BV, PBV, Lit, PA, Answers) :-
    lit_goal(Lit, G),
    catch(findall(Id-BV,
                  ( member(Id-PTs, PA), PTs \== full,
                    member(PBV, PTs), call(G) ),
                  Pairs),
          _, fail),
    !,
    tuple_cap(Cap),
    split_answers(PA, Pairs, Set, Head, Body, BV, Cap, Answers).
side_child_answers(Set, Head, Body, BV, PBV, Lit, PA, Answers) :-
    maplist(child_answers(Set, Head, Body, BV, PBV, Lit), PA, Answers).

split_answers([], _, _, _, _, _, _, []).
split_answers([Id-PTs|PA], Pairs0, Set, Head, Body, BV, Cap, [A|As]) :-
    (   PTs == full
    ->  Pairs = Pairs0,
        ex_answers(Set, Head, Body, BV, Id, A)
    ;   take_id(Pairs0, Id, L, Pairs),
        length(L, N),
        (   N >= Cap
        ->  ex_answers(Set, Head, Body, BV, Id, A)
        ;   sort(L, Ts),
            A = Id-Ts
        )
    ),
    split_answers(PA, Pairs, Set, Head, Body, BV, Cap, As).

%   take_id(+Pairs0, +Id, -Tuples, -Pairs): the leading Id-Tuple pairs of Pairs0.
take_id([Id0-T|Ps0], Id, L, Ps) :-
    Id0 == Id, !,
    L = [T|L1],
    take_id(Ps0, Id, L1, Ps).
take_id(Ps, _, [], Ps).

child_answers(Set, Head, Body, BV, PBV, Lit, Id-PTs, Answers) :-
    (   PTs == full
    ->  ex_answers(Set, Head, Body, BV, Id, Answers)
    ;   tuple_cap(Cap),
        lit_goal(Lit, G),
        catch(findall(BV, ( member(PBV, PTs), call(G) ), L),   % at most
              Err, (coverage_error(Err), L = [])),        % |PTs| < Cap times the literal's answers
        length(L, N),
        (   N >= Cap
        ->  ex_answers(Set, Head, Body, BV, Id, Answers)
        ;   sort(L, Ts),
            Answers = Id-Ts
        )
    ).

%   The answers of short clauses (at most two body literals: the ones every
%   seed's search refines, over most examples) are kept per variant of the
%   clause and its answer variables, as their coverage is (child_coverage/10).
%   Longer clauses cover few examples and are rarely met again.
answers_cache_key(Head, Body, AH, Len, Key) :-
    setting(caching, true),
    setting(cache_clauselength, CL),
    ( CL == inf -> true ; Len =< CL ),
    \+ rec_target(_),
    arg(2, AH, Chain),
    variant_sha1(Head-Body-Chain, Key).

%   The answers of a clause (ans(PosAnswers, NegAnswers)) and the values
%   of a variable per example (vals(PosValues, NegValues)) are kept in the
%   recorded database under the variant hash: they are large terms, which
%   recordz/3 stores ~30 times faster than assertz/1 compiles them.
big_cache(Key, Term) :- recorded(Key, Term).

add_big_cache(Key, Term) :-
    recordz(Key, Term, Ref),
    assertz(cache_record(Ref)).

%   The values of a variable are kept as two records: those on the negatives
%   (most of the examples) apart, so that a look-up copies them only when
%   they are needed (a lazy call not in the cache, a projection of the
%   negatives): vals(PosValues, Ref) under the key, Ref the record
%   vneg(NegValues).
add_vals_cache(Key, PEx, NEx) :-
    recordz(planerel_vneg, vneg(NEx), NRef),
    assertz(cache_record(NRef)),
    add_big_cache(Key, vals(PEx, NRef)).

neg_entry(NRef, NEx) :- recorded(_, vneg(NEx), NRef).

clear_big_cache :-
    forall(retract(cache_record(Ref)), erase(Ref)).

%   answers_on(+Ids, +Answers0, -Answers): the Id-Tuples of Answers0 (sorted
%   by Id, a superset) for the ordset Ids.
answers_on([], _, []).
answers_on([Id|Ids], [Id0-T0|As0], As) :-
    (   Id == Id0
    ->  As = [Id-T0|As1],
        answers_on(Ids, As0, As1)
    ;   answers_on([Id|Ids], As0, As)
    ).

vars_of(Ids, VT, T) :-
    maplist(var_of(VT), Ids, Vs),
    T =.. [t|Vs].

var_of(VT, Id, V) :- K is Id + 1, arg(K, VT, V).

tuple_cap(1000).

ex_answers(Set, Head, Body, BV, Id, Id-Ts) :-
    example_atom(Set, Id, E),
    tuple_cap(Cap),
    catch(findall(BV, limit(Cap, (Head = E, prove_body(Body))), L),
          Err, (coverage_error(Err), L = [])),
    length(L, N),
    (   N >= Cap
    ->  Ts = full
    ;   sort(L, Ts)
    ).

%   projection(+X, +Side, +Ids, -IV, -Proj): Proj is Id-Tuples (or Id-full)
%   for each example of Side covered by the node, the distinct values of the
%   variables Ids (a subset of the node's bound and head variables) as IV.
projection(X, Side, Ids, IV, Proj) :-
    X = x(BV, BIds, VT, AH, _, _, C),
    vars_of(Ids, VT, IV),
    C = cache(A0),
    (   get_assoc(Side-Ids, A0, Proj)
    ->  true
    ;   Ids = [_],
        get_assoc(valsrc-Ids, A0, src(PEx, NRef)),
        X = x(_, _, _, _, PC, NC, _),
        (   Side == pos
        ->  proj_from_vals(PC, PEx, Proj)
        ;   neg_entry(NRef, NEx),
            proj_from_vals(NC, NEx, Proj)
        )
    ->  flag(planerel_proj_reused, PR, PR + 1),
        put_assoc(Side-Ids, A0, Proj, A1),
        setarg(1, C, A1)
    ;   force_answers(AH, PT, NT),
        ( Side == pos -> L = PT ; L = NT ),
        (   Ids = [Id1]
        ->  nth1(K, BIds, Id1), !,
            maplist(project1(K), L, Proj)
        ;   maplist(project(BV, IV), L, Proj)
        ),
        put_assoc(Side-Ids, A0, Proj, A1),
        setarg(1, C, A1)
    ).

%   proj_from_vals(+Ids, +IdValues, -Proj): the projection of a node's
%   answers on one variable (as project1/3 makes it) from the values of the
%   variable per example kept run-wide (big_cache/2, lazy_flat/6): Id-full
%   for an example past the answer cap, Id-[t(V1), ...] for one whose values
%   are all bound (the projected tuples are exactly those, in that order);
%   fails for one with an unbound value (not kept) or not among IdValues.
proj_from_vals([], _, []).
proj_from_vals([Id|Ids], [Id0-E|T], Proj) :-
    (   Id == Id0
    ->  (   E = full(_)
        ->  Proj = [Id-full|Proj1]
        ;   E \= partial(_),
            wrap_t(E, Ts),
            Proj = [Id-Ts|Proj1]
        ),
        proj_from_vals(Ids, T, Proj1)
    ;   Id0 < Id
    ->  proj_from_vals([Id|Ids], T, Proj)
    ).

wrap_t([], []).
wrap_t([V|Vs], [t(V)|Ts]) :- wrap_t(Vs, Ts).

project1(_, Id-full, Id-full) :- !.
project1(K, Id-Ts, Id-Ps) :-
    args_of(Ts, K, P0),                 % no findall: no copy of the tuples
    sort(P0, Ps).

args_of([], _, []).
args_of([T|Ts], K, [t(V)|Vs]) :-
    arg(K, T, V),
    args_of(Ts, K, Vs).

project(_, _, Id-full, Id-full) :- !.
project(BV, IV, Id-Ts, Id-Ps) :-
    findall(IV, member(BV, Ts), P0),
    sort(P0, Ps).

%   child_cover(+Answers, +BV, +Lit, +Set, +Head, +Body1, +Need, -Ids): the
%   examples of Answers (Id-Tuples of the parent's variables BV) that the
%   refined clause covers; fails as soon as fewer than Need could be covered.
child_cover(Proj, IV, Lit, Set, Head, Body1, Need, Ids) :-
    length(Proj, N),
    lit_goal(Lit, G),
    catch(child_cover(Proj, N, Need, IV, G, Set, Head, Body1, Ids, fast), _,
          child_cover(Proj, N, Need, IV, G, Set, Head, Body1, Ids, safe)).

%   One catch/3 around the whole test (fast); only if some literal call
%   raises is the test run again with one catch/3 per call (safe), where an
%   error means "not covered" for that example alone and is reported once.
child_cover([], _, _, _, _, _, _, _, [], _).
child_cover([Id-Ps|T], Left, Need, IV, G, Set, Head, Body1, Ids, Mode) :-
    Left >= Need,
    Left1 is Left - 1,
    (   covered_by(Ps, Id, IV, G, Set, Head, Body1, Mode)
    ->  Ids = [Id|Ids1],
        Need1 is Need - 1
    ;   Ids = Ids1,
        Need1 = Need
    ),
    child_cover(T, Left1, Need1, IV, G, Set, Head, Body1, Ids1, Mode).

%   covered_by(+Answers, +Id, +IV, +G, +Set, +Head, +Body1, +Mode): the
%   refined clause covers example Id: the literal (G, its goal: lit_goal/2)
%   holds for one of the parent's answers Ps (Id-full: the whole clause is
%   proved on the example).
covered_by(Ps, Id, IV, G, Set, Head, Body1, Mode) :-
    (   Ps == full
    ->  covers_id(Set, Head, Body1, Id)
    ;   Mode == fast
    ->  member(P, Ps),
        \+ \+ ( IV = P, call(G) )
    ;   member(P, Ps),
        \+ \+ ( IV = P,
                catch(call(G), E, (coverage_error(E), fail)) )
    ),
    !.

%   capped_cover(+Answers, +IV, +Lit, +Set, +Head, +Body1, +Max, -Ids): as
%   child_cover/8 without a minimum, but fails as soon as more than Max
%   examples are covered.
capped_cover(Proj, IV, Lit, Set, Head, Body1, Max, Ids) :-
    lit_goal(Lit, G),
    catch(capped_cover(Proj, Max, IV, G, Set, Head, Body1, Ids, fast), _,
          capped_cover(Proj, Max, IV, G, Set, Head, Body1, Ids, safe)).

capped_cover([], _, _, _, _, _, _, [], _).
capped_cover([Id-Ps|T], Max, IV, G, Set, Head, Body1, Ids, Mode) :-
    (   covered_by(Ps, Id, IV, G, Set, Head, Body1, Mode)
    ->  Max > 0,
        Max1 is Max - 1,
        Ids = [Id|Ids1]
    ;   Max1 = Max,
        Ids = Ids1
    ),
    capped_cover(T, Max1, IV, G, Set, Head, Body1, Ids1, Mode).

children_of(bl(J, Lit, In, Out, none), Node, X, Ctx, Best0, Best, Cs, T) :- !,
    make_child(J, Lit, In-all, Out, Node, X, Ctx, Best0, Child),
    live_child(Child, Ctx, Best0, Best, Cs, T).
children_of(bl(J, Lit, In, Out, lazy(InPos, CPos)), Node, X, Ctx, Best0, Best, Cs, T) :-
    lazy_constants(Lit, InPos, CPos, Node, X, Ctx, Consts),
    lazy_children(Consts, J, Lit, In, CPos, Out, Node, X, Ctx, Best0, Best, Cs, T).

lazy_children([], _, _, _, _, _, _, _, _, Best, Best, T, T).
lazy_children([C|Cs], J, Lit, In, CPos, Out, Node, X, Ctx, Best0, Best, L, T) :-
    (   budget_left(Ctx)
    ->  set_args(CPos, C, Lit, Lit1),
        make_child(J, Lit1, In-lits, Out, Node, X, Ctx, Best0, Child),
        live_child(Child, Ctx, Best0, Best1, L, L1),
        lazy_children(Cs, J, Lit, In, CPos, Out, Node, X, Ctx, Best1, Best, L1, T)
    ;   Best = Best0, L = T
    ).

set_args(Pos, Vals, Lit, Lit1) :-
    Lit =.. [F|As],
    set_args_(As, 1, Pos, Vals, As1),
    Lit1 =.. [F|As1].

set_args_([], _, _, _, []).
set_args_([A|As], I, Pos, Vals, [B|Bs]) :-
    (   nth1(K, Pos, I)
    ->  nth1(K, Vals, B)
    ;   B = A
    ),
    I1 is I + 1,
    set_args_(As, I1, Pos, Vals, Bs).

%   make_child(..., +Best0, -Child): Child is the refined node, or dead when
%   it can neither be accepted as better than Best0 nor be refined (fewer
%   than minpos positives, or too few positives for its best possible score
%   to reach Best0's); a dead child's negatives are not tested.
make_child(J, Lit, In-How, Out, nd(Body, _, Bound, Len, _, _, _, _, _, _), X, Ctx, Best0, Child) :-
    Ctx = ctx(_, _, Evalfn, bottom(Head, _, _, _, _), _, MinPos, _, _, _),
    append(Body, [Lit], Body1),
    ord_union(Bound, Out, Bound1),
    Len1 is Len + 1,
    count_node,
    X = x(BV, _, _, AH, PC, _, _),
    length(PC, NP),
    pos_needed(Best0, Evalfn, MinPos, Len1, NP, Need),
    (   ( How == all ; Lit = '$rec'(_) )
    ->  LitIds = all
    ;   X = x(_, BIds, _, _, _, _, _),
        ord_union(In, Out, LitIds0),
        ord_intersection(LitIds0, BIds, LitIds)
    ),
    Ctx = ctx(_, CL, _, _, _, _, _, Noise, _),
    (   Len1 >= CL
    ->  NegMax = Noise                % cannot be refined: only acceptable or not
    ;   NegMax = inf
    ),
    child_coverage(Head, Body1, Len1, X, Lit, LitIds, Need-NegMax, Cov),
    (   Cov = cov(PC1, NC1)
    ->  length(PC1, P1),
        length(NC1, N1),
        score(Evalfn, P1, N1, Len1, S),
        flag(planerel_search_nodes, Seq, Seq),
        Child = nd(Body1, J-px(BV, AH), Bound1, Len1, PC1, NC1, P1, N1, S, Seq)
    ;   Child = dead
    ).

%   child_coverage(+Head, +Body1, +Len1, +X, +Lit, +LitIds, +Need, -Cov): Cov
%   is cov(PC1, NC1), the positives and negatives of the parent's (X) that
%   the refined clause Head :- Body1 covers, or dead when fewer than Need
%   positives or the seed would be lost.  With caching (Aleph's setting;
%   here on by default) a clause's coverage is kept per variant of the
%   clause as two bit sets and reused whenever the same clause comes up
%   again: within a search the same refinement is reached once per plane of
%   the object (has_plane(A,B), orientation(B,vertical) for each vertical
%   plane B), and every seed's search starts with the same short clauses.
%   Reuse is exact: a variant clause has the same parent (its body minus the
%   last literal), whose covered examples can only have shrunk since
%   (positives are removed by greedy cover, negatives never change), so the
%   cached set intersected with the parent's is the child's coverage.
%
%   Without a cached set the literal is tested on the parent's answers
%   projected on the literal's own bound variables LitIds (the distinct
%   values, shared by every refinement with the same variables, e.g. the
%   thresholds of one lazily evaluated literal): the literal holds for some
%   answer iff it holds for some projected value, as it touches no other
%   variable.  The parent's answers are computed (force_answers/3) only on
%   a cache miss, outside any condition, so that they are kept for its
%   other refinements.
child_coverage(Head, Body1, Len1, X, Lit, LitIds, Need-NegMax, Cov) :-
    X = x(_, _, _, _, PC, NC, _),
    (   cache_key(Head, Body1, Len1, Key)
    ->  (   cov_inconsistent(Key)
        ->  flag(planerel_cache_hits, H, H + 1),
            Cov = dead
        ;   cov_cache(Key, PB, NB)
        ->  flag(planerel_cache_hits, H, H + 1),
            (   bits_filter(PC, PB, PC1),
                length(PC1, P1),
                P1 >= Need,
                keeps_seed(PC, PC1)
            ->  bits_filter(NC, NB, NC1),
                Cov = cov(PC1, NC1)
            ;   Cov = dead
            )
        ;   projected_cover(X, Head, Body1, Lit, LitIds, Need-NegMax, Cov),
            (   Cov = cov(PC1, NC1)
            ->  ids_bits(PC1, PB),
                ids_bits(NC1, NB),
                assertz(cov_cache(Key, PB, NB))
            ;   Cov = inconsistent
            ->  assertz(cov_inconsistent(Key))
            ;   true
            )
        )
    ;   projected_cover(X, Head, Body1, Lit, LitIds, Need-NegMax, Cov)
    ).

%   A refinement at clauselength cannot be refined, so only whether it is
%   acceptable matters: its negatives are tested first and only until more
%   than noise are covered (Cov = inconsistent, a dead child: the clause
%   covers too many negatives whatever positives are left, so this is kept
%   per variant like a coverage).  Same clauses explored, same theory.
projected_cover(X, Head, Body1, Lit, LitIds, Need-NegMax, Cov) :-
    NegMax \== inf, !,
    X = x(_, _, _, _, PC, _, _),
    length(PC, NP),
    (   Need > NP                      % too few positives whatever the negatives
    ->  Cov = dead
    ;   side_answers(X, neg, LitIds, IV, NProj),   % outside a condition: kept (setarg/3)
        (   capped_cover(NProj, IV, Lit, neg, Head, Body1, NegMax, NC1)
        ->  positive_cover(X, Head, Body1, Lit, LitIds, Need, Cov0),
            (   Cov0 = pos(PC1)
            ->  Cov = cov(PC1, NC1)
            ;   Cov = dead
            )
        ;   Cov = inconsistent
        )
    ).
projected_cover(X, Head, Body1, Lit, LitIds, Need-_, Cov) :-
    positive_cover(X, Head, Body1, Lit, LitIds, Need, Cov0),
    (   Cov0 = pos(PC1)
    ->  side_answers(X, neg, LitIds, IV, NProj),
        child_cover(NProj, IV, Lit, neg, Head, Body1, 0, NC1),
        Cov = cov(PC1, NC1)
    ;   Cov = dead
    ).

%   positive_cover(..., -Cov): pos(PC1), the parent's positives the refined
%   clause covers, or dead (fewer than Need, or the seed lost).
positive_cover(X, Head, Body1, Lit, LitIds, Need, Cov) :-
    X = x(_, _, _, _, PC, _, _),
    side_answers(X, pos, LitIds, IV, PProj),
    (   child_cover(PProj, IV, Lit, pos, Head, Body1, Need, PC1),
        keeps_seed(PC, PC1)
    ->  Cov = pos(PC1)
    ;   Cov = dead
    ).

%   side_answers(+X, +Side, +LitIds, -IV, -Proj): the parent's answers on its
%   covered examples of Side (pos or neg), all of them (LitIds = all) or
%   projected on the literal's variables LitIds, with their variables IV.
side_answers(X, Side, LitIds, IV, Proj) :-
    X = x(BV, _, _, AH, _, _, _),
    (   LitIds == all
    ->  force_answers(AH, PT, NT),
        ( Side == pos -> Proj = PT ; Proj = NT ),
        IV = BV
    ;   projection(X, Side, LitIds, IV, Proj)
    ).

%   cache_key(+Head, +Body, +Len, -Key): the variant hash of the clause, when
%   caching is on, the clause is not longer than cache_clauselength and no
%   target is recursive (its coverage then depends on the examples left).
cache_key(Head, Body, Len, Key) :-
    setting(caching, true),
    setting(cache_clauselength, CL),
    ( CL == inf -> true ; Len =< CL ),
    \+ rec_target(_),
    variant_sha1(Head-Body, Key).

bits_filter([], _, []).
bits_filter([Id|T], Bits, Ids) :-
    (   getbit(Bits, Id) =:= 1
    ->  Ids = [Id|Ids1]
    ;   Ids = Ids1
    ),
    bits_filter(T, Bits, Ids1).

%   ids_bits(+Ids, -Bits): the ordset of ids as one integer.  The bits are
%   gathered per 60-bit word (small integers) and the words combined once,
%   instead of one big integer per id.
ids_bits(Ids, Bits) :- ids_words(Ids, 0, Bits).

ids_words([], Bits, Bits).
ids_words([Id|Ids], Bits0, Bits) :-
    W is Id // 60,
    B0 is 1 << (Id - 60 * W),
    word_bits(Ids, W, B0, Word, Rest),
    Bits1 is Bits0 \/ (Word << (60 * W)),
    ids_words(Rest, Bits1, Bits).

word_bits([], _, Word, Word, []).
word_bits([Id|Ids], W, B0, Word, Rest) :-
    (   Id // 60 =:= W
    ->  B1 is B0 \/ (1 << (Id - 60 * W)),
        word_bits(Ids, W, B1, Word, Rest)
    ;   Word = B0, Rest = [Id|Ids]
    ).

%   keeps_seed(+ParentCovered, +Covered): a refinement of a clause that covers
%   the seed covers it too.  Only a lazily evaluated threshold can lose it
%   (its constant comes from the other covered examples); such a clause is
%   dropped, as it is no generalisation of the seed's bottom clause, and
%   keeping it would leave the seed uncovered and search it again.
keeps_seed(PC, PC1) :-
    (   nb_current(planerel_seed, S), PC = [S|_]
    ->  PC1 = [S|_]
    ;   true
    ).

live_child(dead, _, Best, Best, T, T) :- !.
live_child(Child, Ctx, Best0, Best, [Child|T], T) :-
    consider(Child, Ctx, Best0, Best).

%   pos_needed(+Best, +Evalfn, +MinPos, +Len, +NP, -Need): the fewest
%   positives a clause of Len literals (or a refinement of it) must cover to
%   score at least Best's score (NP + 1 when none can).
pos_needed(none, _, MinPos, _, _, MinPos) :- !.
pos_needed(best(BS, _, _), Evalfn, MinPos, Len, NP, Need) :-
    (   between(MinPos, NP, P),
        child_max(Evalfn, P, Len, M),
        M >= BS
    ->  Need = P
    ;   Need is NP + 1
    ).

child_max(compression, P, Len, M) :- !, M is P - Len + 1.
child_max(Evalfn, P, Len, M) :- bound(Evalfn, P, Len, M).

%   consider(+Node, +Ctx, +Best0, -Best): keep Node if it is acceptable and
%   better (higher score, then fewer literals, then found earlier).
consider(Node, Ctx, Best0, Best) :-
    Node = nd(_, _, Bound, Len, _, _, P, N, S, _),
    Ctx = ctx(_, _, _, bottom(_, _, HOut, _, _), _, MinPos, MinAcc, Noise, _),
    (   P >= MinPos,
        N =< Noise,
        P / (P + N) >= MinAcc,
        ord_subset(HOut, Bound),
        (   Best0 = best(BS, BL, _)
        ->  ( S > BS ; S =:= BS, Len < BL )
        ;   true
        ),
        \+ violates_constraint(Node, Ctx)
    ->  Best = best(S, Len, Node)
    ;   Best = Best0
    ).

%   violates_constraint(+Node, +Ctx): some integrity constraint false :- Body
%   of the background holds while the node's clause is the current
%   hypothesis (user:hypothesis(Head, Body, [P, N, L]), as in Aleph).
violates_constraint(Node, Ctx) :-
    constraint_decl(_, _), !,
    Node = nd(Body, _, _, Len, _, _, P, N, _, _),
    Ctx = ctx(_, _, _, bottom(Head, _, _, _, _), _, _, _, _, _),
    maplist(unwrap_rec, Body, Body1),
    copy_term(Head-Body1, H-B),
    list_to_conj(B, BC),
    setup_call_cleanup(
        ( retractall(user:hypothesis(_, _, _)),
          assertz(user:hypothesis(H, BC, [P, N, Len])) ),
        once(( constraint_decl(CBody, _),
               catch(user:CBody, E, (constraint_error(E), fail)) )),
        retractall(user:hypothesis(_, _, _))).

list_to_conj([], true).
list_to_conj([L], L) :- !.
list_to_conj([L|Ls], (L, C)) :- list_to_conj(Ls, C).

constraint_error(E) :-
    message_to_codes_text(E, T),
    warn_once(constraint_error(T), "an integrity constraint (false :- ...) raised an error (treated as not violated): ~s", [T]).

%   Lazy evaluation: collect the values the literal's input arguments take
%   on the covered positives and negatives, call the predicate with
%   [PosValues, NegValues] in place of each input argument, and use each
%   answer's constants.
%   With caching the constants are kept per variant of the clause and the
%   literal, with the examples the clause covers: they are a function of
%   both (the values come from the clause's answers on those examples), and
%   the same clause comes up once per plane of the object within a search
%   and again in every search before a rule removes positives.  A hit needs
%   no answers of the node (force_answers/3).  The covered examples are
%   identified by their numbers P and N: a clause covers the examples left
%   that it holds for, and during a run the positives left only shrink and
%   the negatives never change, so for one clause two sets of covered
%   examples of the same size are the same set.
lazy_constants(Lit, InPos, CPos, Node, X, Ctx, Consts) :-
    Node = nd(Body, _, _, _, _, _, P, N, _, _),
    Ctx = ctx(_, _, _, bottom(Head, _, _, _, _), _, _, _, _, _),
    (   setting(caching, true),
        \+ rec_target(_)
    ->  variant_sha1(Head-Body-Lit, Key),
        (   lazy_clause_cache(Key, P, N, Consts0)
        ->  Consts = Consts0
        ;   lazy_constants_(Lit, InPos, CPos, Body, Head, X, Consts),
            assertz(lazy_clause_cache(Key, P, N, Consts))
        )
    ;   lazy_constants_(Lit, InPos, CPos, Body, Head, X, Consts)
    ).

lazy_constants_(Lit, InPos, CPos, Body, Head, X, Consts) :-
    Lit =.. [_|LitArgs],
    args_at(InPos, LitArgs, InVars),
    term_variables(InVars, InVarSet),
    X = x(_, _, VT, _, _, _, _),
    var_ids(InVarSet, VT, Ids0),
    sort(Ids0, Ids),
    vars_of(Ids, VT, IV),
    (   InPos = [I1], InVars = [V], var(V), IV = t(V0), V0 == V
    ->  Flat = true,                       % one input variable: flat value lists
        flat_lazy_values(X, Ids, IV, Head, Body, V, PosTuples, NegT, VHash)
    ;   Flat = false,
        projection(X, pos, Ids, IV, PProj),
        lazy_values(PProj, pos, Head, Body, IV, InVars, PosTuples),
        (   PosTuples == []
        ->  NegTuples = []
        ;   projection(X, neg, Ids, IV, NProj),
            lazy_values(NProj, neg, Head, Body, IV, InVars, NegTuples)
        )
    ),
    (   PosTuples == []
    ->  Consts = []
    ;   Lit =.. [F|As],
        length(As, Ar),
        length(CallArgs, Ar),
        (   Flat == true
        ->  nth1(I1, CallArgs, [PosTuples, NegTuples])
        ;   InPos = [I1]                       % one input: the value lists directly
        ->  maplist(first_value, PosTuples, PV),
            maplist(first_value, NegTuples, NV),
            nth1(I1, CallArgs, [PV, NV])
        ;   fill_lazy_args(InPos, 1, PosTuples, NegTuples, CallArgs)
        ),
        Call =.. [F|CallArgs],
        args_at(CPos, CallArgs, CVars),
        fill_fixed(As, CallArgs, InPos, CPos),
        (   Flat == true                   % the value lists by their hash, made once
        ->  set_nth1(CallArgs, I1, '$values'(VHash), KeyArgs),
            KeyCall =.. [F|KeyArgs],
            variant_sha1(KeyCall-CVars, Key)
        ;   variant_sha1(Call-CVars, Key)
        ),
        (   lazy_cache(Key, Consts0)
        ->  Consts = Consts0
        ;   (   Flat == true               % the negatives' values, made only now
            ->  neg_values(NegT, X, Ids, IV, Head, Body, V, NegTuples)
            ;   true
            ),
            findall(CVars,
                    limit(20, catch(user:Call, E, (lazy_error(F/Ar, E), fail))),
                    Sols0),
            include(ground, Sols0, Sols1),
            list_to_set(Sols1, Consts),
            assertz(lazy_cache(Key, Consts))
        )
    ).

first_value([V|_], V).

set_nth1([_|T], 1, X, [X|T]) :- !.
set_nth1([H|T], N, X, [H|T1]) :- N1 is N - 1, set_nth1(T, N1, X, T1).

%   flat_lazy_values(+X, +Ids, +IV, +Head, +Body, +V, -PV, -NVT, -VHash): for
%   a lazily evaluated literal whose input is the one variable V, the values
%   of V on the node's covered positives as a flat list PV (what
%   lazy_values/7 gives, without a [Value] list per value), those on its
%   covered negatives NV as NVT (nv(NV), or nv(NC, NEx): the values NEx per
%   example kept run-wide, made into the list by neg_values/8 only when the
%   lazy call is not in the cache; NV = [] when PV = []) and VHash, which
%   identifies [PV, NV]: the variant hash of PV and of the hash of NV (none
%   when PV = []).  Made once per node and variable, kept in the node's
%   cache: the gteq and the lteq of one measure share them, and the lazy
%   call is cached by that hash instead of a hash of the value lists per
%   literal.
%
%   The hash of NV is kept per run-wide key of the values and number of
%   covered negatives (nv_hash/3): a clause's covered negatives never change
%   during a run (identified by their number, as in lazy_constants/7), and
%   the values are a function of the key and the example
%   (vals_cache_key/5), so NV is the same list whenever the same clause
%   comes up again (in later searches, with fewer positives left): its
%   hash is made once instead of hashing the ~1 000 negatives' values of
%   every such node again, and the list itself is made only for a call.
flat_lazy_values(X, Ids, IV, Head, Body, V, PV, NVT, VHash) :-
    X = x(_, _, _, AH, PC, NC, C),
    arg(1, C, A0),
    (   get_assoc(flat-Ids, A0, fv(PV, NVT, VHash))
    ->  true
    ;   (   vals_cache_key(Head, Body, V, AH, VKey)
        ->  length(NC, NN),
            (   big_cache(VKey, vals(PEx, NRef)),
                ex_values_on(PC, PEx, PV),
                (   PV == []
                ->  NVT = nv([])
                ;   nv_hash(VKey, NN, NVHash0)
                ->  NVT = nv(NC, NRef), NVHash = NVHash0,
                    flag(planerel_nvhash_reused, NR, NR + 1)
                ;   neg_entry(NRef, NEx),
                    ex_values_on(NC, NEx, NV),
                    NVT = nv(NV)
                )
            ->  Src = src(PEx, NRef),
                flag(planerel_vals_reused, VR, VR + 1)
            ;   fresh_flat_values(X, Ids, IV, Head, Body, V, PEx, NEx),
                add_vals_cache(VKey, PEx, NEx),
                fresh_values_on(PC, NC, PEx, NEx, PV, NV),
                NVT = nv(NV),
                Src = none
            ),
            (   PV == []
            ->  VHash = none
            ;   var(NVHash)
            ->  NVT = nv(NV1),
                variant_sha1(NV1, NVHash),
                assertz(nv_hash(VKey, NN, NVHash)),
                variant_sha1(PV-NVHash, VHash)
            ;   variant_sha1(PV-NVHash, VHash)
            )
        ;   fresh_flat_values(X, Ids, IV, Head, Body, V, PEx, NEx),
            fresh_values_on(PC, NC, PEx, NEx, PV, NV),
            NVT = nv(NV),
            Src = none,
            (   PV == []
            ->  VHash = none
            ;   variant_sha1(NV, NVHash),
                variant_sha1(PV-NVHash, VHash)
            )
        ),
        arg(1, C, A1),
        put_assoc(flat-Ids, A1, fv(PV, NVT, VHash), A2),
        (   Src = src(_, _)               % the projection on V without the answers
        ->  put_assoc(valsrc-Ids, A2, Src, A3)
        ;   A3 = A2
        ),
        setarg(1, C, A3)
    ).

%   neg_values(+NVT, +X, +Ids, +IV, +Head, +Body, +V, -NV): the values of V on
%   the node's covered negatives as one list (flat_lazy_values/9).  From the
%   entry NEx kept run-wide that gave the node's positive values; should it
%   not hold every covered negative (it does: see flat_lazy_values/9), the
%   values are computed afresh from the node's answers, which gives the same
%   list.
neg_values(nv(NV), _, _, _, _, _, _, NV).
neg_values(nv(NC, NRef), X, Ids, IV, Head, Body, V, NV) :-
    (   neg_entry(NRef, NEx),
        ex_values_on(NC, NEx, NV0)
    ->  NV = NV0
    ;   X = x(_, _, _, _, PC, _, _),
        fresh_flat_values(X, Ids, IV, Head, Body, V, PEx, NEx1),
        fresh_values_on(PC, NC, PEx, NEx1, _, NV)
    ).

%   fresh_flat_values(+X, +Ids, +IV, +Head, +Body, +V, -PEx, -NEx): the
%   values of V on each covered positive and negative from the node's
%   answers (lazy_flat/6), as Id-Values per example; NEx = none when no
%   positive has a value (the negatives' values are then not needed).
fresh_flat_values(X, Ids, IV, Head, Body, V, PEx, NEx) :-
    projection(X, pos, Ids, IV, PProj),
    lazy_flat(PProj, pos, Head, Body, V, PEx),
    (   ex_values_on_all(PEx, [])
    ->  NEx = none
    ;   projection(X, neg, Ids, IV, NProj),
        lazy_flat(NProj, neg, Head, Body, V, NEx)
    ).

fresh_values_on(PC, NC, PEx, NEx, PV, NV) :-
    ex_values_on(PC, PEx, PV),
    (   PV == []
    ->  NV = []
    ;   ex_values_on(NC, NEx, NV)
    ).

%   ex_vals(+Entry, -Values): the values of one example's entry (lazy_flat/6).
ex_vals(full(Vs), Vs) :- !.
ex_vals(partial(Vs), Vs) :- !.
ex_vals(Vs, Vs).

ex_values_on_all([], []).
ex_values_on_all([_-E|T], L) :-
    ex_vals(E, Vs),
    append(Vs, L1, L),
    ex_values_on_all(T, L1).

%   vals_cache_key(+Head, +Body, +V, +AH, -Key): the run-wide key of the
%   values of V per example (big_cache/2, with caching on and no
%   recursive target): the variant of the clause, V and the answer
%   variables of the node and of each of its ancestors (AH's chain).  The
%   values of V on an example are then a function of the key and the
%   example: all the values of V in the clause's answers, or those of its
%   first 50 proofs past the answer cap, and whether the cap is passed
%   depends only on the clause and the answer variables kept at each step.
%   So when a later search (another seed, fewer positives left) meets the
%   same clause, its values on the examples it covers are taken from the
%   cache instead of from the node's answers: the covered examples can
%   only have shrunk since (positives leave, negatives never change), and
%   an example missing from the cached ones means computing them afresh.
vals_cache_key(Head, Body, V, AH, Key) :-
    setting(caching, true),
    \+ rec_target(_),
    arg(2, AH, Chain),
    variant_sha1(Head-Body-V-Chain, Key).

%   ex_values_on(+Ids, +IdValues, -Values): the values of the examples Ids
%   (an ordset, each of them in IdValues: fails otherwise) in order, as one
%   list (Aleph's lazy protocol).  With set(lazy_examples, true) each
%   example's values stay together as ex(Values) (examples without a value
%   left out), so that a lazily evaluated threshold can count examples
%   instead of values (prolog/compare.pl): an example with many answers
%   -- a staircase's many pairs of parallel planes -- then weighs as one.
ex_values_on(Ids, IdValues, Vals) :-
    (   setting(lazy_examples, true)
    ->  ex_values_grouped(Ids, IdValues, Vals)
    ;   ex_values_flat(Ids, IdValues, Vals)
    ).

ex_values_flat([], _, []).
ex_values_flat([Id|Ids], [Id0-Vs|T], Vals) :-
    (   Id == Id0
    ->  ex_vals(Vs, Vs1),
        append(Vs1, Vals1, Vals),
        ex_values_flat(Ids, T, Vals1)
    ;   Id0 @< Id
    ->  ex_values_flat([Id|Ids], T, Vals)
    ).

ex_values_grouped([], _, []).
ex_values_grouped([Id|Ids], [Id0-Vs|T], Vals) :-
    (   Id == Id0
    ->  ex_vals(Vs, Vs1),
        (   Vs1 == []
        ->  Vals = Vals1
        ;   Vals = [ex(Vs1)|Vals1]
        ),
        ex_values_grouped(Ids, T, Vals1)
    ;   Id0 @< Id
    ->  ex_values_grouped([Id|Ids], T, Vals)
    ).

%   lazy_flat(+Proj, +Set, +Head, +Body, +V, -IdValues): the values of V in
%   the answers of each covered example, in example order (an example past
%   the answer cap: the values of its first 50 proofs), as lazy_values/7,
%   as Id-Entry per example: Entry is the list of values, full(Values) past
%   the cap, partial(Values) when some value was unbound (left out), so
%   that proj_from_vals/3 can tell which entries are a projection.
lazy_flat([], _, _, _, _, []).
lazy_flat([Id-Ps|T], Set, Head, Body, V, [Id-Entry|IVs]) :-
    (   Ps == full
    ->  example_atom(Set, Id, E),
        findall(V, catch(limit(50, (Head = E, prove_body(Body))), _, fail), L0),
        include(ground, L0, Vals),
        Entry = full(Vals)
    ;   ground_values(Ps, Vals, []),
        (   same_length(Ps, Vals)
        ->  Entry = Vals
        ;   Entry = partial(Vals)         % some value unbound (left out)
        )
    ),
    lazy_flat(T, Set, Head, Body, V, IVs).

ground_values([], L, L).
ground_values([t(X)|Ts], L0, L) :-
    (   ground(X)
    ->  L0 = [X|L1]
    ;   L0 = L1
    ),
    ground_values(Ts, L1, L).

%   args_at(+Positions, +Args, -Values): the arguments at Positions (shared,
%   not copied).
args_at([], _, []).
args_at([I|Is], Args, [V|Vs]) :- nth1(I, Args, V), args_at(Is, Args, Vs).

fill_lazy_args([], _, _, _, _).
fill_lazy_args([I|Is], K, PT, NT, CallArgs) :-
    findall(V, (member(T, PT), nth1(K, T, V)), PV),
    findall(V, (member(T, NT), nth1(K, T, V)), NV),
    nth1(I, CallArgs, [PV, NV]),
    K1 is K + 1,
    fill_lazy_args(Is, K1, PT, NT, CallArgs).

fill_fixed(As, CallArgs, InPos, CPos) :-
    forall(( nth1(I, As, A), \+ memberchk(I, InPos), \+ memberchk(I, CPos) ),
           nth1(I, CallArgs, A)).

%   var_ids(+Vars, +VT, -Ids): the bottom clause's variable numbers of Vars.
var_ids(Vars, VT, Ids) :-
    functor(VT, _, N),
    findall(Id, ( member(V, Vars), between(1, N, K), arg(K, VT, W), W == V, Id is K - 1 ), Ids).

%   lazy_values(+Proj, +Set, +Head, +Body, +IV, +InVars, -Tuples): the
%   distinct values of InVars in the answers of each covered example (in
%   example order; Proj is the projection of the answers on InVars' set IV);
%   an example past the answer cap gives the values of its first 50 proofs.
lazy_values(Answers, Set, Head, Body, BV, InVars, Tuples) :-
    foldl(lazy_values_(Set, Head, Body, BV, InVars), Answers, Tuples, []).

lazy_values_(Set, Head, Body, _, InVars, Id-full, T0, T) :- !,
    example_atom(Set, Id, E),
    findall(InVars, catch(limit(50, (Head = E, prove_body(Body))), _, fail), L0),
    include(ground, L0, L),
    append(L, T, T0).
lazy_values_(_, _, _, BV, [V], _-Ts, T0, T) :- BV = t(V), !,   % one variable
    ground_singletons(Ts, T0, T).
lazy_values_(_, _, _, BV, InVars, _-Ts, T0, T) :-
    findall(InVars, member(BV, Ts), L0),
    include(ground, L0, L1),
    sort(L1, L),
    append(L, T, T0).

%   ground_singletons(+Tuples, -L0, +L): the ground values of the t(X) in
%   Tuples as [X] lists, in order, as the difference list L0-L.
ground_singletons([], L, L).
ground_singletons([t(X)|Ts], L0, L) :-
    (   ground(X)
    ->  L0 = [[X]|L1]
    ;   L0 = L1
    ),
    ground_singletons(Ts, L1, L).

example_atom(pos, Id, E) :- pos_ex(Id, E).
example_atom(neg, Id, E) :- neg_ex(Id, E).

lazy_error(PI, E) :-
    message_to_codes_text(E, T),
    warn_once(lazy_error(PI),
              "lazy evaluation of ~w raised an error (it must accept [PosValues, NegValues] in place of its input argument): ~s",
              [PI, T]).

%   open_limit(+Beam, +Search, +Open0, -Open): Aleph's openlist: keep the
%   Beam first nodes of the open list (the best ones for heuristic search).
open_limit(inf, _, O, O) :- !.
open_limit(N, bf, q(F, B), Q) :- !,
    reverse(B, RB), append(F, RB, All),
    (   length(All, L), L > N
    ->  length(Keep, N), append(Keep, _, All), Q = q(Keep, [])
    ;   Q = q(F, B)
    ).
open_limit(N, df, S, S1) :- !,
    (   length(S, L), L > N
    ->  length(S1, N), append(S1, _, S)
    ;   S1 = S
    ).
open_limit(N, heuristic, H, H1) :-
    (   heap_size(H, L), L > N
    ->  heap_to_list(H, Pairs),
        length(Keep, N), append(Keep, _, Pairs),
        list_to_heap(Keep, H1)
    ;   H1 = H
    ).

%   The open list.
open_empty(bf, q([], [])).
open_empty(df, []).
open_empty(heuristic, H) :- empty_heap(H).

open_push(bf, Ns, q(F, B0), q(F, B)) :- reverse(Ns, R), append(R, B0, B).
open_push(df, Ns, S0, S) :- append(Ns, S0, S).
open_push(heuristic, Ns, H0, H) :- foldl(heap_add, Ns, H0, H).

heap_add(Node, H0, H) :-
    Node = nd(_, _, _, Len, _, _, _, _, S, Seq),
    NS is -S,
    add_to_heap(H0, k(NS, Len, Seq), Node, H).

open_pop(bf, q(F, B), N, Q) :-
    (   F = [N|F1]
    ->  Q = q(F1, B)
    ;   B \== [],
        reverse(B, [N|F1]),
        Q = q(F1, [])
    ).
open_pop(df, [N|S], N, S).
open_pop(heuristic, H0, N, H) :- get_from_heap(H0, _, N, H).

                 /*******************************
                 *            INDUCE            *
                 *******************************/

%!  induce is det.
%
%   Learn a theory from the examples read by read_all/1 by greedy cover and
%   print it with the confusion matrix of the training set (and of the test
%   set when test_pos/test_neg are set).
induce :-
    (   loaded_stem(_)
    ->  true
    ;   input_error("induce/0: nothing read; call read_all(Stem) first", [])
    ),
    retractall(theory_clause(_, _, _, _, _)),
    retractall(rec_target(_)),
    retractall(lazy_cache(_, _)),
    retractall(lazy_clause_cache(_, _, _, _)),
    retractall(cov_cache(_, _, _)),
    retractall(cov_inconsistent(_)),
    retractall(nv_hash(_, _, _)),
    clear_big_cache,
    forall(member(F, [planerel_ans_reused, planerel_vals_reused, planerel_proj_reused,
                      planerel_nvhash_reused]),
           flag(F, _, 0)),
    flag(planerel_cache_hits, _, 0),
    retractall(hopeless_bottom(_)),
    flag(planerel_set_aside, _, 0),
    statistics(cputime, T0),
    nb_setval(planerel_t0, T0),
    flag(planerel_nodes, _, 0),
    flag(planerel_rule_no, _, 0),
    findall(F/A, (pos_ex(_, E), functor(E, F, A)), Ts0),
    list_to_set(Ts0, Targets),
    forall(member(T, Targets), check_target(T)),
    setup_extensional,
    load_test_sets,
    print_settings,
    findall(Id, pos_ex(Id, _), Rem),
    cover_loop(Rem),
    statistics(cputime, T1),
    T is T1 - T0,
    nb_setval(planerel_search_time, T),
    print_theory,
    report_performance.

check_target(T) :-
    T = N/A,
    (   mode_decl(h, _, Tm, _, _), functor(Tm, N, A)
    ->  true
    ;   input_error("no modeh declaration for the target ~w/~w of the positive examples", [N, A])
    ),
    body_modes(T, Modes),
    findall(Ty, ( mode_decl(h, _, Tm2, _, _), functor(Tm2, N, A),
                  mode_skeleton(Tm2, _, Ps), member(ph(in, Ty, _), Ps) ), HT),
    findall(Ty, ( member(m(_, Tb, _, _, _), Modes),
                  mode_skeleton(Tb, _, Ps), member(ph(out, Ty, _), Ps) ), OT),
    append(HT, OT, Provided),
    forall(( member(m(_, Tb, _, Seq, _), Modes),
             mode_skeleton(Tb, _, Ps), member(ph(in, Ty, _), Ps) ),
           (   memberchk(Ty, Provided)
           ->  true
           ;   mode_decl(b, _, _, Where, Seq),
               where_text(Where, W),
               input_error("~s: undeclared type ~w in ~q: no modeh input (+~w) and no modeb output (-~w) of target ~w/~w provides it",
                           [W, Ty, Tb, Ty, Ty, N, A])
           )).

load_test_sets :-
    retractall(tpos_ex(_, _)),
    retractall(tneg_ex(_, _)),
    forall(member(S, [test_pos, test_neg]),
           (   setting_value(S, File, Where)
           ->  resolve_file(File, Where, Path, S),
               atom_concat(planerel_id_, S, Flag),
               flag(Flag, _, 0),
               read_source(Path, S)
           ;   true
           )).

resolve_file(File, Where, Path, S) :-
    (   exists_file(File)
    ->  Path = File
    ;   Where = WFile:_,
        file_directory_name(WFile, Dir),
        directory_file_path(Dir, File, P1),
        exists_file(P1)
    ->  Path = P1
    ;   where_text(Where, W),
        input_error("~s: the file ~w of setting ~w does not exist", [W, File, S])
    ).

cover_loop([]) :- !.
cover_loop(Rem0) :-
    sample_seeds(Rem0, Seeds),
    maplist(seed_search(Rem0), Seeds, Results),
    partition(found_clause, Results, Found, Failed),
    findall(Id, member(r(Id, _, _, _, _, _, _, _), Failed), FailedIds0),
    sort(FailedIds0, FailedIds),
    ord_subtract(Rem0, FailedIds, Rem1),
    maplist(set_aside(Rem1), Failed),   % seeds without an acceptable clause
    (   best_result(Found, r(SeedId, Seed, Head, best(_, _, Node), _, NB, Explored, _))
    ->  Node = nd(Body, _, _, _, PC, _, P, N, _, _),
        add_rule(Head, Body, P, N),
        ord_subtract(Rem1, PC, Rem2),
        ord_subtract(Rem2, [SeedId], Rem),   % the seed is covered (P >= minpos >= 1); be safe
        report_seed(SeedId, Seed, NB, Explored, rule, Rem)
    ;   Rem = Rem1
    ),
    cover_loop(Rem).

found_clause(r(_, _, _, best(_, _, _), _, _, _, _)).

%   sample_seeds(+Remaining, -Seeds): the seeds of the next clause.  Without
%   samplesize (0 or 1, Aleph's default 0) the first positive not yet covered;
%   with samplesize K >= 2, K of them spread evenly over the remaining
%   positives in file order (the first among them), and the best clause of
%   the K searches is added (Aleph draws its sample at random; evenly spaced
%   keeps the theory deterministic without a random seed).
sample_seeds(Rem, Seeds) :-
    setting(samplesize, K),
    length(Rem, L),
    (   K >= 2, L >= 2
    ->  M is min(K, L),
        findall(Id, ( between(0, M, I0), I0 < M,
                      Pos is (I0 * L) // M,
                      nth0(Pos, Rem, Id) ), Ids0),
        list_to_set(Ids0, Seeds)
    ;   Rem = [Seed|_],
        Seeds = [Seed]
    ).

%   seed_search(+Remaining, +SeedId, -Result): saturate the seed and search
%   its best acceptable clause over the remaining positives of its target.
%   Result = r(SeedId, Seed, Head, Best, BottomSig, BottomSize, Explored, Why),
%   Best = none when there is no acceptable clause (Why says why).
seed_search(Rem, SeedId, r(SeedId, Seed, Head, Best, Sig, NB, Explored, Why)) :-
    pos_ex(SeedId, Seed),
    functor(Seed, F, A),
    saturate(Seed, Bottom0, VT),
    Bottom0 = bottom(Head, HIn, HOut, LitsT0, NB),
    LitsT0 =.. [_|BLs0],
    maplist(mark_recursive(F/A), BLs0, BLs),
    LitsT =.. [lits|BLs],
    Bottom = bottom(Head, HIn, HOut, LitsT, NB),
    include(same_functor(pos, F, A), Rem, PosIds),
    findall(Id, (neg_ex(Id, E), functor(E, F, A)), NegIds),
    make_ctx(Bottom, VT, Ctx),
    nb_setval(planerel_seed, SeedId),
    flag(planerel_search_nodes, _, 0),
    variant_sha1(Bottom, Sig),
    setting(minpos, MinPos),
    length(PosIds, NLeft),
    (   NLeft < MinPos                  % as Aleph: no search for fewer than minpos left
    ->  Best = none, Why = 'fewer than minpos positives left'
    ;   setting(skip_same_bottom, true),
        hopeless_bottom(Sig)
    ->  Best = none, Why = 'same bottom clause as a seed without a clause'
    ;   search_clause(Bottom, PosIds, NegIds, Ctx, Best),
        Why = 'no acceptable clause'
    ),
    flag(planerel_search_nodes, Explored, Explored).

%   best_result(+Found, -Chosen): of the seeds that found a clause, the one
%   with the best clause (higher score, then fewer literals, then the earlier
%   seed); fails when there is none.
best_result(Found, Chosen) :-
    findall(k(NS, Len, Id)-R,
            ( member(R, Found),
              R = r(Id, _, _, best(S, Len, _), _, _, _, _),
              NS is -S ),
            Keyed),
    keysort(Keyed, [_-Chosen|_]).

%   set_aside(+Remaining, +Result): a seed without an acceptable clause is removed (as
%   Aleph, the seed itself becomes a rule only when minpos =< 1), and later
%   seeds with a variant of its bottom clause are set aside without a search
%   (skip_same_bottom, planerel's own).
set_aside(Rem, r(SeedId, Seed, _, _, Sig, NB, Explored, Why)) :-
    ( hopeless_bottom(Sig) -> true ; assertz(hopeless_bottom(Sig)) ),
    flag(planerel_set_aside, K, K + 1),
    setting(minpos, MinPos),
    (   MinPos =< 1                     % as Aleph: the seed itself is a rule only
    ->  findall(x, (neg_ex(_, NE), NE =@= Seed), Ns),   % if it reaches minpos
        length(Ns, NN),
        add_rule(Seed, [], 1, NN),
        Outcome = rule
    ;   Outcome = set_aside(Why)
    ),
    report_seed(SeedId, Seed, NB, Explored, Outcome, Rem).

report_seed(SeedId, Seed, NB, Explored, Outcome, Rem) :-
    (   setting(verbosity, V), V >= 1
    ->  flag(planerel_rule_no, RN, RN),
        (   Outcome == rule
        ->  format("[seed ~w] ~q: bottom clause of ~w literals, ~w clauses explored -> rule ~w~n",
                   [SeedId, Seed, NB, Explored, RN]),
            functor(Seed, F, A),
            progress_line(F/A, RN, Rem)
        ;   Outcome = set_aside(W),
            format("[seed ~w] ~q: bottom clause of ~w literals, ~w clauses explored -> set aside (~w)~n",
                   [SeedId, Seed, NB, Explored, W])
        )
    ;   true
    ).

%   progress_line(+Target, +RuleNo, +Remaining): one line on stderr per rule
%   added ("progress: ..."), which planerel shows while a long search runs.
progress_line(Target, RN, Rem) :-
    length(Rem, Left),
    aggregate_all(count, pos_ex(_, _), Total),
    nb_getval(planerel_t0, T0),
    statistics(cputime, T1),
    T is T1 - T0,
    theory_clause(RN, _, B, P, N), !,
    length(B, L),
    format(user_error, "progress: ~w rule ~w (~w literals, ~w pos, ~w neg): ~w of ~w positives left, ~1f s CPU~n",
           [Target, RN, L, P, N, Left, Total, T]),
    flush_output(user_error).
progress_line(_, _, _).

same_functor(pos, F, A, Id) :- pos_ex(Id, E), functor(E, F, A).

make_ctx(Bottom, VT, ctx(Search, CL, Evalfn, Bottom, Nodes, MinPos, MinAcc, Noise, VT)) :-
    setting(search, Search),
    setting(clauselength, CL),
    setting(evalfn, Evalfn),
    setting(nodes, Nodes),
    setting(minpos, MinPos),
    setting(minacc, MinAcc),
    setting(noise, Noise).

add_rule(Head, Body, P, N) :-
    maplist(unwrap_rec, Body, Body1),
    copy_term(Head-Body1, H-B),
    flag(planerel_rule_no, K, K + 1),
    K1 is K + 1,
    assertz(theory_clause(K1, H, B, P, N)).

unwrap_rec('$rec'(L), L) :- !.
unwrap_rec(L, L).

                 /*******************************
                 *          EVALUATION          *
                 *******************************/

theory_covers(E) :-
    setting(depth, D),
    catch(\+ \+ prove_theory(E, D), Err, (coverage_error(Err), fail)).

prove_theory(E, D) :-
    D > 0,
    D1 is D - 1,
    theory_clause(_, H, B, _, _),
    H = E,
    prove_tbody(B, D1).

prove_tbody([], _).
prove_tbody([L|Ls], D) :-
    (   functor(L, N, A), rec_target(N/A)
    ->  prove_theory(L, D)
    ;   user:L
    ),
    prove_tbody(Ls, D).

confusion(PosGoal, NegGoal, cm(TP, FN, FP, TN)) :-
    aggregate_all(count, (call(PosGoal, _, E), theory_covers(E)), TP),
    aggregate_all(count, call(PosGoal, _, _), NP),
    FN is NP - TP,
    aggregate_all(count, (call(NegGoal, _, E2), theory_covers(E2)), FP),
    aggregate_all(count, call(NegGoal, _, _), NN),
    TN is NN - FP.

accuracy(cm(TP, FN, FP, TN), Acc) :-
    Tot is TP + FN + FP + TN,
    (   Tot =:= 0 -> Acc = 0.0 ; Acc is (TP + TN) / Tot ).

                 /*******************************
                 *            OUTPUT            *
                 *******************************/

print_settings :-
    (   setting(verbosity, V), V >= 1
    ->  findall(S, ( member(N, [search, evalfn, clauselength, i, nodes, minpos,
                                 minacc, noise, depth]),
                     setting(N, Val), format(string(S), "~w=~w", [N, Val]) ), Ss),
        atomic_list_concat(Ss, ' ', Text),
        format("[planerel learner] ~w~n", [Text])
    ;   true
    ).

clause_text(H, B, Text) :-
    copy_term(H-B, H1-B1),
    numbervars(H1-B1, 0, _),
    Opts = [quoted(true), numbervars(true), spacing(standard)],
    with_output_to(string(HT), write_term(H1, Opts)),
    (   B1 == []
    ->  format(string(Text), "~s.", [HT])
    ;   maplist([L, LT]>>with_output_to(string(LT), write_term(L, Opts)), B1, LTs),
        atomic_list_concat(LTs, ', ', BT),
        format(string(Text), "~s :- ~w.", [HT, BT])
    ).

print_theory :-
    format("~n[theory]~n", []),
    (   theory_clause(_, _, _, _, _)
    ->  forall(theory_clause(K, H, B, P, N),
               ( clause_text(H, B, T),
                 format("[rule ~w] [pos cover = ~w, neg cover = ~w]~n~s~n", [K, P, N, T]) ))
    ;   format("(empty theory)~n", [])
    ).

%!  show_theory is det.
%   Print the learned clauses, one per line.
show_theory :-
    forall(theory_clause(_, H, B, _, _), (clause_text(H, B, T), format("~s~n", [T]))).

report_performance :-
    confusion(pos_ex, neg_ex, CM),
    print_confusion("training set performance", CM),
    (   ( tpos_ex(_, _) ; tneg_ex(_, _) )
    ->  confusion(tpos_ex, tneg_ex, TCM),
        print_confusion("test set performance", TCM)
    ;   true
    ),
    flag(planerel_nodes, Nodes, Nodes),
    format("~n[clauses explored] ~w~n", [Nodes]),
    flag(planerel_cache_hits, Hits, Hits),
    format("[coverage reused from the cache] ~w~n", [Hits]),
    flag(planerel_set_aside, Aside, Aside),
    format("[set aside] ~w~n", [Aside]).

print_confusion(Title, CM) :-
    CM = cm(TP, FN, FP, TN),
    PP is TP + FP, PN is FN + TN, AP is TP + FN, AN is FP + TN, T is AP + AN,
    accuracy(CM, Acc),
    format("~n[~w]~n", [Title]),
    format("~t~14|~tactual +~24|~tactual -~34|~n", []),
    format("pred +~t~w~24|~t~w~34|~t~w~44|~n", [TP, FP, PP]),
    format("pred -~t~w~24|~t~w~34|~t~w~44|~n", [FN, TN, PN]),
    format("~t~w~24|~t~w~34|~t~w~44|~n", [AP, AN, T]),
    format("accuracy: ~3f~n", [Acc]).

%!  write_rules(+File) is det.
%
%   Write the learned clauses to File, one clause per line (valid Prolog).
write_rules(File) :-
    setup_call_cleanup(open(File, write, S, [encoding(utf8)]),
                       forall(theory_clause(_, H, B, _, _),
                              ( clause_text(H, B, T), format(S, "~s~n", [T]) )),
                       close(S)).

                 /*******************************
                 *       DRIVER (planerel)      *
                 *******************************/

%!  planerel_main is det.
%
%   Entry point for `swipl learner.pl -- STEM [NAME=VALUE ...]`: read the
%   problem, apply the settings, induce, then print a machine-readable
%   summary (lines starting with @@) for planerel.ilp.learn.  Exit status 2 on
%   a user error, 3 on any other error.
planerel_main :-
    current_prolog_flag(argv, Argv),
    stack_settings,
    catch(main_(Argv), E, main_error(E)),
    halt(0).

%   stack_settings: at least 32 M cells (256 MB) free on the global stack
%   after each garbage collection (SWI-Prolog's default: 256 K cells).  A
%   search makes garbage fast (answer lists, findall/3 bags, copies of cached
%   entries); with the default the stack is collected and shifted over and
%   over (ramp of 1 000 varied scenes: 81 collections and 13 shifts of the
%   global stack in 2.4 s; with this setting 28 collections and 2 shifts in
%   1.1 s, and no higher peak memory).  Only for the driver's own process.
stack_settings :-
    set_prolog_stack(global, min_free(33554432)).

%!  planerel_score_main is det.
%
%   `swipl -g planerel_learner:planerel_score_main -t 'halt(3)' learner.pl --
%   STEM RULES [covered]`: the theory in the file RULES (clauses, e.g. those
%   of a learner run on other data) scored on STEM.f / STEM.n over STEM.b, as
%   in induce/0; prints `@@score TP FN FP TN`.  Used for held-out accuracy.
%   With `covered`, also `@@covered pos|neg Atom` for each example the theory
%   proves (benchmarks/clause_support.py --names).
planerel_score_main :-
    current_prolog_flag(argv, Argv),
    catch(score_main_(Argv), E, main_error(E)),
    halt(0).

score_main_([Stem, Rules|Opt]) :- ( Opt == [] ; Opt == [covered] ), !,
    read_all(Stem),
    setup_extensional,
    retractall(theory_clause(_, _, _, _, _)),
    setup_call_cleanup(open(Rules, read, In), read_theory(In, 1), close(In)),
    confusion(pos_ex, neg_ex, cm(TP, FN, FP, TN)),
    format("@@score ~w ~w ~w ~w~n", [TP, FN, FP, TN]),
    (   Opt == [covered]
    ->  forall(( member(Kind-Goal, [pos-pos_ex, neg-neg_ex]), call(Goal, _, E),
                 theory_covers(E) ),
               format("@@covered ~w ~q~n", [Kind, E]))
    ;   true
    ).
score_main_(_) :-
    input_error("usage: swipl learner.pl -- STEM RULES [covered]", []).

read_theory(In, K) :-
    read_term(In, C, []),
    (   C == end_of_file
    ->  true
    ;   (   C = (H :- B) -> conj_to_list(B, Bs) ; H = C, Bs = [] ),
        assertz(theory_clause(K, H, Bs, 0, 0)),
        K1 is K + 1,
        read_theory(In, K1)
    ).

conj_to_list((A, B), [A|Bs]) :- !, conj_to_list(B, Bs).
conj_to_list(true, []) :- !.
conj_to_list(A, [A]).

main_([Stem|Sets]) :- !,
    read_all(Stem),
    forall(member(S, Sets), cli_setting(S)),
    induce,
    machine_summary.
main_([]) :-
    input_error("usage: swipl learner.pl -- STEM [NAME=VALUE ...]", []).

cli_setting(Text) :-
    (   sub_atom(Text, B, _, A, '=')
    ->  sub_atom(Text, 0, B, _, Name),
        sub_atom(Text, _, A, 0, VText),
        cli_value(Name, VText, Value),
        format(atom(Where), "--set ~w", [Text]),
        set_setting(Name, Value, Where)
    ;   input_error("--set ~w: expected NAME=VALUE", [Text])
    ).

cli_value(Name, VText, Value) :-
    (   memberchk(Name, [test_pos, test_neg])
    ->  Value = VText
    ;   catch(term_string(T, VText), _, fail), atomic(T)
    ->  Value = T
    ;   Value = VText
    ).

machine_summary :-
    format("@@begin~n", []),
    format("@@engine builtin~n", []),
    forall(theory_clause(_, H, B, _, _),
           ( clause_text(H, B, T), format("@@rule ~s~n", [T]) )),
    confusion(pos_ex, neg_ex, cm(TP, FN, FP, TN)),
    format("@@train ~w ~w ~w ~w~n", [TP, FN, FP, TN]),
    (   ( tpos_ex(_, _) ; tneg_ex(_, _) )
    ->  confusion(tpos_ex, tneg_ex, cm(A, B2, C, D)),
        format("@@test ~w ~w ~w ~w~n", [A, B2, C, D])
    ;   true
    ),
    flag(planerel_nodes, Nodes, Nodes),
    format("@@nodes ~w~n", [Nodes]),
    nb_getval(planerel_search_time, T),
    format("@@cputime ~6f~n", [T]),
    format("@@end~n", []).

main_error(planerel_input_error(Text)) :- !,
    format(user_error, "error: ~s~n", [Text]),
    halt(2).
main_error(E) :-
    message_to_codes_text(E, T),
    format(user_error, "error: ~s~n", [T]),
    halt(3).
