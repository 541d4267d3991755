"""veto22: a rule for ``other`` (a veto) proved only through planes far smaller than a class
rule's proof of the same object does not decide against it.

A veto hit is set aside when its proof scale times ``decision.veto_ratio`` (3) is below the
largest proof scale of a class hit left in the decision (docs/results.md, "Vetoes proved
through slivers").  Prolog runs for real (swipl through pyswip, and ``prolog_predict``'s own
swipl process).
"""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import box, floor, render  # noqa: E402
from test_proof_gate import _answers  # noqa: E402  (classify a (cloud, up) scene)

# the veto is the more precise rule: without the ratio it wins wherever both fire
STATS = [(1, "box", 9, 1), (2, "other", 20, 1)]
RULES = ("box(A) :- has_plane(A,B), orientation(B,horizontal), area(B,C), gteq(C,0.08).\n"
         "other(A) :- has_plane(A,B), orientation(B,vertical), area(B,C), lteq(C,0.05).\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))


def _model(path: Path, ratio=None) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS)
    # the slab's box is proved by a top alone: the long-lying gate (fbox58) would refuse it
    data["decision"]["long_lying_gate"] = False
    if ratio is not None:
        data["decision"]["veto_ratio"] = ratio
    (path / "model.json").write_text(json.dumps(data))
    return path


@pytest.fixture(scope="module")
def scene():
    """A slab of 70 x 50 x 6 cm (top 0.35 m^2, front 0.043 m^2 seen) and a box of 35 x 30 x
    16 cm (top 0.104, front 0.056, side 0.046 m^2) on the floor, seen from 1.0 m, 45 degrees
    down.  On the slab the veto's plane (the front) is 8 times smaller than the box rule's
    (the top): set aside.  On the box the veto's plane (the side) is 2.3 times smaller: it
    still counts, and the more precise veto wins."""
    cloud, _lab, up, _objs = render([floor()] + box(-0.4, 1.3, 0.7, 0.5, 0.06, obj=1)
                                    + box(0.35, 1.2, 0.35, 0.3, 0.16, obj=2),
                                    pitch=45, cam_height=1.0, width=640, height=480,
                                    noise=0.0003)
    return cloud, up


def test_a_veto_through_a_sliver_is_set_aside_and_a_comparable_one_decides(tmp_path, scene):
    _warn, objs = _answers(_model(tmp_path / "m"), scene)
    both = [o for o in objs if ("box", 1) in o.fired and ("other", 2) in o.fired]
    assert len(both) == 2
    slab = [o for o in both if o.refused]
    kept = [o for o in both if not o.refused]
    assert len(slab) == 1 and len(kept) == 1
    o = slab[0]
    assert o.klass == "box" and o.rule.startswith("box(")
    (r,) = o.refused
    assert isinstance(r, M.VetoRefusal)
    assert (r.klass, r.rule, r.by_class, r.by_rule, r.ratio) == ("other", 2, "box", 1, 3.0)
    assert 0.03 < r.scale < 0.05 and 0.3 < r.by_scale < 0.4 and r.scale * 3 < r.by_scale
    assert "rule 2 proves it only with planes of" in r.reason
    assert "box rule 1 proves it with planes of" in r.reason and "3 times larger" in r.reason
    d = o.to_dict()["refused"][0]
    assert d["class"] == "other" and d["rule"] == 2 and d["by_rule"] == 1
    assert d["proof_scale"] == pytest.approx(r.scale, abs=1e-5)
    # the box: its side (0.046 m^2) is not 3 times smaller than its top (0.104): the veto
    # counts and, more precise, answers other
    assert kept[0].klass == "other" and kept[0].rule.startswith("other(")


@pytest.mark.parametrize("how", ["ratio 0 in model.json", "--param ratio 0", "ratio 10"])
def test_without_the_ratio_the_more_precise_veto_wins(tmp_path, scene, how):
    ratio = 0 if how == "ratio 0 in model.json" else None
    kw = {}
    if how == "--param ratio 0":
        kw = {"seg_params": {"decision.veto_ratio": "0"}}
    if how == "ratio 10":
        kw = {"seg_params": {"decision.veto_ratio": "10"}}
    warn, objs = _answers(_model(tmp_path / "m", ratio=ratio), scene, **kw)
    both = [o for o in objs if ("box", 1) in o.fired and ("other", 2) in o.fired]
    assert len(both) == 2 and all(o.klass == "other" and o.refused == () for o in both)
    if how == "--param ratio 0":
        assert any("decision.veto_ratio=0" in w and "differs" in w for w in warn)


