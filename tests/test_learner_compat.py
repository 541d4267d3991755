"""Aleph compatibility of planerel's learner (issue 17, item 3), on small problems written here.

Each problem is in the style of an Aleph example (a .b compiled like a Prolog source file,
structured modes, integrity constraints, Aleph's settings) but written for these tests; the
expected theories follow from the examples by hand.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp.learn import Confusion, learn

pytestmark = pytest.mark.skipif(shutil.which("swipl") is None, reason="SWI-Prolog not installed")

ILP = Path(__file__).parent / "ilp"


def norm(clause: str) -> str:
    return re.sub(r"\s+", "", clause)


def write(tmp_path: Path, name: str, b: str, f: str, n: str | None) -> Path:
    (tmp_path / f"{name}.b").write_text(b)
    (tmp_path / f"{name}.f").write_text(f)
    if n is not None:
        (tmp_path / f"{name}.n").write_text(n)
    return tmp_path / name


TRAINS_B = """\
:- modeh(1, eastbound(+train)).
:- modeb(*, has_car(+train, -car)).
:- modeb(1, short(+car)).
:- modeb(1, closed(+car)).
:- modeb(1, long(+car)).
:- determination(eastbound/1, has_car/2).
:- determination(eastbound/1, short/1).
:- determination(eastbound/1, closed/1).
:- determination(eastbound/1, long/1).
has_car(t1, c11). has_car(t1, c12). has_car(t2, c21). has_car(t3, c31). has_car(t4, c41).
short(c11). short(c21). short(c31).
closed(c11). closed(c21). closed(c41).
long(c12). long(c41).
"""
TRAINS_F = "eastbound(t1).\neastbound(t2).\n"
TRAINS_N = "eastbound(t3).\neastbound(t4).\n"
SHORT_CLOSED = norm("eastbound(A) :- has_car(A,B), short(B), closed(B).")


# --------------------------------------------------------------------------- the .b is compiled


def test_background_is_compiled_with_conditional_compilation_and_arithmetic_functions(tmp_path):
    # The threshold 2*3 = 6 comes from an arithmetic function; the clause in the `else` branch
    # would make every number big, so a learned rule with no false positive proves it was skipped.
    b = """\
:- modeh(1, big(+n)).
:- modeb(1, big_number(+n)).
:- determination(big/1, big_number/1).
:- if(current_prolog_flag(bounded, false)).
:- use_module(library(arithmetic)).
:- arithmetic_function(twice/1).
twice(X, Y) :- Y is 2 * X.
big_number(X) :- X > twice(3).
:- else.
big_number(_).
:- endif.
n(1). n(2). n(7). n(9).
"""
    stem = write(tmp_path, "num", b, "big(7).\nbig(9).\n", "big(1).\nbig(2).\n")
    r = learn(stem)
    assert [norm(c) for c in r.rules] == [norm("big(A) :- big_number(A).")]
    assert r.train == Confusion(tp=2, fn=0, fp=0, tn=2)


def test_a_failing_directive_in_the_background_names_file_and_line(tmp_path):
    stem = write(tmp_path, "d", TRAINS_B + ":- fail.\n", TRAINS_F, TRAINS_N)
    n_line = TRAINS_B.count("\n") + 1
    with pytest.raises(InputError, match=rf"d\.b:{n_line}: the directive fail failed"):
        learn(stem)


def test_an_unknown_predicate_in_a_directive_names_file_and_line(tmp_path):
    stem = write(tmp_path, "d", TRAINS_B + ":- no_such_thing(1).\n", TRAINS_F, TRAINS_N)
    n_line = TRAINS_B.count("\n") + 1
    with pytest.raises(InputError, match=rf"d\.b:{n_line}: .*no_such_thing/1"):
        learn(stem)


def test_a_background_reread_replaces_the_previous_problem(tmp_path):
    # Two problems in one Prolog session: the second one's background must not see the first's.
    import subprocess
    from importlib.resources import as_file, files

    one = write(tmp_path, "one", TRAINS_B, TRAINS_F, TRAINS_N)
    (tmp_path / "two").mkdir()
    two = write(tmp_path / "two", "two", TRAINS_B.replace("closed(c11). ", ""), TRAINS_F, TRAINS_N)
    with as_file(files("planerel.aleph").joinpath("learner.pl")) as pl:
        goal = (f"use_module('{pl}'), read_all('{one}'), read_all('{two}'), "
                "( closed(c11) -> halt(1) ; closed(c21) -> halt(0) ; halt(2) )")
        proc = subprocess.run(["swipl", "-q", "-g", goal, "-t", "halt(3)"], capture_output=True,
                              text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr


# --------------------------------------------------------------------------- integrity constraints


CONSTRAINT = """\
false :- hypothesis(_, Body, _), in_body(closed(_), Body).
in_body(L, (A, B)) :- !, ( in_body(L, A) ; in_body(L, B) ).
in_body(L, L).
"""


def test_without_the_constraint_the_short_closed_rule_is_learned(tmp_path):
    r = learn(write(tmp_path, "tr", TRAINS_B, TRAINS_F, TRAINS_N))
    assert [norm(c) for c in r.rules] == [SHORT_CLOSED]


def test_integrity_constraint_rejects_clauses_that_violate_it(tmp_path):
    # No clause may use closed/1; short alone covers the negative t3, so no rule is acceptable
    # and the two positives stay as unit clauses.
    r = learn(write(tmp_path, "tr", TRAINS_B + CONSTRAINT, TRAINS_F, TRAINS_N))
    assert all("closed" not in c for c in r.rules)
    assert sorted(norm(c) for c in r.rules) == ["eastbound(t1).", "eastbound(t2)."]


def test_integrity_constraint_sees_the_clause_label(tmp_path):
    # Reject clauses with more than 3 literals (head included): the 4-literal rule is excluded.
    c = "false :- hypothesis(_, _, [_, _, L]), L > 3.\n"
    r = learn(write(tmp_path, "tr", TRAINS_B + c, TRAINS_F, TRAINS_N))
    assert SHORT_CLOSED not in [norm(x) for x in r.rules]


# --------------------------------------------------------------------------- structured modes


def test_negated_mode_not_p(tmp_path):
    # Birds fly unless they are penguins: not(penguin(+bird)) is the only separating literal.
    b = """\
