"""split79: a proposal answered ``box`` that holds two boxes of their own is split into them
(``decision.cut_split``, with ``decision.cut_boxes``).

Two boxes standing side by side, touching, are one proposal when the proposal step joins
them (dev_small's touching small boxes); the box rules prove the whole, so the answer was one
box over both.  Each box's own solid (:func:`planerel.features.box_cut.box_solids`) is now
decided as an object of its own, with every gate; when two or more are boxes, they are the
answers.  A box on a stool-like block (one solid: the box's) stays one answer.  Prolog runs
for real (swipl through pyswip).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import box, floor  # noqa: E402
from test_box_cut import STOOL, _answer, _merged, _model  # noqa: E402

#: the demo's box rules 1 and 2 alone (no stairs rule to prove a pile of two levels)
BOX_RULES = ("box(A) :- has_plane(A,B), skirt(B,C).\n"
             "box(A) :- has_plane(A,B), nhorizontal(A,0), tall_face(B).\n"
             "planerel_rule_stats(1, box, 80, 9).\n"
             "planerel_rule_stats(2, box, 23, 1).\n")
#: a 0.2 m and a 0.3 m high box, 0.3 m square, touching side by side
PAIR = [floor()] + box(-0.15, 1.2, 0.3, 0.3, 0.2, obj=2) + box(0.15, 1.2, 0.3, 0.3, 0.3, obj=3)


def _box_model(path: Path, split: bool) -> Path:
    m = _model(path)
    (m / "rules.pl").write_text(BOX_RULES)
    data = json.loads((m / "model.json").read_text())
    data["decision"]["cut_split"] = split
    (m / "model.json").write_text(json.dumps(data))
    return m


def test_two_touching_boxes_in_one_proposal_are_two_box_answers(tmp_path):
    cloud, desc, objs = _merged(PAIR)
    (o,) = desc.objects
    assert {objs[x] for x in o.planes} == {2, 3}
    off = _answer(_box_model(tmp_path / "off", False), cloud, desc)
    assert [a.klass for a in off] == ["box"] and not off[0].cut_off
    ans = _answer(_box_model(tmp_path / "on", True), cloud, desc)
    rest, *boxes = ans
    assert [a.klass for a in boxes] == ["box", "box"]
    assert sorted(min(objs[x] for x in b.labels) for b in boxes) == [2, 3]
    assert all(len({objs[x] for x in b.labels}) == 1 for b in boxes)
    assert all(b.cut_from == rest.object_id for b in boxes)
    assert set(rest.cut_off) == {b.object_id for b in boxes}
    # every plane went to a box: the proposal's own answer keeps none and is `other`
    assert rest.klass == "other" and rest.labels == ()
    assert all(b.rule.startswith("box(") and set(b.proof_planes) <= set(b.planes) for b in boxes)


def test_a_box_on_a_stool_like_block_stays_one_answer(tmp_path):
    # the box's own solid is the only one: the proof may be the box's with its stool, so the
    # answer is left whole
    cloud, desc, objs = _merged(STOOL)
    ans = _answer(_box_model(tmp_path / "on", True), cloud, desc)
    assert [a.klass for a in ans] == ["box"] and not ans[0].cut_off
    assert {objs[x] for x in ans[0].labels} == {2, 3}


def test_the_split_is_a_switch():
    assert M.DecisionParams().cut_split is False   # off by default (a judge's false box)
    with pytest.raises(InputError):
        M.DecisionParams(cut_split="yes")


def _members(path: Path, one) -> Path:
    """A members model of two members, each the model ``one(folder)`` writes (members93)."""
    for n in (1, 2):
        one(path / "members" / str(n))
    top = one(path)
    data = json.loads((top / "model.json").read_text())
    data["members"] = ["members/1", "members/2"]
    (top / "model.json").write_text(json.dumps(data))
    return top


def test_a_members_model_cuts_and_splits_as_a_single_model(tmp_path):
    """cutm93: ``cut_boxes`` and ``cut_split`` for a members model's vote, the rules that proved
    the proposal compared member by member (a rule index names one member's rule)."""
    from test_box_cut import ROUND

    cloud, desc, objs = _merged(PAIR)
    ans = _answer(_members(tmp_path / "split", lambda p: _box_model(p, True)), cloud, desc)
    rest, *boxes = ans
    assert [a.klass for a in boxes] == ["box", "box"] and len(boxes[0].votes) == 2
    assert sorted(min(objs[x] for x in b.labels) for b in boxes) == [2, 3]
    assert all(b.cut_from == rest.object_id for b in boxes) and rest.klass == "other"
    off = _answer(_members(tmp_path / "whole", lambda p: _box_model(p, False)), cloud, desc)
    assert [a.klass for a in off] == ["box"] and not off[0].cut_off
    # a box touching a round thing: the planar gate refuses the whole, its solid is cut
    cloud, desc, objs = _merged(ROUND)
    cut = _answer(_members(tmp_path / "cut", _model), cloud, desc)
    assert [a.klass for a in cut] == ["other", "box"]
    assert cut[1].cut_from == cut[0].object_id and len(cut[1].votes) == 2
