"""core49: a box inside a merged proposal, decided as an object of its own (``decision.cut_boxes``).

A proposal that holds a box with what it touches (a round thing) or stands on (a stool-like
block) is not answered ``box`` (the planar gate refuses the whole, or another class wins);
the solid of a box proof's planes is then decided with the model's rules and every gate, and
cut from the proposal when it is a box.  A dresser-sized block is not: the size gate holds for
the cut solid as for any proposal.  Prolog runs for real (swipl through pyswip).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import Rect, box, floor, render  # noqa: E402
from test_proposals_tabletop import _trough  # noqa: E402

#: the demo's box rules 1 and 2, and a stairs rule that proves any pile of two levels, more
#: precise than both (as the demo's stairs rule 5 took hunt48's box on a stool)
STATS = [(1, "box", 80, 9), (2, "box", 23, 1), (3, "stairs", 50, 0)]
RULES = ("box(A) :- has_plane(A,B), skirt(B,C).\n"
         "box(A) :- has_plane(A,B), nhorizontal(A,0), tall_face(B).\n"
         "stairs(A) :- has_plane(A,B), has_plane(A,C), above(B,C), parallel(B,C).\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))
#: every box and stairs positive fully planar; the demo's box size domain (1.23 m)
PLANAR = [("box", 1.0, 1.0, 100), ("stairs", 1.0, 1.0, 40)]
SIZES = [("box", 1.2295, 137)]


def _model(path: Path, *, cut=True, reach=None, corner=None) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS, planar_domain=PLANAR,
                             size_domain=SIZES)
    data["decision"]["flight_gate"] = False   # the stairs rule is no flight
    data["decision"]["cut_boxes"] = cut
    if reach is not None:
        data["decision"]["cut_reach"] = reach
    if corner is not None:
        data["decision"]["cut_corner"] = corner
    (path / "model.json").write_text(json.dumps(data))
    return path


def _lift(rects, dz, obj):
    return [Rect((r.center[0], r.center[1], r.center[2] + dz), r.e1, r.e2, r.a, r.b, obj)
            for r in rects]


def _merged(rects):
    """The scene rendered, described with everything but the floor as one proposal (how a
    sensor's smoothing or a touching neighbour joins them)."""
    from planerel.features.facts import describe_scene

    cloud, lab, _up, objs = render(rects, pitch=35, cam_height=1.4, width=320, height=240,
                                   noise=0.0005)
    present = sorted(set(np.unique(lab).tolist()) - {-1, 0})
    return cloud, describe_scene(cloud, lab, objects=[present]), objs


def _answer(model, cloud, desc):
    from planerel.classify.classifier import Classifier

    with Classifier(model) as clf:
        return clf.answer_description(desc, xyz=cloud.xyz)


#: a box against the end of a half-pipe (a bowl's inside)
ROUND = [floor()] + _trough(0.0, 1.0, 0.15, 0.3) + box(0.27, 1.15, 0.25, 0.25, 0.2, obj=2)
#: the same with the box's front 1.5 cm from the pipe's outer strip, at 15 degrees: the face
#: goes on into the round surface at a facet's angle
ROUND_FLUSH = [floor()] + _trough(0.0, 1.0, 0.15, 0.3) + box(0.27, 1.0, 0.25, 0.25, 0.2, obj=2)
STOOL = ([floor()] + box(0.0, 1.4, 0.5, 0.5, 0.45, obj=3)
         + _lift(box(0.0, 1.4, 0.3, 0.3, 0.25, obj=2), 0.45, 2))
#: a sideboard 1.8 m wide beside a round thing (its top and front prove `skirt`)
DRESSER = [floor()] + _trough(0.0, 1.6, 0.15, 0.3) + box(0.5, 3.0, 1.8, 0.5, 0.8, obj=2)


def test_a_box_touching_a_round_object_is_cut_on_its_own_planes(tmp_path):
    cloud, desc, objs = _merged(ROUND)
    off = _answer(_model(tmp_path / "off", cut=False), cloud, desc)
    assert [a.klass for a in off] == ["other"]          # the planar gate refuses the whole
    assert [r.klass for r in off[0].refused] == ["box"]
    ans = _answer(_model(tmp_path / "on"), cloud, desc)
    assert [a.klass for a in ans] == ["other", "box"]
    rest, cut = ans
    assert cut.cut_from == rest.object_id and rest.cut_off == (cut.object_id,)
    assert {objs[x] for x in cut.labels} == {2}          # the box's planes, all of them
    assert {objs[x] for x in rest.labels} == {1}         # the round thing stays
    assert set(cut.proof_planes) <= set(cut.planes) and cut.rule.startswith("box(")
    assert cut.planar_fraction == pytest.approx(1.0)
    d = cut.to_dict()
    assert d["cut_from"] == rest.object_id and d["class"] == "box"
    assert rest.to_dict()["cut_off"] == [cut.object_id]
    assert "cut_from" not in off[0].to_dict()


def test_a_box_on_a_stool_like_block_is_cut_from_the_pile(tmp_path):
    # box, stool and a bag in front of the stool in one proposal: box and stairs refused by the
    # planar gate; the box's own solid is a box, the rest stays what the whole was
    cloud, desc, objs = _merged(STOOL + _trough(0.0, 0.85, 0.25, 0.8))
    off = _answer(_model(tmp_path / "off", cut=False), cloud, desc)
    assert [a.klass for a in off] == ["other"]
    assert {r.klass for r in off[0].refused} == {"box", "stairs"}
    ans = _answer(_model(tmp_path / "on"), cloud, desc)
    assert [a.klass for a in ans] == ["other", "box"]
    assert {objs[x] for x in ans[1].labels} == {2} and ans[1].cut_from == ans[0].object_id
    assert {objs[x] for x in ans[0].labels} == {1, 3}


def test_a_pile_answered_another_class_with_box_unrefused_is_not_cut(tmp_path):
    # the stool and the box alone: the stairs rule (more precise) answers, no gate refuses
    # box (as a flight's step proves the skirt clause): nothing is cut
    cloud, desc, _objs = _merged(STOOL)
    ans = _answer(_model(tmp_path / "on"), cloud, desc)
    assert [a.klass for a in ans] == ["stairs"] and not ans[0].cut_off and not ans[0].refused
    assert ("box", 1) in ans[0].fired


def test_faces_going_on_into_a_round_surface_are_not_cut(tmp_path):
    # the price of not cutting two facets of a mug for a box (hunt33 ucn): the box's front
    # and the pipe's strip are adjacent at 15 degrees, as neighbouring facets are.  With
    # decision.cut_corner 3 its top, front and side (three faces at a corner) are cut
    from planerel.features.box_cut import box_solids

    cloud, desc, objs = _merged(ROUND_FLUSH)
    o = desc.objects[0]
    assert box_solids(desc, o.planes, 1.5) == []
    (solid,) = box_solids(desc, o.planes, 1.5, corner=3)
    assert {objs[x] for x in solid} == {2} and len(solid) == 3
    assert box_solids(desc, o.planes, 1.5, corner=4) == []
    assert box_solids(desc, o.planes, 1.5, facet=(5.0, 10.0)) == [solid]
    ans = _answer(_model(tmp_path / "on"), cloud, desc)
    assert [a.klass for a in ans] == ["other"] and not ans[0].cut_off
    ans = _answer(_model(tmp_path / "c3", corner=3), cloud, desc)
    assert [a.klass for a in ans] == ["other", "box"] and ans[1].labels == solid


def test_faces_meeting_as_facets_are_no_solid():
    # a round thing's top with two side strips 30 degrees apart: skirts both, one solid by
    # its edges, but its strips meet as facets do
    from dataclasses import replace

    from planerel.features.box_cut import box_solids

    _cloud, desc, objs = _merged(ROUND)
    o = desc.objects[0]
    (solid,) = box_solids(desc, o.planes, 1.5)
    a, b = [x for x in solid if desc.planes.by_label(x).orientation == "vertical"][:2]
    pairs = tuple(replace(r, angle=30.0, adjacent=True) if {r.a, r.b} == {a, b} else r
                  for r in desc.relations)
    bent = replace(desc, relations=replace(desc.relations, pairs=pairs))
    assert box_solids(bent, o.planes, 1.5) == []
    assert box_solids(bent, o.planes, 1.5, pieces=31.0) == [solid]   # pieces of one face


@pytest.mark.parametrize("reach", [None, 5.0])
def test_a_dresser_sized_block_is_not_cut_for_a_box(tmp_path, reach):
    # default reach: its faces are larger than a box's solid; reach 5 m: the solid is decided
    # and the size gate refuses it as it refuses the whole
    from planerel.features.box_cut import box_solids

    cloud, desc, _objs = _merged(DRESSER)
    assert bool(box_solids(desc, desc.objects[0].planes, reach or 1.5)) == (reach is not None)
    ans = _answer(_model(tmp_path / "on", reach=reach), cloud, desc)
    assert [a.klass for a in ans] == ["other"] and not ans[0].cut_off


def test_the_box_solids_and_the_cut_planar_fraction():
    from planerel.features.box_cut import box_solids, cut_object

    cloud, desc, objs = _merged(ROUND)
    (o,) = desc.objects
    solids = box_solids(desc, o.planes, 1.5)
    assert len(solids) == 1 and {objs[x] for x in solids[0]} == {2}
    assert box_solids(desc, o.planes, 0.1) == []        # no seed within 0.1 m
    assert box_solids(desc, solids[0], 1.5) == []       # the whole: nothing to cut
    # the round thing's pixels as the parent's unexplained ones: those within the margin of
    # the box's bounds count against its planar fraction
    lab = np.asarray(desc.labels).copy()
    round_px = np.isin(lab, [x for x in o.planes if objs[x] == 1])
    lab[round_px] = -1
    from dataclasses import replace

    desc2 = replace(desc, planes=replace(desc.planes, labels=lab))
    parent = replace(o, mask=round_px)
    fr = [cut_object(desc2, parent, solids[0], "c", cloud.xyz, tiny_area=0.0005,
                     curved_below=0.8, margin=m).planar_fraction for m in (0.0, 0.05, 0.3)]
    assert fr[0] >= fr[1] >= fr[2] and fr[2] < fr[0]
    assert cut_object(desc2, replace(o, mask=None), solids[0], "c", cloud.xyz, tiny_area=0.0005,
                      curved_below=0.8, margin=0.3).planar_fraction == pytest.approx(1.0)


@pytest.mark.parametrize("name, value", [("cut_boxes", 1), ("cut_reach", -1.0),
                                         ("cut_margin", float("nan")), ("cut_corner", 1),
                                         ("cut_corner", -2), ("cut_corner", 3.0),
                                         ("cut_pieces", 91.0), ("cut_pieces", True)])
def test_the_settings_are_checked(name, value):
    with pytest.raises(InputError, match=f"decision.{name}"):
        M.DecisionParams(**{name: value})
    assert M.DecisionParams().cut_boxes is True and M.DecisionParams().cut_corner == 0


def test_a_box_a_gate_after_the_decision_refused_is_cut_too(tmp_path):
    """cutpost94: two boxes in one proposal proved ``box`` and refused by a gate after the
    decision (here the crowd gate, bound under the pair's six planes) are cut into their own
    solids, as a refusal inside the decision cuts them; each meets the gates in turn, and a
    proposal none of whose solids stays a box is left whole."""
    two = [floor()] + box(-0.35, 1.4, 0.3, 0.3, 0.25, obj=2) + box(0.35, 1.4, 0.3, 0.3, 0.25,
                                                                   obj=3)
    cloud, desc, objs = _merged(two)
    assert len(desc.objects[0].planes) == 6

    def model(name, crowd, cut=True):
        path = _model(tmp_path / name, cut=cut)
        data = json.loads((path / "model.json").read_text())
        data["decision"].update(crowd_gate=True, crowd_planes=crowd)
        (path / "model.json").write_text(json.dumps(data))
        return path

    (whole,) = _answer(model("wide", 20), cloud, desc)
    assert whole.klass == "box" and not whole.cut_off
    (refused,) = _answer(model("off", 4, cut=False), cloud, desc)
    assert refused.klass == "other"
    assert [type(r) for r in refused.refused] == [M.CrowdRefusal]
    rest, *boxes = _answer(model("on", 4), cloud, desc)
    assert rest.klass == "other" and rest.cut_off == tuple(b.object_id for b in boxes)
    assert [b.klass for b in boxes] == ["box", "box"]
    assert sorted({objs[x] for x in b.labels} for b in boxes) == [{2}, {3}]
    assert all(b.cut_from == rest.object_id and b.rule_index == 1 for b in boxes)
    # a bound under one box's three planes refuses the cut boxes too: no box comes out, and
    # the proposal stays whole, refused as before
    (tight,) = _answer(model("tight", 2), cloud, desc)
    assert tight.klass == "other" and not tight.cut_off
    assert set(tight.labels) == set(desc.objects[0].planes)
    assert [type(r) for r in tight.refused] == [M.CrowdRefusal]
