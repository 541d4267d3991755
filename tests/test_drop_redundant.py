"""Clauses that add only false positives are left out of a learned model (drop_redundant)."""

from __future__ import annotations

import json

import pytest

from planerel.cli import main
from planerel.ilp import pipeline as P
from planerel.ilp import scenes as S
from planerel.synth.generator import generate_dataset


def _model(rules: dict) -> P.Model:
    return P.Model(("box", "ramp"), rules)


def test_a_clause_whose_positives_another_proves_is_left_out_with_its_false_positives():
    model = _model({"box": ("box(A) :- b1(A).",),
                    "ramp": ("ramp(A) :- r1(A).", "ramp(A) :- r2(A).")})
    truth = {"b": "box", "r1": "ramp", "r2": "ramp", "r3": "ramp", "o": "other", "w": "box"}
    # clause 2 (ramp r1) proves r1, r2 (both also proved by clause 3) and the box w
    fired = {"b": [("box", 1, {}, "")],
             "r1": [("ramp", 2, {}, ""), ("ramp", 3, {}, "")],
             "r2": [("ramp", 2, {}, ""), ("ramp", 3, {}, "")],
             "r3": [("ramp", 3, {}, "")],
             "w": [("box", 1, {}, ""), ("ramp", 2, {}, "")],
             "o": []}
    kept, renumbered = P.drop_redundant(model, fired, truth)
    assert kept.rules == {"box": ("box(A) :- b1(A).",), "ramp": ("ramp(A) :- r2(A).",)}
    assert kept.dropped == (("ramp", "ramp(A) :- r1(A).", 2, 1),)
    # indices follow the kept clauses: old 3 is now 2; the left-out clause's hits are gone
    assert renumbered["r1"] == [("ramp", 2, {}, "")]
    assert renumbered["w"] == [("box", 1, {}, "")]
    stats, cofire = P._stats_from_fired(kept, renumbered, truth)
    assert stats == ((1, "box", 2, 0), (2, "ramp", 3, 0))
    assert cofire == ()
    text = kept.text()
    assert "ramp(A) :- r1(A)." not in [ln.strip() for ln in text.splitlines()]
    assert "%   ramp: ramp(A) :- r1(A).  (proved 2 ramp, 1 other objects)" in text


def test_a_redundant_clause_without_false_positives_and_a_clause_with_its_own_positive_stay():
    model = _model({"box": ("box(A) :- b1(A).", "box(A) :- b2(A).", "box(A) :- b3(A).")})
    truth = {"x": "box", "y": "box", "z": "box", "n": "ramp"}
    fired = {"x": [("box", 1, {}, ""), ("box", 2, {}, "")],   # clause 2: redundant, no false positive
             "y": [("box", 1, {}, ""), ("box", 3, {}, "")],
             "z": [("box", 3, {}, "")],                        # clause 3: z is its own
             "n": [("box", 3, {}, "")]}
    kept, renumbered = P.drop_redundant(model, fired, truth)
    assert kept is model and renumbered is fired


def test_of_two_clauses_proving_the_same_positives_the_one_with_more_false_positives_goes():
    model = _model({"box": ("box(A) :- b1(A).", "box(A) :- b2(A).")})
    truth = {"x": "box", "y": "box", "n1": "ramp", "n2": "other", "n3": "ramp"}
    fired = {"x": [("box", 1, {}, ""), ("box", 2, {}, "")],
             "y": [("box", 1, {}, ""), ("box", 2, {}, "")],
             "n1": [("box", 1, {}, "")],
             "n2": [("box", 2, {}, "")], "n3": [("box", 2, {}, "")]}
    kept, _ = P.drop_redundant(model, fired, truth)
    assert kept.rules["box"] == ("box(A) :- b1(A).",)      # one stays: its positives are its own now
    assert [d[1] for d in kept.dropped] == ["box(A) :- b2(A)."]
    # equal false positives: the later clause goes
    fired["n1"] = [("box", 1, {}, "")]
    fired["n3"] = []
    kept, _ = P.drop_redundant(model, fired, truth)
    assert kept.rules["box"] == ("box(A) :- b1(A).",)


@pytest.fixture(scope="module")
def small_set(tmp_path_factory):
    out = tmp_path_factory.mktemp("ds") / "train"
    generate_dataset(out, n_box=3, n_stairs=3, n_ramp=3, seed=3, size=(640, 480), subsample=4)
    return out


@pytest.fixture(scope="module")
def gt_descs(small_set):
    descs, skipped = S.describe_scenes(small_set, method="gt", jobs=1, cache="none")
    assert not skipped
    return descs


def test_redundant_clauses_are_found_by_the_real_rule_query(gt_descs):
    """A theory with a clause that only adds false positives (``has_plane`` alone proves every
    object; the inclined-plane clause proves every ramp), proved on real scenes by swipl: the
    broad clause is left out and the statistics are measured on what is kept."""
    broad = "ramp(A) :- has_plane(A,B)."
    incl = "ramp(A) :- has_plane(A,B), orientation(B,inclined)."
    box = "box(A) :- has_plane(A,B), orientation(B,horizontal), skirt(B,C)."
    model = P.Model(("box", "stairs", "ramp"), {"box": (box,), "stairs": (), "ramp": (broad, incl)})
    examples = P._examples(gt_descs)
    truth = dict(examples)
    fired = P._parse_fired(P._prolog_run(model, gt_descs, [o for o, _ in examples], 120.0))
    kept, renumbered = P.drop_redundant(model, fired, truth)
    assert kept.rules["ramp"] == (incl,) and kept.rules["box"] == (box,)
    n_ramps = sum(k == "ramp" for _, k in examples)
    assert kept.dropped == (("ramp", broad, n_ramps, len(examples) - n_ramps),)
    stats, _ = P._stats_from_fired(kept, renumbered, truth)
    full, _ = P.training_stats(model, gt_descs)
    assert stats == (full[0], (2, *full[2][1:]))
    assert stats[1][2:] == (n_ramps, 0)


def test_learn_rules_keeps_every_clause_on_request(gt_descs):
    """learn_rules runs the step on the learner's answer: every clause it returned is either
    kept or recorded as left out, and ``keep_redundant`` keeps them all."""
    classes = ["box", "stairs", "ramp"]
    pruned = P.learn_rules(gt_descs, classes, engine="builtin", jobs=1)
    full = P.learn_rules(gt_descs, classes, engine="builtin", jobs=1, keep_redundant=True)
    assert full.dropped == ()
    kept = {k: set(v) for k, v in pruned.rules.items()}
    assert all(kept[k] <= set(full.rules[k]) for k in classes)
    left_out = {(k, t) for k, t, _, _ in pruned.dropped}
    assert {(k, t) for k in classes for t in full.rules[k]} == {(k, t) for k in classes for t in kept[k]} | left_out


def test_learn_cli_writes_what_it_left_out(small_set, tmp_path, capsys):
    for flag, name in (([], "m"), (["--keep-redundant"], "full")):
        assert main(["learn", str(small_set), "-o", str(tmp_path / name), "--jobs", "1",
                     "--engine", "builtin", "--method", "gt", "--cache", "none", *flag]) == 0
    out = capsys.readouterr().out
    pruned = json.loads((tmp_path / "m" / "metrics.json").read_text())
    full = json.loads((tmp_path / "full" / "metrics.json").read_text())
    assert full["dropped_redundant"] == []
    for k, text, _, _ in pruned["dropped_redundant"]:
        assert text in full["rules"][k] and text not in pruned["rules"][k]
        assert f"% left out: {text}" in out
