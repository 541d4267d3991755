"""``benchmarks/clause_support.py``: each literal of a learned clause against the training
examples it keeps out, scored by the real ``swipl`` with the builtin learner's coverage test."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))

import clause_support as cs  # noqa: E402

LYING = "box(A) :- has_plane(A,B), oblique_share(A,C), lying(B), lteq(C,0.02)."


def test_parse_and_the_literals_that_can_be_dropped():
    head, body = cs.parse_clause(LYING)
    assert head == "box(A)"
    assert body == ["has_plane(A,B)", "oblique_share(A,C)", "lying(B)", "lteq(C,0.02)"]
    # has_plane(A,B) links lying(B): never dropped; oblique_share goes with its bound
    assert cs.variants(head, body) == [
        ("oblique_share(A,C), lteq(C,0.02)", ["has_plane(A,B)", "lying(B)"]),
        ("lying(B)", ["has_plane(A,B)", "oblique_share(A,C)", "lteq(C,0.02)"]),
        ("lteq(C,0.02)", ["has_plane(A,B)", "oblique_share(A,C)", "lying(B)"]),
    ]
    # a literal that binds a variable another (non-comparison) literal uses stays
    head, body = cs.parse_clause("stairs(A) :- has_plane(A,B), parallel(B,C), stair_step(C,B).")
    assert [d for d, _ in cs.variants(head, body)] == ["stair_step(C,B)"]
    # commas inside arguments and quoted atoms do not split literals
    assert cs.split_top("f(A,'x,Y'), g([1,2],B)") == ["f(A,'x,Y')", "g([1,2],B)"]
    assert cs._vars("f(A,'X',b)") == {"A"}


def test_read_rules_keeps_the_class_clauses_only(tmp_path):
    f = tmp_path / "rules.pl"
    f.write_text(":- dynamic(planerel_rule_stats/4).\n% a comment\n" + LYING + "\n"
                 "planerel_rule_stats(1, box, 3, 0).\nplanerel_x(A) :- true.\n")
    assert cs.read_rules(f) == [LYING]


def _task(folder: Path) -> Path:
    """A box task by hand: three boxes lying flat, two flat things with an inclined part
    (oblique share 0.5) and one object with no lying top (share 0)."""
    facts = [":- modeh(1, box(+obj)).", "lteq(X, T) :- number(X), X =< T."]
    for o, lying, share in (("p1", True, 0.0), ("p2", True, 0.0), ("p3", True, 0.01),
                            ("n1", True, 0.5), ("n2", True, 0.5), ("n3", False, 0.0)):
        facts += [f"has_plane({o}, {o}_t).", f"oblique_share({o}, {share})."]
        if lying:
            facts.append(f"lying({o}_t).")
    (folder / "box.b").write_text("\n".join(facts) + "\n")
    (folder / "box.f").write_text("box(p1).\nbox(p2).\nbox(p3).\n")
    (folder / "box.n").write_text("box(n1).\nbox(n2).\nbox(n3).\n")
    return folder


@pytest.mark.skipif(not shutil.which("swipl"), reason="swipl not installed")
def test_support_counts_what_each_literal_keeps_out(tmp_path, capsys):
    (tmp_path / "aleph").mkdir()
    stage = _task(tmp_path / "aleph")
    rules = tmp_path / "rules.pl"
    rules.write_text(LYING + "\n")
    rows = cs.support(rules, [stage], timeout=120)
    got = {r["dropped"]: (r["tp"], r["fp"]) for r in rows}
    assert got == {None: (3, 0),
                   "oblique_share(A,C), lteq(C,0.02)": (3, 2),  # the bound keeps out n1, n2
                   "lying(B)": (3, 1),  # n3 has a plane but no lying top
                   "lteq(C,0.02)": (3, 2)}
    # the command prints the table, each dropped literal with what it keeps out
    assert cs.main([str(rules), str(stage)]) == 0
    out = capsys.readouterr().out
    assert "| | | `lying(B)` | 3 (+0) | 1 (+1) | 1 negatives |" in out
    # ... and with --names, which negatives: the learner's covered examples
    assert cs.main([str(rules), str(stage), "--names"]) == 0
    out = capsys.readouterr().out
    assert "| 3 (+0) | 2 (+2) | 2 negatives: n1, n2 |" in out
    assert "| | | `lying(B)` | 3 (+0) | 1 (+1) | 1 negatives: n3 |" in out
    # a stage folder that does not exist is a one-line usage error
    with pytest.raises(SystemExit):
        cs.main([str(rules), str(tmp_path / "missing")])
    # ... and so is a rules file that does not exist
    with pytest.raises(SystemExit):
        cs.main([str(tmp_path / "none.pl"), str(stage)])
    # a task whose background does not load: one line on stderr, exit 1, no traceback
    (stage / "box.b").write_text("this is not prolog(.\n")
    capsys.readouterr()
    assert cs.main([str(rules), str(stage)]) == 1
    assert capsys.readouterr().err.startswith("clause_support: ")


@pytest.mark.skipif(not shutil.which("swipl"), reason="swipl not installed")
def test_theory_coverage_names_the_examples_it_proves(tmp_path):
    from planerel.ilp.learn import score_theory, theory_coverage

    (tmp_path / "aleph").mkdir()
    stem = _task(tmp_path / "aleph") / "box"
    rules = ["box(A) :- has_plane(A,B), lying(B)."]
    cm = score_theory(stem, rules)
    got, pos, neg = theory_coverage(stem, rules)
    assert got == cm and (cm.tp, cm.fp) == (3, 2)
    assert pos == ("box(p1)", "box(p2)", "box(p3)") and neg == ("box(n1)", "box(n2)")
