"""End to end: data set -> rules -> cross-validation -> classification by logic query."""

from __future__ import annotations

import json
import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from planerel.cli import main
from planerel.commands.classify import measures_line
from planerel.errors import DependencyError, InputError, LearnerError, PrologError
from planerel.ilp import metrics as M
from planerel.ilp import pipeline as P
from planerel.ilp import scenes as S
from planerel.ilp.prolog import support_files
from planerel.synth.generator import generate_dataset


@pytest.fixture(scope="module")
def small_set(tmp_path_factory):
    """4 box, 4 stairs, 4 ramp scenes at 160x120."""
    out = tmp_path_factory.mktemp("ds") / "train"
    generate_dataset(out, n_box=4, n_stairs=4, n_ramp=4, seed=3, size=(640, 480), subsample=4)
    return out


@pytest.fixture(scope="module")
def gt_descs(small_set):
    descs, skipped = S.describe_scenes(small_set, method="gt", jobs=1, cache="none")
    assert not skipped
    return descs


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PLANEREL_CACHE", str(tmp_path / "cache"))


def test_classes_learned_in_parallel_give_the_same_model_and_log_progress(gt_descs):
    lines: list[str] = []
    one = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin", jobs=1)
    two = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin", jobs=2,
                        log=lines.append)
    assert two.rules == one.rules and two.stats == one.stats
    # one line per clause added (from the learner, while it runs) and one per class
    for k in ("box", "stairs", "ramp"):
        done = [ln for ln in lines if ln.startswith(f"[{k}] learned ")]
        per_clause = [ln for ln in lines if ln.startswith(f"[{k}] {k}/1 rule ")]
        assert len(done) == 1 and len(per_clause) >= len(one.rules[k]) >= 1


def test_rules_from_ground_truth_planes_are_relational(gt_descs):
    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")
    assert all(model.rules[k] for k in model.classes)
    stairs = " ".join(model.rules["stairs"])
    ramp = " ".join(model.rules["ramp"])
    # the default task has no hand-written detector: stairs come from pairwise relations
    assert "step_up" not in stairs
    assert re.search(r"\b(adjacent|parallel|perpendicular|above)\([A-Z],[A-Z]\)", stairs), stairs
    assert "inclined" in ramp or "incline" in ramp
    # every clause is scored on the training objects; none covers another class
    assert {s[1] for s in model.stats} == {"box", "stairs", "ramp"}
    assert all(fp == 0 for _, _, _, fp in model.stats)
    preds = P.prolog_predict(model, gt_descs)
    truth = {o.id: o.klass for d in gt_descs for o in d.objects}
    assert all(p.klass == truth[p.object_id] for p in preds)
    # the explanation binds planes of the object's own scene: a proof of a rule that starts
    # with has_plane(A, B) (the stairs rule does) binds at least one plane
    assert all(r.startswith("stairs(A) :- has_plane(A,B)") for r in model.rules["stairs"])
    for p in preds:
        if p.rule.split(":-")[1].strip().startswith("has_plane(A,B)"):
            assert p.planes and all(x.startswith(p.object_id.split("_")[0] + "_p") for x in p.planes)
        else:
            assert not p.planes
    assert sum(1 for p in preds if p.planes) >= 4


