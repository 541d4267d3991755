"""fbox31: a box rule is not trusted on a proof that binds a plane far longer than any plane
of the training box proofs.

The model keeps, per class, the furthest-reaching plane (a face's height, another plane's
``plane_length/2``: ``metrics.plane_extents``) of the most compact proof of each training
positive (``model.json``, ``size_domain``); with ``decision.size_gate`` the decision refuses a
rule of a class named in ``decision.size_classes`` (``box``) whose proof binds a plane reaching
further than ``1 + decision.size_margin`` times that.  On real rooms nobody on the
team had seen, the demo's box rules proved a dining table's 2.2 m top over its apron
(``skirt``), a wardrobe's 1.6 m side and a door's jamb seen to the image's top (``tall_face``);
the demo world's boxes are at most 1.2 m long (docs/objects.md, "False boxes on real rooms").
Prolog runs for real (swipl through pyswip, and ``prolog_predict``'s own swipl process).
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

#: the demo's box rules 1 and 2 (make demo, main d9ec8cc) and their training statistics
STATS = [(1, "box", 80, 9), (2, "box", 23, 1)]
RULES = ("box(A) :- has_plane(A,B), skirt(B,C).\n"
         "box(A) :- has_plane(A,B), nhorizontal(A,0), tall_face(B).\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))
#: the demo model's box domain (make demo on this branch): a 1.2 m box's top, 137 positives
SIZES = [("box", 1.2295, 137)]
TABLE, WARDROBE = 9, 8


def _model(path: Path, *, sizes=SIZES, gate=True, hang=False) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS, size_domain=sizes or ())
    data["decision"]["size_gate"] = gate
    # false57's hang gate refuses the table's apron too (it hangs over the space under the
    # top): off here unless asked, so these tests see the size gate alone
    data["decision"]["hang_gate"] = hang
    if sizes is None:   # a model.json written before fbox31
        del data["size_domain"]
        for k in ("size_gate", "size_margin", "size_classes"):
            del data["decision"][k]
    (path / "model.json").write_text(json.dumps(data))
    return path


def _dining_table(cx=0.0, cy=2.3, sx=2.0, sy=0.9, h=0.75, apron=0.13):
    """A dining table's top and its apron flush under the top's edges (front and both ends),
    as the NYU dining room's (legs left out: the apron is what ``skirt`` takes)."""
    return [Rect((cx, cy, h), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, TABLE),
            Rect((cx, cy - sy / 2, h - apron / 2), (1, 0, 0), (0, 0, 1), sx / 2, apron / 2, TABLE),
            Rect((cx - sx / 2, cy, h - apron / 2), (0, 1, 0), (0, 0, 1), sy / 2, apron / 2, TABLE),
            Rect((cx + sx / 2, cy, h - apron / 2), (0, 1, 0), (0, 0, 1), sy / 2, apron / 2, TABLE)]


def _scene(kind: str):
    """``(cloud, up, labels, object of each label)``: ``table`` a 2 x 0.9 m dining table with
    its apron and a 50 x 40 x 35 cm box in front of it, seen from 1.5 m; ``wardrobe`` a
    1.9 m tall wardrobe (1.0 x 0.6 m) and a 0.9 m tall carton (0.6 x 0.5 m) seen from 0.8 m
    (neither top in view: ``tall_face``)."""
    if kind == "table":
        rects = [floor(), *_dining_table(), *box(0.8, 1.3, 0.5, 0.4, 0.35, obj=1)]
        view = dict(pitch=35, cam_height=1.5, width=320, height=240, noise=0.001)
    else:
        wardrobe = [Rect(r.center, r.e1, r.e2, r.a, r.b, WARDROBE)
                    for r in box(-0.8, 3.0, 1.0, 0.6, 1.9)]
        rects = [floor(), *wardrobe, *box(0.6, 2.6, 0.6, 0.5, 0.9, obj=1)]
        view = dict(pitch=0, cam_height=0.8, width=320, height=240, noise=0.001)
    cloud, lab, up, objs = render(rects, **view)
    return cloud, up, lab, objs


def _answers(kind, model, **kw):
    """``{true object: its proposal's answer}`` (the proposal holding most of its pixels)."""
    from planerel.classify.classifier import Classifier

    cloud, up, lab, objs = _scene(kind)
    truth = np.where(lab >= 0, np.asarray(objs)[np.maximum(lab, 0)], -1)
    with Classifier(model, **kw) as clf:
        ans = clf.classify(cloud, up=up)
    out = {}
    for obj in (1, TABLE if kind == "table" else WARDROBE):
        held = [(int((np.isin(ans.labels, o.labels) & (truth == obj)).sum()), o)
                for o in ans.objects]
        n, o = max(held, key=lambda t: t[0])
        assert n > 0.5 * (truth == obj).sum(), (kind, obj, n)
        out[obj] = o
    return out