def test_veto_refusals_by_hand():
    stats = [(1, "box", 9, 1), (2, "stairs", 5, 1), (3, "other", 20, 1), (4, "other", 3, 1),
             (5, "box", 1, 4)]
    st, veto, big = ("stairs", 2, {}, "", 0.15), ("other", 3, {}, "", 0.004), ("other", 4, {}, "", 0.06)
    kept, refused = M.veto_refusals([st, veto, big], stats, 3.0)
    assert kept == [st, big] and [(r.rule, r.by_rule, r.by_scale) for r in refused] == [(3, 2, 0.15)]
    # the largest class proof counts: a small box proof beside the stairs proof changes nothing
    kept, _ = M.veto_refusals([("box", 1, {}, "", 0.001), st, veto], stats, 3.0)
    assert veto not in kept
    # exactly at the ratio: kept (0.05 * 3 == 0.15 is not below 0.15)
    edge = ("other", 3, {}, "", 0.05)
    assert M.veto_refusals([st, edge], stats, 3.0)[0] == [st, edge]
    # off, no class hit, a class hit without a scale, or one that takes no part: nothing set aside
    assert M.veto_refusals([st, veto], stats, 0) == ([st, veto], ())
    assert M.veto_refusals([veto, big], stats, 3.0) == ([veto, big], ())
    assert M.veto_refusals([("stairs", 2, {}, "", None), veto], stats, 3.0)[1] == ()
    assert M.veto_refusals([("box", 5, {}, "", 0.5), veto], stats, 3.0)[1] == ()
    # a veto without a scale (curved(A): it binds no plane) or a four-element hit is kept
    for v in (("other", 3, {}, "", None), ("other", 3, {}, "")):
        assert v in M.veto_refusals([st, v], stats, 3.0)[0]
    # a veto that takes no part is left out silently (it would not count anyway)
    assert M.veto_refusals([st, ("other", 6, {}, "", 0.001)], stats + [(6, "other", 1, 3)],
                           3.0) == ([st], ())
    # decide: the default here is off (callers pass the model's setting); the class hit must
    # survive the proof gate to set a veto aside
    classes = ["box", "stairs"]
    assert M.decide([st, veto], stats, classes)[0] == veto
    best, refused = M.decide([st, veto], stats, classes, veto_ratio=3.0)
    assert best == st and isinstance(refused[0], M.VetoRefusal)
    dom = [(2, "stairs", 0.3, 0.6, 12)]          # the stairs proof (0.15) is refused first
    best, refused = M.decide([st, veto], stats, classes, proofs=dom, veto_ratio=3.0)
    assert best == veto and [type(r) for r in refused] == [M.ProofRefusal]


def test_decision_params_check_the_ratio():
    assert M.DecisionParams().veto_ratio == M.VETO_RATIO == 3.0
    assert M.DecisionParams(veto_ratio=0).veto_ratio == 0
    for bad in (-1.0, float("nan"), float("inf"), "3", True):
        with pytest.raises(InputError, match="veto_ratio must be a number >= 0"):
            M.DecisionParams(veto_ratio=bad)


def test_prolog_predict_decides_with_the_same_ratio(scene):
    """The learner's own scoring (cross-validation, held-out sets) decides as classify does."""
    from planerel.features.facts import describe_scene
    from planerel.ilp import pipeline as P
    from planerel.segment import segment

    cloud, up = scene
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s0003", up=up)
    rules = RULES.split("planerel_rule_stats")[0].strip().splitlines()
    model = P.Model(("box",), {"box": (rules[0],), "other": (rules[1],)}, stats=tuple(STATS))
    assert model.veto_ratio == 3.0
    on = {p.object_id: p for p in P.prolog_predict(model, [desc])}
    off = {p.object_id: p for p in P.prolog_predict(replace(model, veto_ratio=0.0), [desc])}
    both = [o for o, p in off.items() if ("box", 1) in p.fired and ("other", 2) in p.fired]
    assert len(both) == 2 and all(off[o].klass == "other" for o in both)
    assert sorted(on[o].klass for o in both) == ["box", "other"]
    (set_aside,) = [on[o] for o in both if on[o].refused]
    assert set_aside.klass == "box" and isinstance(set_aside.refused[0], M.VetoRefusal)
