"""proof22: a rule is not trusted where it proves an object only with planes far smaller than
in any of its training proofs.

Each rule's proof scale on an object is the largest, over its proofs, of the smallest plane
area a proof binds (``planerel_proof_scale/4``).  The model keeps, per rule, the least scale
among the objects of its class it proved in training (``model.json``, ``proof_domain``); with
``decision.proof_gate`` the decision refuses the rule on an object whose scale lies more than
``decision.proof_margin`` below it (docs/results.md, "The proof gate").  Prolog runs for real
(swipl through pyswip, and ``prolog_predict``'s own swipl process).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import box, floor, render  # noqa: E402

STATS = [(1, "box", 9, 1), (2, "stairs", 5, 2)]
# a hand-written model: any object with two perpendicular planes is a box; with two planes
# at all, stairs (less precise)
RULES = ("box(A) :- has_plane(A,B), perpendicular(B,C).\n"
         "stairs(A) :- has_plane(A,B), has_plane(A,C), B \\== C.\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))
# the box rule's training proofs: planes of 0.04-0.3 m^2 (refused under 0.04 * (0.04 / 0.3)
# ** 0.3 = 0.0219)
PROOFS = [(1, "box", 0.04, 0.3, 12)]


def _model(path: Path, *, proofs=PROOFS, gate=True) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS, proof_domain=proofs or ())
    data["decision"]["proof_gate"] = gate
    data["decision"]["flight_gate"] = False  # its stairs rule proves boxes (pile26's gate off)
    if proofs is None:   # a model.json written before proof22
        del data["proof_domain"]
        for key in ("proof_gate", "proof_margin"):
            del data["decision"][key]
    (path / "model.json").write_text(json.dumps(data))
    return path


@pytest.fixture(scope="module")
def scene():
    """A box of 40 x 30 x 25 cm (faces 0.07-0.12 m^2 seen) and one of 14 x 12 x 10 cm (top
    and front seen, 0.017 and 0.014 m^2) on the floor, seen from 1.0 m, 45 degrees down;
    the cloud and its up vector."""
    cloud, _lab, up, _objs = render([floor()] + box(-0.35, 1.2, 0.4, 0.3, 0.25, obj=1)
                                    + box(0.25, 1.0, 0.14, 0.12, 0.10, obj=2),
                                    pitch=45, cam_height=1.0, width=640, height=480,
                                    noise=0.0003)
    return cloud, up


def _answers(model, scene, **kw):
    from planerel.classify.classifier import Classifier

    cloud, up = scene
    with Classifier(model, **kw) as clf:
        return clf.warnings, clf.classify(cloud, up=up).objects


def _describe(scene, scene_id):
    from planerel.features.facts import describe_scene
    from planerel.segment import segment

    cloud, up = scene
    return describe_scene(cloud, segment(cloud).labels, scene_id=scene_id, up=up)


def test_proof_scale_is_the_largest_proof_of_its_smallest_plane(scene):
    """The scale ``planerel_proof_scale/4`` prints (swipl, the learner's rule query) against the
    same number computed from the description in Python: over the object's perpendicular
    pairs, the largest of the smaller plane's area."""
    from planerel.ilp import pipeline as P

    desc = _describe(scene, "s0001")
    rules = RULES.split("planerel_rule_stats")[0].strip().splitlines()
    model = P.Model(("box", "stairs"), {"box": (rules[0],), "stairs": (rules[1],)})
    ids = [o.id for o in desc.objects]
    fired = P._parse_fired(P._prolog_run(model, [desc], ids, 120.0))
    area = {p.label: p.area for p in desc.planes}
    checked = 0
    for o in desc.objects:
        own = set(o.planes)
        pairs = [(r.a, r.b) for r in desc.relations
                 if r.perpendicular and r.a in own and r.b in own]
        scales = {h[1]: h[4] for h in fired[o.id]}
        if not pairs:
            assert 1 not in scales
            continue
        want = max(min(area[a], area[b]) for a, b in pairs)
        assert scales[1] == pytest.approx(want, abs=5.1e-4)  # area/2 facts hold 3 decimals
        # the stairs rule: any two planes, so the object's second largest plane
        second = sorted(area[k] for k in own)[-2]
        assert scales[2] == pytest.approx(second, abs=5.1e-4)  # area/2 facts hold 3 decimals
        checked += 1
    assert checked == 2


def test_a_proof_of_small_planes_is_refused_and_a_large_one_kept(tmp_path, scene):
    _warn, objs = _answers(_model(tmp_path / "m"), scene)
    boxes = [o for o in objs if ("box", 1) in o.fired]
    assert len(boxes) == 2
    small = [o for o in boxes if any(isinstance(r, M.ProofRefusal) for r in o.refused)]
    large = [o for o in boxes if not o.refused]
    assert len(small) == 1 and len(large) == 1
    assert large[0].klass == "box" and large[0].rule.startswith("box(")
    o = small[0]
    # the box rule is refused; the stairs rule (no domain entry) still proves it
    assert o.klass == "stairs" and o.rule.startswith("stairs(")
    r = o.refused[0]
    assert (r.klass, r.rule, r.low, r.high, r.margin) == ("box", 1, 0.04, 0.3, 0.3)
    assert r.bound == pytest.approx(0.04 * (0.04 / 0.3) ** 0.3) and 0.01 < r.scale < 0.02
    assert "rule 1 proves it with planes of" in r.reason and "under 0.0219" in r.reason
    assert "its training box proofs 0.0400-0.3000 m^2, margin 0.3" in r.reason
    d = o.to_dict()["refused"][0]
    assert d["rule"] == 1 and d["class"] == "box" and d["proofs_low"] == 0.04
    assert d["proof_scale"] == pytest.approx(r.scale, abs=1e-5)


@pytest.mark.parametrize("how", ["no domain", "gate off", "margin 1"])
def test_without_the_gate_every_rule_decides(tmp_path, scene, how):
    kw = {"seg_params": {"decision.proof_margin": "1.0"}} if how == "margin 1" else {}
    warn, objs = _answers(_model(tmp_path / "m", proofs=None if how == "no domain" else PROOFS,
                                 gate=how != "gate off"), scene, **kw)
    boxes = [o for o in objs if ("box", 1) in o.fired]
    assert len(boxes) == 2 and all(o.klass == "box" and o.refused == () for o in boxes)
    if how == "margin 1":
        assert any("decision.proof_margin=1.0 differs" in w for w in warn)


def test_the_domain_is_the_least_scale_of_the_rules_true_positives():
    fired = {"a": [("box", 1, {}, "", 0.05), ("stairs", 2, {}, "", 0.01)],
             "b": [("box", 1, {}, "", 0.2)],
             "c": [("box", 1, {}, "", 0.001)],          # a false positive: not in the domain
             "d": [("stairs", 2, {}, "", 0.3), ("other", 3, {}, "", 0.5)],
             "f": [("stairs", 2, {}, "", 0.6)],
             "e": [("box", 1, {}, "", None)]}           # no plane with an area bound
    truth = {"a": "box", "b": "box", "c": "other", "d": "stairs", "e": "box", "f": "stairs"}
    assert M.proof_domain(fired, truth) == ((1, "box", 0.05, 0.2, 2), (2, "stairs", 0.3, 0.6, 2))
    # the bound: the training range widened below by the margin's share of its log width
    assert M.proof_bound(0.05, 0.2, 0.3) == pytest.approx(0.05 * 0.25 ** 0.3)   # 0.0330
    assert M.proof_bound(0.3, 0.6, 0.3) == pytest.approx(0.3 * 0.5 ** 0.3)      # 0.2437
    assert M.proof_bound(0.05, 0.2, 0.0) == 0.05 and M.proof_bound(0.0, 0.2) == 0.0
    assert M.proof_bound(0.0421, 0.4545) == pytest.approx(0.0206, abs=1e-4)    # the demo's rule 4
    dom = M.proof_domain(fired, truth)
    stats = [(1, "box", 9, 1), (2, "stairs", 3, 1), (3, "other", 1, 0)]
    hits = [("box", 1, {}, "", 0.032), ("stairs", 2, {}, "", 0.25)]
    kept, refused = M.proof_refusals(hits, stats, dom, 0.3, 1)       # 0.032 < 0.0330
    assert kept == [hits[1]] and [(r.klass, r.rule) for r in refused] == [("box", 1)]
    kept, refused = M.proof_refusals([("box", 1, {}, "", 0.034)], stats, dom, 0.3, 1)
    assert len(kept) == 1 and refused == ()
    # an entry measured on fewer true positives than min_positives (default 10) does not count
    assert M.PROOF_MIN_POSITIVES == M.DecisionParams().proof_min_positives == 10
    assert M.proof_refusals(hits, stats, dom)[0] == hits
    assert M.proof_refusals(hits, stats, dom, 0.3, 2)[0] == [hits[1]]   # 2 positives each
    # no scale, a four-element hit (hand-made callers) or no entry: kept
    for hit in (("box", 1, {}, "", None), ("box", 1, {}, ""), ("ramp", 7, {}, "", 0.0)):
        assert M.proof_refusals([hit], stats, dom, 0.3, 1)[0] == [hit]
    # a refused rule that does not take part in the decision (fp >= tp) is not reported
    kept, refused = M.proof_refusals([("stairs", 2, {}, "", 0.01)], [(2, "stairs", 1, 1)],
                                     dom, 0.3, 1)
    assert kept == [] and refused == ()
    # decide: the proof gate, then the planar gate, then the precision order
    best, refused = M.decide(hits, stats, ["box", "stairs"], proofs=dom, proof_min_positives=1)
    assert best[0] == "stairs" and [r.rule for r in refused] == [1]
    assert M.decide(hits, stats, ["box", "stairs"])[0][0] == "box"
    with pytest.raises(InputError, match="proof_margin must be a number in 0..1"):
        M.DecisionParams(proof_margin=2.0)
    with pytest.raises(InputError, match="proof_gate must be true or false"):
        M.DecisionParams(proof_gate="on")
    with pytest.raises(InputError, match="proof_min_positives must be a whole number"):
        M.DecisionParams(proof_min_positives=0)


def test_model_json_keeps_the_domain(tmp_path):
    from planerel.ilp.model_settings import read_settings

    path = _model(tmp_path / "m")
    s = read_settings(path / "rules.pl")
    assert s.proof_domain == tuple(PROOFS)
    assert s.decision_params().proof_gate is True and s.decision_params().proof_margin == 0.3
    data = json.loads((path / "model.json").read_text())
    data["proof_domain"] = [{"rule": "one", "class": "box"}]
    (path / "model.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match="proof_domain entry"):
        read_settings(path / "rules.pl")


def test_prolog_predict_decides_with_the_same_gate(scene):
    """The learner's own scoring (cross-validation, held-out sets) decides as classify does."""
    from dataclasses import replace

    from planerel.ilp import pipeline as P

    desc = _describe(scene, "s0007")
    rules = RULES.split("planerel_rule_stats")[0].strip().splitlines()
    model = P.Model(("box", "stairs"), {"box": (rules[0],), "stairs": (rules[1],)},
                    stats=tuple(STATS), proof_domain=tuple(PROOFS), flight_gate=False)
    on = P.prolog_predict(model, [desc])
    off = P.prolog_predict(replace(model, proof_gate=False), [desc])
    assert model.proof_gate and M.DecisionParams().proof_gate
    boxed = [p for p in off if p.klass == "box"]
    assert len(boxed) == 2
    refused = [p for p in on if p.refused]
    assert len(refused) == 1 and refused[0].klass == "stairs"
    assert [p.klass for p in on].count("box") == 1
