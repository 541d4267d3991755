"""fallback93: a decision gate applied after the decision (crowd, far proofs, slope parts, ...)
that refuses the chosen class gives the next class that holds, as a refusal inside the decision
does, not ``other``; that class then passes the gates too (docs/objects.md "A gate's refusal
falls back to the next class").

Rendered scenes are ray-cast rectangles (tests/scenes_analytic.py); Prolog runs for real.  With
``PLANEREL_INDEPENDENT_DATA`` the case it was found on is checked: a generated flight seen from
its top whose ``ramp`` answer the slope-parts gate refused while its ``stairs`` rule held.
"""

from __future__ import annotations

import dataclasses
import os
import sys
from pathlib import Path

import pytest

from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ramp_model import one_rule_model, rules_text  # noqa: E402
from test_far_gate import _box_answer, _described  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

# the demo's lying clause, and a second class's clause on the same top that loses the decision
# to it (Laplace 41/46 = 0.89 against 11/17 = 0.65)
STATS = [(1, "box", 40, 4), (2, "ramp", 10, 5)]
RULES = rules_text("box(A) :- has_plane(A,B), oblique_share(A,C), lying(B), lteq(C,0.02).\n"
                   "ramp(A) :- has_plane(A,B), lying(B).\n", STATS)


def _answers(tmp_path, far=False, **decision):
    from planerel.classify.classifier import Classifier

    cloud, desc, top = _described()
    if far:
        desc = dataclasses.replace(desc, far=frozenset({top}))
    with Classifier(one_rule_model(tmp_path / "m", RULES, STATS, **decision)) as clf:
        return _box_answer(clf.answer_description(desc, xyz=cloud.xyz), desc.plane_id(top))


def test_the_decision_keeps_the_runner_up(tmp_path):
    a = _answers(tmp_path)
    assert a.klass == "box" and a.rule_index == 1
    assert {f[0] for f in a.fired} == {"box", "ramp"}
    assert a.runner_up is not None and a.runner_up.klass == "ramp"
    assert a.runner_up.rule_index == 2 and a.runner_up.runner_up is None
    assert "runner_up" not in a.to_dict()


def test_a_gate_after_the_decision_falls_back_to_the_next_class(tmp_path):
    # the long-lying gate (box only; a top alone longer than 0.1 m) refuses the box: the ramp
    # clause held, so the answer is ramp
    a = _answers(tmp_path, long_lying_length=0.1)
    assert a.klass == "ramp" and a.rule_index == 2 and a.rule.startswith("ramp(")
    assert a.proof_planes and a.precision == pytest.approx(11 / 17)
    why = [r for r in a.refused if isinstance(r, M.LongLyingRefusal)]
    assert len(why) == 1 and why[0].klass == "box" and why[0].rule == 1
    assert a.runner_up is None
    # with the gate off the box stands
    assert _answers(tmp_path, long_lying_length=0.1, long_lying_gate=False).klass == "box"


def test_the_class_fallen_back_to_passes_the_gates_too(tmp_path):
    # the far gate refuses box and ramp proved through a far plane: box falls back to ramp,
    # which the gates judge again and refuse as well
    a = _answers(tmp_path, far=True)
    assert a.klass == "other" and a.rule is None and a.proof_planes == ()
    why = [r for r in a.refused if isinstance(r, M.FarPlaneRefusal)]
    assert [r.klass for r in why] == ["box", "ramp"]
    # a gate only the first class meets still falls back to the second
    b = _answers(tmp_path, far=True, far_gate=False, long_lying_length=0.1)
    assert b.klass == "ramp"


def test_a_members_vote_keeps_no_runner_up():
    from planerel.classify.classifier import ObjectAnswer, _voted

    nxt = ObjectAnswer("s_o1", ("s_p1",), (1,), "ramp", "ramp(A) :- x.", rule_index=2,
                       precision=0.6)
    one = ObjectAnswer("s_o1", ("s_p1",), (1,), "box", "box(A) :- x.", rule_index=1,
                       precision=0.9, runner_up=nxt)
    voted = _voted([[one], [one]])
    assert voted[0].klass == "box" and voted[0].runner_up is None


DEV = Path(os.environ.get("PLANEREL_INDEPENDENT_DATA", "/nonexistent"))


@pytest.mark.skipif(not (DEV / "dev_rake" / "i0019.npy").is_file(),
                    reason="PLANEREL_INDEPENDENT_DATA not set")
def test_a_flight_from_its_top_whose_ramp_is_refused_is_stairs(demo_model):  # noqa: F811
    """dev_rake's i0019: a descending flight of nine steps seen from its top (risers leaning
    20 degrees, hidden). Both the stairs and the ramp clause prove it; the ramp wins the
    decision and the slope-parts gate refuses it (its treads make no one flat slope): the
    answer is the flight's ``stairs``."""
    import numpy as np

    from planerel.classify.classifier import Classifier
    from planerel.io import readers as io

    path = DEV / "dev_rake" / "i0019.npy"
    truth = np.load(path.with_name("i0019.objects.npy"))
    with Classifier(str(demo_model)) as clf:
        ans = clf.classify(io.read(path), scene_id="i0019")
    # the proposal holding most of the flight (object 1 of the generator's labels)
    flight = max(ans.objects, key=lambda o: int((np.isin(ans.labels, o.labels) & (truth == 1)).sum()))
    assert flight.klass == "stairs" and flight.rule_index is not None
    assert any(isinstance(r, M.SlopePartsRefusal) and r.klass == "ramp" for r in flight.refused)


def _members_model(path: Path, **decision) -> Path:
    """A members model of two members, each the two clauses above (its ``decision`` settings
    updated with ``decision``)."""
    import json

    for n in (1, 2):
        one_rule_model(path / "members" / str(n), RULES, STATS, **decision)
    one_rule_model(path, RULES, STATS, **decision)
    data = json.loads((path / "model.json").read_text())
    data["members"] = ["members/1", "members/2"]
    (path / "model.json").write_text(json.dumps(data))
    return path


def test_a_members_vote_meets_the_gates_after_the_decision(tmp_path):
    """members93: a members model's vote is judged by the gates after the decision, as a single
    model's answer is (before, the vote returned before them)."""
    from planerel.classify.classifier import Classifier

    cloud, desc, top = _described()
    top_id = desc.plane_id(top)
    with Classifier(_members_model(tmp_path / "m")) as clf:
        assert clf.members and clf.long_lying is not None and clf.far_gate
        a = _box_answer(clf.answer_description(desc, xyz=cloud.xyz), top_id)
    assert a.klass == "box" and len(a.votes) == 2
    with Classifier(_members_model(tmp_path / "g", long_lying_length=0.1)) as clf:
        b = _box_answer(clf.answer_description(desc, xyz=cloud.xyz), top_id)
    # the vote keeps no runner-up: the refused box gives other
    assert b.klass == "other" and len(b.votes) == 2
    assert [type(r) for r in b.refused if isinstance(r, M.LongLyingRefusal)] == [M.LongLyingRefusal]
    far = dataclasses.replace(desc, far=frozenset({top}))
    with Classifier(_members_model(tmp_path / "f")) as clf:
        c = _box_answer(clf.answer_description(far, xyz=cloud.xyz), top_id)
    assert c.klass == "other"
    assert any(isinstance(r, M.FarPlaneRefusal) for r in c.refused)