def test_stratified_folds_balance_classes():
    labels = ["a"] * 7 + ["b"] * 5 + ["c"] * 3
    folds = M.stratified_folds(labels, 5, seed=1)
    assert folds == M.stratified_folds(labels, 5, seed=1)
    sizes = np.bincount(folds, minlength=5)
    assert sizes.max() - sizes.min() <= 1
    for k in "abc":
        per = np.bincount([f for f, lab in zip(folds, labels, strict=True) if lab == k], minlength=5)
        assert per.max() - per.min() <= 1
    with pytest.raises(InputError, match="folds"):
        M.stratified_folds(labels, 1)
    with pytest.raises(InputError, match="at most 15"):
        M.stratified_folds(labels, 16)


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
    cv = metrics["cross_validation"]
    # the accuracy is the confusion matrix's trace over its total (recomputed here), and the
    # matrix's rows hold the data set's 4 scenes per class
    conf = np.array(cv["confusion"])
    assert conf.sum(axis=1)[:3].tolist() == [4, 4, 4]
    assert cv["accuracy"] == pytest.approx(np.trace(conf[:, :3]) / conf.sum())
    assert f"3-fold cross-validation: accuracy {cv['accuracy']:.3f}" in out
    assert (model / "confusion.png").is_file()
    assert sorted(p.name for p in (model / "aleph").iterdir())[:3] == ["box.b", "box.f", "box.n"]
    rules = (model / "rules.pl").read_text()
    # the model loads by itself with the support predicates, without warnings
    import subprocess

    support = [str(p) for p in support_files()]
    r = subprocess.run(["swipl", "-q", "--on-warning=status", "--on-error=status", "-g",
                        "maplist(consult, [" + ", ".join(f"'{s}'" for s in support + [str(model / 'rules.pl')]) + "])",
                        "-t", "halt"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert "planerel_rule_stats(" in rules

    # one scene of each class (the data set's truth is in each scene's sidecar)
    scenes = sorted(small_set.glob("s*.depth.png"))
    truth = {p: json.loads(p.with_name(p.name.split(".")[0] + ".json").read_text())["class"]
             for p in scenes}
    pick = [next(p for p in scenes if truth[p] == k) for k in ("box", "stairs", "ramp")]
    outdir = tmp_path / "cls"
    assert main(["classify", str(model / "rules.pl"), *map(str, pick), "-o", str(outdir),
                 "--json"]) == 0
    answers = json.loads(capsys.readouterr().out)
    assert [a["input"] for a in answers] == [str(p) for p in pick]
    for a, p in zip(answers, pick, strict=True):
        # a generated scene holds one object, of the scene's class
        assert [o["class"] for o in a["objects"]] == [truth[p]], a
        o = a["objects"][0]
        assert o["rule"].startswith(truth[p] + "(")
        assert set(o["proof_planes"]) <= set(o["planes"])
    assert sorted(f.name for f in outdir.glob("*.classified.png")) == sorted(
        p.name.split(".")[0] + ".classified.png" for p in pick)

    # without --json: one text block per scan, its object's class and the rule that proved it
    assert main(["classify", str(model / "rules.pl"), *map(str, pick)]) == 0
    lines = capsys.readouterr().out.splitlines()
    heads = [n for n, ln in enumerate(lines) if not ln.startswith(" ")]
    assert [lines[n].split(":")[0] for n in heads] == [str(p) for p in pick]
    for n, p, a in zip(heads, pick, answers, strict=True):
        o = a["objects"][0]
        assert lines[n].startswith(f"{p}: {a['n_planes']} planes, 1 object(s) [")
        # the rule's training precision: Laplace (tp + 1) / (tp + fp + 2) of its statistics
        tp, fp = next((tp, fp) for i, _, tp, fp in
                      json.loads((model / "metrics.json").read_text())["rule_stats"]
                      if i == o["rule_index"])
        # the class, then the object's planar fraction (a generated box/stairs/ramp: flat)
        shape = f"  (planar fraction {o['planar_fraction']:.2f})"
        assert o["curved"] is False and o["planar_fraction"] > 0.9
        # a stairs or ramp answer's flight or slope, in words, right under its class
        measured = ([f"    {measures_line(truth[p], o['measures'])}"] if o.get("measures")
                    else [])
        assert bool(measured) == (truth[p] in ("stairs", "ramp") and "measures" in o)
        want = [f"  {o['object']}: {truth[p]}{shape}", *measured,
                f"    rule:   {o['rule']}  (training precision "
                f"{(tp + 1) / (tp + fp + 2):.3f})",
                "    planes: " + (", ".join(o["proof_planes"]) or "(the rule binds no plane)")]
        assert lines[n + 1:n + 1 + len(want)] == want


def test_classifier_explains_stairs_with_planes(gt_descs, tmp_path):
    from planerel.classify.classifier import Classifier, explanation_image
    from planerel.synth.generator import generate_scene

    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")
    (tmp_path / "rules.pl").write_text(model.text())
    clf = Classifier(tmp_path / "rules.pl")
    scene = generate_scene("stairs", seed=11, size=(640, 480), subsample=4, steps=4,
                           sides="open", walls=0)
    ans = clf.classify(scene.cloud, scene_id="s0100")
    assert [o.klass for o in ans.objects] == ["stairs"], [o.to_dict() for o in ans.objects]
    obj = ans.objects[0]
    # the learned stairs rule joins planes of the object by pairwise relations
    # (learn_rules on these scenes gives ``stairs(A) :- has_plane(A,B), parallel(B,C)``)
    assert len(obj.proof_planes) >= 2
    assert set(obj.proof_planes) <= set(obj.planes)
    # checked against the generator's ground truth: each proof plane is mostly one true face,
    # and every pairwise literal of the rule holds between the true faces of its planes
    inv = {v: k for k, v in ans.plane_ids.items()}
    face = {}
    for var, pid in obj.bindings.items():
        if pid in obj.proof_planes:
            g = scene.gt_labels[ans.labels == inv[pid]]
            g = g[g >= 0]
            face[var] = scene.planes[int(np.bincount(g).argmax())]
            assert face[var].object_index == 1
    checked = 0
    for name, a, b in re.findall(r"\b(parallel|perpendicular)\(([A-Z]),([A-Z])\)", obj.rule):
        fa, fb = face[a], face[b]
        angle = np.degrees(np.arccos(min(1.0, abs(float(np.dot(fa.normal, fb.normal))))))
        assert angle <= 10.0 if name == "parallel" else angle >= 80.0
        checked += 1
    assert checked >= 1, obj.rule
    pic = explanation_image(ans, scene.cloud.depth)
    assert pic.shape == (120, 160, 3)
    # the proof planes are drawn in colour, the rest of the image grey (R = G = B)
    proof = np.isin(ans.labels, [inv[p] for p in obj.proof_planes])
    grey = (pic[..., 0] == pic[..., 1]) & (pic[..., 1] == pic[..., 2])
    assert not grey[proof].any()
    assert grey[ans.labels < 0].all()


def _rules_file(path, stats, cofire=()):
    """Two rules that both fire on a staircase (any object with a plane is a box; one with a
    step is stairs), with the given training statistics ``{class: (tp, fp)}`` and
    ``planerel_rule_cofire(1, 2, Class, N)`` rows ``{class: n}``."""
    path.write_text(
        ":- dynamic(planerel_rule_stats/4).\n:- multifile(planerel_rule_stats/4).\n"
        ":- dynamic(planerel_rule_cofire/4).\n:- multifile(planerel_rule_cofire/4).\n"
        ":- style_check(-singleton).\n"
        "box(A) :- has_plane(A,B).\n"
        "stairs(A) :- has_plane(A,B), step_up(B,C).\n"
        f"planerel_rule_stats(1, box, {stats['box'][0]}, {stats['box'][1]}).\n"
        f"planerel_rule_stats(2, stairs, {stats['stairs'][0]}, {stats['stairs'][1]}).\n"
        + "".join(f"planerel_rule_cofire(1, 2, {k}, {n}).\n" for k, n in dict(cofire).items()))
    return path


@pytest.mark.parametrize("cofire, want", [
    # no co-firing statistics: precision alone (box 61/74 = 0.824 > stairs 31/38 = 0.816)
    ({}, "box"),
    # the training objects both rules proved were stairs (and clutter): stairs wins the pair
    ({"stairs": 1, "other": 4}, "stairs"),
    # as many of each: precision decides
    ({"stairs": 2, "box": 2}, "box"),
    ({"box": 3, "stairs": 1}, "box"),
])
def test_classifier_decides_a_conflict_by_what_both_rules_proved_in_training(tmp_path, cofire,
                                                                            want):
    """The demo model's case: a box rule 60/12 and a stairs rule 30/6 both prove a flight;
    ``planerel_rule_cofire/4`` says what the training objects they both proved were."""
    from planerel.classify.classifier import Classifier
    from planerel.synth.generator import generate_scene

    clf = Classifier(_rules_file(tmp_path / "rules.pl", {"box": (60, 12), "stairs": (30, 6)},
                                 cofire))
    assert sorted(clf.cofire) == sorted((1, 2, k, n) for k, n in cofire.items())
    scene = generate_scene("stairs", seed=11, size=(640, 480), subsample=4, steps=4,
                           sides="open", walls=0)
    o = clf.classify(scene.cloud, scene_id="s0100").objects[0]
    assert o.fired == (("box", 1), ("stairs", 2))
    assert o.klass == want and o.rule.startswith(want + "(")


def test_choose_class_three_classes_by_pairs():
    """Each pair of classes decided on its co-fired training objects; most pairs won wins."""
    stats = [(1, "box", 60, 12), (2, "stairs", 30, 6), (3, "ramp", 22, 4)]
    hits = [("box", 1, {}, "b"), ("stairs", 2, {}, "s"), ("ramp", 3, {}, "r")]
    # box-stairs: stairs (1 vs 0); box-ramp: box (2 vs 0); stairs-ramp: stairs (2 vs 0)
    cofire = [(1, 2, "stairs", 1), (1, 2, "other", 4), (1, 3, "box", 2), (2, 3, "stairs", 2)]
    assert M.choose_class(hits, stats, ["box", "stairs", "ramp"], cofire)[0] == "stairs"
    # without them: precision (box 0.824, ramp 0.821, stairs 0.816)
    assert M.choose_class(hits, stats, ["box", "stairs", "ramp"])[0] == "box"
    # a rule wrong as often as right stays out of the vote
    bad = [(1, "box", 60, 12), (2, "stairs", 6, 6), (3, "ramp", 22, 4)]
    assert M.choose_class(hits, bad, ["box", "stairs", "ramp"], cofire)[0] == "box"


def test_rule_stats_count_what_two_rules_proved_together(gt_descs):
    """A box rule that fires on every object and a stairs rule that fires on the staircases:
    on the 4 staircases both fire, so the model carries ``(1, 2, stairs, 4)``, and the
    file writes it as ``planerel_rule_cofire/4``."""
    model = P.Model(("box", "stairs"), {"box": ("box(A) :- has_plane(A,B).",),
                                        "stairs": ("stairs(A) :- has_plane(A,B), step_up(B,C).",)})
    stats, cofire = P.training_stats(model, gt_descs)
    assert stats == ((1, "box", 4, 8), (2, "stairs", 4, 0))
    assert cofire == ((1, 2, "stairs", 4),)
    text = P.Model(model.classes, model.rules, stats, cofire=cofire).text()
    assert "planerel_rule_cofire(1, 2, stairs, 4)." in text
    assert P.rule_stats(model, gt_descs) == stats      # without cofire: the stats alone


@pytest.mark.parametrize("stats, want", [
    # Laplace precision (tp + 1) / (tp + fp + 2): box 3/10 < stairs 5/6
    ({"box": (2, 6), "stairs": (4, 0)}, "stairs"),
    # box 9/10 > stairs 2/4
    ({"box": (8, 0), "stairs": (1, 1)}, "box"),
    # equal precision 5/6 and equal coverage: the class whose rule comes first in the file
    ({"box": (4, 0), "stairs": (4, 0)}, "box"),
    # equal precision 3/5 (box 2/1, stairs 5/3): more training objects covered wins
    ({"box": (2, 1), "stairs": (5, 3)}, "stairs"),
    # both rules were wrong as often as right in training (precision 1/2): none of the classes
    ({"box": (1, 1), "stairs": (3, 3)}, "other"),
    # a rule wrong more often than right does not count, however many objects it covered
    ({"box": (9, 12), "stairs": (1, 0)}, "stairs"),
])
def test_classifier_chooses_between_two_classes_that_fire(tmp_path, stats, want):
    from planerel.classify.classifier import Classifier
    from planerel.synth.generator import generate_scene

    clf = Classifier(_rules_file(tmp_path / "rules.pl", stats))
    scene = generate_scene("stairs", seed=11, size=(640, 480), subsample=4, steps=4,
                           sides="open", walls=0)
    ans = clf.classify(scene.cloud, scene_id="s0100")
    assert len(ans.objects) == 1
    o = ans.objects[0]
    assert o.fired == (("box", 1), ("stairs", 2))  # both rules proved the object
    assert o.klass == want
    if want == "other":
        assert o.rule is None and o.precision is None
    else:
        assert o.rule.startswith(want + "(")
        tp, fp = stats[want]
        assert o.precision == pytest.approx((tp + 1) / (tp + fp + 2))
        assert o.to_dict()["rule_index"] == (1 if want == "box" else 2)


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
    from planerel.classify.classifier import Classifier

    bad = tmp_path / "rules.pl"
    bad.write_text("stairs(A) :- has_plane(A, B), .\n")
    with pytest.raises(PrologError, match="rules.pl"):
        Classifier(bad)
    with pytest.raises(InputError, match="no such rules file"):
        Classifier(tmp_path / "missing.pl")


def test_classifier_takes_the_model_folder(tmp_path):
    """`planerel learn -o MODEL` writes MODEL/rules.pl: the folder names the model too."""
    from planerel.classify.classifier import Classifier

    (tmp_path / "model").mkdir()
    (tmp_path / "model" / "rules.pl").write_text("ramp(A) :- ninclined(A, 1).\n")
    clf = Classifier(tmp_path / "model")
    assert clf.rules_path == tmp_path / "model" / "rules.pl"
    assert clf.classes == ("ramp",)
    with pytest.raises(InputError, match="no such rules file"):
        Classifier(tmp_path)  # a folder without rules.pl


def test_no_swipl_on_path(gt_descs, monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(DependencyError, match="apt-get install swi-prolog-nox"):
        P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")


def test_empty_scene_gives_no_object(gt_descs, tmp_path):
    from planerel.classify.classifier import Classifier
    from planerel.io.cloud import Cloud, Intrinsics

    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")
    (tmp_path / "rules.pl").write_text(model.text())
    clf = Classifier(tmp_path / "rules.pl")
    intr = Intrinsics.kinect(160, 120)
    v, u = np.mgrid[0:120, 0:160].astype(float)
    z = np.full((120, 160), 2.0)
    xyz = np.stack([(u - intr.cx) * z / intr.fx, (v - intr.cy) * z / intr.fy, z], axis=2)
    ans = clf.classify(Cloud(xyz, intr), scene_id="s0200")  # one wall, nothing else
    # a fronto-parallel wall at 2 m is one plane and a support surface, not an object
    assert ans.n_planes == 1
    assert ans.objects == ()


def test_classify_dataset_scores_against_the_sidecar_truth(small_set, gt_descs, tmp_path):
    """classify_dataset (the held-out figure of docs/results.md) with a ramp-only model."""
    from planerel.classify.classifier import Classifier, classify_dataset

    model = P.learn_rules(gt_descs, ["box", "stairs", "ramp"], engine="builtin")
    # a model that knows ramps only: box and stairs scenes must come out "other"
    (tmp_path / "ramp.pl").write_text(":- style_check(-singleton).\n"
                                      + "\n".join(model.rules["ramp"]) + "\n")
    res = classify_dataset(Classifier(tmp_path / "ramp.pl"), small_set, out_dir=tmp_path / "o",
                           progress=False)
    truth = {p.name.split(".")[0]: json.loads(p.read_text())["class"]
             for p in sorted(small_set.glob("s*.json"))}
    assert [r["scene"] for r in res["scenes"]] == sorted(truth)
    assert [r["class"] for r in res["scenes"]] == [truth[k] for k in sorted(truth)]
    pred = [r["predicted"] for r in res["scenes"]]
    # accuracy and confusion recomputed from the per-scene answers
    assert res["accuracy"] == pytest.approx(
        sum(r["predicted"] == r["class"] for r in res["scenes"]) / 12)
    classes = res["classes"]
    assert classes[0] == "ramp" and set(classes) == {"box", "stairs", "ramp"}
    cols = classes + ["other"]
    want = [[sum(1 for r in res["scenes"] if r["class"] == c and r["predicted"] == q)
             for q in cols] for c in classes]
    assert res["confusion"] == want
    for r in res["scenes"]:
        if r["class"] != "ramp":  # no inclined plane, so the ramp rule cannot fire
            assert r["predicted"] == "other" and r["rule"] is None
    assert pred.count("ramp") == 4
    assert sorted(f.name for f in (tmp_path / "o").glob("*.classified.json")) == sorted(
        f"{k}.classified.json" for k in truth)
    assert 0 < res["ms_per_scene"]


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
    a, _ = S.describe_scenes(small_set, method="regiongrow", jobs=1, cache=cache)
    every = sorted((cache / "seg").glob("*.npy"))
    files = [f for f in every if not f.name.endswith(".far.npy")]
    # each scene's labels and the far growing's planes among them (segment_cached_far)
    assert len(files) == 12 and len(every) == 24
    stamp = [f.stat().st_mtime_ns for f in every]
    b, _ = S.describe_scenes(small_set, method="regiongrow", jobs=2, cache=cache)
    assert [f.stat().st_mtime_ns for f in sorted((cache / "seg").glob("*.npy"))] == stamp
    assert [d.scene_id for d in a] == [d.scene_id for d in b]
    assert [[o.planes for o in d.objects] for d in a] == [[o.planes for o in d.objects] for d in b]
    assert Path(files[0]).suffix == ".npy"


def test_score_objects_counts_other_as_an_answer():
    ex = [("a", "box"), ("b", "other"), ("c", "ramp"), ("d", "other"), ("e", "stairs")]
    pred = {"a": "box", "b": "other", "c": "box", "d": "ramp", "e": "other"}
    res = M.score_objects(ex, pred, ("box", "stairs", "ramp"))
    # class objects a, c, e: only a right
    assert res["accuracy"] == pytest.approx(1 / 3) and res["n_examples"] == 3
    assert res["confusion"] == [[1, 0, 0, 0], [0, 0, 0, 1], [1, 0, 0, 0]]
    assert res["other"] == {"n": 2, "rejected": 0.5, "predicted": {"other": 1, "ramp": 1}}
    # all five objects: a and b right
    assert res["open_set_accuracy"] == pytest.approx(2 / 5)
    assert res["open_set_confusion"][3] == [0, 0, 1, 1]
    assert res["open_set_per_class"] == {"box": 1.0, "stairs": 0.0, "ramp": 0.0, "other": 0.5}


def test_error_kinds_tell_a_lost_decision_from_an_unproved_object():
    # rules 1 box (10 right, 1 wrong), 2 stairs (5, 5: does not count), 3 other (8, 2)
    stats = ((1, "box", 10, 1), (2, "stairs", 5, 5), (3, "other", 8, 2))
    ex = [("a", "box"), ("b", "box"), ("c", "stairs"), ("d", "other"), ("e", "other"),
          ("f", "other")]
    pred = {"a": "box", "b": "other", "c": "other", "d": "box", "e": "box", "f": "other"}
    fired = {"a": (("box", 1),), "b": (("box", 1), ("other", 3)), "c": (("stairs", 2),),
             "d": (("box", 1), ("other", 3)), "e": (("box", 1),), "f": ()}
    res = M.error_kinds(ex, pred, fired, stats)
    # b and d: the right rule fired and lost; c: its only rule does not count; e: no other rule
    # fired (a decision could still answer other); only c is beyond any decision
    assert res == {"decision": 2, "unproved": 1, "unvetoed": 1, "n": 6,
                   "decision_bound": pytest.approx(5 / 6)}


def test_learn_scores_a_held_out_set(small_set, tmp_path):
    held = tmp_path / "held"
    generate_dataset(held, n_box=2, n_stairs=2, n_ramp=3, seed=77, size=(640, 480), subsample=4)
    # a model whose only rule says "an object with one inclined plane is a ramp": on
    # ground-truth planes the ramps are ramps and every other object is none of the classes
    model = P.Model(("box", "stairs", "ramp"), {"ramp": ("ramp(A) :- ninclined(A,1).",)},
                    ((1, "ramp", 5, 0),))
    res = P.held_out_scores(model, held, method="gt", jobs=1, cache="none")
    truth = {p.name.split(".")[0] + "_o1": json.loads(p.read_text())["class"]
             for p in sorted(held.glob("s*.json"))}
    assert res["predictions"] == {o: ("ramp" if k == "ramp" else "other") for o, k in truth.items()}
    assert res["accuracy"] == pytest.approx(3 / 7) and res["n_scenes"] == 7
    assert res["confusion"] == [[0, 0, 0, 2], [0, 0, 0, 2], [0, 0, 3, 0]]
    # the four wrong answers: no rule of their class fired
    assert res["errors"] == {"decision": 0, "unproved": 4, "unvetoed": 0, "n": 7,
                             "decision_bound": pytest.approx(3 / 7)}

    # planerel learn --heldout writes the same kind of figures into metrics.json
    m = P.learn_model(small_set, tmp_path / "model", method="gt", jobs=1, engine="builtin",
                      heldout=held, log=lambda s: None)
    h = m["heldout"]
    assert h["n_examples"] == 7 and sum(map(sum, h["confusion"])) == 7
    assert h["accuracy"] == pytest.approx(
        sum(h["predictions"][o] == k for o, k in truth.items()) / 7)
    assert json.loads((tmp_path / "model" / "metrics.json").read_text())["heldout"]["accuracy"] \
        == pytest.approx(h["accuracy"])


def test_a_class_prefixed_setting_changes_that_class_only(gt_descs):
    classes = ["box", "stairs", "ramp"]
    plain = P.learn_rules(gt_descs, classes, engine="builtin", jobs=1)
    # box:minpos above the number of box positives (4): no box clause is acceptable
    one = P.learn_rules(gt_descs, classes, engine="builtin", jobs=1, settings={"box:minpos": 50})
    assert plain.rules["box"] and not one.rules["box"]
    assert one.rules["stairs"] == plain.rules["stairs"] and one.rules["ramp"] == plain.rules["ramp"]
    common, per_class = P.split_class_settings({"noise": 6, "box:noise": 12, "ramp:i": 2}, classes)
    assert common == {"noise": 6} and per_class == {"box": {"noise": 12}, "ramp": {"i": 2}}
    with pytest.raises(InputError, match="'chair' is not a class"):
        P.split_class_settings({"chair:noise": 1}, classes)
    # other's settings wait for rules for other: none are learned here, so they are left out
    assert P.split_class_settings({"noise": 6, "other:noise": 5}, classes) == ({"noise": 6}, {})
    assert P.split_class_settings({"other:noise": 5}, [*classes, "other"])[1] == {
        "other": {"noise": 5}}


def test_learn_command_reads_class_settings():
    from planerel.commands.learn import _settings

    assert _settings(["noise=6", "box:noise=12"]) == {"noise": "6", "box:noise": "12"}
    with pytest.raises(InputError, match="NAME=VALUE"):
        _settings(["box:noise"])


def _ramps_as_other(descs):
    """The scenes with every ramp relabelled ``other`` (clutter: none of the classes)."""
    from dataclasses import replace

    return [replace(d, objects=tuple(replace(o, klass="other") if o.klass == "ramp" else o
                                     for o in d.objects)) for d in descs]


def test_other_rules_prove_none_of_the_classes(gt_descs, tmp_path):
    """With ``other`` objects in the data, a theory for ``other`` is learned too: its rules
    compete by precision, an object they prove is answered ``other`` *with* the rule, and the
    model's classes stay the real ones (in Python and in the classifier)."""
    from planerel.classify.classifier import Classifier

    descs = _ramps_as_other(gt_descs)
    model = P.learn_rules(descs, ["box", "stairs"], engine="builtin", other_rules=True)
    assert model.classes == ("box", "stairs")
    assert model.targets == ("box", "stairs", "other")
    assert model.rules["other"], "no rule for other learned"
    # statistics: one row per clause in file order, other's rules last, measured on the
    # training objects (an other rule's true positives are other objects)
    assert [k for _, k, _, _ in model.stats] == [k for k in model.targets
                                                 for _ in model.rules.get(k, ())]
    assert all(tp > 0 for _, k, tp, _ in model.stats if k == "other")
    text = model.text()
    assert "% ---- other" in text and text.index("% ---- other") > text.index("% ---- stairs")
    preds = P.prolog_predict(model, descs)
    truth = {o.id: o.klass for d in descs for o in d.objects}
    others = [p for p in preds if truth[p.object_id] == "other"]
    assert others and all(p.klass == "other" for p in others)
    # proved by a rule of other, not only left over
    assert all(p.rule and p.rule.startswith("other(") for p in others)
    assert all(p.klass == truth[p.object_id] for p in preds)
    (tmp_path / "rules.pl").write_text(text)
    clf = Classifier(tmp_path / "rules.pl")
    assert clf.classes == ("box", "stairs")
    assert {k for _, k, _, _ in clf.stats} == {"box", "stairs", "other"}


def test_no_other_rules_leaves_other_as_what_no_rule_proves(gt_descs):
    descs = _ramps_as_other(gt_descs)
    model = P.learn_rules(descs, ["box", "stairs"], engine="builtin")  # the default
    assert model.targets == ("box", "stairs") and "other" not in model.rules
    preds = P.prolog_predict(model, descs)
    truth = {o.id: o.klass for d in descs for o in d.objects}
    assert all(p.rule is None for p in preds if p.klass == "other")
    assert [p.klass for p in preds if truth[p.object_id] == "other"].count("other") >= 3


def test_learn_cli_other_rules(gt_descs, small_set, tmp_path):
    """`planerel learn --other-rules` on a data set whose ramps are labelled other: the model
    file has a section of rules for other; without the flag it has none."""
    import json as _json

    ds = tmp_path / "ds"
    shutil.copytree(small_set, ds)
    for p in ds.glob("s*.json"):
        d = _json.loads(p.read_text())
        if d["class"] == "ramp":
            for o in d["objects"]:
                if o["class"] == "ramp":
                    o["class"] = "other"
            d["class"] = "other"
            p.write_text(_json.dumps(d))
    assert main(["learn", str(ds), "-o", str(tmp_path / "m"), "--method", "gt",
                 "--other-rules", "--cache", "none"]) == 0
    rules = (tmp_path / "m" / "rules.pl").read_text()
    assert "% ---- other" in rules
    assert main(["learn", str(ds), "-o", str(tmp_path / "m2"), "--method", "gt",
                 "--cache", "none"]) == 0
    assert "% ---- other" not in (tmp_path / "m2" / "rules.pl").read_text()


# ---- clauses that add only false positives are left out (drop_redundant)


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


def test_learn_rules_keeps_each_rules_proof_scales(gt_descs):
    """proof22: the model keeps, per rule, the least and largest proof scale over the objects
    of its class the rule proves in training, measured by the real rule query."""
    classes = ["box", "stairs", "ramp"]
    model = P.learn_rules(gt_descs, classes, engine="builtin", jobs=1)
    examples = P._examples(gt_descs)
    truth = dict(examples)
    fired = P._parse_fired(P._prolog_run(model, gt_descs, [o for o, _ in examples], 120.0))
    area = {f"{d.scene_id}_p{p.label:02d}": p.area for d in gt_descs for p in d.planes}
    assert model.proof_domain
    for i, k, lo, hi, n in model.proof_domain:
        scales = [h[4] for o, hits in fired.items() for h in hits
                  if h[1] == i and truth[o] == k]
        tp = {j: t for j, _, t, _ in model.stats}[i]
        assert n == len(scales) == tp and 0 < lo <= hi
        assert (lo, hi) == (round(min(scales), 5), round(max(scales), 5))
        # a scale is at least the first proof's smallest plane (area/2 facts are rounded)
        for hits in fired.values():
            for h in hits:
                if h[1] == i and h[4] is not None:
                    planes = [v for v in h[2].values() if v in area]
                    assert planes and h[4] >= min(area[v] for v in planes) * 0.999 - 5e-4
    # under the gate (counted on however few positives) no training positive loses its class:
    # each one's own proofs lie inside its rule's range
    from dataclasses import replace

    on = {p.object_id: p.klass
          for p in P.prolog_predict(replace(model, proof_min_positives=1), gt_descs)}
    off = {p.object_id: p.klass
           for p in P.prolog_predict(replace(model, proof_gate=False), gt_descs)}
    right = [o for o, k in examples if off[o] == k]
    assert right and all(on[o] == truth[o] for o in right)


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


def test_one_class_learned_has_the_others_as_negatives(small_set, tmp_path):
    """``--classes box`` on a set of boxes, staircases and ramps (user103): every scene is
    kept, the staircases and ramps as objects of class other, the box task's negatives."""
    out = tmp_path / "m"
    m = P.learn_model(small_set, out, classes=["box"], method="gt", jobs=1, engine="builtin")
    assert m["classes"] == ["box"]
    assert m["n_scenes"] == 12
    pos = (out / "aleph" / "box.f").read_text().splitlines()
    neg = (out / "aleph" / "box.n").read_text().splitlines()
    assert len(pos) == 4 and len(neg) == 8
    descs, _ = S.describe_scenes(small_set, classes=["box"], method="gt", jobs=1, cache="none")
    kinds = sorted(o.klass for d in descs for o in d.objects)
    assert kinds == ["box"] * 4 + ["other"] * 8