@pytest.mark.parametrize("kind,rule,extent", [("table", 1, 2.0), ("wardrobe", 2, 1.9)])
def test_furniture_longer_than_any_box_is_refused(tmp_path, kind, rule, extent):
    ans = _answers(kind, _model(tmp_path / "m"))
    big = ans[TABLE if kind == "table" else WARDROBE]
    assert big.klass == "other" and ("box", rule) in big.fired
    (r,) = big.refused
    assert isinstance(r, M.SizeRefusal) and (r.klass, r.rule) == ("box", rule)
    assert r.extent == pytest.approx(extent, abs=0.06) and r.bound == pytest.approx(1.2295 * 1.2)
    assert r.reason == (f"rule {rule} proves it with a plane reaching {r.extent:.2f} m, over "
                        "1.48 m: the training box proofs' planes reach at most 1.23 m, margin 0.2")
    d = big.to_dict()["refused"][0]
    assert d["class"] == "box" and d["proofs_high"] == 1.2295 and d["margin"] == 0.2
    # the box beside it: the same rule, a box's planes
    assert ans[1].klass == "box" and ans[1].rule_index == rule and ans[1].refused == ()


@pytest.mark.parametrize("how", ["no domain", "gate off", "param off", "class off", "margin"])
def test_without_the_gate_the_furniture_is_box(tmp_path, how):
    kw = {"param off": {"seg_params": {"decision.size_gate": "false"}},
          "class off": {"seg_params": {"decision.size_classes": "stairs"}},
          "margin": {"seg_params": {"decision.size_margin": "0.7"}}}.get(how, {})
    ans = _answers("table", _model(tmp_path / "m", sizes=None if how == "no domain" else SIZES,
                                   gate=how != "gate off"), **kw)
    assert ans[TABLE].klass == "box" and ans[TABLE].refused == ()
    assert ans[1].klass == "box"


def test_a_face_reaches_as_high_as_it_is_tall():
    """A vertical plane's extent is its height: a row of boxes makes one long front, never a
    face taller than its boxes; a top's is its length."""
    from planerel.features.facts import describe_scene
    from planerel.segment import segment

    row = [Rect((0.0, 2.0, 0.2), (1, 0, 0), (0, 0, 1), 1.0, 0.2, 1),     # 2.0 m long, 0.4 m high
           Rect((0.0, 2.3, 0.4), (1, 0, 0), (0, 1, 0), 1.0, 0.3, 1)]     # its top, 2.0 x 0.6 m
    cloud, _lab, up, _objs = render([floor(), *row], pitch=30, cam_height=1.5, width=320,
                                    height=240, noise=0.0005)
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s", up=up)
    ext = M.plane_extents([desc])
    front = [p for p in desc.planes if p.orientation == "vertical" and p.length > 1.5]
    top = [p for p in desc.planes if p.orientation == "horizontal" and not p.is_floor
           and p.length > 1.5]
    assert len(front) == 1 and len(top) == 1
    assert ext[desc.plane_id(front[0].label)] == pytest.approx(0.4, abs=0.03)
    assert ext[desc.plane_id(top[0].label)] == pytest.approx(top[0].length) == pytest.approx(
        2.0, abs=0.05)


