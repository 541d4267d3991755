"""Named learning recipes (planerel.ilp.recipes): `planerel learn --recipe varied`."""

from __future__ import annotations

import json

import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp.recipes import RECIPES, VARIED, apply_recipe, recipe_decision
from planerel.synth.generator import generate_dataset


def test_no_recipe_passes_the_callers_values_through():
    assert apply_recipe(None, task="t.pl", settings={"noise": "3"}, other_rules=False) == (
        "t.pl", {"noise": "3"}, False)


def test_explicit_values_win_over_the_recipe():
    task, settings, other = apply_recipe("varied", settings={"noise": "3", "box:minpos": "2"})
    assert task == VARIED.task == "modes_varied.pl"
    assert other is True
    assert settings["noise"] == "3" and settings["box:minpos"] == "2"
    # every other value is the recipe's
    assert {k: v for k, v in settings.items() if k not in ("noise", "box:minpos")} == {
        k: v for k, v in VARIED.settings.items() if k != "noise"}
    task, _, _ = apply_recipe("varied", task="modes_slope.pl")
    assert task == "modes_slope.pl"
    assert VARIED.settings["noise"] == "30", "apply_recipe changed the recipe itself"


def test_every_recipe_is_a_valid_task_and_settings():
    from planerel.ilp.aleph_export import check_setting, load_task

    for recipe in RECIPES.values():
        _, modes, _, _ = load_task(recipe.task)
        assert modes
        for name, value in recipe.settings.items():
            check_setting(name.rpartition(":")[2], value)


def test_unknown_recipe_is_refused():
    with pytest.raises(InputError, match="unknown recipe 'nope'.*varied"):
        apply_recipe("nope")


@pytest.fixture(scope="module")
def varied_set(tmp_path_factory):
    """A few varied-world scenes at 160x120 (objects of class other among them)."""
    out = tmp_path_factory.mktemp("ds") / "varied"
    generate_dataset(out, n_box=3, n_stairs=3, n_ramp=3, seed=4, size=(640, 480), subsample=4,
                     world="varied")
    return out


def test_learn_with_the_varied_recipe(varied_set, tmp_path, monkeypatch):
    """`--recipe varied` learns with the varied task, the recipe's settings (one replaced by
    --set) and rules for other, and writes the model with its decision settings (no proof
    gate); metrics.json and model.json record all of it, classify reads it back."""
    monkeypatch.setenv("PLANEREL_CACHE", str(tmp_path / "cache"))
    out = tmp_path / "m"
    assert main(["learn", str(varied_set), "-o", str(out), "--method", "gt", "--engine",
                 "builtin", "--recipe", "varied", "--set", "minpos=2", "-j", "1",
                 "--cache", "none"]) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["recipe"] == "varied"
    assert metrics["task"] == "modes_varied.pl"
    assert metrics["other_rules"] is True
    assert metrics["learner_settings"]["minpos"] == "2"
    assert metrics["learner_settings"]["lazy_band"] == "true"
    assert metrics["learner_settings"]["other:noise"] == "5"
    b = (out / "aleph" / "box.b").read_text()
    assert "modeb(*, facing(+plane, -plane))" in b
    assert ":- set(minpos, 2)." in b and ":- set(noise, 30)." in b
    assert ":- set(lazy_band, true)." in b
    # other's own settings replace the common ones in its file only
    other_b = (out / "aleph" / "other.b").read_text()
    assert ":- set(noise, 5)." in other_b and ":- set(cutoff_slack, off)." in other_b
    assert "% ---- other" in (out / "rules.pl").read_text()
    # the recipe's decision: recorded, written into model.json, read by classify
    assert metrics["decision"] == {"proof_gate": False} == VARIED.decision
    assert json.loads((out / "model.json").read_text())["decision"]["proof_gate"] is False
    from planerel.classify import Classifier

    with Classifier(out) as clf:
        assert clf.settings.decision_params().proof_gate is False
        assert clf.proof_domain == () and not any("proof_gate" in w for w in clf.warnings)
    with Classifier(out, seg_params={"decision.proof_gate": "true"}) as clf:
        assert clf.settings.decision_params().proof_gate is True
        assert any("proof_gate" in w for w in clf.warnings)


@pytest.mark.parametrize("args, message", [
    (["--recipe", "nope"], "unknown recipe"),
    (["--task", "no_such_task.pl"], "no_such_task.pl"),
    (["--set", "noise=lots"], "illegal value 'lots'"),
    (["--recipe", "varied", "--set", "lazy_band=maybe"], "illegal value 'maybe'"),
])
def test_a_bad_recipe_task_or_setting_fails_first(varied_set, tmp_path, capsys, args, message):
    """Refused before any scene is described, and nothing is written."""
    out = tmp_path / "m"
    assert main(["learn", str(varied_set), "-o", str(out), "--cache", "none", *args]) != 0
    err = capsys.readouterr().err
    assert message in err
    assert "describing" not in err
    assert not out.exists()


def test_the_varied_recipe_on_a_set_without_clutter(tmp_path, monkeypatch):
    """A data set with no object of class other: the recipe's settings for other are left out
    with its rules for other, and the classes are learned with the rest."""
    monkeypatch.setenv("PLANEREL_CACHE", str(tmp_path / "cache"))
    ds = generate_dataset(tmp_path / "paper", n_box=2, n_stairs=2, n_ramp=2, seed=3,
                          size=(640, 480), subsample=4)
    out = tmp_path / "m"
    assert main(["learn", str(ds), "-o", str(out), "--method", "gt", "--engine", "builtin",
                 "--recipe", "varied", "--set", "minpos=1", "-j", "1", "--cache", "none"]) == 0
    assert sorted(p.name for p in (out / "aleph").glob("*.b")) == ["box.b", "ramp.b", "stairs.b"]
    assert "% ---- other" not in (out / "rules.pl").read_text()


def test_recipe_decision():
    assert recipe_decision(None) == {}
    d = recipe_decision("varied")
    assert d == {"proof_gate": False}
    d["proof_gate"] = True
    assert VARIED.decision == {"proof_gate": False}, "recipe_decision returned the recipe's dict"
    with pytest.raises(InputError, match="unknown recipe"):
        recipe_decision("nope")


def test_a_decision_setting_reaches_the_model_and_its_folder(tmp_path):
    """with_decision sets a model's (or every member's) decision fields; training_settings
    writes them into model.json's decision section and refuses an unknown one."""
    from planerel.ilp.model_settings import training_settings
    from planerel.ilp.pipeline import Members, Model, with_decision

    m = Model(("box",), {"box": ("box(A) :- has_plane(A,B).",)})
    assert with_decision(m, {}) is m and m.proof_gate is True
    assert with_decision(m, {"proof_gate": False}).proof_gate is False
    two = with_decision(Members((m, m)), {"proof_gate": False, "veto_ratio": 0.0})
    assert all(x.proof_gate is False and x.veto_ratio == 0.0 for x in two.models)
    js = training_settings("regiongrow", {}, decision={"proof_gate": False})
    assert js["decision"]["proof_gate"] is False
    assert js["decision"]["planar_gate"] is training_settings("regiongrow", {})["decision"]["planar_gate"]
    with pytest.raises(InputError, match="unknown decision setting"):
        training_settings("regiongrow", {}, decision={"nope": 1})
