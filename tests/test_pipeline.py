"""End to end: data set -> rules -> cross-validation -> classification by logic query."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from planerel import pipeline as P
from planerel.cli import main
from planerel.errors import DependencyError, InputError, LearnerError, PrologError
from planerel.synth import generate_dataset


@pytest.fixture(scope="module")
def small_set(tmp_path_factory):
    """4 box, 4 stairs, 4 ramp scenes at 160x120."""
    out = tmp_path_factory.mktemp("ds") / "train"
    generate_dataset(out, n_box=4, n_stairs=4, n_ramp=4, seed=3, size=(640, 480), subsample=4)
    return out


@pytest.fixture(scope="module")
def gt_descs(small_set):
    descs, skipped = P.describe_scenes(small_set, method="gt", jobs=1, cache="none")
    assert not skipped
    return descs


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PLANEREL_CACHE", str(tmp_path / "cache"))


def test_rules_from_ground_truth_planes_are_relational(gt_descs):
    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")
    assert all(model.rules[k] for k in model.classes)
    stairs = " ".join(model.rules["stairs"])
    ramp = " ".join(model.rules["ramp"])
    assert "step_up" in stairs or "nhorizontal" in stairs
    assert "inclined" in ramp or "incline" in ramp
    # every clause is scored on the training objects; none covers another class
    assert {s[1] for s in model.stats} == {"box", "stairs", "ramp"}
    assert all(fp == 0 for _, _, _, fp in model.stats)
    preds = P.prolog_predict(model, gt_descs)
    truth = {o.id: o.klass for d in gt_descs for o in d.objects}
    assert all(p.klass == truth[p.object_id] for p in preds)
    # the explanation binds planes of the object for plane-level rules
    for p in preds:
        if "step_up" in (p.rule or "") or "orientation" in (p.rule or ""):
            assert p.planes and all(x.startswith(p.object_id.split("_")[0] + "_p") for x in p.planes)


def test_stratified_folds_balance_classes():
    labels = ["a"] * 7 + ["b"] * 5 + ["c"] * 3
    folds = P.stratified_folds(labels, 5, seed=1)
    assert folds == P.stratified_folds(labels, 5, seed=1)
    sizes = np.bincount(folds, minlength=5)
    assert sizes.max() - sizes.min() <= 1
    for k in "abc":
        per = np.bincount([f for f, lab in zip(folds, labels, strict=True) if lab == k], minlength=5)
        assert per.max() - per.min() <= 1
    with pytest.raises(InputError, match="folds"):
        P.stratified_folds(labels, 1)
    with pytest.raises(InputError, match="at most 15"):
        P.stratified_folds(labels, 16)


def test_cross_validation_is_deterministic(gt_descs):
    a = P.cross_validate(gt_descs, ["box", "stairs", "ramp"], folds=3, seed=0, engine="builtin")
    b = P.cross_validate(gt_descs, ["box", "stairs", "ramp"], folds=3, seed=0, engine="builtin")
    for f in a["folds"] + b["folds"]:
        f.pop("seconds")  # wall-clock time is the one thing allowed to differ
    assert a == b
    assert len(a["folds"]) == 3
    assert sum(len(f["test"]) for f in a["folds"]) == a["n_examples"] == 12
    assert sum(map(sum, a["confusion"])) == 12
    assert a["accuracy"] >= 0.75


def test_learn_cli_then_classify_cli(small_set, tmp_path, capsys):
    model = tmp_path / "model"
    assert main(["learn", str(small_set), "-o", str(model), "--folds", "3", "--jobs", "1",
                 "--engine", "builtin"]) == 0
    out = capsys.readouterr().out
    assert "3-fold cross-validation: accuracy" in out
    metrics = json.loads((model / "metrics.json").read_text())
    assert metrics["n_scenes"] == 12 and metrics["classes"] == ["box", "stairs", "ramp"]
    assert 0.0 <= metrics["cross_validation"]["accuracy"] <= 1.0
    assert (model / "confusion.png").is_file()
    assert sorted(p.name for p in (model / "aleph").iterdir())[:3] == ["box.b", "box.f", "box.n"]
    rules = (model / "rules.pl").read_text()
    # the model loads by itself with the support predicates, without warnings
    import subprocess

    support = [str(p) for p in P.support_files()]
    r = subprocess.run(["swipl", "-q", "--on-warning=status", "--on-error=status", "-g",
                        "maplist(consult, [" + ", ".join(f"'{s}'" for s in support + [str(model / 'rules.pl')]) + "])",
                        "-t", "halt"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert "planerel_rule_stats(" in rules

    scenes = sorted(small_set.glob("s*.depth.png"))
    outdir = tmp_path / "cls"
    assert main(["classify", str(model / "rules.pl"), *map(str, scenes[:3]), "-o", str(outdir),
                 "--json"]) == 0
    answers = json.loads(capsys.readouterr().out)
    assert len(answers) == 3
    for a in answers:
        for o in a["objects"]:
            assert o["class"] in ("box", "stairs", "ramp", "unknown")
            if o["class"] != "unknown":
                assert o["rule"] and o["rule"].split("(")[0] in ("box", "stairs", "ramp")
    assert len(list(outdir.glob("*.classified.png"))) == 3


def test_classifier_explains_stairs_with_planes(gt_descs, tmp_path):
    from planerel.classify import Classifier, explanation_image
    from planerel.synth import generate_scene

    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")
    (tmp_path / "rules.pl").write_text(model.text())
    clf = Classifier(tmp_path / "rules.pl")
    scene = generate_scene("stairs", seed=11, size=(640, 480), subsample=4, steps=4,
                           sides="open", walls=0)
    ans = clf.classify(scene.cloud, scene_id="s0100")
    stairs = [o for o in ans.objects if o.klass == "stairs"]
    assert stairs, [o.to_dict() for o in ans.objects]
    if "step_up" in stairs[0].rule:
        assert len(stairs[0].proof_planes) == 2
        pic = explanation_image(ans, scene.cloud.depth)
        assert pic.shape == (120, 160, 3)


# ------------------------------------------------------------------ bad input


def test_one_class_data_set_is_refused(tmp_path):
    ds = tmp_path / "boxes"
    generate_dataset(ds, n_box=3, n_stairs=0, n_ramp=0, seed=1, size=(640, 480), subsample=4)
    with pytest.raises(InputError, match="at least two classes"):
        P.learn_model(ds, tmp_path / "model", method="gt", jobs=1, engine="builtin")
    assert not (tmp_path / "model").exists()


def test_class_without_examples_is_refused(small_set, tmp_path):
    with pytest.raises(InputError, match="no scene of class cylinder"):
        P.learn_model(small_set, tmp_path / "m", classes=["box", "cylinder"], method="gt", jobs=1)


def test_learner_timeout_leaves_no_model(small_set, tmp_path):
    out = tmp_path / "model"
    with pytest.raises(LearnerError, match="timed out"):
        P.learn_model(small_set, out, method="gt", jobs=1, engine="builtin", timeout=0.05)
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".model")]


def test_existing_model_is_replaced_only_when_complete(small_set, tmp_path):
    out = tmp_path / "model"
    P.learn_model(small_set, out, method="gt", jobs=1, engine="builtin")
    before = (out / "rules.pl").read_text()
    with pytest.raises(LearnerError):
        P.learn_model(small_set, out, method="gt", jobs=1, engine="builtin", timeout=0.05)
    assert (out / "rules.pl").read_text() == before


def test_rules_file_with_syntax_error(tmp_path):
    from planerel.classify import Classifier

    bad = tmp_path / "rules.pl"
    bad.write_text("stairs(A) :- has_plane(A, B), .\n")
    with pytest.raises(PrologError, match="rules.pl"):
        Classifier(bad)
    with pytest.raises(InputError, match="no such rules file"):
        Classifier(tmp_path / "missing.pl")


def test_no_swipl_on_path(gt_descs, monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(DependencyError, match="apt-get install swi-prolog-nox"):
        P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")


def test_empty_scene_gives_no_object(gt_descs, tmp_path):
    from planerel.classify import Classifier
    from planerel.cloud import Cloud, Intrinsics

    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")
    (tmp_path / "rules.pl").write_text(model.text())
    clf = Classifier(tmp_path / "rules.pl")
    intr = Intrinsics.kinect(160, 120)
    v, u = np.mgrid[0:120, 0:160].astype(float)
    z = np.full((120, 160), 2.0)
    xyz = np.stack([(u - intr.cx) * z / intr.fx, (v - intr.cy) * z / intr.fy, z], axis=2)
    ans = clf.classify(Cloud(xyz, intr), scene_id="s0200")  # one wall, nothing else
    assert all(o.klass in ("unknown", "box", "stairs", "ramp") for o in ans.objects)
    assert ans.n_planes >= 1


@pytest.mark.skipif(not shutil.which("swipl"), reason="swipl missing")
@pytest.mark.real_aleph
@pytest.mark.skipif(not os.environ.get("PLANEREL_ALEPH"),
                    reason="the real Aleph is not installed: set PLANEREL_ALEPH=/path/aleph.pl")
def test_real_aleph_learns_the_task(gt_descs):
    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="aleph")
    preds = P.prolog_predict(model, gt_descs)
    truth = {o.id: o.klass for d in gt_descs for o in d.objects}
    assert sum(p.klass == truth[p.object_id] for p in preds) >= 10
    assert "aleph" in model.engine.lower()


def test_describe_uses_cache(small_set, tmp_path):
    cache = tmp_path / "segcache"
    a, _ = P.describe_scenes(small_set, method="regiongrow", jobs=1, cache=cache)
    files = sorted((cache / "seg").glob("*.npy"))
    assert len(files) == 12
    stamp = [f.stat().st_mtime_ns for f in files]
    b, _ = P.describe_scenes(small_set, method="regiongrow", jobs=2, cache=cache)
    assert [f.stat().st_mtime_ns for f in sorted((cache / "seg").glob("*.npy"))] == stamp
    assert [d.scene_id for d in a] == [d.scene_id for d in b]
    assert [[o.planes for o in d.objects] for d in a] == [[o.planes for o in d.objects] for d in b]
    assert Path(files[0]).suffix == ".npy"