def test_the_domain_is_the_longest_compact_proof_of_the_class_positives():
    extents = {"p1": 0.5, "p2": 0.3, "p3": 1.1, "p4": 0.2, "p5": 2.0, "p6": 0.9}
    fired = {"a": [("box", 1, {"B": "p1", "C": "p2"}, "", None),     # extent 0.5
                   ("box", 2, {"B": "p3"}, "", None)],               # 1.1: the compact one counts
             "b": [("box", 2, {"B": "p6", "D": 89}, "", None)],      # 0.9
             "c": [("box", 1, {"B": "p5", "C": "p4"}, "", None)],    # other: not counted
             "d": [("stairs", 3, {"B": "p5"}, "", None), ("box", 1, {"B": "p4"}, "", None)],
             "e": [("box", 1, {"X": "nothing"}, "", None)]}          # no plane bound
    truth = {"a": "box", "b": "box", "c": "other", "d": "stairs", "e": "box"}
    assert M.size_domain(fired, truth, extents) == (("box", 0.9, 2), ("stairs", 2.0, 1))
    assert M.proof_extent({"B": "p1", "C": "p5", "N": 3}, extents) == 2.0
    assert M.proof_extent({"N": 3}, extents) is None
    assert M.size_gated((("box", 0.9, 2), ("stairs", 2.0, 1))) == (("box", 0.9, 2),)
    assert M.size_gated((("box", 0.9, 2), ("stairs", 2.0, 1)), " stairs, ramp") == (
        ("stairs", 2.0, 1),)
    dom = (("box", 1.0, 12),)
    stats = [(1, "box", 9, 1), (2, "stairs", 3, 1), (3, "box", 1, 1)]
    hits = [("box", 1, {"B": "p5"}, ""), ("stairs", 2, {"B": "p5"}, ""),
            ("box", 1, {"B": "p1"}, "")]
    kept, refused = M.size_refusals(hits, stats, extents, dom)
    assert kept == hits[1:] and [(r.rule, r.extent, r.high) for r in refused] == [(1, 2.0, 1.0)]
    # within the margin: kept; a bigger margin, no domain, no extents: nothing refused
    assert M.size_refusals(hits, stats, {**extents, "p5": 1.19}, dom) == (hits, ())
    assert M.size_refusals(hits, stats, extents, dom, margin=1.5) == (hits, ())
    assert M.size_refusals(hits, stats, extents, ()) == (hits, ())
    assert M.size_refusals(hits, stats, None, dom) == (hits, ())
    # an entry measured on too few positives is no bound; extents asked only when needed
    assert M.size_refusals(hits, stats, extents, (("box", 1.0, 9),)) == (hits, ())
    asked = []
    assert M.size_refusals(hits[1:2], stats, lambda: asked.append(1) or extents, dom) == (
        hits[1:2], ())
    assert asked == []
    # a refused rule that takes no part in the decision (fp >= tp) is not reported
    assert M.size_refusals([("box", 3, {"B": "p5"}, "")], stats, extents, dom) == ([], ())
    # decide: the box hit over the bound goes, the one within decides
    best, refused = M.decide(hits[:2], stats, ["box", "stairs"], extents=extents, sizes=dom)
    assert best[0] == "stairs" and [r.klass for r in refused] == ["box"]
    assert M.decide(hits[:2], stats, ["box", "stairs"], extents=extents)[0][0] == "box"


def test_model_json_keeps_the_domain(tmp_path):
    from planerel.ilp.model_settings import read_settings, with_overrides

    path = _model(tmp_path / "m")
    s = read_settings(path / "rules.pl")
    assert s.size_domain == tuple(SIZES) and s.decision_params().size_gate is True
    assert with_overrides(s, overrides={"theta": 20})[0].size_domain == tuple(SIZES)
    assert read_settings(_model(tmp_path / "old", sizes=None) / "rules.pl").size_domain == ()
    data = json.loads((path / "model.json").read_text())
    data["size_domain"] = [{"class": "box", "high": "long"}]
    (path / "model.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match="size_domain entry"):
        read_settings(path / "rules.pl")


def test_prolog_predict_decides_with_the_same_gate():
    """The learner's own scoring (cross-validation, held-out sets) decides as classify does,
    and learning keeps the domain of what its rules proved."""
    from dataclasses import replace

    from planerel.features.facts import describe_scene
    from planerel.ilp import pipeline as P
    from planerel.segment import segment

    cloud, up, _lab, _objs = _scene("table")
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s0007", up=up)
    model = P.Model(("box",), {"box": (RULES.splitlines()[0],)}, stats=tuple(STATS[:1]),
                    size_domain=tuple(SIZES))
    on = P.prolog_predict(model, [desc])
    off = P.prolog_predict(replace(model, size_gate=False), [desc])
    assert model.size_gate
    assert sum(p.klass == "box" for p in off) == 2
    assert sum(p.klass == "box" for p in on) == 1
    assert [(r.klass, r.rule) for p in on for r in p.refused] == [("box", 1)]
    fired = P._parse_fired(P._prolog_run(model, [desc], [o.id for o in desc.objects], 60))
    extents = M.plane_extents([desc])
    small = next(o.id for o in desc.objects if max(extents[desc.plane_id(x)]
                                                  for x in o.planes) < 1.0)
    (entry,) = M.size_domain(fired, {small: "box"}, extents)
    assert entry[0] == "box" and 0.45 < entry[1] < 0.6 and entry[2] == 1   # the 0.5 m top
