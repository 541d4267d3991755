"""slab36: a box rule is not trusted on a proof whose top is a strip far more slender than any
top of the training box proofs.

The model keeps, per class, the most slender top (a horizontal or inclined plane's
``plane_length`` over its ``plane_width``: ``metrics.plane_slenderness``) of the least slender
proof of each training positive (``model.json``, ``slender_domain``); with
``decision.slender_gate`` the decision refuses a rule of a class named in
``decision.slender_classes`` (``box``) whose proof binds a top more than ``1 +
decision.slender_margin`` times as slender.  On the independent development sets the demo's
``skirt`` rule proved the 8 cm top strips of a staircase's side walls with a face below them
(docs/objects.md, "Thin walls and slabs are no boxes").  Prolog runs for real (swipl through
pyswip, and ``prolog_predict``'s own swipl process).
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
from scenes_analytic import box, floor, render  # noqa: E402
from test_size_gate import RULES, SIZES, STATS  # noqa: E402

#: the demo model's box domain (make demo on this branch): 104 positives proved with a top,
#: the most slender 5.97 times as long as wide
SLENDERS = [("box", 5.9696, 104)]
WALL = 7


def _model(path: Path, *, slenders=SLENDERS, gate=True) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS, size_domain=SIZES,
                             slender_domain=slenders or ())
    data["decision"]["slender_gate"] = gate
    # a thin wall with its top strip: slab101's gate refuses it too; off here, these tests
    # isolate the slender gate
    data["decision"]["slab_gate"] = False
    if slenders is None:   # a model.json written before slab36
        del data["slender_domain"]
        for k in ("slender_gate", "slender_margin", "slender_classes"):
            del data["decision"][k]
    (path / "model.json").write_text(json.dumps(data))
    return path


def _scene(length=1.2, height=0.6):
    """``(cloud, up, labels, object of each label)``: a wall 8 cm thick, ``length`` long and
    ``height`` high (a parapet, a staircase's side wall: its top an 8 cm strip, its side face
    hanging below it), and a 50 x 40 x 35 cm box beside it, seen from 1.5 m."""
    rects = [floor(), *box(-0.55, 2.3, length, 0.08, height, obj=WALL),
             *box(0.8, 1.8, 0.5, 0.4, 0.35, obj=1)]
    cloud, lab, up, objs = render(rects, pitch=35, cam_height=1.5, width=320, height=240,
                                  noise=0.001)
    return cloud, up, lab, objs


def _answers(model, **kw):
    """``{true object: its proposal's answer}`` (the proposal holding most of its pixels)."""
    from planerel.classify.classifier import Classifier

    cloud, up, lab, objs = _scene()
    truth = np.where(lab >= 0, np.asarray(objs)[np.maximum(lab, 0)], -1)
    with Classifier(model, **kw) as clf:
        ans = clf.classify(cloud, up=up)
    out = {}
    for obj in (1, WALL):
        held = [(int((np.isin(ans.labels, o.labels) & (truth == obj)).sum()), o)
                for o in ans.objects]
        n, o = max(held, key=lambda t: t[0])
        assert n > 0.5 * (truth == obj).sum(), (obj, n)
        out[obj] = o
    return out


def test_a_thin_wall_with_its_top_strip_is_refused(tmp_path):
    ans = _answers(_model(tmp_path / "m"))
    wall = ans[WALL]
    assert wall.klass == "other" and ("box", 1) in wall.fired
    (r,) = wall.refused
    assert isinstance(r, M.SlenderRefusal) and (r.klass, r.rule) == ("box", 1)
    assert 10 < r.slenderness < 16 and r.bound == pytest.approx(5.9696 * 1.5)
    assert r.reason == (f"rule 1 proves it with a top {r.slenderness:.1f} times as long as "
                        "wide, over 9.0: the training box proofs' tops reach 6.0, margin 0.5 "
                        "(a thin wall's or a slab's strip)")
    d = wall.to_dict()["refused"][0]
    assert d["class"] == "box" and d["proofs_high"] == 5.9696 and d["margin"] == 0.5
    # the box beside it: the same rule, a box's top
    assert ans[1].klass == "box" and ans[1].rule_index == 1 and ans[1].refused == ()


@pytest.mark.parametrize("how", ["no domain", "gate off", "param off", "class off", "margin"])
def test_without_the_gate_the_wall_is_box(tmp_path, how):
    kw = {"param off": {"seg_params": {"decision.slender_gate": "false"}},
          "class off": {"seg_params": {"decision.slender_classes": "stairs"}},
          "margin": {"seg_params": {"decision.slender_margin": "2.0"}}}.get(how, {})
    ans = _answers(_model(tmp_path / "m", slenders=None if how == "no domain" else SLENDERS,
                          gate=how != "gate off"), **kw)
    assert ans[WALL].klass == "box" and ans[WALL].refused == ()
    assert ans[1].klass == "box"


def test_the_domain_is_the_most_slender_top_of_the_least_slender_proofs():
    slender = {"p1": 2.0, "p3": 5.0, "p5": 12.0, "p6": 3.0}   # tops only: p2, p4 are faces
    fired = {"a": [("box", 1, {"B": "p1", "C": "p2"}, "", None),    # 2.0: the least counts
                   ("box", 1, {"B": "p3", "C": "p4"}, "", None)],   # 5.0
             "b": [("box", 1, {"B": "p6", "C": "p2"}, "", None),    # 3.0
                   ("box", 2, {"B": "p2"}, "", None)],              # no top: not counted
             "c": [("box", 1, {"B": "p5", "C": "p4"}, "", None)],   # other: not counted
             "d": [("stairs", 3, {"B": "p5"}, "", None)],
             "e": [("box", 2, {"B": "p4"}, "", None)]}              # no top at all
    truth = {"a": "box", "b": "box", "c": "other", "d": "stairs", "e": "box"}
    assert M.slender_domain(fired, truth, slender) == (("box", 3.0, 2), ("stairs", 12.0, 1))
    assert M.proof_slenderness({"B": "p1", "C": "p5", "N": 3}, slender) == 12.0
    assert M.proof_slenderness({"B": "p2"}, slender) is None
    dom = (("box", 6.0, 12),)
    stats = [(1, "box", 9, 1), (2, "stairs", 3, 1), (3, "box", 1, 1)]
    hits = [("box", 1, {"B": "p5", "C": "p2"}, ""), ("stairs", 2, {"B": "p5"}, ""),
            ("box", 1, {"B": "p1", "C": "p2"}, "")]
    kept, refused = M.slender_refusals(hits, stats, slender, dom)
    assert kept == hits[1:]
    assert [(r.rule, r.slenderness, r.high) for r in refused] == [(1, 12.0, 6.0)]
    # within the margin (6 x 1.5 = 9), a bigger margin, no domain, no slenderness: kept
    assert M.slender_refusals(hits, stats, {**slender, "p5": 8.9}, dom) == (hits, ())
    assert M.slender_refusals(hits, stats, slender, dom, margin=1.5) == (hits, ())
    assert M.slender_refusals(hits, stats, slender, ()) == (hits, ())
    assert M.slender_refusals(hits, stats, None, dom) == (hits, ())
    # an entry measured on too few positives is no bound; slenderness asked only when needed
    assert M.slender_refusals(hits, stats, slender, (("box", 6.0, 9),)) == (hits, ())
    asked = []
    assert M.slender_refusals(hits[1:2], stats, lambda: asked.append(1) or slender, dom) == (
        hits[1:2], ())
    assert asked == []
    # a face alone (a wall's end, a tall narrow box's face) is never refused
    assert M.slender_refusals([("box", 1, {"B": "p2"}, "")], stats, slender, dom) == (
        [("box", 1, {"B": "p2"}, "")], ())
    # decide: the box hit over the bound goes, the stairs hit decides
    best, refused = M.decide(hits[:2], stats, ["box", "stairs"], slender=slender, slenders=dom)
    assert best[0] == "stairs" and [type(r) for r in refused] == [M.SlenderRefusal]
    assert M.decide(hits[:2], stats, ["box", "stairs"], slender=slender)[0][0] == "box"


def test_model_json_keeps_the_domain(tmp_path):
    from planerel.ilp.model_settings import read_settings, with_overrides

    path = _model(tmp_path / "m")
    s = read_settings(path / "rules.pl")
    assert s.slender_domain == tuple(SLENDERS) and s.decision_params().slender_gate is True
    assert s.size_domain == tuple(SIZES)
    assert with_overrides(s, overrides={"theta": 20})[0].slender_domain == tuple(SLENDERS)
    old = read_settings(_model(tmp_path / "old", slenders=None) / "rules.pl")
    assert old.slender_domain == () and old.size_domain == tuple(SIZES)
    data = json.loads((path / "model.json").read_text())
    data["slender_domain"] = [{"class": "box", "high": "thin"}]
    (path / "model.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match="slender_domain entry"):
        read_settings(path / "rules.pl")


def test_prolog_predict_decides_with_the_same_gate():
    """The learner's own scoring (cross-validation, held-out sets) decides as classify does,
    and learning keeps the domain of what its rules proved."""
    from dataclasses import replace

    from planerel.features.facts import describe_scene
    from planerel.ilp import pipeline as P
    from planerel.segment import segment

    cloud, up, _lab, _objs = _scene()
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s0007", up=up)
    model = P.Model(("box",), {"box": (RULES.splitlines()[0],)}, stats=tuple(STATS[:1]),
                    slender_domain=tuple(SLENDERS))
    on = P.prolog_predict(model, [desc])
    off = P.prolog_predict(replace(model, slender_gate=False), [desc])
    assert model.slender_gate
    assert sum(p.klass == "box" for p in off) == 2
    assert sum(p.klass == "box" for p in on) == 1
    assert [(r.klass, r.rule) for p in on for r in p.refused] == [("box", 1)]
    fired = P._parse_fired(P._prolog_run(model, [desc], [o.id for o in desc.objects], 60))
    slender = M.plane_slenderness([desc])
    boxed = next(o.id for o in desc.objects
                 if max(slender.get(desc.plane_id(x), 0.0) for x in o.planes) < 3.0)
    (entry,) = M.slender_domain(fired, {boxed: "box"}, slender)
    assert entry[0] == "box" and 1.1 < entry[1] < 1.4 and entry[2] == 1   # the 0.5 x 0.4 top