:- modeh(1, flies(+bird)).
:- modeb(1, bird(+bird)).
:- modeb(1, not(penguin(+bird))).
:- determination(flies/1, bird/1).
:- determination(flies/1, (not)/1).
bird(tweety). bird(polly). bird(jack). bird(pingu). bird(skipper).
penguin(pingu). penguin(skipper).
"""
    stem = write(tmp_path, "fly", b, "flies(tweety).\nflies(polly).\nflies(jack).\n",
                 "flies(pingu).\nflies(skipper).\n")
    r = learn(stem)
    assert [norm(c) for c in r.rules] == [norm("flies(A) :- not(penguin(A)).")]
    assert r.accuracy == 1.0


def test_list_pattern_mode_learns_recursive_membership(tmp_path):
    # in_list(X, L): the list pattern (+list)=[-any|-list] takes the list apart; the theory is
    # the textbook membership program (first element, or in the tail).
    b = """\
:- mode(*, in_list(+any, +list)).
:- mode(1, ((+list) = ([-any|-list]))).
:- set(i, 3).
:- determination(in_list/2, in_list/2).
:- determination(in_list/2, '='/2).
"""
    # Lists closed under taking the tail, every member a positive (the recursive literal is
    # proved from the positives during the search, as in Aleph).
    lists = ["[a]", "[b,a]", "[c,b,a]", "[d,c,b,a]"]
    f = "".join(f"in_list({x}, {lst}).\n" for lst in lists for x in lst.strip("[]").split(","))
    n = "".join(f"in_list({x}, {lst}).\n" for x, lst in [
        ("a", "[]"), ("b", "[a]"), ("c", "[b,a]"), ("d", "[c,b,a]"), ("e", "[d,c,b,a]")])
    r = learn(write(tmp_path, "mem", b, f, n))
    assert sorted(norm(c) for c in r.rules) == sorted([norm("in_list(A,B) :- B=[A|C]."),
                                                       norm("in_list(A,B) :- B=[C|D], in_list(A,D).")])
    assert r.train == Confusion(tp=10, fn=0, fp=0, tn=5)


def test_structured_mode_with_a_variable_inside_is_an_error(tmp_path):
    stem = write(tmp_path, "m", ":- modeb(1, not(p(X))).\n", "q(a).\n", None)
    with pytest.raises(InputError, match=r"m\.b:1: mode .* has a variable argument"):
        learn(stem)


# --------------------------------------------------------------------------- settings


@pytest.mark.parametrize("name,value", [("prune_tree", "true"), ("check_good", "true"),
                                        ("prior", "[0.5,0.5]"), ("refineop", "false"),
                                        ("mingain", "0.05"), ("threads", "1")])
def test_real_aleph_settings_warn_and_do_not_reject(tmp_path, name, value):
    stem = write(tmp_path, "tr", f":- set({name}, {value}).\n" + TRAINS_B, TRAINS_F, TRAINS_N)
    r = learn(stem)
    assert any(f"setting {name}" in w for w in r.warnings)
    assert [norm(c) for c in r.rules] == [SHORT_CLOSED]


def test_verbose_is_alephs_other_name_of_verbosity(tmp_path):
    stem = write(tmp_path, "tr", ":- set(verbose, 0).\n" + TRAINS_B, TRAINS_F, TRAINS_N)
    r = learn(stem)
    assert "[seed" not in r.output               # verbosity 0: no per-seed lines
    assert not r.warnings
    r1 = learn(write(tmp_path, "tr1", TRAINS_B, TRAINS_F, TRAINS_N))
    assert "[seed" in r1.output                  # the default prints them


def test_aleph_set_of_the_pack_module_is_accepted(tmp_path):
    stem = write(tmp_path, "tr", ":- aleph_set(clauselength, 3).\n" + TRAINS_B, TRAINS_F, TRAINS_N)
    r = learn(stem)
    assert all(len(c.split(",")) <= 2 for c in r.rules)   # 3 literals: head + 2 at most
    assert SHORT_CLOSED not in [norm(c) for c in r.rules]


def test_a_name_aleph_does_not_have_is_still_an_error(tmp_path):
    stem = write(tmp_path, "tr", ":- set(clauselenght, 3).\n" + TRAINS_B, TRAINS_F, TRAINS_N)
    with pytest.raises(InputError, match=r"tr\.b:1: unknown setting clauselenght"):
        learn(stem)


def test_evalfn_posonly_is_refused_with_a_clear_error(tmp_path):
    stem = write(tmp_path, "tr", ":- set(evalfn, posonly).\n" + TRAINS_B, TRAINS_F, None)
    with pytest.raises(InputError, match=r"tr\.b:1: evalfn\(posonly\) .* not implemented .* "
                                         r"negative examples"):
        learn(stem)
    with pytest.raises(InputError, match=r"evalfn\(posonly\)"):
        learn(write(tmp_path, "tr2", TRAINS_B, TRAINS_F, TRAINS_N), settings={"evalfn": "posonly"})


def test_abducible_is_a_clear_warning(tmp_path):
    stem = write(tmp_path, "tr", TRAINS_B + ":- abducible(short/1).\n", TRAINS_F, TRAINS_N)
    r = learn(stem)
    assert any("abducible(short/1)" in w and "abduction is not implemented" in w for w in r.warnings)
    assert [norm(c) for c in r.rules] == [SHORT_CLOSED]


def test_openlist_is_a_beam_on_the_open_list():
    # A beam of one node keeps only the first child of each expansion: the search explores fewer
    # clauses and misses the short-closed rule that the unbounded search finds.
    full = learn(ILP / "trains", settings={"search": "heuristic", "evalfn": "laplace"})
    beam = learn(ILP / "trains", settings={"search": "heuristic", "evalfn": "laplace", "openlist": 1})
    assert not beam.warnings and not full.warnings
    assert [norm(c) for c in full.rules] == [norm("eastbound(A) :- has_car(A,B), short(B), closed(B).")]
    assert beam.clauses_explored < full.clauses_explored
    wide = learn(ILP / "trains", settings={"search": "heuristic", "evalfn": "laplace", "openlist": 10_000})
    assert wide.rules == full.rules and wide.clauses_explored == full.clauses_explored


def test_searchtime_bounds_each_search():
    # A search that may use 0.1 ms of CPU stops after its first clauses: no rule is found and the
    # positives stay as unit clauses; inf is the default.
    r = learn(ILP / "trains", settings={"searchtime": 0.0001})
    assert all(":-" not in c for c in r.rules) and len(r.rules) == 5
    with pytest.raises(InputError, match=r"illegal value -1 for setting searchtime"):
        learn(ILP / "trains", settings={"searchtime": -1})


def test_explore_decides_whether_an_acceptable_clause_covering_every_positive_ends_the_search(tmp_path):
    # With noise 1, has_car(A,B), short(B) covers both positives and one negative: acceptable.
    # Aleph's default (explore false) stops there; explore(true) searches on and finds the
    # consistent short-closed rule, whose laplace score 3/4 beats 3/5.
    stem = write(tmp_path, "tr", ":- set(noise, 1).\n:- set(search, heuristic).\n"
                 ":- set(evalfn, laplace).\n" + TRAINS_B, TRAINS_F, TRAINS_N)
    quick = learn(stem)
    assert [norm(c) for c in quick.rules] == [norm("eastbound(A) :- has_car(A,B), short(B).")]
    assert quick.train == Confusion(tp=2, fn=0, fp=1, tn=1)
    full = learn(stem, settings={"explore": "true"})
    assert [norm(c) for c in full.rules] == [SHORT_CLOSED]
    assert full.clauses_explored > quick.clauses_explored
