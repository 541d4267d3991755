"""range40: a rule is not trusted on a proof made farther from the sensor than any training
proof of its class.

The model keeps, per class, the farthest plane (its centroid's distance from the sensor, the
``distance/2`` fact: ``metrics.plane_ranges``) of the nearest proof of each training positive
(``model.json``, ``range_domain``); with ``decision.range_gate`` the decision refuses a rule of
a class named in ``decision.range_classes`` (``box,stairs,ramp``) whose proof binds a plane
more than ``1 + decision.range_margin`` times as far.  On real outdoor frames (stereo,
densified LiDAR) the demo's ramp rule proved verges, lawns and road strips 10.5-17.4 m away;
its training ramps lie at most 3.54 m away (docs/results.md, "Proofs farther away than any training proof").  Scenes
are ray-cast (tests/scenes_analytic.py), segmented and described for real; Prolog runs for real
(swipl through pyswip, and ``prolog_predict``'s own swipl process).
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
from scenes_analytic import floor, ramp, render  # noqa: E402

STATS = [(1, "ramp", 73, 0)]
# the demo model's ramp clause, by hand
RULES = ("ramp(A) :- has_plane(A,B), slope(B,C), area(B,D), gteq(D,0.53), lteq(C,28).\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))
#: the demo model's ramp domain (make demo on this branch): 73 positives, the farthest proof
#: plane 3.54 m from the sensor
RANGES = [("ramp", 3.5373, 73)]
NEAR, FAR = 1, 2


def _model(path: Path, *, ranges=RANGES, gate=True) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS, range_domain=ranges or ())
    data["decision"]["range_gate"] = gate
    if ranges is None:   # a model.json written before range40
        del data["range_domain"]
        for k in ("range_gate", "range_margin", "range_classes"):
            del data["decision"][k]
    (path / "model.json").write_text(json.dumps(data))
    return path


@pytest.fixture(scope="module")
def scene():
    """``(cloud, up, object of each pixel)``: a 15-degree ramp 1.5 m long rising from the
    floor 1.6 m ahead (``NEAR``), and a 12-degree slope 3 x 3 m rising from the floor 8 m
    ahead (``FAR``, its centroid about 9.4 m away: a far verge or lawn), seen from 1.4 m."""
    rects = ([floor(size=30.0, y=10.0)] + ramp(-0.9, 1.6, 15.0, 1.5, 1.0, obj=NEAR)
             + ramp(1.5, 8.0, 12.0, 3.0, 3.0, obj=FAR))
    cloud, lab, up, objs = render(rects, pitch=15, cam_height=1.4, width=320, height=240,
                                  noise=0.0003)
    truth = np.where(lab >= 0, np.asarray(objs)[np.maximum(lab, 0)], -1)
    return cloud, up, truth


def _answers(scene, model, **kw):
    """``{true object: its proposal's answer}`` (the proposal holding most of its pixels)."""
    from planerel.classify.classifier import Classifier

    cloud, up, truth = scene
    with Classifier(model, **kw) as clf:
        ans = clf.classify(cloud, up=up, scene_id="s")
    out = {}
    for obj in (NEAR, FAR):
        held = [(int((np.isin(ans.labels, o.labels) & (truth == obj)).sum()), o)
                for o in ans.objects]
        n, o = max(held, key=lambda t: t[0])
        assert n > 0.5 * (truth == obj).sum(), (obj, n)
        out[obj] = o
    return out


def test_a_far_slope_is_refused_and_a_near_ramp_kept(scene, tmp_path):
    ans = _answers(scene, _model(tmp_path / "m"))
    far = ans[FAR]
    assert far.klass == "other" and ("ramp", 1) in far.fired
    (r,) = far.refused
    assert isinstance(r, M.RangeRefusal) and (r.klass, r.rule) == ("ramp", 1)
    assert 8.5 < r.distance < 10.5 and r.bound == pytest.approx(3.5373 * 2.0)
    assert r.reason == (f"rule 1 proves it with a plane {r.distance:.2f} m from the sensor, "
                        "over 7.07 m: the training ramp proofs' planes lie at most 3.54 m "
                        "away, margin 1 (no evidence that far)")
    d = far.to_dict()["refused"][0]
    assert d["class"] == "ramp" and d["proofs_high"] == 3.5373 and d["margin"] == 1.0
    assert d["proof_distance"] == pytest.approx(r.distance, abs=1e-4)
    # the near ramp: the same rule, within the training range
    assert ans[NEAR].klass == "ramp" and ans[NEAR].rule_index == 1 and ans[NEAR].refused == ()


@pytest.mark.parametrize("how", ["no domain", "gate off", "param off", "class off", "margin"])
def test_without_the_gate_the_far_slope_is_ramp(scene, tmp_path, how):
    kw = {"param off": {"seg_params": {"decision.range_gate": "false"}},
          "class off": {"seg_params": {"decision.range_classes": "box,stairs"}},
          "margin": {"seg_params": {"decision.range_margin": "2.0"}}}.get(how, {})
    ans = _answers(scene, _model(tmp_path / "m", ranges=None if how == "no domain" else RANGES,
                                 gate=how != "gate off"), **kw)
    assert ans[FAR].klass == "ramp" and ans[FAR].refused == ()
    assert ans[NEAR].klass == "ramp"


def test_classify_json_says_why(scene, tmp_path):
    """``planerel classify --json``'s refusals carry the range refusal."""
    from planerel.classify.classifier import Classifier

    cloud, up, _truth = scene
    with Classifier(_model(tmp_path / "m")) as clf:
        doc = clf.classify(cloud, up=up, scene_id="s").to_dict()
    refused = [r for o in doc["objects"] for r in o["refused"]]
    assert [(r["class"], r["rule"]) for r in refused] == [("ramp", 1)]
    assert "from the sensor" in refused[0]["reason"] and refused[0]["proofs_high"] == 3.5373


def test_the_domain_is_the_farthest_plane_of_the_nearest_proofs():
    ranges = {"p1": 1.0, "p2": 2.5, "p3": 4.0, "p4": 12.0, "p5": 3.0}
    fired = {"a": [("ramp", 1, {"B": "p1", "C": "p2"}, "", None),   # 2.5: the nearest counts
                   ("ramp", 2, {"B": "p3"}, "", None)],            # 4.0
             "b": [("ramp", 1, {"B": "p5"}, "", None)],            # 3.0
             "c": [("ramp", 1, {"B": "p4"}, "", None)],            # other: not counted
             "d": [("stairs", 3, {"B": "p4", "C": "p1"}, "", None)],
             "e": [("ramp", 1, {"N": 3}, "", None)]}               # no plane: not counted
    truth = {"a": "ramp", "b": "ramp", "c": "other", "d": "stairs", "e": "ramp"}
    assert M.range_domain(fired, truth, ranges) == (("ramp", 3.0, 2), ("stairs", 12.0, 1))
    assert M.proof_range({"B": "p1", "C": "p4", "N": 3}, ranges) == 12.0
    assert M.proof_range({"N": 3}, ranges) is None
    dom = (("ramp", 3.5, 73),)
    stats = [(1, "ramp", 73, 0), (2, "box", 9, 1)]
    hits = [("ramp", 1, {"B": "p4"}, ""), ("box", 2, {"B": "p4"}, ""),
            ("ramp", 1, {"B": "p3"}, "")]
    kept, refused = M.range_refusals(hits, stats, ranges, dom)
    assert kept == hits[1:]   # 4.0 m is within 3.5 x 2; box is not gated
    assert [(r.rule, r.distance, r.high, r.bound) for r in refused] == [(1, 12.0, 3.5, 7.0)]
    # within the margin, a bigger margin, no domain, no ranges: kept
    assert M.range_refusals(hits, stats, {**ranges, "p4": 6.9}, dom) == (hits, ())
    assert M.range_refusals(hits, stats, ranges, dom, margin=3.0) == (hits, ())
    assert M.range_refusals(hits, stats, ranges, ()) == (hits, ())
    assert M.range_refusals(hits, stats, None, dom) == (hits, ())
    # an entry measured on too few positives is no bound; ranges asked only when needed
    assert M.range_refusals(hits, stats, ranges, (("ramp", 3.5, 9),)) == (hits, ())
    asked = []
    assert M.range_refusals(hits[1:2], stats, lambda: asked.append(1) or ranges, dom) == (
        hits[1:2], ())
    assert asked == []
    # decide: the ramp hit over the bound goes, the box hit decides
    best, refused = M.decide(hits[:2], stats, ["box", "ramp"], distances=ranges, ranges=dom)
    assert best[0] == "box" and [type(r) for r in refused] == [M.RangeRefusal]
    assert M.decide(hits[:2], stats, ["box", "ramp"], distances=ranges)[0][0] == "ramp"


def test_model_json_keeps_the_domain(tmp_path):
    from planerel.ilp.model_settings import read_settings, with_overrides

    path = _model(tmp_path / "m")
    s = read_settings(path / "rules.pl")
    assert s.range_domain == tuple(RANGES) and s.decision_params().range_gate is True
    assert with_overrides(s, overrides={"theta": 20})[0].range_domain == tuple(RANGES)
    old = read_settings(_model(tmp_path / "old", ranges=None) / "rules.pl")
    assert old.range_domain == () and old.decision_params().range_gate is True
    data = json.loads((path / "model.json").read_text())
    data["range_domain"] = [{"class": "ramp", "high": "far"}]
    (path / "model.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match="range_domain entry"):
        read_settings(path / "rules.pl")


def test_prolog_predict_decides_with_the_same_gate(scene):
    """The learner's own scoring (cross-validation, held-out sets) decides as classify does,
    and learning keeps the domain of what its rules proved."""
    from dataclasses import replace

    from planerel.features.facts import describe_scene
    from planerel.ilp import pipeline as P
    from planerel.segment import segment

    cloud, up, truth = scene
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s0040", up=up)
    model = P.Model(("ramp",), {"ramp": (RULES.splitlines()[0],)}, stats=tuple(STATS),
                    range_domain=tuple(RANGES))
    on = P.prolog_predict(model, [desc])
    off = P.prolog_predict(replace(model, range_gate=False), [desc])
    assert model.range_gate
    assert sum(p.klass == "ramp" for p in off) == 2
    assert sum(p.klass == "ramp" for p in on) == 1
    assert [(r.klass, r.rule) for p in on for r in p.refused] == [("ramp", 1)]
    fired = P._parse_fired(P._prolog_run(model, [desc], [o.id for o in desc.objects], 60))
    ranges = M.plane_ranges([desc])
    near = next(o.id for o in desc.objects
                if o.planes and max(ranges[desc.plane_id(x)] for x in o.planes) < 4.0
                and o.id in fired)
    (entry,) = M.range_domain(fired, {near: "ramp"}, ranges)
    assert entry[0] == "ramp" and 1.5 < entry[1] < 3.0 and entry[2] == 1


@pytest.mark.parametrize("gate, default, margin, classes", [
    ("size", M.SIZE_GATE, 0.2, "box"),
    ("slender", M.SLENDER_GATE, 0.5, "box"),
    ("range", M.RANGE_GATE, 1.0, "box,stairs,ramp"),
])
def test_the_bounded_gates_settings_and_their_checks(gate, default, margin, classes):
    """The three gates over a training domain's high (size, slenderness, range): defaults,
    and a one-line error for a bad value of each setting."""
    p = M.DecisionParams()
    assert default is getattr(p, f"{gate}_gate") is True
    assert getattr(p, f"{gate}_margin") == margin and getattr(p, f"{gate}_classes") == classes
    with pytest.raises(InputError, match=f"{gate}_gate must be true or false"):
        M.DecisionParams(**{f"{gate}_gate": "on"})
    with pytest.raises(InputError, match=f"{gate}_margin must be a number >= 0"):
        M.DecisionParams(**{f"{gate}_margin": -0.1})
    with pytest.raises(InputError, match=f"{gate}_classes must be class names"):
        M.DecisionParams(**{f"{gate}_classes": ["box"]})
