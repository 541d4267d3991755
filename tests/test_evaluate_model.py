"""``planerel evaluate-model``: a saved model scored on a held-out set gives what ``planerel
learn --heldout`` gave when the model was learned (real swipl, real learner; the two answer
through different paths: the classifier's Prolog module and ``prolog_predict``'s process)."""

from __future__ import annotations

import json

import pytest

from planerel.classify import Classifier
from planerel.classify.evaluate import evaluate_model
from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp import pipeline as P
from planerel.synth.generator import generate_dataset


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PLANEREL_CACHE", str(tmp_path / "cache"))


@pytest.fixture(scope="module")
def sets(tmp_path_factory):
    """A varied-world training set and a held-out set of another seed (objects of class other
    in both), 160x120."""
    root = tmp_path_factory.mktemp("ds")
    generate_dataset(root / "train", n_box=4, n_stairs=4, n_ramp=4, seed=4, size=(640, 480),
                     subsample=4, world="varied")
    generate_dataset(root / "held", n_box=3, n_stairs=3, n_ramp=3, seed=1004, size=(640, 480),
                     subsample=4, world="varied")
    return root / "train", root / "held"


@pytest.fixture(scope="module")
def learned(sets, tmp_path_factory):
    """A single and a 2-member model learned with --heldout, and their metrics."""
    train, held = sets
    out = tmp_path_factory.mktemp("m")
    kw = dict(method="gt", jobs=1, engine="builtin", heldout=held, cache="none",
              log=lambda s: None, other_rules=True, settings={"minpos": 2})
    single = P.learn_model(train, out / "single", **kw)
    members = P.learn_model(train, out / "members", members=2, **kw)
    return {"single": (out / "single", single), "members": (out / "members", members)}


@pytest.mark.parametrize("kind", ["single", "members"])
def test_a_saved_model_scores_what_learn_heldout_scored(learned, sets, kind):
    folder, metrics = learned[kind]
    want = metrics["heldout"]
    got = evaluate_model(folder, sets[1], jobs=1, cache="none")
    assert want["n_examples"] > 0 and want["other"]["n"] > 0  # class and other objects
    # every object's answer, then every figure, as learning reported them
    assert got["predictions"] == want["predictions"]
    for key in ("accuracy", "open_set_accuracy", "per_class", "confusion",
                "open_set_confusion", "n_examples", "other", "excluded", "n_scenes"):
        assert got[key] == want[key], key
    assert got["errors"] == want["errors"]
    assert got["model"] == str(folder) and got["dataset"] == str(sets[1])


def test_an_open_classifier_is_scored_and_left_open(learned, sets):
    folder, metrics = learned["single"]
    with Classifier(folder) as clf:
        got = evaluate_model(clf, sets[1], jobs=1, cache="none")
        assert got["predictions"] == metrics["heldout"]["predictions"]
        assert clf.module  # still usable
        desc = P.describe_scenes(sets[1], method="gt", jobs=1, cache="none")[0][0]
        answers = clf.answer_description(desc)
        assert [a.object_id for a in answers] == [o.id for o in desc.objects]
        assert all(a.klass == got["predictions"].get(a.object_id, a.klass) for a in answers)


def test_the_command_prints_the_figures_and_writes_json(learned, sets, tmp_path, capsys):
    folder, metrics = learned["members"]
    out = tmp_path / "sub" / "scores.json"
    assert main(["evaluate-model", str(folder), str(sets[1]), "-j", "1", "--cache", "none",
                 "--json", str(out)]) == 0
    text = capsys.readouterr().out
    h = metrics["heldout"]
    assert f"accuracy (class objects) {h['accuracy']:.3f}" in text
    assert f"open-set accuracy (all objects, other included): {h['open_set_accuracy']:.3f}" in text
    data = json.loads(out.read_text())
    assert data["predictions"] == h["predictions"]


def test_bad_inputs_are_one_line_errors(learned, sets, tmp_path, capsys):
    folder, _ = learned["single"]
    with pytest.raises(InputError, match="no such rules file"):
        evaluate_model(tmp_path / "nope", sets[1])
    with pytest.raises(InputError, match="no scenes|manifest|not a data set|no such"):
        evaluate_model(folder, tmp_path)
    # a --json that cannot be written is refused before any scene is described
    (tmp_path / "file").write_text("x")
    assert main(["evaluate-model", str(folder), str(sets[1]), "--json",
                 str(tmp_path / "file" / "x.json")]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot write" in err[0] and "x.json" in err[0]


def test_decision_settings_score_as_classify_answers_with_them(learned, sets, capsys):
    """``--param decision.NAME=VALUE`` scores the model as ``planerel classify --param`` answers
    with the same settings; anything but a decision setting is refused (the scenes are
    described with the model's training settings)."""
    folder, _ = learned["members"]
    params = {"decision.proof_gate": "false", "decision.veto_ratio": "0"}
    got = evaluate_model(folder, sets[1], jobs=1, cache="none", params=params)
    assert got["params"] == params
    descs = P.describe_scenes(sets[1], method="gt", jobs=1, cache="none")[0]
    with Classifier(folder, seg_params=params) as clf:
        assert clf.settings.decision_params().proof_gate is False
        assert clf.settings.decision_params().veto_ratio == 0
        want = {a.object_id: a.klass for d in descs for a in clf.answer_description(d)}
    assert got["predictions"] and all(want[o] == k for o, k in got["predictions"].items())
    assert main(["evaluate-model", str(folder), str(sets[1]), "-j", "1", "--cache", "none",
                 "--param", "decision.proof_gate=false", "--param", "decision.veto_ratio=0"]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0] == "decision: decision.proof_gate=false, decision.veto_ratio=0"
    assert f"open-set accuracy (all objects, other included): {got['open_set_accuracy']:.3f}" in out
    with pytest.raises(InputError, match="decision settings only"):
        evaluate_model(folder, sets[1], params={"theta": "12"})
    with pytest.raises(InputError, match="has no parameter"):
        evaluate_model(folder, sets[1], params={"decision.nope": "1"})
    with Classifier(folder) as clf, pytest.raises(InputError, match="open classifier"):
        evaluate_model(clf, sets[1], params=params)
